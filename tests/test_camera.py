"""The 4D camera rig: turning the slice, the frustum switch, the orbit, the return, and its levels."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from levels_builder import LevelBuilder

from across_dimensions.core.frustum import frustum_project
from across_dimensions.core.shapes import make_shape
from across_dimensions.core.transform import orthonormality_error, rotation4
from across_dimensions.game.actions import Actions
from across_dimensions.game.camera import CameraRig, nearest_axes
from across_dimensions.game.energy import EnergyBar
from across_dimensions.game.sim import Game
from across_dimensions.game.systems import camera as camera_system
from across_dimensions.world.level import LevelError, load_level

ROOT = Path(__file__).resolve().parents[1]
LEVELS = ROOT / "levels"
SWITCH = Actions(presses=(("switch_camera", 1),))


def _run(game: Game, n: int, **kw) -> None:
    for _ in range(n):
        game.step(Actions(**kw))


@pytest.mark.slow
# ----------------------------------------------------------------------- the rig
def test_pose_stays_orthonormal_over_a_long_run():
    """100 000 ticks (28 minutes of play) of random turning in all three planes: the rotation
    stays a rotation to rounding (each tick is re-orthonormalized), and the pivot stays put."""
    rng = np.random.default_rng(7)
    rig = CameraRig()
    pivot = np.array([1.0, 1.6, -2.0, 0.3])
    start = rig.to_world(pivot)
    for _ in range(100_000):
        rig.turn(tuple(rng.uniform(-1.0, 1.0, 3)), 1 / 60, pivot)
    assert orthonormality_error(rig.rotation) < 1e-13
    assert np.linalg.det(rig.rotation) == pytest.approx(1.0, abs=1e-13)
    # The eye's world point is the pivot of every turn: it has not drifted (rounding only).
    assert np.allclose(rig.to_world(pivot), start, atol=1e-9)


def test_turning_keeps_the_eye_in_place_and_turns_the_slice_axes():
    rig = CameraRig()
    pivot = np.array([2.0, 1.6, 3.0, 0.0])
    rig.set_rotation(rotation4("zw", np.pi / 2), pivot)
    assert np.allclose(rig.to_world(pivot), pivot)
    # After a quarter turn in zw, walking along the slice's z moves along the world's w.
    ahead = rig.to_world(pivot + [0.0, 0.0, 5.0, 0.0])
    assert np.allclose(ahead - pivot, [0.0, 0.0, 0.0, 5.0], atol=1e-12)
    assert rig.angles_deg() == pytest.approx((0.0, 0.0, 90.0))
    assert not rig.aligned


@pytest.mark.parametrize("seed", range(5))
def test_snapping_lands_exactly_on_the_nearest_axes(seed):
    rng = np.random.default_rng(seed)
    rig = CameraRig()
    pivot = np.array([0.0, 1.6, 0.0, 0.0])
    rig.turn(tuple(rng.uniform(-0.6, 0.6, 3)), 1.0, pivot)  # up to 34 degrees in each plane
    expected = nearest_axes(rig.rotation)
    rig.snap()
    landed = [rig.advance_glide(np.radians(120.0), 1 / 60, pivot) for _ in range(200)]
    assert landed.count(True) == 1
    assert np.array_equal(rig.rotation, expected)  # exactly: entries are 0, 1 or -1
    assert set(np.unique(rig.rotation)) <= {-1.0, 0.0, 1.0}
    assert np.linalg.det(rig.rotation) == 1.0


def test_four_quarter_steps_come_back_to_the_plain_slice():
    rig = CameraRig()
    pivot = np.array([0.5, 1.6, -1.0, 0.2])
    angles = []
    for _ in range(4):
        rig.step("xw", 1)
        while not rig.advance_glide(np.radians(120.0), 1 / 60, pivot):
            pass
        angles.append(rig.angles_deg()[0])
    assert angles == pytest.approx([90.0, 180.0, -90.0, 0.0])
    assert np.array_equal(rig.rotation, np.eye(4))
    assert rig.aligned  # the pivot never moved, so the anchor is back at exactly 0


def test_frustum_output_is_finite_all_round_the_orbit_and_at_the_focus_point():
    mesh = make_shape("tesseract")
    rig = CameraRig(fov_deg=60.0)
    eye = np.array([0.0, 1.6, -3.0])
    rig.detach(eye, np.array([0.0, 0.0, 1.0]), 0.0, 3.0)  # focus at (0, 1.6, 0): inside the tesseract's reach
    model = np.eye(5)
    model[:4, 4] = [0.0, 1.6, 0.0, 0.0]
    for deg in range(0, 360, 5):
        rig.orbit = np.radians(deg)
        pose, _ = rig.frustum_pose(eye, 0.0)
        tri = frustum_project(mesh, pose, fov_deg=rig.fov_deg, near=0.05, model=model)
        assert np.isfinite(tri.vertices).all() and np.isfinite(tri.depth).all()
    # The camera standing on the focus point itself, and on one of the mesh's vertices.
    for at in (rig.focus, model[:4, 4] + 0.5):
        pose, _ = rig.frustum_pose(eye, 0.0)
        pose[:4, 4] = at
        tri = frustum_project(mesh, pose, fov_deg=rig.fov_deg, near=0.05, model=model)
        assert np.isfinite(tri.vertices).all()
        pts, scale = rig.project_points(np.array([at, at + [0, 0, 0, 1.0]]), pose, np.eye(4))
        assert scale[0] == 0.0 and np.isnan(pts[0]).all()  # on the camera: behind the near hyperplane
        assert np.isfinite(pts[1]).all()


def test_the_focus_point_keeps_its_place_on_screen_while_the_camera_orbits():
    rig = CameraRig(fov_deg=70.0)
    eye = np.array([1.0, 1.6, 2.0])
    rig.detach(eye, np.array([1.0, 0.0, 1.0]) / np.sqrt(2), 0.4, 4.0)
    for deg in (0, 30, 90, 170):
        rig.orbit = np.radians(deg)
        pose, place = rig.frustum_pose(eye, 0.4)
        pts, _ = rig.project_points(rig.focus[None], pose, place)
        assert np.allclose(pts[0], rig.focus_u, atol=1e-9)


# ---------------------------------------------------------- levels and the game
def test_level_without_camera_table_leaves_the_slice_alone():
    game = Game(load_level(LEVELS / "02_crystal_cache.toml"))
    assert not game.level.camera.enabled
    before = game.state_hash()
    game.step(Actions(presses=(("step_zw_pos", 1), ("switch_camera", 1))))
    _run(game, 30, turn_xw_pos=True)
    assert game.camera.aligned and game.camera.mode == "synced"
    assert before != game.state_hash()  # the tick moved on, but the rig adds nothing
    assert camera_system.frustum_view(game) is None


def test_turning_the_slice_carries_the_player_into_the_orthogonal_world():
    level = load_level(LEVELS / "07_orthogonal_worlds.toml")
    # Without the turn there is no way across: the walker falls into the chasm.
    plain = Game(level)
    _run(plain, 420, forward=1.0)
    assert plain.outcome is None and plain.respawns >= 1
    # With the turn the glass bridge is under the player's feet.
    game = Game(level)
    game.energy.gain(game.energy.maximum_milli)  # the turn costs energy: as if the crystals were taken
    _run(game, 40, forward=1.0)
    _run(game, 20)
    game.step(Actions(presses=(("step_zw_pos", 1),)))
    _run(game, 60)
    assert game.event_counts["slice_aligned"] == 1
    assert game.camera.angles_deg() == pytest.approx((0.0, 0.0, 90.0))
    _run(game, 360, forward=1.0)
    assert game.outcome == "complete" and game.respawns == 0


def _eye_w(game: Game) -> float:
    """The player's eye's w in the world (not the slice offset the w gauge shows)."""
    p = game.player
    return float(game.camera.to_world(np.append(p.eye(), p.position[3]))[3])


def _turned_at_the_edge() -> Game:
    """Orthogonal Worlds: the slice turned 90 degrees in zw on the start platform."""
    game = Game(load_level(LEVELS / "07_orthogonal_worlds.toml"))
    game.energy.gain(game.energy.maximum_milli)  # the turn costs energy: as if the crystals were taken
    _run(game, 30, forward=1.0)
    game.step(Actions(presses=(("step_zw_pos", 1),)))
    _run(game, 60)
    return game


def test_the_slice_never_turns_back_at_a_w_outside_the_level():
    game = _turned_at_the_edge()
    lo, hi = game.level.w_range
    _run(game, 140, forward=1.0)  # half way along the glass bridge: walking ahead is walking ana
    assert _eye_w(game) > 9.0
    rotation, anchor = game.camera.rotation.copy(), game.camera.anchor.copy()
    # A step back and a held turn back are refused there, paid for or not: the slice stays as it was.
    game.energy.gain(game.energy.maximum_milli)
    game.step(Actions(presses=(("step_zw_neg", 1),)))
    _run(game, 60)
    _run(game, 60, turn_zw_neg=True)
    assert np.array_equal(game.camera.rotation, rotation) and np.array_equal(game.camera.anchor, anchor)
    assert game.event_counts["slice_aligned"] == 1 and game.event_counts["slice_turn_refused"] == 2
    assert "Walk back" in game.frame().hud.message
    # The w keys never carry the player's world w out of the range either (they move along z now).
    _run(game, 90, w=1.0)
    assert _eye_w(game) > hi and game.camera.angles_deg() == pytest.approx((0.0, 0.0, 90.0))
    # Back on the start platform, where the world w is inside the range, the slice turns back,
    # and the player's w (the gauge, the range's clamp) is their world w again.
    while _eye_w(game) > 0.0:
        game.step(Actions(forward=-1.0))
    game.energy.gain(game.energy.maximum_milli)  # turning back is a turn too: it costs a step's price
    game.step(Actions(presses=(("step_zw_neg", 1),)))
    _run(game, 60)
    assert game.event_counts["slice_aligned"] == 2
    assert game.camera.angles_deg() == pytest.approx((0.0, 0.0, 0.0))
    assert game.camera.anchor[3] == 0.0 and game.player.position[3] == pytest.approx(_eye_w(game))
    game.energy.gain(game.energy.maximum_milli)  # moving along w costs energy too
    _run(game, 120, w=1.0)
    assert _eye_w(game) == pytest.approx(hi)
    _run(game, 240, w=-1.0)
    assert _eye_w(game) == pytest.approx(lo)


def test_energy_drains_at_the_stated_rate_and_the_return_starts_at_zero():
    game = Game(load_level(LEVELS / "08_around_the_corner.toml"))
    rate = game.level.camera.frustum_cost_milli  # thousandths per second
    game.energy = EnergyBar.of(2.5, 20.0)
    game.step(SWITCH)
    start = game.energy.milli
    for n in range(1, 121):
        game.step(Actions())
        assert start - game.energy.milli == rate * n // 60  # to the thousandth, never rounded up early
    # Run dry: the return starts on the tick the bar reaches zero, and ends a second later.
    ticks = 0
    while game.camera.mode == "frustum":
        game.step(Actions())
        ticks += 1
    assert game.energy.milli == 0
    kinds = [e.kind for e in game.events]
    assert "energy_empty" in kinds and "camera_switched" in kinds
    assert [e.reason for e in game.events if e.kind == "camera_switched"] == ["energy"]
    assert ticks == pytest.approx(0.5 * 60, abs=1)  # 2.5 - 2.0 paid so far = 0.5 s left
    _run(game, round(game.level.camera.return_time * 60))
    assert game.camera.mode == "synced" and game.event_counts["camera_switched"] == 3


def test_the_frustum_view_stays_put_while_the_player_walks():
    game = Game(load_level(LEVELS / "08_around_the_corner.toml"))
    _run(game, 20)
    game.step(SWITCH)
    first = {d.key: d for d in game.frame().drawables if d.key.startswith("frustum:")}
    _run(game, 30, forward=1.0, yaw=0.02)
    later = {d.key: d for d in game.frame().drawables if d.key.startswith("frustum:")}
    assert first.keys() == later.keys() and first
    # The crystals turn on their own (re-projected as they spin); the door and the switch do not.
    still = {k: d for k, d in first.items() if game.entities.get(int(k.rsplit(":", 1)[1])).kind != "crystal"}
    assert {game.entities.get(int(k.rsplit(":", 1)[1])).kind for k in still} == {"object", "target"}
    for key, d in still.items():  # the same meshes (not re-projected) at the same place
        assert later[key].revision == d.revision and later[key].mesh is d.mesh
        assert np.array_equal(later[key].model, d.model)
    assert not game.events or all(e.kind != "camera_switched" for e in game.events)


def test_bullets_seen_through_the_4d_camera_hit_around_the_corner():
    level = load_level(LEVELS / "08_around_the_corner.toml")

    def shot(orbit_ticks: int, frustum: bool = True) -> bool:
        game = Game(level)
        _run(game, 14, forward=1.0)  # onto the mark, facing the door
        _run(game, 30)
        if frustum:
            game.step(SWITCH)
            _run(game, orbit_ticks, orbit_left=True)
        game.step(Actions(yaw=np.radians(-36.0), pitch=np.radians(-20.0)))  # low, ahead on the left
        game.step(Actions(presses=(("fire", 1),)))
        target = game.entities.of_kind("target")[0]
        for _ in range(60):
            game.step(Actions())
            for b in game.entities.of_kind("bullet"):  # no bullet ever reaches the switch in 4D
                assert np.linalg.norm(b.center(game) - target.center(game)) > target.radius + b.radius
        return game.event_counts["target_hit"] == 1

    assert not shot(0, frustum=False)  # cross-section: the switch is out of reach
    assert not shot(0)  # unorbited, its image lies deep under the floor
    assert shot(135)  # 90 degrees round the orbit its image sits on the floor in the hall: the same shot hits


def test_camera_modes_replay_deterministically():
    level = load_level(LEVELS / "08_around_the_corner.toml")
    script = (
        [Actions(forward=1.0)] * 14
        + [SWITCH]
        + [Actions(orbit_right=True)] * 50
        + [Actions(presses=(("fire", 1),))]
        + [Actions(orbit_left=True, forward=0.5)] * 20
        + [SWITCH]
        + [Actions(yaw=0.01)] * 70
    )
    hashes = []
    for _ in range(2):
        game = Game(level, seed=3)
        row = []
        for a in script:
            game.step(a)
            row.append(game.state_hash())
        hashes.append(row)
        assert game.event_counts["camera_switched"] == 3
    assert hashes[0] == hashes[1]
    assert len(set(hashes[0])) == len(script)


@pytest.mark.parametrize(
    "entry, needle",
    [
        ({"turn_speed": 0.0}, "'turn_speed'"),
        ({"fov": 170.0}, "'fov'"),
        ({"frustum": 1}, "'frustum'"),
        ({"orbit": 3.0}, "'orbit'"),
    ],
)
def test_bad_camera_table_names_the_file_and_the_entry(tmp_path, entry, needle):
    with pytest.raises(LevelError) as e:
        LevelBuilder(floor=(10.0, 1.0, 10.0)).table("camera", **entry).load(tmp_path, "cam.toml")
    lines = str(e.value).splitlines()
    assert any("[camera]" in ln and needle in ln for ln in lines), lines
    assert "cam.toml" in str(e.value)


def test_check_level_accepts_the_camera_levels():
    for name in ("07_orthogonal_worlds.toml", "08_around_the_corner.toml"):
        done = subprocess.run(
            [sys.executable, "-m", "across_dimensions", "check-level", str(LEVELS / name)],
            capture_output=True,
            text=True,
            timeout=300,
        )
        assert done.returncode == 0, done.stderr
        assert "ok" in done.stdout


def test_picture_in_picture_shows_the_other_projection_and_costs_nothing_when_off():
    game = Game(load_level(LEVELS / "08_around_the_corner.toml"))
    _run(game, 10)
    frame = game.frame()
    assert frame.pip is None and game.camera.cache is None  # no frustum projection was made
    inset = game.frame(pip=True).pip
    assert inset and all(d.key.startswith("pip-frustum:") for d in inset)  # what the switch would show
    game.step(SWITCH)
    main = game.frame(pip=True)
    assert any(d.key.startswith("frustum:") for d in main.drawables)
    assert main.pip and all(d.key.startswith("pip:") for d in main.pip)  # the cross-section, inset


def test_radar_pins_say_what_reaches_the_slice_while_the_frustum_camera_is_out():
    (path,) = LEVELS.glob("*around_the_corner.toml")
    game = Game(load_level(path))
    _run(game, 20)
    synced = [(p.kind, p.visible) for p in game.frame().radar.pins]
    game.step(SWITCH)
    _run(game, 5)
    assert game.camera.detached

    # Nothing moved along w: the pins say what they said in the slice (not a stale frame's).
    def things():
        return [(p.kind, p.visible) for p in game.frame().radar.pins if not p.kind.startswith("camera_")]

    assert things() == synced
    assert any(v for _, v in synced)
    # Far along w (as a move along w while the camera is out would take it), nothing reaches.
    game.player.position[3] += 50.0
    assert things() and not any(v for _, v in things())
