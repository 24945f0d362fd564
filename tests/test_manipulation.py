"""Manipulable 4D objects: turning, snapping, energy, ghosts, the Bridge and its replay."""

from __future__ import annotations

import dataclasses
import json
import os
import re
import subprocess
import sys

import numpy as np
import pytest
from levels_builder import LevelBuilder

from across_dimensions.core.section import cross_section
from across_dimensions.core.transform import translation
from across_dimensions.game.actions import Actions
from across_dimensions.game.playback import play
from across_dimensions.game.replay import Replay
from across_dimensions.game.sim import Game
from across_dimensions.game.systems import manipulation
from across_dimensions.world.level import LevelError, load_level
from across_dimensions.world.resources import levels_dir

BRIDGE = levels_dir() / "06_bridge.toml"
BRIDGE_REPLAY = levels_dir() / "replays" / "06_bridge.json"


def _at_the_edge() -> Game:
    """The Bridge, the player walked to the edge and aiming at the slab."""
    game = Game(load_level(BRIDGE))
    for _ in range(60):
        game.step(Actions(forward=1.0))
    for _ in range(6):  # 10 degrees down: the beam is 11 m ahead, 1.6 m below the eye
        game.step(Actions(pitch=-0.03))
    return game


def _slab(game):
    return game.entities.named("slab")


def test_grab_turn_snap_and_let_go():
    game = _at_the_edge()
    assert game.states.manipulation.aimed == _slab(game).id
    game.step(Actions(manipulate=True))
    assert game.event_counts["manipulation_started"] == 1
    z = game.player.position[2]
    for _ in range(25):  # 25 ticks at 45 deg/s = 18.75 degrees, then let the key go
        game.step(Actions(manipulate=True, right=1.0, forward=1.0))
    d = _slab(game).data
    assert game.player.position[2] == z, "the walking keys turn the object while it is held"
    assert d.offsets["zw"] == 18750 and d.offsets["yw"] == 18750
    for _ in range(30):
        game.step(Actions(manipulate=True))
    assert d.offsets == {"yw": 30000, "zw": 30000}  # snapped on to the next 15-degree step; yw stops at its limit
    assert game.event_counts["manipulated"] == 2
    game.step(Actions())
    assert game.event_counts["manipulation_ended"] == 1
    # Undo by turning back: a left turn snaps back down to 0.
    game.step(Actions(manipulate=True))
    for _ in range(5):
        game.step(Actions(manipulate=True, right=-1.0, forward=-1.0))
    for _ in range(60):
        game.step(Actions(manipulate=True))
    assert d.offsets == {"yw": 15000, "zw": 15000}


def test_limits_hold():
    game = _at_the_edge()
    for _ in range(400):
        game.step(Actions(manipulate=True, right=1.0))
    assert _slab(game).data.offsets["zw"] == 90000


def test_energy_accounting_is_exact():
    game = _at_the_edge()
    start = game.energy.milli
    spent = []
    for i in range(300):
        game.step(Actions(manipulate=True, right=1.0 if i < 200 else -1.0, forward=1.0 if i % 50 < 7 else 0.0))
        spent += [e.milli for e in game.events if e.kind == "energy_spent"]
    d = _slab(game).data
    # 250 milli per degree: ceil(250 * millidegrees / 1000) thousandths, to the last one.
    assert d.paid == -((-250 * d.turned) // 1000)
    assert start - game.energy.milli == d.paid == sum(spent)
    assert d.turned > 0


def test_turning_stops_where_the_energy_runs_out(tmp_path):
    text = BRIDGE.read_text().replace("start = 40.0", "start = 5.0")
    p = tmp_path / "poor.toml"
    p.write_text(text)
    game = Game(load_level(p))
    for _ in range(60):
        game.step(Actions(forward=1.0))
    for _ in range(6):  # 10 degrees down: the beam is 11 m ahead, 1.6 m below the eye
        game.step(Actions(pitch=-0.03))
    for _ in range(300):
        game.step(Actions(manipulate=True, right=1.0))
    d = _slab(game).data
    assert game.energy.milli == 0 and d.paid == 5000
    assert d.offsets["zw"] == 20000  # 5 energy at 0.25 per degree


def test_a_ghost_is_the_section_after_the_previewed_turn():
    game = _at_the_edge()
    game.step(Actions(manipulate=True))
    game.step(Actions(manipulate=True, w=1.0))  # move along w: ghosts are cut where the player is
    w = float(game.player.position[3])
    assert w != 0.0
    frame = game.frame()
    ghosts = [d for d in frame.drawables if d.style == "ghost"]
    slab = _slab(game)
    previews = manipulation.ghost_offsets(slab.data)
    assert len(ghosts) == len(previews) == 3  # yw + and -, zw +; zw - is at its limit
    for g, (plane, sign, offsets) in zip(ghosts, previews):
        assert g.key.endswith(f"{plane}{'+' if sign > 0 else '-'}")
        truth = cross_section(slab.mesh, translation((0, 0, 0, w)), slab.data.model(offsets))
        assert np.array_equal(g.mesh.vertices, truth.vertices) and np.array_equal(g.mesh.faces, truth.faces)
        # Placed by a uniform scale and a move only: the shape is the section's.
        m = g.model
        assert np.allclose(m[:3, :3], m[0, 0] * np.eye(3)) and 0 < m[0, 0] <= 1.0
    # Ghosts are drawables only: never entities, never colliders.
    assert all(not e.name.startswith("ghost") for e in game.entities)
    assert len(game.sections_at(w)) == 1


def test_ghosts_can_be_switched_off():
    game = _at_the_edge()
    game.show_ghosts = False
    game.step(Actions(manipulate=True))
    assert not [d for d in game.frame().drawables if d.style == "ghost"]
    (label,) = game.frame().hud.labels
    assert "{strafe_right}" in label.text  # the keys are still shown


def test_a_turn_that_would_swallow_the_player_is_refused(tmp_path):
    game = _at_the_edge()
    # Stand where the bridge will be, below its top: turning it would close around the player.
    game.player.position = np.array([0.0, -0.2, 5.0, 0.0])
    game.player.velocity[:] = 0.0
    before = _slab(game).data.offsets["zw"]
    game.states.manipulation.held = _slab(game).id
    for _ in range(200):
        game.player.position[1] = -0.2
        game.step(Actions(manipulate=True, right=1.0))
    # It turned until its section would reach the player, and no further.
    lo = np.array([-0.3, -0.2, 4.7])
    hi = np.array([0.3, 1.55, 5.3])
    from across_dimensions.game import section_collision as sc

    assert _slab(game).data.offsets["zw"] > before
    assert _slab(game).data.offsets["zw"] < 90000
    assert not sc.box_blocked(lo, hi, game.sections_at(0.0)[0])


def _manipulation_free(replay: Replay) -> Replay:
    acts = [
        dataclasses.replace(a, manipulate=False, presses=tuple(p for p in a.presses if p[0] != "manipulate"))
        for a in replay.actions
    ]
    return dataclasses.replace(replay, actions=acts, hashes={}, final_hash="")


@pytest.mark.slow
def test_the_bridge_replay_finishes_and_without_manipulation_does_not():
    replay = Replay.load(BRIDGE_REPLAY)
    game = Game(load_level(BRIDGE), seed=replay.seed)
    result = play(replay, game)
    assert result.divergence is None and result.outcome == "complete"
    assert game.event_counts["manipulation_started"] >= 1 and game.event_counts["manipulated"] >= 1
    stripped = _manipulation_free(replay)
    game = Game(load_level(BRIDGE), seed=replay.seed)
    result = play(stripped, game, check=False)
    assert result.outcome is None
    assert game.event_counts["manipulation_started"] == 0
    # And walking on for another minute does not get there either.
    for _ in range(3600):
        game.step(Actions(forward=1.0))
    assert game.outcome is None


def test_manipulation_is_deterministic_and_in_the_state_hash():
    a, b, c = _at_the_edge(), _at_the_edge(), _at_the_edge()
    assert a.state_hash() == b.state_hash()
    for i in range(120):
        act = Actions(manipulate=True, right=1.0 if i < 70 else 0.0)
        a.step(act)
        b.step(act)
        c.step(Actions(manipulate=True, right=1.0 if 1 <= i < 70 else 0.0))  # starts one tick later
        assert a.state_hash() == b.state_hash()
        if 0 <= i < 70:  # mid-turn the angles differ, and so do the hashes
            assert c.state_hash() != a.state_hash()
    # Letting go mid-step snaps on at the same rate: both settle on the same 15-degree step.
    assert _slab(c).data.offsets == _slab(a).data.offsets == {"yw": 0, "zw": 60000}


def test_replay_command_plays_the_bridge():
    env = dict(os.environ)
    out = subprocess.run(
        [sys.executable, "-m", "across_dimensions", "replay", str(BRIDGE), str(BRIDGE_REPLAY), "--json"],
        capture_output=True,
        text=True,
        env=env,
        timeout=600,
    )
    assert out.returncode == 0, out.stderr
    summary = json.loads(out.stdout)
    assert summary["outcome"] == "complete" and summary["divergence"] is None
    assert summary["events"]["manipulation_started"] >= 1


BAD = [
    ("max = { qw = 90.0 }", "[[manipulable]] #1 'slab': field 'max': unknown rotation plane 'qw'"),
    ("min = { zw = 10.0 }\nmax = { zw = 5.0 }", "[[manipulable]] #1 'slab': plane 'zw': limits min = 10, max = 5"),
    ("max = { zw = 90.0 }\nstep = 0.0", "[[manipulable]] #1 'slab': field 'step': expected a number > 0"),
    ('max = { zw = 90.0 }\nobject = "nope"', "field 'object': no [[object]] is named 'nope'"),
]


@pytest.mark.parametrize("body, needle", BAD)
def test_bad_manipulation_entries_are_one_line_each(tmp_path, body, needle):
    text = BRIDGE.read_text()
    text = text[: text.index("[[manipulable]]")] + "[[manipulable]]\n" + body + "\n"
    if "object =" not in body:
        text += 'object = "slab"\n'
    p = tmp_path / "bad.toml"
    p.write_text(text)
    with pytest.raises(LevelError) as info:
        load_level(p)
    lines = [line for line in str(info.value).splitlines() if needle in line]
    assert len(lines) == 1 and str(p) in lines[0], str(info.value)
    out = subprocess.run(
        [sys.executable, "-m", "across_dimensions", "check-level", str(p)], capture_output=True, text=True, timeout=300
    )
    assert out.returncode == 2 and needle in out.stderr


def table_level(plane: str) -> LevelBuilder:
    """A cube resting on a table the player may turn 45 degrees in ``plane``."""
    return (
        LevelBuilder(spawn=(0.0, 0.0, -6.0, 0.0), goal=(30.0, 1.0, 0.0), floor=(20.0, 1.0, 20.0))
        .object([0.0, 1.0, 0.0, 0.0], name="table", scale=[3.0, 0.3, 3.0, 3.0])
        .object([0.0, 1.4, 0.0, 0.0], name="cube", scale=0.5, body="hypercube")
        .add("manipulable", object="table", max={plane: 45.0}, speed=30.0)
    )


#: How far a resting body may sink into what it rests on: the physics solver's
#: contact slop is a few millimetres; 2 cm is far below any visible overlap.
SINK = 0.02


@pytest.mark.parametrize("plane, falls", [("xy", True), ("yw", False)])
def test_a_body_on_a_turned_object_follows_it_or_falls_and_never_sinks_in(tmp_path, plane, falls):
    game = Game(table_level(plane).load(tmp_path, "table.toml"))
    cube, table = game.entities.named("cube"), game.entities.named("table")
    for _ in range(60):
        game.step(Actions())
    game.states.manipulation.held = table.id
    for i in range(240):
        game.step(Actions(manipulate=True, forward=1.0 if i < 90 else 0.0))
        m = table.model(game)
        local = np.linalg.solve(m[:4, :4], game.physics.body_position(cube.motion.body) - m[:4, 4])
        over = np.all(np.abs(local[[0, 2, 3]]) < 0.5)  # above the table's top, in the table's frame
        if over:
            assert (0.15 + 0.25) - local[1] * 0.3 < SINK, f"tick {i}: the cube sank into the table"
            if not falls:
                assert local[1] * 0.3 < 0.4 + SINK  # and stays on it: carried along by the turn
    assert table.data.offsets[plane] == 45000
    y = game.physics.body_position(cube.motion.body)[1]
    if falls:
        assert y == pytest.approx(0.25, abs=SINK)  # slid off the 45-degree slope onto the floor
    else:
        assert y > 0.6  # still on the table, turned with it through w


_PROMPT = """
import pyglet
pyglet.options["headless"] = True  # no X display needed: the input module is only imported
from across_dimensions.app.input import with_keys
from across_dimensions.app.settings import default_settings
print(with_keys({message!r}, default_settings("azerty")))
"""


def test_the_window_shows_the_prompt_with_the_players_own_keys():
    game = _at_the_edge()
    game.step(Actions(manipulate=True))
    hud = game.frame().hud
    (label,) = hud.labels
    message = label.text + "\n" + hud.message
    assert "{move_forward}" in message
    # In a fresh process: pyglet's import must not meet the suite's GL contexts.
    out = subprocess.run(
        [sys.executable, "-c", _PROMPT.format(message=message)], capture_output=True, text=True, timeout=300
    )
    if out.returncode != 0 and "pyglet" in out.stderr:
        pytest.skip(f"pyglet does not import here: {out.stderr.strip().splitlines()[-1]}")
    assert out.returncode == 0, out.stderr
    text = out.stdout.strip()
    # AZERTY: forward is Z, strafing Q/D; the tool stays on F.
    assert "[Z/UP] [S/DOWN] turn yw (0 deg)" in text and "[D/RIGHT] [Q/LEFT] turn zw (0 deg)" in text, text
    assert "let go of F to release" in text and "{" not in text


def test_an_object_may_slide_along_w_paid_like_the_players_own_moves(tmp_path):
    text = BRIDGE.read_text().replace("reach = 12.0", "reach = 12.0\nslide = [-0.5, 0.2]")
    assert "w_cost = 2.0" in text  # the Bridge's own price of w, paid by the slide too
    p = tmp_path / "slide.toml"
    p.write_text(text)
    game = Game(load_level(p))
    for _ in range(60):
        game.step(Actions(forward=1.0))
    for _ in range(6):  # 10 degrees down: the beam is 11 m ahead, 1.6 m below the eye
        game.step(Actions(pitch=-0.03))
    slab = _slab(game)
    assert slab.data.planes == ["yw", "zw", "w"]
    start = game.energy.milli
    w_player = game.player.position[3]
    for _ in range(60):  # the w keys slide the object now (three key pairs in use), not the player
        game.step(Actions(manipulate=True, w=-1.0))
    assert game.player.position[3] == w_player
    assert slab.data.offsets["w"] == -500_000  # stopped at its limit, half a metre kata
    assert slab.center(game)[3] == pytest.approx(-0.5, abs=1e-12)
    assert start - game.energy.milli == 1000  # 0.5 m at 2 per unit of w
    # Its ghosts preview the slide too, cut at the player's w.
    previews = manipulation.ghost_offsets(slab.data)
    assert ("w", 1, {**slab.data.offsets, "w": -250_000}) in previews
    assert "slide along w" in game.frame().hud.labels[0].text


def test_bad_slide_is_one_line(tmp_path):
    text = BRIDGE.read_text().replace("reach = 12.0", "reach = 12.0\nslide = [0.3, -0.2]")
    p = tmp_path / "bad_slide.toml"
    p.write_text(text)
    with pytest.raises(LevelError) as info:
        load_level(p)
    lines = [line for line in str(info.value).splitlines() if "field 'slide'" in line]
    assert len(lines) == 1 and "[[manipulable]] #1 'slab'" in lines[0] and str(p) in lines[0]


def test_the_keys_are_shown_next_to_the_held_object_on_screen():
    from across_dimensions.render.hud import hud_quads, label_rect

    game = _at_the_edge()
    game.step(Actions(manipulate=True))
    frame = game.frame()
    (label,) = frame.hud.labels
    assert label.text.splitlines() == [
        "[{move_forward}] [{move_back}] turn yw (0 deg)",
        "[{strafe_right}] [{strafe_left}] turn zw (0 deg)",
    ]
    # The slab's section, projected with the frame's own camera and projection: the label's
    # left edge is at its rightmost point on screen, its middle between its top and bottom.
    slab = _slab(game)
    b = game.sections.bounds(f"tick:{slab.id}")
    corners = np.array([[b[i, 0], b[j, 1], b[k, 2], 1.0] for i in (0, 1) for j in (0, 1) for k in (0, 1)])
    W, H = 1280, 720
    clip = frame.camera.projection_matrix(W / H) @ frame.camera.view_matrix() @ corners.T
    front = clip[3] > 0
    px = W / 2 * (1 + clip[0, front] / clip[3, front])
    py = H / 2 * (1 - clip[1, front] / clip[3, front])
    # As the window shows it: each {action} becomes the player's keys (as long as "W/UP").
    label = dataclasses.replace(label, text=re.sub(r"\{\w+\}", "W/UP", label.text))
    x, y, bw, bh = label_rect(label, W, H)
    # Just right of the object, or just left of it when there is no room on the right.
    assert px.max() <= x <= px.max() + 30 or px.min() - 30 <= x + bw <= px.min()
    assert y <= np.clip(0.5 * (py.min() + py.max()), bh / 2, H - bh / 2) <= y + bh
    assert len(hud_quads(frame.hud, W, H)) > len(hud_quads(dataclasses.replace(frame.hud, labels=[]), W, H))
    assert "let go of {manipulate}" in frame.hud.message
