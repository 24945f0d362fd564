"""Per-tick action frames: what the player asks for, independent of keys.

The window turns keys and mouse motion into one :class:`Actions` per tick
(after key bindings, sensitivity and inversion), and replays store exactly these
frames, so rebinding keys or changing mouse settings never breaks a replay.

Two kinds of buttons:

- **held** (:data:`BUTTONS`): true on every tick the button is down (jump).
- **presses** (:data:`PRESSES`): one-shot actions (fire, switch weapon, switch
  camera, manipulate, ...) counted between two ticks and delivered on the next
  one, so a tap shorter than a tick is never lost and two quick taps are two.
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass, fields, replace

# Button actions packed into one integer per tick in replays. Append only:
# a bit's meaning must never change once replays exist.
BUTTONS = (
    "jump",
    "fire",
    "alt_fire",
    "switch_camera",
    "manipulate",
    "next_weapon",
    "turn_xw_pos",
    "turn_xw_neg",
    "turn_yw_pos",
    "turn_yw_neg",
    "turn_zw_pos",
    "turn_zw_neg",
    "orbit_left",
    "orbit_right",
    "reduced_motion",
)
#: The held buttons that turn the slice (xw, yw, zw; positive then negative) and move the orbit.
CAMERA_BUTTONS = BUTTONS[6:14]
#: Largest look change in one tick, radians, for yaw and for pitch alike. Half a
#: turn per tick is far beyond any mouse (a flick of 180 degrees in 1/60 s), and
#: a bound keeps a hand-edited replay from feeding the simulation 1e300 radians.
MAX_LOOK = math.pi
#: One-shot actions, counted per tick. Append only: replays name them.
PRESSES = (
    "fire",
    "alt_fire",
    "next_weapon",
    "previous_weapon",
    "switch_camera",
    "manipulate",
    "weapon_1",
    "weapon_2",
    "weapon_3",
    "seek",
    "seek_jump",
    "snap_slice",
    "step_xw_pos",
    "step_xw_neg",
    "step_yw_pos",
    "step_yw_neg",
    "step_zw_pos",
    "step_zw_neg",
)
#: Most presses of one action in one tick that a replay may carry (a key repeat
#: or a wheel spin gives a few; more is a corrupt file).
MAX_PRESSES = 100
_AXES = ("forward", "right", "yaw", "pitch", "w")
_AXIS_LIMIT = {"forward": 1.0, "right": 1.0, "yaw": MAX_LOOK, "pitch": MAX_LOOK, "w": 1.0}
_NUMBER = (int, float)  # compared with type(): bool is an int subclass, and no axis value
#: The button flags for each packed ``buttons`` value, in BUTTONS order.
_BUTTON_SETS = tuple(tuple(bool(bits >> i & 1) for i in range(len(BUTTONS))) for bits in range(1 << len(BUTTONS)))


@dataclass(frozen=True)
class Actions:
    """One tick of player intent.

    Parameters
    ----------
    forward, right : float
        Walking input in [-1, 1] (forward along the view, right strafes).
    yaw, pitch : float
        Look change this tick, radians (positive yaw turns right, positive
        pitch looks up), each within ``[-MAX_LOOK, MAX_LOOK]``.
    w : float
        Motion along the fourth axis in [-1, 1] (+1 is ana, +w).
    jump, fire, alt_fire, switch_camera, manipulate, next_weapon : bool
        Buttons; true on the ticks they are held.
    turn_xw_pos, turn_xw_neg, turn_yw_pos, turn_yw_neg, turn_zw_pos, turn_zw_neg : bool
        Held: turn the slice in that plane (the paper's t, u, v), one way or the other.
    orbit_left, orbit_right : bool
        Held: move the detached 4D camera along its orbit round the focus point.
    reduced_motion : bool
        The player's "reduce motion" setting, on every tick it is on: what glides (slice
        steps and snap, seek, the camera's return, held turns and the orbit) snaps instead
        (:mod:`.motion`). A flag of the frame rather than of the game, so a replay records
        it and plays back the same way whatever the settings of whoever watches it.
    presses : tuple of (str, int)
        One-shot actions pressed since the last tick and how often, in
        :data:`PRESSES` order (build it with :meth:`count_presses`; read it
        with :meth:`pressed`).

    Every field is finite and within its bound when the frame comes from a
    replay (:meth:`from_row` refuses anything else) or from the window
    (:meth:`clamped`).
    """

    forward: float = 0.0
    right: float = 0.0
    yaw: float = 0.0
    pitch: float = 0.0
    w: float = 0.0
    jump: bool = False
    fire: bool = False
    alt_fire: bool = False
    switch_camera: bool = False
    manipulate: bool = False
    next_weapon: bool = False
    turn_xw_pos: bool = False
    turn_xw_neg: bool = False
    turn_yw_pos: bool = False
    turn_yw_neg: bool = False
    turn_zw_pos: bool = False
    turn_zw_neg: bool = False
    orbit_left: bool = False
    orbit_right: bool = False
    reduced_motion: bool = False
    presses: tuple = ()

    def pressed(self, action: str) -> int:
        """How many times the one-shot ``action`` (one of :data:`PRESSES`) was pressed since the last tick."""
        for name, count in self.presses:
            if name == action:
                return count
        return 0

    def to_row(self) -> list:
        """Compact replay form ``[forward, right, yaw, pitch, w, buttons]``, plus
        ``{action: count}`` of the presses when there were any."""
        bits = 0
        for i, name in enumerate(BUTTONS):
            if getattr(self, name):
                bits |= 1 << i
        row = [self.forward, self.right, self.yaw, self.pitch, self.w, bits]
        if self.presses:
            row.append(dict(self.presses))
        return row

    @staticmethod
    def count_presses(counts: dict) -> tuple:
        """``presses`` from ``{action: count}``: known actions only, in :data:`PRESSES` order, zeros dropped."""
        return tuple((name, int(counts[name])) for name in PRESSES if counts.get(name))

    @classmethod
    def from_row(cls, row) -> Actions:
        """Inverse of :meth:`to_row`; raises ValueError on a malformed row.

        The five axes must be finite numbers (not booleans) within their
        bounds: forward, right and w in [-1, 1], yaw and pitch in
        [-MAX_LOOK, MAX_LOOK]. ``buttons`` is a whole number whose set bits are
        all known buttons (``0 <= buttons < 2 ** len(BUTTONS)``).
        """
        if type(row) not in (list, tuple) or len(row) not in (6, 7):
            raise ValueError(
                f"expected [forward, right, yaw, pitch, w, buttons] or the same with "
                f"{{action: presses}} after it, got {short_repr(row)}"
            )
        if len(row) == 7:
            return replace(cls.from_row(row[:6]), presses=_presses(row[6]))
        f, r, y, p, w, bits = row
        # One expression for the common case (a replay has up to 432,000 rows);
        # type() is not isinstance(), so True is not a number here. Comparing
        # before converting: float() of a huge int overflows, and int/float
        # comparison is exact at any size. Comparisons are false for NaN.
        if (
            type(f) in _NUMBER
            and type(r) in _NUMBER
            and type(y) in _NUMBER
            and type(p) in _NUMBER
            and type(w) in _NUMBER
            and type(bits) is int
            and -1.0 <= f <= 1.0
            and -1.0 <= r <= 1.0
            and -MAX_LOOK <= y <= MAX_LOOK
            and -MAX_LOOK <= p <= MAX_LOOK
            and -1.0 <= w <= 1.0
            and 0 <= bits < len(_BUTTON_SETS)
        ):
            return cls(float(f), float(r), float(y), float(p), float(w), *_BUTTON_SETS[bits])
        for name, v in zip(_AXES, row):
            limit = _AXIS_LIMIT[name]
            if type(v) not in _NUMBER or not -limit <= v <= limit:
                raise ValueError(
                    f"{name}: expected a finite number in [{-limit:.6g}, {limit:.6g}], got {short_repr(v)}"
                )
        raise ValueError(f"buttons: expected a whole number from 0 to {len(_BUTTON_SETS) - 1}, got {short_repr(bits)}")

    def clamped(self) -> Actions:
        """This frame made safe to simulate and record: each axis clamped to its
        bound, a non-finite axis set to 0, ``-0.0`` written as ``0.0`` (so equal
        frames have equal replay rows)."""
        changes = {}
        for name in _AXES:
            v = getattr(self, name)
            limit = _AXIS_LIMIT[name]
            try:
                f = float(v)
            except OverflowError:  # an int too large for a float: past the bound anyway
                f = limit if v > 0 else -limit
            safe = min(max(f, -limit), limit) + 0.0 if math.isfinite(f) else 0.0
            if safe != v or math.copysign(1.0, safe) != math.copysign(1.0, v) or type(v) is not float:
                changes[name] = safe
        return replace(self, **changes) if changes else self

    def same_row(self, other: Actions) -> bool:
        """True when both frames have the same replay row, signs of zeros included
        (``0.0 == -0.0`` in Python, but the simulation can tell them apart)."""
        if self != other:
            return False
        return all(math.copysign(1.0, getattr(self, n)) == math.copysign(1.0, getattr(other, n)) for n in _AXES)


def _presses(value) -> tuple:
    """Check a replay row's ``{action: count}``."""
    if type(value) is not dict or not value:
        raise ValueError(f"presses: expected a table of action = count, got {short_repr(value)}")
    for name, count in value.items():
        if name not in PRESSES:
            raise ValueError(f"presses: unknown action {short_repr(name)} (expected one of {', '.join(PRESSES)})")
        if type(count) is not int or not 1 <= count <= MAX_PRESSES:
            raise ValueError(
                f"presses: '{name}': expected a whole number from 1 to {MAX_PRESSES}, got {short_repr(count)}"
            )
    return Actions.count_presses(value)


def short_repr(value, limit: int = 40) -> str:
    """A short repr for messages: a hostile file must not make a message long."""
    if isinstance(value, int) and not isinstance(value, bool) and abs(value) > 10**limit:
        try:
            return f"a number of {len(str(abs(value)))} digits"
        except ValueError:  # beyond Python's int-to-text limit (4300 digits)
            return f"a number of about {int(value.bit_length() * 0.30103) + 1} digits"
    text = repr(value)
    return text if len(text) <= limit else text[: limit - 3] + "..."


IDLE = Actions()

assert [f.name for f in fields(Actions)][5:-1] == list(BUTTONS)


class ActionRuns:
    """Per-tick actions kept as runs of equal frames.

    Iterating yields one :class:`Actions` per tick, lazily; ``len`` is the
    number of ticks. Memory is O(number of runs), whatever the length.

    Parameters
    ----------
    frames : iterable of Actions, optional
        Ticks to start with.
    """

    __slots__ = ("_runs", "_ticks")

    def __init__(self, frames=()):
        self._runs: list[list] = []  # [count, Actions], adjacent rows differ
        self._ticks = 0
        for a in frames:
            self.append(a)

    def append(self, actions: Actions, count: int = 1) -> None:
        """Add ``count`` ticks of ``actions`` (merged into the last run when equal)."""
        if count < 1:
            raise ValueError(f"count must be positive, got {count}")
        if self._runs and self._runs[-1][1].same_row(actions):
            self._runs[-1][0] += count
        else:
            self._runs.append([count, actions])
        self._ticks += count

    @property
    def runs(self) -> list[tuple[int, Actions]]:
        """The runs as ``(count, actions)`` pairs."""
        return [(c, a) for c, a in self._runs]

    def __len__(self) -> int:
        return self._ticks

    def __iter__(self):
        return itertools.chain.from_iterable(itertools.repeat(a, c) for c, a in self._runs)

    def __eq__(self, other) -> bool:
        if not isinstance(other, ActionRuns):
            return NotImplemented
        return len(self._runs) == len(other._runs) and all(
            c == d and a.same_row(b) for (c, a), (d, b) in zip(self._runs, other._runs)
        )

    def __repr__(self) -> str:
        return f"ActionRuns({self._ticks} ticks in {len(self._runs)} runs)"
