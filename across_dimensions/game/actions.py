"""Per-tick action frames: what the player asks for, independent of keys.

The window turns keys and mouse motion into one :class:`Actions` per tick
(after key bindings, sensitivity and inversion), and replays store exactly these
frames, so rebinding keys or changing mouse settings never breaks a replay.
"""

from __future__ import annotations

from dataclasses import dataclass, fields

# Button actions packed into one integer per tick in replays. Append only:
# a bit's meaning must never change once replays exist.
BUTTONS = ("jump", "fire", "alt_fire", "switch_camera", "manipulate", "next_weapon")


@dataclass(frozen=True)
class Actions:
    """One tick of player intent.

    Parameters
    ----------
    forward, right : float
        Walking input in [-1, 1] (forward along the view, right strafes).
    yaw, pitch : float
        Look change this tick, radians (positive yaw turns right, positive
        pitch looks up).
    w : float
        Motion along the fourth axis in [-1, 1] (+1 is ana, +w).
    jump, fire, alt_fire, switch_camera, manipulate, next_weapon : bool
        Buttons; true on the ticks they are held.
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

    def to_row(self) -> list:
        """Compact replay form ``[forward, right, yaw, pitch, w, buttons]``."""
        bits = 0
        for i, name in enumerate(BUTTONS):
            if getattr(self, name):
                bits |= 1 << i
        return [self.forward, self.right, self.yaw, self.pitch, self.w, bits]

    @classmethod
    def from_row(cls, row) -> "Actions":
        """Inverse of :meth:`to_row`; raises ValueError on a malformed row."""
        if not isinstance(row, (list, tuple)) or len(row) != 6:
            raise ValueError(f"expected [forward, right, yaw, pitch, w, buttons], got {row!r}")
        *axes, bits = row
        if not all(isinstance(a, (int, float)) and not isinstance(a, bool) for a in axes) or not isinstance(bits, int):
            raise ValueError(f"expected five numbers and an integer, got {row!r}")
        if any(abs(a) > 1.0 for a in (axes[0], axes[1], axes[4])):
            raise ValueError(f"forward, right and w must lie in [-1, 1], got {row!r}")
        buttons = {name: bool(bits >> i & 1) for i, name in enumerate(BUTTONS)}
        return cls(float(axes[0]), float(axes[1]), float(axes[2]), float(axes[3]), float(axes[4]), **buttons)


IDLE = Actions()

assert [f.name for f in fields(Actions)][5:] == list(BUTTONS)
