"""Command-line option values: the error a user can fix, and the parsers that raise it.

Kept apart from :mod:`.cli` (which builds the parser and dispatches) and
:mod:`.commands` (which does the work) so neither has to import the other.
Every parser raises :class:`UserError` with one line naming the option, what
was given and what was expected.
"""

from __future__ import annotations

import argparse
import math

from ..core.errors import InputError

__all__ = [
    "PROG",
    "UserError",
    "parse_size",
    "positive_float",
    "fov_degrees",
    "positive_int",
    "SIZE_RANGE",
    "OPTION_LIMIT",
    "FOV_RANGE",
    "axis_values",
]

#: The command's name, as users type it and as every message starts.
PROG = "across-dimensions"
#: Screenshot sizes accepted by ``--size``, pixels per side.
SIZE_RANGE = (16, 8192)
#: Largest magnitude accepted for --rotate degrees, --translate, --distance and --depth:
#: beyond it float32 vertices lose all precision or overflow.
OPTION_LIMIT = 1e6


class UserError(InputError):
    """A problem the user can fix; printed as one line."""


def parse_size(text: str) -> tuple[int, int]:
    """``"640x360"`` as ``(640, 360)``; each side within :data:`SIZE_RANGE`."""
    lo, hi = SIZE_RANGE
    try:
        w, h = (int(v) for v in text.lower().split("x"))
        if not (lo <= w <= hi and lo <= h <= hi):
            raise ValueError
    except ValueError:
        raise UserError(f"--size: expected WIDTHxHEIGHT between {lo} and {hi}, got {text!r}") from None
    return w, h


def _number(text: str) -> float:
    try:
        x = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a number") from None
    if not math.isfinite(x):
        raise argparse.ArgumentTypeError(f"expected a finite number, got {text!r}")
    return x


def positive_float(text: str) -> float:
    """argparse type: a finite number in ``(0, OPTION_LIMIT]``."""
    x = _number(text)
    if not 0 < x <= OPTION_LIMIT:
        raise argparse.ArgumentTypeError(f"expected a positive number up to {OPTION_LIMIT:g}, got {text!r}")
    return x


#: Lengths accepted for sizes such as ``--depth``, metres: the level format's own range.
LENGTH_RANGE = (1e-3, 1e4)


def length(text: str) -> float:
    """argparse type: a length in metres within :data:`LENGTH_RANGE`."""
    x = _number(text)
    lo, hi = LENGTH_RANGE
    if not lo <= x <= hi:
        raise argparse.ArgumentTypeError(f"expected a length from {lo:g} to {hi:g}, got {text!r}")
    return x


#: Field of view accepted by ``--fov``, degrees: inside (0, 180), with a margin so
#: the projection's 1 / tan(fov / 2) stays finite.
FOV_RANGE = (0.001, 179.999)


def fov_degrees(text: str) -> float:
    """argparse type: a field of view in degrees, strictly between 0 and 180 (see :data:`FOV_RANGE`)."""
    x = _number(text)
    lo, hi = FOV_RANGE
    if not lo <= x <= hi:
        raise argparse.ArgumentTypeError(
            f"expected degrees strictly between 0 and 180 ({lo:g} to {hi:g}), got {text!r}"
        )
    return x


def positive_int(text: str) -> int:
    """argparse type: a whole number from 1 to 10**6."""
    try:
        n = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a whole number, got {text!r}") from None
    if not 1 <= n <= 10**6:
        raise argparse.ArgumentTypeError(f"expected a whole number from 1 to 1000000, got {text!r}")
    return n


def axis_values(items, kind: str, option: str) -> dict[str, float]:
    """``--rotate xw=30`` / ``--translate w=0.3`` items as a dict, each value finite and bounded.

    Raises
    ------
    UserError
        Naming ``option`` and the item.
    """
    from ..core.transform import parse_axis_assignments

    try:
        values = parse_axis_assignments(items, kind)
    except ValueError as e:
        raise UserError(f"{option} {e}") from None
    for key, x in values.items():
        if not (math.isfinite(x) and abs(x) <= OPTION_LIMIT):
            raise UserError(
                f"{option} {key}={x}: expected a finite number between {-OPTION_LIMIT:g} and {OPTION_LIMIT:g}"
            )
    return values
