"""The level format as a JSON Schema, made from the loader's own models.

Editors that understand JSON Schema (VS Code with the Even Better TOML
extension, JetBrains IDEs, taplo) check a level file as the designer types:
unknown fields, wrong types, values out of range. The schema is generated from
:data:`across_dimensions.world.level.MODELS`, the same models the loader reads
tables with, so the two cannot disagree on a field, a default or a range. Checks
that span fields (a spawn inside the w range, exactly one of ``shape`` or
``asset``, the limits on counts and tetrahedra) stay the loader's:
``across-dimensions check-level`` is the final word.

``across-dimensions level-schema -o levels/level.schema.json`` writes it; the
shipped copy is kept up to date by a test.
"""

from __future__ import annotations

from ..core.shapes import SHAPE_PARAM_RULES
from ..core.transform import PLANES
from .fields import REQUIRED, Field
from .hints import UNTIL
from .level import ARRAY_TABLES, FORMATS, MODELS
from .limits import MAX_COUNTS, MAX_NAME_CHARS

SCHEMA_URI = "https://json-schema.org/draft/2020-12/schema"
#: Nested arrays of tables inside a table, and the model each entry follows.
NESTED = {("world", "box"): "box", ("world", "mesh"): "mesh"}


def _number(f: Field) -> dict:
    out: dict = {"type": "number"}
    if f.range is not None:
        out["minimum"], out["maximum"] = f.range.lo, f.range.hi
    if f.sign == "positive" and out.get("minimum", 0) <= 0:
        out.pop("minimum", None)
        out["exclusiveMinimum"] = 0
    elif f.sign == "nonnegative":
        out["minimum"] = max(out.get("minimum", 0), 0)
    return out


def _field(table: str, name: str, f: Field) -> dict:
    """The schema of one field."""
    if f.kind == "number":
        return _number(f)
    if f.kind == "vector":
        item = _number(Field("number", range=f.range, sign=f.sign))
        return {"type": "array", "items": item, "minItems": f.n, "maxItems": f.n}
    if f.kind == "scale":
        one = _number(Field("number", range=f.range, sign=f.sign))
        return {"oneOf": [one, {"type": "array", "items": one, "minItems": f.n, "maxItems": f.n}]}
    if f.kind == "string":
        return {"type": "string", "enum": list(f.choices)} if f.choices else {"type": "string"}
    if f.kind == "text":
        return {"type": "string", "maxLength": int(f.range.hi) if f.range else MAX_NAME_CHARS}
    if f.kind == "bool":
        return {"type": "boolean"}
    if f.kind == "color":
        comp = {"type": "number", "minimum": 0, "maximum": 1}
        return {"type": "array", "items": comp, "minItems": 3, "maxItems": 4, "description": "RGB or RGBA, 0 to 1"}
    if f.kind == "angles":
        deg = _number(Field("number", range=f.range))
        return {
            "type": "object",
            "properties": dict.fromkeys(PLANES, deg),
            "additionalProperties": False,
            "description": "degrees per rotation plane",
        }
    if f.kind == "asset":
        return {"type": "string", "minLength": 1, "description": "a mesh file inside the assets folder"}
    if f.kind == "params":
        props = {}
        for p, (kind, (lo, hi)) in SHAPE_PARAM_RULES.items():
            props[p] = {"type": "integer" if kind == "whole" else "number", "minimum": lo, "maximum": hi}
        return {"type": "object", "properties": props, "additionalProperties": False}
    if f.kind == "hints":
        limit, _ = MAX_COUNTS["hints"]
        until = {key: _field("until", key, u) for key, u in UNTIL.items()}
        done_by = {"type": "object", "properties": until, "additionalProperties": False, "minProperties": 1}
        table = {
            "type": "object",
            "properties": {"text": {"type": "string", "minLength": 1}, "until": done_by},
            "required": ["text"],
            "additionalProperties": False,
        }
        return {"type": "array", "items": {"anyOf": [{"type": "string"}, table]}, "maxItems": limit}
    if f.kind == "words":
        return {"type": "array", "items": {"enum": list(f.choices)}, "uniqueItems": True}
    if f.kind == "tables":
        return {"type": "array", "items": {"$ref": f"#/$defs/{NESTED[(table, name)]}"}}
    raise ValueError(f"no JSON Schema for field kind {f.kind!r} ({table}.{name})")


def _table(name: str, model: dict) -> dict:
    props = {key: _field(name, key, f) for key, f in model.items()}
    if name == "level":
        props["format"] = {"enum": list(FORMATS), "description": "2 for crystals, energy and the radar"}
    required = [key for key, f in model.items() if f.default is REQUIRED]
    out = {"type": "object", "properties": props, "additionalProperties": False}
    if required:
        out["required"] = required
    return out


def level_schema() -> dict:
    """The JSON Schema (draft 2020-12) of a level file, as a dict ready for ``json.dump``."""
    defs = {name: _table(name, model) for name, model in MODELS.items()}
    props = {}
    for name in MODELS:
        if name in ARRAY_TABLES:
            limit, _ = MAX_COUNTS.get(name, (None, None))
            arr = {"type": "array", "items": {"$ref": f"#/$defs/{name}"}}
            if limit is not None:
                arr["maxItems"] = limit
            props[name] = arr
        else:
            props[name] = {"$ref": f"#/$defs/{name}"}
    return {
        "$schema": SCHEMA_URI,
        "title": "Across Dimensions level",
        "description": "A level file (TOML). Generated from the game's level models; check-level has the final word.",
        "type": "object",
        "properties": props,
        "required": ["level", "spawn", "goal"],
        "additionalProperties": False,
        "$defs": defs,
    }
