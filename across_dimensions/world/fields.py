"""The building block of the level format's models: one :class:`Field` per field of a table.

Each TOML table of a level file has a model: a dict of field name to
:class:`Field`, saying what kind of value the field holds, its default and
its accepted range. ``world.level`` reads tables by their models and
``world.json_schema`` turns the same models into a JSON Schema, so the loader
and designers' editors can never disagree.
"""

from __future__ import annotations

from dataclasses import dataclass

from .limits import Range

REQUIRED = object()  # a Field default: the field must be given


@dataclass(frozen=True)
class Field:
    """One field of a table.

    Parameters
    ----------
    kind : str
        ``number``, ``vector`` (``n`` numbers), ``scale`` (a number or ``n``
        numbers), ``string``, ``text`` (a string with a length limit),
        ``bool``, ``color``, ``angles`` (a table of plane = degrees),
        ``asset``, ``params`` (shape parameters), ``hints``, ``tables``
        (an array of tables read by its own model).
    n : int
        Number of components of a ``vector`` or ``scale``.
    default : object
        Used when the field is absent; :data:`REQUIRED` makes it a problem.
    range : Range, optional
        Accepted values (per component for vectors, per plane for angles).
    sign : {None, "positive", "nonnegative"}
        Checked before the range, with the format's first messages
        ("expected a number > 0"), which players and tests know.
    choices : tuple of str
        Accepted strings.
    names : str
        Component names for messages (``"xyzw"``, ``"ab"``).
    length : float, optional
        Largest Euclidean length of a ``vector`` (gravity).
    """

    kind: str
    n: int = 1
    default: object = REQUIRED
    range: Range | None = None
    sign: str | None = None
    choices: tuple = ()
    names: str = "xyzw"
    length: float | None = None
