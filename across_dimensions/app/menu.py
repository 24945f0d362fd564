"""The menus as a model: screens, items, a selection, and what each input does.

No window and no GL here: the window turns keys, mouse buttons and the wheel
into a few *verbs* (:data:`VERBS`, via :func:`menu_verb`, which also honours the
player's own movement and pause keys) and pointer events into item indices
(the layout is :func:`across_dimensions.render.menu.menu_layout`), and asks
:meth:`Menu.view` what to draw. So tests drive every screen headless with the
same calls the window makes.

Screens:

* ``title``: Continue, Level select, Settings, Quit (and the kernel compile's
  progress while it runs).
* ``pause``: Resume, Restart level, (Skip the prologue,) Settings, Quit to title.
* ``levels``: the campaign, each level unlocked or locked, finished with its best
  time and crystals found; a row switches the levels it starts to time trials.
* ``complete``: a level finished (:meth:`Menu.open_results`): its results, drawn above
  the rows, then Continue, Retry, Time trial, Level select.
* ``settings``: Controls, mouse sensitivity, invert X and Y, field of view,
  render scale, volume, colour-blind-safe and high-contrast palettes, reduce motion,
  text size, captions. Every change is applied at once (``on_change``) and the
  window saves the file.
* ``controls``: the keyboard layout preset (QWERTY, AZERTY) and one row per
  action; Left/Right on a held action's row (w moves, manipulation, orbit, slice
  turns) switches it between hold and toggle. Selecting a row waits for the next key or mouse button; a key that
  another action uses opens ``conflict``: swap the two actions' keys, bind it to
  both (the rows stay marked until resolved), or cancel.

Selecting an item that leaves the menus returns a *command* string for the
window: ``"continue"``, ``"play:<level>"``, ``"trial:<level>"``, ``"resume"``, ``"restart"``,
``"skip"``, ``"quit_to_title"``, ``"quit"``, or on the complete screen ``"next"``, ``"retry"``
and ``"time_trial"``.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

from ..world.campaign import CampaignEntry, locked_because
from .keymap import ACTION_DESCRIPTIONS, ACTIONS, PRESETS, TOGGLEABLE_ACTIONS
from .menu_settings import AUTO_VALUES, SETTINGS_ORDER, SLIDERS, TOGGLES
from .saves import Progress
from .settings import Settings

#: What the window tells the menu. ``clear`` unbinds a key in the controls list.
VERBS = ("up", "down", "left", "right", "select", "back", "clear")
#: Rows of items visible at once; longer lists scroll.
VISIBLE_ROWS = 10

#: Keys that always work in the menus, whatever the bindings.
_FIXED_VERBS = {
    "UP": "up",
    "DOWN": "down",
    "LEFT": "left",
    "RIGHT": "right",
    "RETURN": "select",
    "NUM_ENTER": "select",
    "SPACE": "select",
    "ESCAPE": "back",
    "BACKSPACE": "clear",
    "DELETE": "clear",
    "MOUSE_WHEEL_UP": "up",
    "MOUSE_WHEEL_DOWN": "down",
}
#: The player's own actions that also steer the menus (WASD or ZQSD, and their pause key).
_ACTION_VERBS = {
    "move_forward": "up",
    "move_back": "down",
    "strafe_left": "left",
    "strafe_right": "right",
    "pause": "back",
}


def menu_verb(key: str, settings: Settings) -> str | None:
    """The menu verb of a key or mouse-wheel name (``"W"``, ``"RETURN"``, ``"MOUSE_WHEEL_UP"``), or None."""
    if key in _FIXED_VERBS:
        return _FIXED_VERBS[key]
    for action, verb in _ACTION_VERBS.items():
        if key in settings.keys_for(action):
            return verb
    return None


@dataclass
class Item:
    """One row of a menu screen.

    Attributes
    ----------
    key : str
        What it is: ``"continue"``, ``"level:01_first_steps"``, ``"set:fov_deg"``, ``"bind:jump"``...
    label : str
        Shown on the left.
    value : str
        Shown on the right (a setting's value, a level's best time, an action's keys).
    enabled : bool
        Disabled rows (locked levels) are drawn dim and cannot be selected.
    note : str
        A second, smaller line (what a level teaches, whom a key conflicts with).
    warn : bool
        Draw the row in the warning colour (a key bound to two actions).
    fraction : float or None
        A slider's fill, 0..1; None for other rows.
    """

    key: str
    label: str
    value: str = ""
    enabled: bool = True
    note: str = ""
    warn: bool = False
    fraction: float | None = None


@dataclass
class MenuView:
    """Everything :mod:`across_dimensions.render.menu` needs to draw a screen.

    ``items[first:first + rows]`` are visible; ``prompt`` is a modal line (waiting for a
    key); ``progress`` is ``(done, total, label)`` while the kernels compile; ``dim`` asks
    for the scene behind to be darkened (pause) rather than hidden (title).
    """

    screen: str
    title: str
    items: list[Item]
    selected: int
    first: int
    rows: int
    footer: str
    prompt: str | None = None
    message: str = ""
    progress: tuple | None = None  # (steps done, steps, what, fraction 0..1): the warm-up's line
    dim: bool = False
    summary: tuple = ()  # (label, value, highlight) lines above the rows: a finished level's results


_TITLES = {
    "title": "ACROSS DIMENSIONS",
    "pause": "PAUSED",
    "levels": "LEVEL SELECT",
    "settings": "SETTINGS",
    "controls": "CONTROLS",
    "conflict": "KEY ALREADY IN USE",
    "complete": "LEVEL COMPLETE",
}


def format_time(seconds: float) -> str:
    """``83.25`` -> ``"1:23.2"``."""
    minutes, rest = divmod(max(0.0, seconds), 60.0)
    return f"{int(minutes)}:{rest:04.1f}"


def key_label(name: str) -> str:
    """A key name as a player reads it: ``"_1"`` -> ``"1"``, ``"MOUSE_LEFT"`` -> ``"mouse left"``."""
    if name.startswith("MOUSE_"):
        return name.replace("MOUSE_", "mouse ").replace("_", " ").lower()
    return name.lstrip("_")


class Menu:
    """The menus' state machine.

    Parameters
    ----------
    settings : Settings
        Changed in place by the settings and controls screens.
    progress : Progress
        Read for the level select and *Continue*.
    campaign : list of CampaignEntry
    on_change : callable, optional
        Called with the setting's name (``"bindings"`` for keys) after every change,
        so the window applies it at once and saves.
    """

    def __init__(
        self,
        settings: Settings,
        progress: Progress,
        campaign: list[CampaignEntry],
        on_change: Callable[[str], None] | None = None,
    ):
        self.settings = settings
        self.progress = progress
        self.campaign = campaign
        self.on_change = on_change or (lambda name: None)
        self.stack: list[str] = []
        self.selected: dict[str, int] = {}
        self.first: dict[str, int] = {}
        self.capturing: str | None = None  # the action waiting for its new key
        self.conflict: tuple[str, str, tuple[str, ...]] | None = None  # (action, key, other actions)
        self.progress_bar: tuple | None = None
        self.message = ""
        self.skippable = False  # the paused level may be skipped (the prologue): the pause menu says so
        self.optional = frozenset(e.stem for e in campaign if e.optional)
        self.trial = False  # the level select starts time trials
        self.results: tuple = ()  # the complete screen's summary and rows (open_results)
        self.finish_rows: list[Item] = []
        #: Rows shown at once: the window lowers it when larger text leaves room for fewer.
        self.rows = VISIBLE_ROWS

    # ------------------------------------------------------------------ screens
    @property
    def screen(self) -> str | None:
        """The screen shown, or None when the menus are closed (playing)."""
        return self.stack[-1] if self.stack else None

    def open(self, screen: str) -> None:
        """Show ``screen`` as the root (``"title"`` or ``"pause"``), its first enabled row selected."""
        self.stack = [screen]
        self.capturing = None
        self.selected[screen] = self._first_enabled(self.items())
        self.first[screen] = 0

    def open_results(self, results: tuple, following: str, time_trial: bool) -> None:
        """Open the level-complete screen: the ``results`` lines ``(label, value, highlight)`` over
        Continue (to ``following``), Retry, Time trial (``time_trial``: a 4D level) and Level select."""
        self.results = results
        trial = [Item("time_trial", "Time trial", "race your best run")] if time_trial else []
        self.finish_rows = [Item("next", "Continue", following), Item("retry", "Retry"), *trial]
        self.finish_rows.append(Item("levels", "Level select"))
        self.open("complete")

    def close(self) -> None:
        self.stack = []
        self.capturing = None

    def push(self, screen: str) -> None:
        self.stack.append(screen)
        self.message = ""
        items = self.items()
        keep = self.selected.get(screen, 0)
        if screen in ("conflict", "title", "pause") or not (0 <= keep < len(items) and items[keep].enabled):
            keep = self._first_enabled(items)
        self.selected[screen] = keep
        self._scroll_to_selected()

    def pop(self) -> str | None:
        """Go back one screen; from a root screen, pause resumes and the title stays."""
        self.message = ""
        if len(self.stack) > 1:
            self.stack.pop()
            return None
        return "resume" if self.screen == "pause" else None

    @staticmethod
    def _first_enabled(items: list[Item]) -> int:
        return next((i for i, it in enumerate(items) if it.enabled), 0)

    def items(self) -> list[Item]:
        """The rows of the current screen, built from the settings and progress as they are now."""
        return getattr(self, f"_items_{self.screen}")() if self.screen else []

    def _items_title(self) -> list[Item]:
        stems = [e.stem for e in self.campaign]
        stem, checkpoint = self.progress.continue_level(stems, self.optional)
        if stem is None:
            value = "campaign complete"
        else:
            value = self._title_of(stem) + ("" if checkpoint is None else f", checkpoint {checkpoint + 1}")
        return [
            Item("continue", "Continue", value, enabled=stem is not None),
            Item("levels", "Level select"),
            Item("settings", "Settings"),
            Item("quit", "Quit"),
        ]

    def _items_pause(self) -> list[Item]:
        skip = [Item("skip", "Skip the prologue")] if self.skippable else []
        return [
            Item("resume", "Resume"),
            Item("restart", "Restart level"),
            *skip,
            Item("settings", "Settings"),
            Item("quit_to_title", "Quit to title"),
        ]

    def _items_levels(self) -> list[Item]:
        stems = [e.stem for e in self.campaign]
        rows = []
        for i, (entry, open_) in enumerate(zip(self.campaign, self.progress.unlocked(stems, self.optional))):
            best = self.progress.finished.get(entry.stem)
            found = self.progress.crystals.get(entry.stem)
            if not open_:
                value = "locked"
            elif best is None:
                value = "new"
            else:
                value = f"done  {format_time(best)}"
            if open_ and found and found[1]:
                value += f"  crystals {found[0]}/{found[1]}"
            secrets = self.progress.secrets.get(entry.stem)
            if open_ and secrets and secrets[1]:
                value += f"  secrets {len(secrets[0])}/{secrets[1]}"
            rows.append(Item(f"level:{entry.stem}", f"{i + 1}. {entry.title}", value, open_, entry.teaches))
        trial = Item("trial_mode", "Time trial", "on" if self.trial else "off", note="race the ghost of your best run")
        return rows + [trial, Item("back", "Back")]

    def _items_complete(self) -> list[Item]:
        return self.finish_rows

    def _items_settings(self) -> list[Item]:
        rows = [Item("controls", "Controls", self.settings.preset.upper())]
        for name in SETTINGS_ORDER:
            if not hasattr(self.settings, name):  # added by another part of the game, maybe not yet
                continue
            value = getattr(self.settings, name)
            if name in SLIDERS:
                s = SLIDERS[name]
                number = self._number(name)
                fraction = (number - s.lo) / (s.hi - s.lo)
                shown = s.show(number) if value == number else f"{value} {s.show(number)}"
                rows.append(Item(f"set:{name}", s.label, shown, fraction=min(1.0, max(0.0, fraction))))
            else:
                rows.append(Item(f"set:{name}", TOGGLES[name], "on" if value else "off"))
        return rows + [Item("back", "Back")]

    def _items_controls(self) -> list[Item]:
        conflicts = self.settings.conflicts()
        rows = [Item("preset", "Keyboard layout (resets keys)", self.settings.preset.upper())]
        for action in ACTIONS:
            keys = self.settings.keys_for(action)
            others = sorted({a for k in keys for a in conflicts.get(k, ()) if a != action}, key=ACTIONS.index)
            note = ("also bound to: " + ", ".join(ACTION_DESCRIPTIONS[a] for a in others)) if others else ""
            value = " / ".join(key_label(k) for k in keys) or "(unbound)"
            if action in TOGGLEABLE_ACTIONS:  # Left/Right switches hold and toggle
                value += "  [toggle]" if action in self.settings.toggle_actions else "  [hold]"
            rows.append(Item(f"bind:{action}", ACTION_DESCRIPTIONS[action], value, note=note, warn=bool(others)))
        return rows + [Item("back", "Back")]

    def _items_conflict(self) -> list[Item]:
        action, key, others = self.conflict
        old = self.settings.keys_for(action)
        swap = f"{ACTION_DESCRIPTIONS[others[0]]} gets {key_label(old[0])}" if old else "it leaves the others"
        # What each choice does: on the row's second line (a long description would run over it).
        return [
            Item("swap", "Swap keys", "", note=swap if len(others) == 1 and old else "move it here"),
            Item("both", "Bind it to both", "", note="shown as a conflict"),
            Item("cancel", "Cancel"),
        ]

    def _title_of(self, stem: str) -> str:
        return next((e.title for e in self.campaign if e.stem == stem), stem)

    # -------------------------------------------------------------------- input
    def input(self, verb: str) -> str | None:
        """Apply one verb of :data:`VERBS`; returns a command for the window, or None."""
        if verb not in VERBS:
            raise ValueError(f"unknown menu verb {verb!r}; expected one of {VERBS}")
        if not self.screen:
            return None
        if self.capturing:  # the window sends keys to capture(); a verb here means Esc
            self.capturing = None
            return None
        items = self.items()
        i = self.selected.get(self.screen, 0)
        if verb in ("up", "down"):
            self._move(items, -1 if verb == "up" else 1)
            return None
        if verb == "back":
            return self.pop()
        if not items:
            return None
        item = items[i]
        if verb in ("left", "right"):
            self._adjust(item, -1 if verb == "left" else 1)
            return None
        if verb == "clear":
            if item.key.startswith("bind:"):
                self._bind(item.key[5:], ())
            return None
        return self._activate(item)

    def _move(self, items: list[Item], step: int) -> None:
        if not any(it.enabled for it in items):
            return
        i = self.selected.get(self.screen, 0)
        for _ in range(len(items)):
            i = (i + step) % len(items)
            if items[i].enabled:
                break
        self.selected[self.screen] = i
        self._scroll_to_selected()

    def _scroll_to_selected(self) -> None:
        i, first = self.selected.get(self.screen, 0), self.first.get(self.screen, 0)
        if i < first:
            first = i
        elif i >= first + self.rows:
            first = i - self.rows + 1
        self.first[self.screen] = max(0, min(first, max(0, len(self.items()) - self.rows)))

    def fit_rows(self, rows: int) -> None:
        """Show at most ``rows`` rows at once (up to :data:`VISIBLE_ROWS`), the selection kept in view."""
        rows = max(1, min(VISIBLE_ROWS, int(rows)))
        if rows != self.rows:
            self.rows = rows
            if self.screen:
                self._scroll_to_selected()

    def scroll(self, rows: int) -> None:
        """Scroll the list by ``rows`` (the mouse wheel) without moving the selection off screen."""
        n = len(self.items())
        first = max(0, min(self.first.get(self.screen, 0) + rows, max(0, n - self.rows)))
        self.first[self.screen] = first
        i = self.selected.get(self.screen, 0)
        self.selected[self.screen] = min(max(i, first), first + self.rows - 1, n - 1)

    def point(self, index: int) -> None:
        """The pointer is over row ``index`` (of :meth:`items`): select it if it is enabled."""
        items = self.items()
        if 0 <= index < len(items) and items[index].enabled and not self.capturing:
            self.selected[self.screen] = index

    def click(self, index: int, fraction: float | None = None) -> str | None:
        """A click on row ``index``; ``fraction`` (0..1) is where along a slider's bar it landed."""
        items = self.items()
        self.message = ""
        if self.capturing or not (0 <= index < len(items)):
            return None
        if not items[index].enabled:  # a locked level: say which one opens it
            self.message = locked_because(self.campaign, self.progress.finished, items[index].key[6:])
            return None
        self.selected[self.screen] = index
        item = items[index]
        if item.fraction is not None and fraction is not None:
            name = item.key[4:]
            s = SLIDERS[name]
            self._set(name, s.lo + min(1.0, max(0.0, fraction)) * (s.hi - s.lo))
            return None
        return self._activate(item)

    def _activate(self, item: Item) -> str | None:
        key = item.key
        if not item.enabled:
            return None
        if key in ("continue", "resume", "restart", "skip", "quit_to_title", "quit", "next", "retry", "time_trial"):
            return key
        if key.startswith("level:"):
            return ("trial:" if self.trial else "play:") + key[6:]
        if key == "trial_mode":
            self.trial = not self.trial
            return None
        if key in ("levels", "settings", "controls"):
            self.push(key)
            return None
        if key == "back":
            return self.pop()
        if key == "preset":
            self._adjust(item, 1)
            return None
        if key.startswith("set:"):
            name = key[4:]
            if name in TOGGLES:
                self._set(name, not getattr(self.settings, name))
            return None
        if key.startswith("bind:"):
            self.capturing = key[5:]
            return None
        if self.screen == "conflict":
            return self._resolve(key)
        return None

    def _adjust(self, item: Item, step: int) -> None:
        key = item.key
        if key == "trial_mode":
            self.trial = not self.trial
        elif key == "preset":
            names = list(PRESETS)
            preset = names[(names.index(self.settings.preset) + step) % len(names)]
            self.settings.preset = preset
            self.settings.bindings = {a: tuple(PRESETS[preset].get(a, ())) for a in ACTIONS}
            self.on_change("bindings")
        elif key.startswith("bind:") and key[5:] in TOGGLEABLE_ACTIONS:
            action, on = key[5:], set(self.settings.toggle_actions)
            on ^= {action}
            self.settings.toggle_actions = tuple(a for a in TOGGLEABLE_ACTIONS if a in on)
            self.on_change("toggle_actions")
        elif key.startswith("set:"):
            name = key[4:]
            if name in TOGGLES:
                self._set(name, not getattr(self.settings, name))
            elif name in SLIDERS:
                s = SLIDERS[name]
                self._set(name, self._number(name) + step * s.step)

    def _number(self, name: str) -> float:
        """A slider setting's number: a word such as ``render_scale = "auto"`` counts as its
        :data:`AUTO_VALUES` entry until the player moves the slider."""
        value = getattr(self.settings, name)
        return AUTO_VALUES.get(name, SLIDERS[name].lo) if isinstance(value, str) else float(value)

    def _set(self, name: str, value) -> None:
        if name in SLIDERS:
            s = SLIDERS[name]
            # Snap to the slider's steps, so keyboard and mouse reach the same values.
            value = s.lo + round((min(s.hi, max(s.lo, float(value))) - s.lo) / s.step) * s.step
            value = round(min(s.hi, max(s.lo, value)), 6)
        setattr(self.settings, name, value)
        self.on_change(name)

    # ---------------------------------------------------------------- rebinding
    def capture(self, key: str) -> None:
        """The key or mouse button pressed while a row waits for one (``"ESCAPE"`` cancels)."""
        action, self.capturing = self.capturing, None
        if action is None or key == "ESCAPE":
            return
        if key in ("BACKSPACE", "DELETE"):
            self._bind(action, ())
            return
        others = tuple(a for a in ACTIONS if a != action and key in self.settings.keys_for(a))
        if others:
            self.conflict = (action, key, others)
            self.push("conflict")
            return
        self._bind(action, self._with_primary(action, key))

    def _with_primary(self, action: str, key: str) -> tuple[str, ...]:
        """``action``'s keys with ``key`` in place of its first one (the others stay: W and UP)."""
        old = self.settings.keys_for(action)
        return (key, *[k for k in old[1:] if k != key])

    def _bind(self, action: str, keys: tuple[str, ...]) -> None:
        self.settings.bindings[action] = tuple(keys)
        self.on_change("bindings")

    def _resolve(self, choice: str) -> None:
        action, key, others = self.conflict
        if choice == "swap":
            old = self.settings.keys_for(action)
            for other in others:
                keys = [k for k in self.settings.keys_for(other) if k != key]
                if old and len(others) == 1 and old[0] not in keys:
                    keys.insert(0, old[0])  # the other action takes this one's old key
                self.settings.bindings[other] = tuple(keys)
            self._bind(action, self._with_primary(action, key))
        elif choice == "both":
            self._bind(action, self._with_primary(action, key))
        self.conflict = None
        self.stack.pop()
        return None

    # --------------------------------------------------------------------- view
    def view(self) -> MenuView | None:
        """What to draw now, or None when the menus are closed."""
        if not self.screen:
            return None
        screen = self.screen
        items = self.items()
        prompt = None
        if self.capturing:
            prompt = (
                f"Press a key or mouse button for: {ACTION_DESCRIPTIONS[self.capturing]}"
                "   (Esc cancels, Backspace unbinds)"
            )
        elif screen == "conflict":
            action, key, others = self.conflict
            prompt = (
                f"{key_label(key)} is used by: {', '.join(ACTION_DESCRIPTIONS[a] for a in others)}."
                f" Bind it to {ACTION_DESCRIPTIONS[action]}?"
            )
        footer = "Up/Down or mouse: choose    Enter or click: select    Esc: back"
        if screen in ("settings", "controls"):
            footer = "Left/Right: change    Enter: select    Esc: back    changes are saved at once"
        if screen == "controls":
            footer = "Enter: new key    Backspace: unbind    Left/Right: preset, or hold/toggle    Esc: back"
        if screen == "complete":
            footer = "Up/Down or mouse: choose    Enter or click: select"
        return MenuView(
            screen=screen,
            title=_TITLES[screen],
            items=items,
            selected=self.selected.get(screen, 0),
            first=self.first.get(screen, 0),
            rows=self.rows,
            footer=footer,
            prompt=prompt,
            message=self.message,
            progress=self.progress_bar if screen == "title" else None,
            dim="pause" in self.stack or "complete" in self.stack,
            summary=self.results if screen == "complete" else (),
        )
