"""Tests for across_dimensions.app.settings: presets, the TOML file, mouse look.

Every test runs with ACROSS_DIMENSIONS_CONFIG_DIR pointing into tmp_path (see
the autouse fixture), so nothing here can read or write the real config folder.
"""

from __future__ import annotations

import ast
import importlib.util
import math
import os
from pathlib import Path

import pytest
import tomli_w

from across_dimensions.app import settings as settings_mod
from across_dimensions.app.settings import (
    ACTION_DESCRIPTIONS,
    ACTIONS,
    CONFIG_DIR_ENV,
    KEY_NAMES,
    PRESETS,
    Settings,
    default_settings,
    load_settings,
    look_delta,
    save_settings,
    settings_path,
)


@pytest.fixture(autouse=True)
def config_dir(tmp_path, monkeypatch):
    folder = tmp_path / "config"
    monkeypatch.setenv(CONFIG_DIR_ENV, str(folder))
    return folder


def write(path: Path, text: str) -> Path:
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(text, encoding="utf-8")
    return path


# --------------------------------------------------------------------------
# Actions, key names, presets
# --------------------------------------------------------------------------


def test_actions_have_descriptions_and_required_names():
    required = {
        "move_forward",
        "move_back",
        "strafe_left",
        "strafe_right",
        "jump",
        "w_ana",
        "w_kata",
        "fire",
        "alt_fire",
        "next_weapon",
        "switch_camera",
        "manipulate",
        "record",
        "screenshot",
        "toggle_fps",
        "toggle_fullscreen",
        "pause",
    }
    assert ACTIONS == tuple(ACTION_DESCRIPTIONS)
    assert required <= set(ACTIONS)
    assert len(set(ACTIONS)) == len(ACTIONS)
    for action, text in ACTION_DESCRIPTIONS.items():
        assert text.strip() and "\n" not in text, action


@pytest.mark.parametrize("preset", sorted(PRESETS))
def test_presets_bind_every_action_to_known_keys_without_conflicts(preset):
    s = default_settings(preset)
    for action in ACTIONS:
        assert s.keys_for(action), f"{preset}: {action} unbound"
        assert set(s.keys_for(action)) <= KEY_NAMES
    assert s.conflicts() == {}
    assert s.problems() == []


def test_qwerty_preset():
    s = default_settings("qwerty")
    expected = {
        "W": "move_forward",
        "A": "strafe_left",
        "S": "move_back",
        "D": "strafe_right",
        "UP": "move_forward",
        "LEFT": "strafe_left",
        "DOWN": "move_back",
        "RIGHT": "strafe_right",
        "SPACE": "jump",
        "E": "w_ana",
        "Q": "w_kata",
        "MOUSE_LEFT": "fire",
        "MOUSE_RIGHT": "alt_fire",
        "TAB": "switch_camera",
        "F": "manipulate",
        "F9": "record",
        "F12": "screenshot",
        "F3": "toggle_fps",
        "F11": "toggle_fullscreen",
        "ESCAPE": "pause",
        "R": "next_weapon",
    }
    for key, action in expected.items():
        assert s.action_for_key(key) == action, key
    assert s.action_for_key("Z") is None


def test_azerty_preset_binds_zqsd():
    s = default_settings("azerty")
    assert s.action_for_key("Z") == "move_forward"
    assert s.action_for_key("Q") == "strafe_left"
    assert s.action_for_key("S") == "move_back"
    assert s.action_for_key("D") == "strafe_right"
    assert s.action_for_key("A") == "w_kata"
    assert s.action_for_key("E") == "w_ana"
    assert s.action_for_key("UP") == "move_forward"
    assert s.action_for_key("W") is None
    # "rest the same"
    for action in (
        "jump",
        "fire",
        "alt_fire",
        "next_weapon",
        "switch_camera",
        "manipulate",
        "record",
        "screenshot",
        "toggle_fps",
        "toggle_fullscreen",
        "pause",
    ):
        assert s.keys_for(action) == default_settings("qwerty").keys_for(action)


def test_key_names_are_pyglet_symbol_names():
    """Every keyboard name must exist in pyglet.window.key, or the window could
    not map it. key.py is loaded by file path: importing pyglet.window needs a
    display, which test machines may lack."""
    pyglet = pytest.importorskip("pyglet")
    key_py = Path(pyglet.__file__).parent / "window" / "key.py"
    spec = importlib.util.spec_from_file_location("_pyglet_key_symbols", key_py)
    key = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(key)
    for name in KEY_NAMES - set(settings_mod.MOUSE_BUTTONS):
        assert isinstance(getattr(key, name, None), int), name
    for name in ("W", "SPACE", "LSHIFT", "RSHIFT", "LCTRL", "TAB", "ESCAPE", "F1", "F12", "_1", "_9"):
        assert name in KEY_NAMES


def test_settings_module_does_not_import_pyglet():
    # Checked on the source, not sys.modules: other modules of the package may
    # legitimately import pyglet, and this must hold whatever they do.
    tree = ast.parse(Path(settings_mod.__file__).read_text(encoding="utf-8"))
    imported = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            imported.update(alias.name for alias in node.names)
        elif isinstance(node, ast.ImportFrom) and node.module:
            imported.add(node.module)
    assert not any(name.split(".")[0] == "pyglet" for name in imported), imported


# --------------------------------------------------------------------------
# The Settings object
# --------------------------------------------------------------------------


def test_defaults():
    s = default_settings()
    assert s == Settings()
    assert s.preset == "qwerty"
    assert 0 < s.mouse_sensitivity < 0.1 and s.mouse_sensitivity == pytest.approx(0.0025)
    assert s.fov_deg == 75 and s.vsync is True
    assert (s.width, s.height) == (1280, 720)
    assert not (s.invert_x or s.invert_y or s.fullscreen or s.show_fps)
    assert list(s.bindings) == list(ACTIONS)


def test_partial_bindings_override_the_preset():
    s = Settings(preset="azerty", bindings={"jump": ("x", "MOUSE_MIDDLE"), "record": ()})
    assert s.keys_for("jump") == ("X", "MOUSE_MIDDLE")
    assert s.keys_for("record") == ()
    assert s.keys_for("move_forward") == ("Z", "UP")


def test_settings_do_not_alias_presets():
    s = default_settings()
    s.bindings["jump"] = ("X",)
    assert default_settings().keys_for("jump") == ("SPACE",)
    assert PRESETS["qwerty"]["jump"] == ("SPACE",)


@pytest.mark.parametrize(
    "kwargs",
    [
        {"mouse_sensitivity": 0.0},
        {"mouse_sensitivity": 0.1},
        {"mouse_sensitivity": math.nan},
        {"fov_deg": 49.9},
        {"fov_deg": 120.5},
        {"width": 319},
        {"height": 239},
        {"width": 800.0},
        {"vsync": 1},
        {"preset": "dvorak"},
        {"bindings": {"fly": ("F",)}},
        {"bindings": {"jump": ("SPCE",)}},
    ],
)
def test_invalid_construction_raises(kwargs):
    with pytest.raises(ValueError):
        Settings(**kwargs)


def test_keys_for_unknown_action_raises():
    with pytest.raises(KeyError):
        default_settings().keys_for("fly")


def test_key_bound_to_two_actions_is_a_problem():
    s = Settings(bindings={"jump": ("SPACE", "W")})
    assert s.conflicts() == {"W": ("move_forward", "jump")}
    [problem] = s.problems()
    assert "'W'" in problem and "move_forward" in problem and "jump" in problem
    assert s.action_for_key("W") == "move_forward"  # first in ACTIONS order, deterministically
    assert s.action_for_key("space") == "jump"


# --------------------------------------------------------------------------
# Mouse look
# --------------------------------------------------------------------------


def test_look_delta_directions_and_scale():
    s = default_settings()
    dyaw, dpitch = look_delta(s, 10, 4)
    assert dyaw == pytest.approx(10 * s.mouse_sensitivity) and dyaw > 0  # right turns right
    assert dpitch == pytest.approx(4 * s.mouse_sensitivity) and dpitch > 0  # up looks up
    assert look_delta(s, 0, 0) == (0.0, 0.0)


def test_invert_y_flips_pitch_only():
    normal = default_settings()
    inverted = Settings(invert_y=True)
    assert look_delta(inverted, 7, 5)[1] == -look_delta(normal, 7, 5)[1]
    assert look_delta(inverted, 7, 5)[0] == look_delta(normal, 7, 5)[0]


def test_invert_x_flips_yaw_only():
    normal, inverted = default_settings(), Settings(invert_x=True)
    assert look_delta(inverted, 7, 5) == (-look_delta(normal, 7, 5)[0], look_delta(normal, 7, 5)[1])


# --------------------------------------------------------------------------
# Paths
# --------------------------------------------------------------------------


def test_settings_path_honours_env(config_dir):
    assert settings_path() == config_dir / "settings.toml"


def test_settings_path_without_env_uses_platformdirs(monkeypatch):
    # Only computes the path; nothing is read or written there.
    monkeypatch.delenv(CONFIG_DIR_ENV)
    path = settings_path()
    assert path.name == "settings.toml" and "across-dimensions" in str(path)


# --------------------------------------------------------------------------
# Loading and saving
# --------------------------------------------------------------------------


def test_missing_file_gives_defaults_silently(config_dir):
    assert load_settings() == (default_settings(), [])
    assert not config_dir.exists()  # loading never creates anything


@pytest.mark.parametrize("preset", sorted(PRESETS))
def test_defaults_round_trip_exactly(preset, config_dir):
    s = default_settings(preset)
    written = save_settings(s)
    assert written == config_dir / "settings.toml"
    loaded, warnings = load_settings()
    assert warnings == []
    assert loaded == s


def test_custom_settings_round_trip_exactly(tmp_path):
    s = Settings(
        preset="azerty",
        bindings={"jump": ("SPACE", "MOUSE_RIGHT"), "alt_fire": (), "record": ("_8",)},
        mouse_sensitivity=0.0031415926535,
        invert_x=True,
        invert_y=True,
        fov_deg=101.25,
        fullscreen=True,
        vsync=False,
        show_fps=True,
        width=2560,
        height=1440,
    )
    path = tmp_path / "deep" / "er" / "s.toml"
    path.parent.mkdir(parents=True)  # a folder given explicitly is never created (only the config folder is)
    save_settings(s, path)
    assert load_settings(path) == (s, [])
    # Only the differences from the preset are written under [bindings].
    doc = settings_mod.tomllib.loads(path.read_text(encoding="utf-8"))
    assert doc["bindings"] == {"jump": ["SPACE", "MOUSE_RIGHT"], "alt_fire": [], "record": ["_8"]}
    assert doc["preset"] == "azerty"


def test_file_overrides_only_listed_actions(tmp_path):
    path = write(tmp_path / "s.toml", 'preset = "azerty"\n[bindings]\njump = ["x", "8"]\n')
    s, warnings = load_settings(path)
    assert warnings == []
    assert s.keys_for("jump") == ("X", "_8")
    assert s.keys_for("move_forward") == ("Z", "UP")


def test_wrong_type_warns_names_file_and_entry_and_keeps_other_entries(tmp_path):
    path = write(
        tmp_path / "s.toml", 'mouse_sensitivity = "fast"\nfov_deg = 90\ninvert_y = true\n[bindings]\njump = ["X"]\n'
    )
    s, warnings = load_settings(path)
    assert len(warnings) == 1
    assert str(path) in warnings[0] and "mouse_sensitivity" in warnings[0]
    assert "expected" in warnings[0]
    assert s.mouse_sensitivity == default_settings().mouse_sensitivity
    assert s.fov_deg == 90.0 and s.invert_y is True and s.keys_for("jump") == ("X",)


def test_invalid_toml_gives_one_warning_and_all_defaults(tmp_path):
    path = write(tmp_path / "s.toml", "fov_deg = 90\nthis is not = = toml [\n")
    s, warnings = load_settings(path)
    assert s == default_settings()
    assert len(warnings) == 1 and str(path) in warnings[0] and "TOML" in warnings[0]


def test_unreadable_file_warns(tmp_path):
    path = tmp_path / "s.toml"
    path.mkdir()  # a folder where the file should be
    s, warnings = load_settings(path)
    assert s == default_settings() and len(warnings) == 1 and str(path) in warnings[0]


def test_non_utf8_file_warns(tmp_path):
    path = tmp_path / "s.toml"
    path.write_bytes(b'preset = "\xff\xfe"\n')
    s, warnings = load_settings(path)
    assert s == default_settings() and len(warnings) == 1


def test_byte_order_mark_is_tolerated(tmp_path):
    path = tmp_path / "s.toml"
    path.write_bytes("\ufefffov_deg = 80\n".encode("utf-8"))
    assert load_settings(path) == (Settings(fov_deg=80), [])


def test_unknown_action_warns_and_is_ignored(tmp_path):
    path = write(tmp_path / "s.toml", '[bindings]\nfly = ["G"]\njump = ["X"]\n')
    s, warnings = load_settings(path)
    assert len(warnings) == 1
    assert str(path) in warnings[0] and "'fly'" in warnings[0] and "unknown action" in warnings[0]
    assert s.keys_for("jump") == ("X",)


def test_unknown_key_warns_and_uses_that_actions_default(tmp_path):
    path = write(tmp_path / "s.toml", '[bindings]\njump = ["SPCE"]\nfire = ["G"]\n')
    s, warnings = load_settings(path)
    assert len(warnings) == 1
    w = warnings[0]
    assert str(path) in w and "jump" in w and "SPCE" in w and "did you mean 'SPACE'" in w
    assert s.keys_for("jump") == ("SPACE",)
    assert s.keys_for("fire") == ("G",)


def test_key_bound_to_two_actions_warns_on_load(tmp_path):
    path = write(tmp_path / "s.toml", '[bindings]\njump = ["W"]\n')
    s, warnings = load_settings(path)
    assert len(warnings) == 1
    assert str(path) in warnings[0] and "'W'" in warnings[0]
    assert "move_forward" in warnings[0] and "jump" in warnings[0]


def test_unknown_preset_warns_and_overrides_still_apply(tmp_path):
    path = write(tmp_path / "s.toml", 'preset = "dvorak"\n[bindings]\njump = ["X"]\n')
    s, warnings = load_settings(path)
    assert len(warnings) == 1 and "preset" in warnings[0] and "'qwerty'" in warnings[0]
    assert s.preset == "qwerty" and s.keys_for("jump") == ("X",) and s.keys_for("move_forward") == ("W", "UP")


def test_unknown_top_level_setting_warns(tmp_path):
    path = write(tmp_path / "s.toml", "gamma = 2.2\nfov_deg = 60\n")
    s, warnings = load_settings(path)
    assert len(warnings) == 1 and "'gamma'" in warnings[0]
    assert s.fov_deg == 60


def test_bindings_not_a_table_warns(tmp_path):
    path = write(tmp_path / "s.toml", 'bindings = "WASD"\n')
    s, warnings = load_settings(path)
    assert len(warnings) == 1 and "bindings" in warnings[0]
    assert s == default_settings()


BAD_VALUES = {
    "preset": [3, "dvorak", True],
    "mouse_sensitivity": ["fast", 0, -0.001, 0.1, 0.5, math.inf, math.nan, True, [0.002]],
    "invert_x": [1, "yes"],
    "invert_y": [0, "no"],
    "fov_deg": [30, 121, "wide", True, math.nan],
    "fullscreen": ["true"],
    "vsync": [1],
    "show_fps": [{"a": 1}],
    "width": [100, 1280.0, "1280", False, 10**9],
    "height": [100, 720.5, "720"],
}


@pytest.mark.parametrize("name,value", [(n, v) for n, vs in BAD_VALUES.items() for v in vs])
def test_each_bad_scalar_warns_and_defaults_just_that_entry(name, value, tmp_path):
    path = tmp_path / "s.toml"
    doc = {"fov_deg": 99.0, "show_fps": True, name: value}
    if name in ("fov_deg", "show_fps"):
        doc["width"] = 1920
    path.write_text(tomli_w.dumps(doc), encoding="utf-8")
    s, warnings = load_settings(path)
    assert len(warnings) == 1, warnings
    assert str(path) in warnings[0] and name in warnings[0] and "expected" in warnings[0]
    assert getattr(s, name) == getattr(default_settings(), name)
    for other, v in doc.items():
        if other != name:
            assert getattr(s, other) == v


@pytest.mark.parametrize("value", [5, "SPACE, W", [1, 2], [["W"]], {"key": "W"}])
def test_bad_binding_types_warn(value, tmp_path):
    path = tmp_path / "s.toml"
    path.write_text(tomli_w.dumps({"bindings": {"jump": value}}), encoding="utf-8")
    s, warnings = load_settings(path)
    assert len(warnings) == 1 and "jump" in warnings[0] and str(path) in warnings[0]
    assert s.keys_for("jump") == ("SPACE",)


def test_a_single_key_string_is_accepted(tmp_path):
    path = write(tmp_path / "s.toml", '[bindings]\njump = "X"\n')
    assert load_settings(path) == (Settings(bindings={"jump": ("X",)}), [])


def test_load_never_raises_on_random_documents(tmp_path):
    hypothesis = pytest.importorskip("hypothesis")
    st = hypothesis.strategies
    scalars = st.one_of(st.booleans(), st.integers(-(10**6), 10**6), st.floats(allow_nan=True), st.text(max_size=8))
    values = st.recursive(
        scalars, lambda c: st.lists(c, max_size=3) | st.dictionaries(st.text(max_size=5), c, max_size=3), max_leaves=6
    )
    names = st.sampled_from([*settings_mod.RULES, "bindings", "other"])
    bindings = st.dictionaries(
        st.sampled_from([*ACTIONS, "fly"]),
        st.one_of(values, st.lists(st.sampled_from([*sorted(KEY_NAMES), "w", "1", "BAD"]), max_size=3)),
        max_size=4,
    )
    docs = st.dictionaries(names, values, max_size=6) | st.builds(
        lambda d, b: {**d, "bindings": b}, st.dictionaries(names, values, max_size=4), bindings
    )
    path = tmp_path / "s.toml"

    @hypothesis.settings(max_examples=150, deadline=None, database=None)
    @hypothesis.given(docs)
    def check(doc):
        path.write_text(tomli_w.dumps(doc), encoding="utf-8")
        s, warnings = load_settings(path)
        assert isinstance(s, Settings) and all(isinstance(w, str) for w in warnings)
        save_settings(s, path)  # whatever was loaded is valid, saves, and reloads the same
        again, warnings = load_settings(path)
        assert again == s and len(warnings) == len(s.problems())

    check()


# --------------------------------------------------------------------------
# Atomic save
# --------------------------------------------------------------------------


def test_save_leaves_no_temp_file_and_creates_folder(config_dir):
    save_settings(default_settings())
    save_settings(Settings(fov_deg=90))  # replace an existing file too
    assert sorted(os.listdir(config_dir)) == ["settings.toml"]
    assert load_settings()[0].fov_deg == 90


@pytest.mark.parametrize("fail_at", ["fsync", "replace"])
def test_failed_save_keeps_the_old_file(fail_at, config_dir, monkeypatch):
    save_settings(Settings(fov_deg=90))
    before = (config_dir / "settings.toml").read_bytes()

    def boom(*args, **kwargs):
        raise OSError(28, "No space left on device")

    # A nested context: monkeypatch.undo() would also drop the config-dir
    # variable and point later loads at the real config folder.
    with monkeypatch.context() as m:
        m.setattr(settings_mod.os, fail_at, boom)
        with pytest.raises(OSError):
            save_settings(Settings(fov_deg=110))

    assert (config_dir / "settings.toml").read_bytes() == before
    assert sorted(os.listdir(config_dir)) == ["settings.toml"]
    assert load_settings() == (Settings(fov_deg=90), [])


def test_save_rejects_settings_made_invalid_after_construction(config_dir):
    s = default_settings()
    s.fov_deg = 500
    with pytest.raises(ValueError):
        save_settings(s)
    assert not (config_dir / "settings.toml").exists()
