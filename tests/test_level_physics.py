"""Level 3: 4D rigid bodies in the game, through its recorded replay and scripted runs."""

import numpy as np
import pytest

from across_dimensions.game.actions import Actions
from across_dimensions.game.playback import play
from across_dimensions.game.replay import Replay
from across_dimensions.game.sim import TICK_RATE, Game
from across_dimensions.world.level import load_level
from across_dimensions.world.resources import levels_dir

LEVEL2 = levels_dir() / "03_tumbling_hall.toml"
REPLAY2 = levels_dir() / "replays" / "03_tumbling_hall.json"


@pytest.fixture(scope="module")
def level2():
    return load_level(LEVEL2)


def body(game, name):
    entity = game.entities.named(name)
    return entity, entity.motion.body


def in_slice(game, entity) -> bool:
    """Does the entity's cross-section at the player's w have any triangles?"""
    w = float(game.player.position[3])
    tri, _ = game.sections.section(f"test:{entity.id}", entity.mesh, entity.model(game), w)
    return not tri.is_empty


def test_replay_finishes_and_is_deterministic(level2):
    replay = Replay.load(REPLAY2)
    first = play(replay, Game(level2))
    second = play(replay, Game(level2))
    assert first.divergence is None and first.outcome == "complete"
    assert first.final_hash == second.final_hash


def test_bodies_enter_and_leave_the_slice_during_the_replay(level2):
    replay = Replay.load(REPLAY2)
    game = Game(level2)
    bodies = game.entities.of_kind("body")
    seen = {e.name: [] for e in bodies}

    def record(g):
        for e in bodies:
            seen[e.name].append(in_slice(g, e))

    play(replay, game, on_tick=record)
    changes = {name: int(np.sum(np.diff(np.array(v, int)) != 0)) for name, v in seen.items()}
    # Something leaves the slice and something arrives (the drifter, the
    # visitor, the stack and the block as the player steps along w).
    assert sum(changes.values()) >= 4, changes
    assert changes["block"] >= 1 and changes["stack-1"] >= 1, changes


def test_bodies_settle_on_the_floor(level2):
    game = Game(level2)
    for _ in range(6 * TICK_RATE):
        game.step(Actions())
    for name, rest_height in (("drifter", 0.45), ("visitor", 0.4), ("block", 0.55)):
        _, b = body(game, name)
        p = game.physics.body_position(b)
        v, _ = game.physics.body_velocity(b)
        # Down on the floor (y = radius), maybe still rolling: nothing slows a
        # rolling hypersphere but the walls.
        assert p[1] == pytest.approx(rest_height, abs=0.02), f"{name} is not on the floor: {p}"
        assert abs(v[1]) < 0.05, f"{name} is bouncing: {v}"
    _, t = body(game, "tumbler")
    v, omega = game.physics.body_velocity(t)
    assert game.physics.body_position(t)[1] == pytest.approx(0.4, abs=0.02)  # resting on a cell
    assert np.linalg.norm(v) < 0.05 and np.linalg.norm(omega) < 0.05
    # The stack of three still stands, each cube on the one below.
    heights = [game.physics.body_position(body(game, f"stack-{k}")[1])[1] for k in (1, 2, 3)]
    assert heights == pytest.approx([0.35, 1.05, 1.75], abs=0.02)


def walk(game, ticks, **kw):
    for _ in range(ticks):
        game.step(Actions(**kw))


def test_player_is_blocked_by_bodies_in_the_slice_and_pushes_them(level2):
    game = Game(level2)
    walk(game, 2 * TICK_RATE)  # let everything land
    _, bottom = body(game, "stack-1")
    z0 = game.physics.body_position(bottom)[2]
    gaps = []
    for _ in range(4 * TICK_RATE):  # straight into the stack at x = 0
        game.step(Actions(forward=1.0))
        # Player's front face against the bottom cube's back face.
        gaps.append(game.physics.body_position(bottom)[2] - 0.35 - (game.player.position[2] + 0.3))
    assert min(gaps) > -0.08, "walked into a body in the slice"
    assert game.physics.body_position(bottom)[2] > z0 + 0.3, "the body was not pushed"


def test_player_passes_where_the_bodies_are_not_in_the_slice(level2):
    game = Game(level2)
    game.energy.gain(5000)  # steps along w cost energy here
    walk(game, 2 * TICK_RATE)
    walk(game, TICK_RATE, w=1.0)  # the stack spans w in [-0.35, 0.35]
    assert game.player.position[3] > 0.9
    _, bottom = body(game, "stack-1")
    z0 = game.physics.body_position(bottom)[2]
    walk(game, 4 * TICK_RATE, forward=1.0)
    assert game.player.position[2] > 5.0
    assert game.physics.body_position(bottom)[2] == pytest.approx(z0, abs=1e-6)


def test_cannot_step_along_w_into_a_body(level2):
    game = Game(level2)
    game.energy.gain(5000)  # steps along w cost energy here
    walk(game, 2 * TICK_RATE, w=1.0)  # at w ~ 1.2, away from the stack
    # Stand where the stack is (x = 0, z = 3) but at another w, then try to go back to w = 0.
    game.player.position[:3] = [0.0, 0.0, 3.0]
    walk(game, 2 * TICK_RATE, w=-1.0)
    assert game.player.position[3] > 0.35, "stepped along w into the stack"


@pytest.mark.slow
def test_bodies_stay_in_the_w_range_and_sleep_after_twenty_minutes(level2):
    """Issue 7.10: two hyperspheres used to roll out along w (|w| = 217 after
    20 minutes) and never sleep. Walls at the w_range ends and the level's
    rolling resistance keep them in and bring them to rest."""
    game = Game(level2)
    physics = game.physics
    lo, hi = level2.w_range
    # A hypersphere's whole extent must stay inside; for a box, its centre.
    reach = {}
    for e in game.entities.of_kind("body"):
        sphere = next(o for o in game.scene.objects if o.name == e.name).body == "hypersphere"
        reach[e.motion.body] = e.radius if sphere else 0.0
    assert sum(r > 0 for r in reach.values()) >= 2  # the two rolling hyperspheres are among them
    for tick in range(20 * 60 * TICK_RATE):
        game.step(Actions())
        if tick % TICK_RATE == 0:
            for b, r in reach.items():
                w = physics.body_position(b)[3]
                # 0.03: contacts are soft, a body may sink that far into a wall.
                assert lo - 0.03 <= w - r and w + r <= hi + 0.03, (tick, b, w)
    awake = [e.name for e in game.entities.of_kind("body") if not physics.is_sleeping(e.motion.body)]
    assert not awake, f"awake after 20 minutes: {awake}"
    assert level2.rolling_resistance > 0.0
