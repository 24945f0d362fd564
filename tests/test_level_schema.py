"""The level format as a JSON Schema: made from the loader's models, shipped up to date, and
agreeing with the loader on what it can see (types, fields, ranges)."""

import json
import os
import subprocess
import sys
import tomllib
from pathlib import Path

import pytest

from across_dimensions.world.json_schema import level_schema
from across_dimensions.world.level import MODELS
from across_dimensions.world.resources import level_files

jsonschema = pytest.importorskip("jsonschema")

ROOT = Path(__file__).resolve().parents[1]
SHIPPED = ROOT / "levels" / "level.schema.json"


@pytest.fixture(scope="module")
def validator():
    schema = level_schema()
    jsonschema.Draft202012Validator.check_schema(schema)
    return jsonschema.Draft202012Validator(schema)


def errors(validator, text: str) -> list[str]:
    return [e.message for e in validator.iter_errors(tomllib.loads(text))]


def test_shipped_schema_is_up_to_date():
    assert json.loads(SHIPPED.read_text()) == level_schema(), (
        "levels/level.schema.json is stale: run across-dimensions level-schema -o levels/level.schema.json"
    )


def test_every_table_of_the_format_is_in_the_schema():
    schema = level_schema()
    assert set(schema["properties"]) == set(MODELS)
    for name, model in MODELS.items():
        assert set(schema["$defs"][name]["properties"]) == set(model)


LEVEL_FILES = level_files()  # the 4D levels: the prologue has its own format


@pytest.mark.parametrize("path", LEVEL_FILES + [ROOT / "tests" / "data" / "crystals.toml"], ids=lambda p: p.stem)
def test_shipped_levels_validate(validator, path):
    assert errors(validator, path.read_text()) == []


def test_readme_example_validates(validator):
    text = (ROOT / "levels" / "README.md").read_text()
    example = text.split("```toml", 1)[1].split("```", 1)[0]
    assert errors(validator, example) == []


@pytest.mark.parametrize(
    "edit, why",
    [
        (("[spawn]", "[spawn]\nheight = 2.0"), "Additional properties"),  # unknown field
        (("yaw = 0.0", 'yaw = "north"'), "is not of type 'number'"),
        (("format = 2", "format = 3"), "is not one of"),
        (("w_cost = 4.0", "w_cost = -1.0"), "less than the minimum"),
        (("range = 16.0", "range = 0.0"), "less than the minimum"),
        (('name = "kata cache"', 'name = "kata cache"\nshape = "cube"'), "is not one of"),
        (("energy = 3.0\n", "energy = 0.0\n"), "less than or equal to the minimum"),  # a crystal
    ],
)
def test_bad_values_are_caught_as_you_type(validator, edit, why):
    text = (ROOT / "levels" / "02_crystal_cache.toml").read_text()
    old, new = edit
    assert old in text
    found = errors(validator, text.replace(old, new, 1))
    assert any(why in m for m in found), found


def test_level_schema_command(tmp_path):
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(p for p in (str(ROOT), os.environ.get("PYTHONPATH")) if p))
    out = tmp_path / "schema.json"
    r = subprocess.run(
        [sys.executable, "-m", "across_dimensions", "level-schema", "-o", str(out)],
        capture_output=True,
        text=True,
        env=env,
        timeout=120,
    )
    assert r.returncode == 0, r.stderr
    assert json.loads(out.read_text()) == level_schema()
    r = subprocess.run(
        [sys.executable, "-m", "across_dimensions", "level-schema", "-o", str(tmp_path / "no" / "s.json")],
        capture_output=True,
        text=True,
        env=env,
        timeout=120,
    )
    assert r.returncode == 2 and "does not exist" in r.stderr and "Traceback" not in r.stderr
