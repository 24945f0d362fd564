"""Ghosts: sections just off the slice, drawn only (issue 18, points 1, 2 and 4)."""

from pathlib import Path

import numpy as np
import pytest
from levels_builder import LevelBuilder

from across_dimensions.core.section import cross_section
from across_dimensions.core.transform import translation
from across_dimensions.game.actions import Actions
from across_dimensions.game.sim import Game
from across_dimensions.game.systems import ghosts
from across_dimensions.game.systems.ghosts import GhostView
from across_dimensions.world.level import LevelError, load_level

LEVELS = Path(__file__).parent.parent / "levels"


def ghosts_level(**ghosts) -> LevelBuilder:
    """A wall a little ana, a body a little kata and a world's wall at w = 0.6, with ``[ghosts]`` set
    to ``ghosts`` (left out when empty)."""
    level = LevelBuilder(
        "Ghost test", w_range=(-1.5, 1.5), goal=(0.0, 1.0, 40.0), goal_size=(2.0, 2.0, 2.0), floor=(40.0, 1.0, 100.0)
    )
    if ghosts:
        level.table("ghosts", **ghosts)
    # a solid wall a little ana: absent at w = 0, present at w = 0.6
    level.object([0.0, 1.0, 3.0, 0.6], name="wall", scale=[3.0, 2.0, 0.5, 0.5], color=[0.8, 0.2, 0.2])
    # a rigid body a little kata
    level.object(
        [0.0, 0.5, 5.0, -0.6],
        "hypersphere",
        name="ball",
        params={"subdivisions": 1},
        scale=0.5,
        color=[0.2, 0.6, 1.0],
        body="hypersphere",
        mass=1.0,
    )
    veil = {"center": [0.0, 1.0, 8.0], "size": [4.0, 2.0, 0.3]}
    return level.world(0.6, 0.8, name="veil", profile="prism", color=[0.3, 1.0, 0.4], boxes=[veil])


@pytest.fixture
def ghost_level(tmp_path):
    return ghosts_level(distance=0.6).load(tmp_path, "ghosts.toml")


def ghost_drawables(frame):
    return {d.key: d for d in frame.drawables if d.style == "ghost"}


def test_ghost_at_w_plus_d_is_the_section_at_w_plus_d_tinted(ghost_level):
    game = Game(ghost_level)
    game.step(Actions())
    frame = game.frame(alpha=1.0)
    shown = ghost_drawables(frame)
    wall, ball = game.entities.named("wall"), game.entities.named("ball")
    d = ghost_level.ghosts.distance
    for entity, key, w in ((wall, f"ghost+1:entity:{wall.id}", d), (ball, f"ghost-1:entity:{ball.id}", -d)):
        assert key in shown
        truth = cross_section(entity.mesh, translation((0.0, 0.0, 0.0, w)), entity.model(game, 1.0))
        assert not truth.is_empty
        # The same kernel on the same inputs: equal to float32 round-off.
        np.testing.assert_allclose(shown[key].mesh.vertices, truth.vertices, atol=1e-6)
        np.testing.assert_array_equal(shown[key].mesh.faces, truth.faces)
    # The extended world exists at w = 0.6 (and not at 0): its ana ghost is drawn.
    assert "ghost+1:world:0" in shown and "ghost-1:world:0" not in shown
    assert shown[f"ghost+1:entity:{wall.id}"].tint == ghosts.ANA_TINT
    assert shown[f"ghost-1:entity:{ball.id}"].tint == ghosts.KATA_TINT
    # Neither is in the slice itself: without ghosts the player would see nothing of them.
    solid_keys = {d.key for d in frame.drawables if d.style != "ghost" and not d.mesh.is_empty}
    solid_keys |= {f"entity:{e.id}" for e in (wall, ball) if game.entity_sections.has_section(e.id)}  # batched
    assert f"entity:{wall.id}" not in solid_keys and f"entity:{ball.id}" not in solid_keys


def test_ghost_sides_differ_in_pattern_as_well_as_hue(ghost_level):
    game = Game(ghost_level)
    frame = game.frame()
    ana = [d for d in frame.drawables if d.key.startswith("ghost+")]
    kata = [d for d in frame.drawables if d.key.startswith("ghost-")]
    assert ana and kata
    assert {d.pattern for d in ana} == {"stripes"} and {d.pattern for d in kata} == {"dots"}
    a, k = np.array(ghosts.ANA_TINT[:3]), np.array(ghosts.KATA_TINT[:3])
    assert np.abs(a - k).max() > 0.5  # clearly different hues too (warm vs cool)


def test_ghosts_take_part_in_no_collision_or_ray_cast(ghost_level):
    moves = [Actions(forward=1.0)] * 90 + [Actions(w=1.0)] * 40 + [Actions(forward=1.0, w=-1.0)] * 60
    drawn, plain = Game(ghost_level), Game(ghost_level)
    plain.ghost_view = GhostView(enabled=False)
    for a in moves:
        drawn.step(a)
        plain.step(a)
        frame = drawn.frame()
        assert plain.frame().drawables and not ghost_drawables(plain.frame())
    assert ghost_drawables(frame), "ghosts were drawn all along"
    assert drawn.state_hash() == plain.state_hash()

    game = Game(ghost_level)
    game.frame()
    wall = game.entities.named("wall")
    assert f"ghost+1:entity:{wall.id}" in ghost_drawables(game.frame())
    # The wall's ghost is straight ahead, but the slice at w = 0 has nothing there to walk into...
    boxes = game.colliders_at(0.0)
    ahead = np.isfinite(boxes).all(axis=(1, 2)) & (boxes[:, 0, 2] > 1.0) & (boxes[:, 1, 2] < 4.0)
    assert not ahead.any()
    for _ in range(80):
        game.step(Actions(forward=1.0))
    assert game.player.position[2] > 3.0, "walked straight through where the ghost is drawn"
    # ...and a ray in the slice passes the ball's ghost (the ball is kata, at w = -0.6).
    ball = game.entities.named("ball")
    centre = ball.center(game)
    origin = np.array([centre[0], centre[1], centre[2] - 3.0, 0.0])
    hit = game.physics.raycast(origin, (0.0, 0.0, 1.0, 0.0), 6.0, include_world=False)
    assert hit is None
    hit = game.physics.raycast(origin + [0, 0, 0, centre[3]], (0.0, 0.0, 1.0, 0.0), 6.0, include_world=False)
    assert hit is not None, "the same ray at the ball's w does hit it"


def test_ghosts_fade_with_distance_and_the_side_moved_towards_grows(ghost_level):
    game = Game(ghost_level)
    game.ghost_view = GhostView(layers=2)
    layers = ghosts.layers_of(game, float(game.player.position[3]))
    by = {(lay.side, lay.k): lay for lay in layers}
    assert by[(1, 1)].opacity > by[(1, 2)].opacity > 0
    assert by[(1, 1)].w == pytest.approx(0.6) and by[(-1, 2)].w == pytest.approx(-1.2)
    still = by[(1, 1)].opacity
    for _ in range(10):  # full w speed after 9 ticks; w is then about 0.1
        game.step(Actions(w=1.0))
    moving = {(lay.side, lay.k): lay for lay in ghosts.layers_of(game, float(game.player.position[3]))}
    assert moving[(1, 1)].opacity > 1.5 * still, "ana grows while moving ana"
    assert moving[(-1, 1)].opacity < still
    # The ghost of the wall about to appear is drawn stronger than the same ghost at rest.
    wall = game.entities.named("wall")
    frame = game.frame()
    assert ghost_drawables(frame)[f"ghost+1:entity:{wall.id}"].opacity > 1.5 * still


def test_ghost_layers_stay_inside_the_w_range_and_switch_off(ghost_level):
    game = Game(ghost_level)
    game.player.position[3] = 1.2  # 1.2 + 0.6 is past the range's end (1.5)
    assert [lay.side for lay in ghosts.layers_of(game, float(game.player.position[3]))] == [-1]
    game.ghost_view = GhostView(enabled=False)
    assert ghosts.layers_of(game, float(game.player.position[3])) == []
    assert not ghost_drawables(game.frame())
    assert not any(k.startswith("ghost") for k in game.sections._entries), "their sections are freed"


def test_level_can_turn_ghosts_off_and_checks_the_table(tmp_path):
    game = Game(ghosts_level(enabled=False).load(tmp_path, "off.toml"))
    assert not ghost_drawables(game.frame())
    with pytest.raises(LevelError) as e:
        ghosts_level(distance=-1, layers=3).load(tmp_path, "off.toml")
    text = str(e.value)
    assert "[ghosts]" in text and "distance" in text and "layers" in text


def test_tumbling_hall_bodies_stay_visible_as_ghosts():
    """Level 3 (and the issue's level-2 complaint): bodies that roll out of the slice are still seen."""
    game = Game(load_level(LEVELS / "03_tumbling_hall.toml"))
    lost = 0
    for t in range(600):
        game.step(Actions())
        if t % 30:
            continue
        frame = game.frame()
        solid = {d.key for d in frame.drawables if d.style != "ghost"}
        solid |= {k for b in frame.batches if b.style != "ghost" for k in b.members}  # sliced together
        ghost = {d.key.split(":", 1)[1] for d in frame.drawables if d.style == "ghost"}
        for e in game.entities.of_kind("body"):
            near_w = abs(e.center(game)[3] - game.player.position[3]) <= e.radius + game.level.ghosts.distance
            if near_w and f"entity:{e.id}" not in solid:
                assert f"entity:{e.id}" in ghost, (t, e.name)
                lost += 1
    assert lost > 0, "some body left the slice and was followed by its ghost"


def test_ghost_of_a_wall_that_would_block_a_step_along_w_is_stronger(ghost_level):
    game = Game(ghost_level)
    wall = game.entities.named("wall")
    key = f"ghost+1:entity:{wall.id}"
    frame = game.frame()
    away = ghost_drawables(frame)[key].opacity
    assert frame.hud.w_blocked == ()
    game.player.position[:3] = [0.0, 0.0, 3.0]  # inside the wall's footprint (absent at w = 0)
    frame = game.frame()
    inside = ghost_drawables(frame)[key].opacity
    assert inside == pytest.approx(away * ghosts.BLOCK_GAIN)
    # Ghosts show only their outer faces, so from inside the w gauge says it instead.
    assert frame.hud.w_blocked == (1,)
    assert all(d.outside_only for d in ghost_drawables(frame).values())
    # And it does block: a step ana is refused there.
    for _ in range(30):
        game.step(Actions(w=1.0))
    assert game.player.position[3] < 0.6 - 0.25 + 1e-9


def test_levels_readme_ghosts_and_seek_snippet_loads(tmp_path):
    import re

    text = (LEVELS / "README.md").read_text(encoding="utf-8")
    (snippet,) = [b for b in re.findall(r"^``` ?toml\n(.*?)^```", text, re.S | re.M) if "[ghosts]" in b]
    level = ghosts_level().load(tmp_path, "snippet.toml", extra=snippet)  # without its own [ghosts]
    assert level.ghosts.enabled and level.ghosts.distance == 0.3 and not level.seek.enabled


def test_no_ghost_where_it_would_be_the_section_itself():
    from across_dimensions.core.shapes import cell120, tesseract
    from across_dimensions.core.transform import rotation, scaling

    slab = tesseract(1.0)
    deep = scaling((9.0, 4.0, 0.4, 3.0))  # w from -1.5 to 1.5: the same box at every w inside
    assert ghosts.same_as_slice(slab, deep, 0.0, 1.0) and ghosts.same_as_slice(slab, deep, 0.5, -0.9)
    assert not ghosts.same_as_slice(slab, deep, 0.0, 1.6)  # past its cap: the ghost differs (nothing)
    assert not ghosts.same_as_slice(slab, deep @ rotation("xw", 0.3), 0.0, 1.0)  # turned into w
    assert not ghosts.same_as_slice(cell120(1.0), np.eye(5), 0.0, 0.2)  # every slice differs
    # The Hive's gate is such a slab: the slice shows it, and no ghost veils it.
    (hive,) = (Path(__file__).resolve().parents[1] / "levels").glob("*hive.toml")
    game = Game(load_level(hive))
    gate = game.entities.named("hive gate")
    keys = {d.key for d in game.frame().drawables}
    assert not any(k.endswith(f":entity:{gate.id}") and k.startswith("ghost") for k in keys)


def test_standing_against_a_4d_wall_is_not_being_inside_its_ghost():
    (first,) = (Path(__file__).resolve().parents[1] / "levels").glob("01_*.toml")
    game = Game(load_level(first))
    for _ in range(120):  # walk into the blue wall that exists only near w = 0, and stop there
        game.step(Actions(forward=1.0))
    frame = game.frame()
    assert any(d.style == "ghost" for d in frame.drawables)  # its ghosts are drawn beside the player
    assert frame.hud.w_blocked == ()  # but a step along w is free: the gauge says nothing


def test_ghost_layers_of_moving_things_take_turns_a_frame_behind_at_most(tmp_path):
    """Animated things cut together for their ghosts: each layer is cut again every other frame,
    ana and kata in turn, and in between shows exactly its cut of the frame before; a step along w
    cuts every layer at once; two frames of one tick leave every layer that tick's."""
    from across_dimensions.bench.systems import enemy_level_text
    from across_dimensions.game.systems import enemies

    path = tmp_path / "enemies.toml"
    path.write_text(enemy_level_text(2), encoding="utf-8")
    game = Game(load_level(path))
    game.step(Actions())
    enemies.hold(game, 0.0, 10**9)
    es = game.entity_sections

    def cuts():
        return {tag: (b.revision, b.vertices.copy()) for tag, b in es.ghost_batches.items()}

    game.step(Actions())
    game.frame()
    turns = []
    for _ in range(4):
        before = cuts()
        game.step(Actions())
        game.frame()
        after = cuts()
        assert set(after) == {"ghost+1", "ghost-1"}
        cut = [tag for tag in after if after[tag][0] != before[tag][0]]
        assert len(cut) == 1, "one layer is cut again a frame, the other waits"
        (waiting,) = set(after) - set(cut)
        np.testing.assert_array_equal(after[waiting][1], before[waiting][1])
        turns += cut
    assert turns[::2] == [turns[0]] * 2 and turns[1::2] == [turns[1]] * 2 and turns[0] != turns[1]

    before = cuts()
    p = game.player
    game.place_player((*p.position[:3], p.position[3] + 0.05), p.yaw, p.pitch)
    game.frame()
    assert all(b.revision != before[tag][0] for tag, b in es.ghost_batches.items()), "a step along w cuts both"

    game.step(Actions())
    game.frame()
    game.frame()
    models = dict(zip((e.id for e in game.entity_models.entities), game.entity_models.models(game, 1.0)))
    for layer in ghosts.layers_of(game, game.player.position[3]):
        batch = es.ghost_batches[layer.tag]
        assert batch.instances()[0], "both enemies reach both layers"
        for key in batch.instances()[0]:
            e = game.entities.get(key)
            truth = cross_section(e.mesh, translation((0.0, 0.0, 0.0, layer.w)), models[key])
            start, count = batch.instance_rows(key)
            got = {tuple(np.round(v, 4)) for v in batch.vertices[start : start + count, :3]}
            assert got and got <= {tuple(np.round(v, 4)) for v in truth.vertices}
