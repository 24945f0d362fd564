"""The ``[[object]]`` table of a level: a 4D object, either a named shape or a 3D asset lifted to
4D, with its pose, and what is checked across its fields (exactly one of shape or asset, the
shape's parameters, its estimated tetrahedra, a rigid body's proportions).
"""

from __future__ import annotations

import inspect
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..core.shapes import SHAPE_PARAM_RULES
from . import limits
from .fields import REQUIRED, Field
from .level_reader import TableReader, is_number
from .limits import ANGLE, COORD, MASS, MAX_COUNTS, MAX_NAME_CHARS, SCALE, SIZE, SPEED, SPIN, Range

OBJECT_BODIES = ("none", "hypersphere", "hypercube")
OBJECT_COLOR = (0.95, 0.55, 0.2, 1.0)
OBJECT = {
    "name": Field("text", default=None, range=Range(0, MAX_NAME_CHARS)),
    "shape": Field("string", default=None),
    "asset": Field("asset", default=None),
    "params": Field("params", default=None),
    "depth": Field("number", default=1.0, range=SIZE, sign="positive"),
    "position": Field("vector", 4, range=COORD),
    "rotation": Field("angles", default=None, range=ANGLE),
    "scale": Field("scale", 4, default=1.0, range=SCALE, sign="positive"),
    "color": Field("color", default=OBJECT_COLOR),
    "spin": Field("angles", default=None, range=SPIN),
    "solid": Field("bool", default=True),
    "walkable_in_frustum": Field("bool", default=False),
    "body": Field("string", default="none", choices=OBJECT_BODIES),
    "mass": Field("number", default=1.0, range=MASS, sign="positive"),
    "velocity": Field("vector", 4, default=(0.0, 0.0, 0.0, 0.0), range=SPEED),
}
# Shape parameters: how each is checked (the builders in core/shapes.py take these names).
# One table of rules for the core's builders and for levels (core.shapes.SHAPE_PARAM_RULES);
# lengths are in metres here.
_PARAM_RULES = {
    name: (kind, Range(lo, hi, "m" if kind == "positive" else ""))
    for name, (kind, (lo, hi)) in SHAPE_PARAM_RULES.items()
}


def _param_problem(name, value) -> str | None:
    if name == "color":
        return "set the colour with the object's 'color' field, not in 'params'"
    kind, rng = _PARAM_RULES.get(name, (None, None))
    if kind == "positive":
        if not (is_number(value) and value > 0):
            return f"'{name}' must be a positive number, got {value!r}"
        if value not in rng:
            return f"'{name}' must be a number {rng.text()}, got {value!r}"
    if kind == "whole" and not (isinstance(value, int) and not isinstance(value, bool) and value in rng):
        return f"'{name}' must be a whole number from {rng.lo:g} to {rng.hi:g}, got {value!r}"
    return None


@dataclass
class ObjectSpec:
    """A 4D object: a named shape or a lifted 3D asset, with a 4D pose."""

    name: str
    shape: str | None
    params: dict
    asset: Path | None
    depth: float
    position: np.ndarray
    rotation_deg: dict
    scale: np.ndarray
    color: tuple
    spin_deg: dict
    solid: bool
    body: str
    mass: float
    velocity: np.ndarray = field(default_factory=lambda: np.zeros(4))
    walkable_in_frustum: bool = False


def read_object(r: TableReader, ot: dict, i: int) -> ObjectSpec:
    where = f"[[object]] #{i}"
    r.unknown(ot, OBJECT, where)
    name = r.read(ot, OBJECT, where, keys=("name",), name=f"object{i}")["name"]
    where = f"[[object]] #{i} '{name}'"
    shape, asset = _shape_or_asset(r, ot, where)
    params, params_ok = _shape_params(r, ot, where, shape)
    r.add_tets(_object_tets(r, where, shape, params, params_ok, asset), where)
    v = r.read(
        ot,
        OBJECT,
        where,
        keys=(
            "depth",
            "position",
            "rotation",
            "scale",
            "color",
            "spin",
            "solid",
            "body",
            "mass",
            "velocity",
            "walkable_in_frustum",
        ),
    )
    if v["body"] != "none":
        _check_body(r, where, v, (shape, params) if params_ok else None, asset)
        if v["walkable_in_frustum"]:
            r.problem(
                where,
                "field 'walkable_in_frustum': a rigid body cannot be walked on as its image (expected body = 'none')",
            )
    return ObjectSpec(
        name,
        shape,
        params,
        asset,
        v["depth"],
        v["position"],
        v["rotation"],
        v["scale"],
        v["color"],
        v["spin"],
        v["solid"],
        v["body"],
        v["mass"],
        v["velocity"],
        v["walkable_in_frustum"],
    )


def _shape_or_asset(r: TableReader, ot: dict, where: str) -> tuple[str | None, Path | None]:
    """The object's 4D shape name or its 3D asset to lift: exactly one of them (the other None;
    both None when that is reported, or the shape is unknown)."""
    from ..core.shapes import SHAPES  # the shape registry; imported here to keep level parsing light

    if ("shape" in ot) == ("asset" in ot):
        r.problem(where, "expected exactly one of 'shape' (a 4D shape name) or 'asset' (a 3D mesh to lift)")
        return None, None
    if "asset" in ot:
        return None, r._asset(ot, "asset", where, OBJECT["asset"], REQUIRED)
    shape = r._string(ot, "shape", where, Field("string", choices=tuple(SHAPES)), REQUIRED)
    return (shape, None) if shape == ot["shape"] else (None, None)  # no params checked against a stand-in


def _shape_params(r: TableReader, ot: dict, where: str, shape: str | None) -> tuple[dict, bool]:
    """The shape's ``params`` table, and whether it is fine for ``shape`` (False when there is no
    shape to check it against)."""
    from ..core.shapes import SHAPES

    params = ot.get("params", {})
    if not isinstance(params, dict):
        r.problem(where, f"field 'params': expected a table of shape parameters, got {params!r}")
        return {}, False
    if shape not in SHAPES:
        return params, False
    try:
        inspect.signature(SHAPES[shape]).bind(**params)
    except TypeError as e:
        accepted = ", ".join(inspect.signature(SHAPES[shape]).parameters)
        r.problem(where, f"field 'params': {e} (shape '{shape}' accepts: {accepted})")
        return params, False
    n = len(r.problems)
    for k, val in params.items():
        why = _param_problem(k, val)
        if why:
            r.problem(where, f"field 'params': {why}")
    return params, len(r.problems) == n


def _object_tets(r: TableReader, where: str, shape, params: dict, params_ok: bool, asset) -> int:
    """The object's estimated tetrahedra, reporting a shape too thin or too fine to build."""
    if not params_ok:
        return limits.asset_object_tets() if asset is not None else 0
    why = limits.shape_aspect_problem(shape, params)
    if why:
        r.problem(where, f"field 'params': {why}")
    tets = limits.shape_tets(shape, params)
    if tets > limits.MAX_OBJECT_TETS:
        r.problem(
            where,
            f"field 'params': shape '{shape}' with these parameters has {tets:,} tetrahedra; "
            f"an object may have at most {limits.MAX_OBJECT_TETS:,}",
        )
    return tets


def _check_body(r: TableReader, where: str, v: dict, shape_params, asset) -> None:
    """A rigid body counts against the level's limit, and its collider must have sane proportions.
    ``shape_params`` is ``(shape, params)`` when those are fine, else None."""
    r.counts["body"] += 1
    limit, what = MAX_COUNTS["body"]
    if r.counts["body"] == limit + 1:
        r.problem(where, f"field 'body': a level may have at most {limit} {what}")
    n = len(r.problems)
    vertices = None
    if shape_params is not None:
        vertices = limits.shape_vertices(*shape_params)
    elif asset is not None and len(r.problems) == n:
        vertices = _asset_vertices(asset, v["depth"])
    if vertices is not None:
        why = limits.body_problem(limits.body_extent(vertices, v["scale"], v["body"]))
        if why:
            r.problem(where, f"field 'scale': {why}")


def _asset_vertices(asset: Path, depth: float):
    """Vertices ``(2n, 4)`` of the asset lifted to a prism ``depth`` deep, or None if it
    cannot be read (that is reported when the level is played and the asset baked)."""
    from .bake import (
        load_surface,  # trimesh is imported only for a body made from an asset
    )

    try:
        v3, _ = load_surface(asset)
    except (ValueError, OSError):
        return None
    half = np.full((len(v3), 1), depth / 2)
    return np.concatenate([np.hstack([v3, -half]), np.hstack([v3, half])])
