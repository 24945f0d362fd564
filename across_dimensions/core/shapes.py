"""Ready-made 4D solids as closed, positively oriented :class:`TetMesh4`.

Every builder returns a validated mesh centred at the origin, with ``float32``
vertices, ``uint32`` tets, a ``name`` and a gentle default per-vertex colour
(pass ``color=`` to override it).

=================  =========================================  =====================
name               solid                                      size parameter
=================  =========================================  =====================
``5-cell``         regular simplex, 5 tetrahedral cells       circumradius
``tesseract``      hypercube ``[-size/2, size/2]^4``          edge ``size``
``16-cell``        cross-polytope, 16 tetrahedral cells       circumradius
``24-cell``        24 octahedral cells                        circumradius (= edge)
``120-cell``       120 dodecahedral cells                     circumradius
``600-cell``       600 tetrahedral cells                      circumradius
``hypersphere``    tessellated 3-sphere (600-cell, split)     radius
``duoprism``       p-gon x q-gon                              circumradii r1, r2
``cubinder``       disc x square                              radius, height
``duocylinder``    disc x disc                                radius
``spherinder``     ball x segment                             radius, height
=================  =========================================  =====================

Method
------
All the solids are convex, so one generic builder serves them all:
:func:`~.polytope.convex_polytope` triangulates the convex hull of the
vertices from its outward facet normals (see :mod:`.polytope`).
:mod:`.polychora` holds the regular polychora and the 3-sphere,
:mod:`.products` the products of polygons, discs and balls. This module names
them (:data:`SHAPES`) and checks what a level or the command line asks for
(:func:`make_shape`).
"""

from __future__ import annotations

import inspect
from collections.abc import Callable

import numpy as np

from .errors import InputError
from .mesh import TetMesh4
from .polychora import cell16, cell24, cell120, cell600, hypersphere, simplex5, tesseract
from .polytope import PolytopeLattice, convex_polytope, polytope_lattice, pulling_tets
from .products import cubinder, duocylinder, duoprism, icosphere, spherinder

__all__ = [
    "SHAPES",
    "SHAPE_PARAM_RULES",
    "PolytopeLattice",
    "cell16",
    "cell24",
    "cell120",
    "cell600",
    "convex_polytope",
    "cubinder",
    "duocylinder",
    "duoprism",
    "hypersphere",
    "icosphere",
    "make_shape",
    "polytope_lattice",
    "pulling_tets",
    "shape_param_problem",
    "simplex5",
    "spherinder",
    "tesseract",
]


# ================================================================ registry
SHAPES: dict[str, Callable[..., TetMesh4]] = {
    "5-cell": simplex5,
    "simplex": simplex5,
    "tesseract": tesseract,
    "16-cell": cell16,
    "24-cell": cell24,
    "120-cell": cell120,
    "600-cell": cell600,
    "hypersphere": hypersphere,
    "duoprism": duoprism,
    "cubinder": cubinder,
    "duocylinder": duocylinder,
    "spherinder": spherinder,
}


#: What each shape parameter may be, for :func:`make_shape` and for levels
#: (``world/level.py`` checks an object's ``params`` with the same table).
#: ``(kind, (lo, hi))``: ``"whole"`` is an integer from ``lo`` to ``hi``;
#: ``"positive"`` is a finite number from ``lo`` to ``hi`` (sizes, in world
#: units). The whole-number bounds keep every shape under about 3 s and 400 MB
#: to build (``hypersphere`` with ``subdivisions=3`` has 307,200 tets, a
#: 128 x 128 ``duoprism`` 96,768); each subdivision multiplies the work by 8.
SHAPE_PARAM_RULES: dict[str, tuple[str, tuple[float, float]]] = {
    "radius": ("positive", (1e-3, 1e3)),
    "size": ("positive", (1e-3, 1e3)),
    "height": ("positive", (1e-3, 1e3)),
    "r1": ("positive", (1e-3, 1e3)),
    "r2": ("positive", (1e-3, 1e3)),
    "p": ("whole", (3, 128)),
    "q": ("whole", (3, 128)),
    "segments": ("whole", (3, 128)),
    "subdivisions": ("whole", (0, 3)),
}


def shape_param_problem(name: str, value) -> str | None:
    """Why ``value`` is not allowed for the shape parameter ``name`` (None if it is).

    Parameters outside :data:`SHAPE_PARAM_RULES` (``color``) are not judged here.
    """
    if name not in SHAPE_PARAM_RULES:
        return None
    kind, (lo, hi) = SHAPE_PARAM_RULES[name]
    is_number = isinstance(value, (int, float, np.integer, np.floating)) and not isinstance(value, (bool, np.bool_))
    if kind == "whole":
        whole = is_number and (isinstance(value, (int, np.integer)) or float(value).is_integer())
        if not (whole and lo <= value <= hi):
            return f"'{name}' must be a whole number from {lo} to {hi}, got {value!r}"
    elif not (is_number and np.isfinite(value) and lo <= value <= hi):
        return f"'{name}' must be a finite number from {lo:g} to {hi:g}, got {value!r}"
    return None


def make_shape(name: str, **params) -> TetMesh4:
    """Build a shape by its command-line name.

    Every parameter is checked against :data:`SHAPE_PARAM_RULES` before any
    work starts, so ``subdivisions=50`` is refused at once instead of filling
    memory.

    Parameters
    ----------
    name : str
        A key of :data:`SHAPES` (case and ``_``/``-`` are forgiven).
    **params
        Keyword arguments of that shape's builder.

    Returns
    -------
    TetMesh4

    Raises
    ------
    InputError
        One line naming the known shapes, or the parameter and its range.
    """
    key = str(name).strip().lower().replace("_", "-")
    if key not in SHAPES:
        raise InputError(f"unknown shape {name!r}; known shapes: {', '.join(SHAPES)}")
    builder = SHAPES[key]
    accepted = list(inspect.signature(builder).parameters)
    unknown = [p for p in params if p not in accepted]
    if unknown:
        raise InputError(f"shape {key!r} takes {', '.join(accepted)}; got unknown parameter(s) {', '.join(unknown)}")
    for pname, value in params.items():
        problem = shape_param_problem(pname, value)
        if problem:
            raise InputError(f"shape {key!r}: {problem}")
    try:
        return builder(**params)
    except (TypeError, ValueError) as e:
        given = ", ".join(f"{k}={v!r}" for k, v in params.items())
        raise InputError(f"shape {key!r} with {given}: {e}") from None
