"""The playable walk: level 1 through replays, determinism, and what the player sees."""

import dataclasses
import json

import numpy as np
import pytest

from across_dimensions.game.actions import Actions
from across_dimensions.game.playback import play
from across_dimensions.game.replay import Recorder, Replay
from across_dimensions.game.sim import TICK_RATE, Game
from across_dimensions.game.systems.ghosts import GhostView
from across_dimensions.world.level import load_level
from across_dimensions.world.resources import levels_dir

LEVEL1 = levels_dir() / "01_first_steps.toml"
DEMO = levels_dir() / "replays" / "01_first_steps.json"


@pytest.fixture(scope="module")
def level1():
    return load_level(LEVEL1)


@pytest.fixture(scope="module")
def demo():
    return Replay.load(DEMO)


def fresh(level, seed=0):
    return Game(level, seed=seed)


def test_recorded_replay_finishes_level_one(level1, demo):
    result = play(demo, fresh(level1))
    assert result.divergence is None
    assert result.outcome == "complete"


def test_same_run_without_moving_along_w_never_reaches_the_goal(level1, demo):
    # The same inputs with the w axis zeroed, and ten more seconds of walking
    # forward and jumping at the wall: the blue wall blocks the corridor.
    no_w = [dataclasses.replace(a, w=0.0) for a in demo.actions]
    no_w += [Actions(forward=1.0, jump=(i % 30 == 0)) for i in range(10 * TICK_RATE)]
    game = fresh(level1)
    for a in no_w:
        game.step(a)
    assert game.outcome is None
    # Stopped flush against the wall's near face (z = 1.7) at w = 0.
    assert game.player.position[3] == 0.0
    assert game.player.position[2] == pytest.approx(1.7 - 0.3, abs=0.01)


def test_wall_blocks_at_w0_and_is_gone_at_w1(level1):
    game = fresh(level1)
    wall = np.array([[-3.5, 0.0, 1.7], [3.5, 4.0, 2.3]])

    def wall_present(w):
        boxes = game.colliders_at(w)
        return bool(np.any(np.all(np.abs(boxes - wall) < 1e-6, axis=(1, 2))))

    assert wall_present(0.0)
    assert not wall_present(1.0)
    # In between it shrinks about its centre (the round profile) before vanishing.
    world = game.scene.worlds[0]
    assert 0 < world.scale_at(0.5) < 1 and world.scale_at(0.8) == 0.0


def test_replay_is_deterministic(level1, demo):
    def hashes():
        out = []
        game = fresh(level1)
        play(demo, game, on_tick=lambda g: out.append(g.state_hash()))
        return out

    a, b = hashes(), hashes()
    assert a == b and len(a) == len(demo.actions)


def test_divergence_is_reported_at_its_tick(level1, demo, tmp_path):
    data = json.loads(DEMO.read_text())
    data["hashes"]["120"] = "0000000000000000"
    path = tmp_path / "tampered.json"
    path.write_text(json.dumps(data))
    result = play(Replay.load(path), fresh(level1))
    assert result.divergence is not None and "tick 120" in result.divergence
    assert result.outcome == "complete"  # the run itself still finishes


def test_changed_level_is_detected(level1, demo, tmp_path):
    edited = tmp_path / "01_first_steps.toml"
    edited.write_text(LEVEL1.read_text().replace("depth = 1.6", "depth = 1.4", 1))
    result = play(demo, Game(load_level(edited)))
    assert result.divergence is not None and "level file changed" in result.divergence


def test_recorder_round_trip_is_bit_identical(level1, tmp_path):
    rng = np.random.default_rng(5)
    game = fresh(level1, seed=3)
    rec = Recorder(game, "01_first_steps")
    for _ in range(200):
        a = Actions(
            forward=float(rng.uniform(-1, 1)),
            right=float(rng.uniform(-1, 1)),
            yaw=float(rng.normal(0, 0.02)),
            pitch=float(rng.normal(0, 0.01)),
            w=float(rng.choice([-1.0, 0.0, 1.0])),
            jump=bool(rng.random() < 0.05),
        )
        game.step(a)
        rec.record(a)
    replay = rec.finish()
    replay.save(tmp_path / "r.json")
    back = Replay.load(tmp_path / "r.json")
    assert back.actions == replay.actions
    assert back.seed == 3
    result = play(back, fresh(level1, seed=3))
    assert result.divergence is None
    assert result.final_hash == game.state_hash()


def test_static_4d_objects_are_sliced_only_when_something_moves(level1):
    level = dataclasses.replace(level1, objects=[dataclasses.replace(o, spin_deg={}) for o in level1.objects])
    game = Game(level)
    game.frame()
    before = game.sections.computed
    for _ in range(30):
        game.step(Actions(forward=1.0))
        game.frame()
    assert game.sections.computed == before  # walking in 3D re-slices nothing
    game.step(Actions(w=1.0))
    game.frame()
    assert game.sections.computed > before  # moving the hyperplane does


def test_interpolated_camera_lies_between_ticks(level1):
    game = fresh(level1)
    for _ in range(10):
        game.step(Actions(forward=1.0))
    z0 = game.frame(alpha=0.0).camera.position[2]
    z1 = game.frame(alpha=1.0).camera.position[2]
    zh = game.frame(alpha=0.5).camera.position[2]
    assert z0 < zh < z1 and zh == pytest.approx((z0 + z1) / 2)


def test_the_frame_carries_the_interpolated_4d_eye():
    """Between ticks the eye's w lies between the two ticks' w, like its x, y and z; the HUD's w
    gauge, the radar and the slice drawn all read it from the frame."""
    game = Game(load_level(levels_dir() / "03_tumbling_hall.toml"))  # bodies on the radar
    game.energy.gain(5000)  # steps along w cost energy here
    for _ in range(20):
        game.step(Actions(w=1.0))
    w0 = float(game.player.position[3])
    game.step(Actions(w=1.0))
    w1 = float(game.player.position[3])
    assert w1 > w0
    half, whole = game.frame(alpha=0.5), game.frame(alpha=1.0)
    assert whole.camera.w == w1 and whole.hud.w == w1  # exactly the player's w at the tick
    assert half.camera.w == pytest.approx((w0 + w1) / 2) and half.hud.w == half.camera.w
    assert np.array_equal(half.camera.eye4, np.append(half.camera.position, half.camera.w))
    lift = (w1 - w0) / 2 * game.level.radar.w_scale * game.radar_view.height_scale  # pins stand taller
    assert half.radar.pins and [p.height for p in half.radar.pins] == pytest.approx(
        [p.height + lift for p in whole.radar.pins]
    )


def test_no_draw_path_reads_the_players_w():
    """What a frame shows is cut at the frame's eye (``frame.camera.w``), never at the player's w
    of the last tick: the draw hooks and the projection stage never read ``position[3]``."""
    import inspect

    from across_dimensions.game import projection
    from across_dimensions.game.systems import SYSTEMS, ghosts

    hooks = [s.draw for s in SYSTEMS if s.draw is not None] + [projection.project, ghosts.layers_of]
    readers = [f"{f.__module__}.{f.__name__}" for f in hooks if "position[3]" in inspect.getsource(f)]
    assert not readers, readers


# ------------------------------------------------------------------ pixels
@pytest.fixture
def draw(gl_ctx):
    from across_dimensions.render.context import Offscreen
    from across_dimensions.render.renderer import Renderer

    renderer = Renderer(gl_ctx)
    target = Offscreen(gl_ctx, 160, 90)

    def image(game, hud=True):
        # The slice itself, without the w ghosts (tests/test_ghosts*.py look at those).
        game.ghost_view = GhostView(enabled=False)
        target.use()
        renderer.draw(game.frame(), target.viewport, hud=hud)
        return target.read_rgb()

    yield image
    assert gl_ctx.error == "GL_NO_ERROR"
    target.release()
    renderer.release()


@pytest.mark.gl
def test_level_one_renders_and_the_wall_goes_away_along_w(level1, draw):
    game = fresh(level1)
    for _ in range(60):
        game.step(Actions(forward=1.0))
    at_w0 = draw(game, hud=False)
    assert at_w0.std() > 10, "the image is blank"
    centre = at_w0[35:55, 70:90].reshape(-1, 3).mean(axis=0)
    assert centre[2] > centre[0] + 20, f"expected the blue wall ahead, centre colour {centre}"
    while game.player.position[3] < 1.0:
        game.step(Actions(w=1.0))
    at_w1 = draw(game, hud=False)
    centre1 = at_w1[35:55, 70:90].reshape(-1, 3).mean(axis=0)
    assert np.abs(centre1 - centre).max() > 15, "the wall's pixels did not change when moving along w"
    assert centre1[2] < centre1[0] + 20, f"the blue wall should be gone at w = 1, centre colour {centre1}"


@pytest.mark.gl
def test_level_one_golden_image(level1, draw, compare_golden):
    game = fresh(level1)
    for _ in range(45):
        game.step(Actions(forward=1.0, w=0.5))
    compare_golden("level01_walk", draw(game))
