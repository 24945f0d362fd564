"""The base of every game event and the list of their kinds."""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar


@dataclass(frozen=True)
class Event:
    """Base class of every game event. ``causes`` names a field whose value is counted beside
    the kind, as ``"kind:value"`` in ``game.cause_counts`` (the replay summary's ``causes``)."""

    kind: ClassVar[str] = "event"
    causes: ClassVar[str | None] = None


def event_kinds() -> list[str]:
    """Every event kind defined so far (subclasses of :class:`Event` anywhere), sorted."""
    found, todo = set(), [Event]
    while todo:
        for sub in todo.pop().__subclasses__():
            found.add(sub.kind)
            todo.append(sub)
    return sorted(found)
