"""Soft-lock proofs: cheap arguments that the intended route can no longer win from a state.

The intended route is the shipped replay's plan (:mod:`.route`): the switches it throws,
the enemies it beats, the angles it turns objects to, the bodies it brings where it uses
them. From the state a strategy leaves, each proof below shows that some step still to do
cannot be done, by an argument that holds whatever the player does next:

- **energy**: the steps left cost more energy than the bar holds (a shot for each switch,
  a hit for each point of an enemy's health, the degrees still to turn, the w still to go to
  the goal's w), and nothing can refill it: no crystal lies in the level or grows back, no
  enemy still carries loot the bar could pay to shake loose, no gun fires rounds;
- **body**: a body the route stands on can no longer be pushed back to its start or to
  where the route leaves it. The player pushes a body only by walking into it, so to push it
  one way the player's box must fit against its other side; a flood fill over the floor
  (10 cm cells) from where the body is, moving it only where it fits and the player fits
  behind it, never meets those places. Everything that could open (doors, 4D objects) is
  counted as open and the player is assumed able to walk anywhere, so the fill finds more
  ways back than there are, under one assumption: the body stays square to the axes and
  moves only where a push on one of its faces sends it. The physics can turn a body at a
  corner contact, after which a push has a sideways part; bullets nudge bodies and the blast
  moves them along w. None of that is modelled, so a body finding holds for a body that
  stays square (the bot's own attempt to push it back, run before the proof, is the check);
- **switch**: a switch the route throws lies, in w, beyond every bullet's swing from every
  w the player can stand at, and no blast can bring it and no frustum camera can see it.

Each proof returns a short sentence, or None when it cannot show anything.
"""

from __future__ import annotations

import numpy as np

from . import read

CELL = 0.1  # metres: the flood fill's grid
LEDGE = 0.35  # what the player steps up without jumping (game.player.STEP_HEIGHT)
SLACK = 0.01  # metres: boxes taken this much smaller, so contact depths never close a way


def softlocks(game, route) -> list[str]:
    """Every proof that holds in ``game``'s state, as sentences (empty: nothing proven)."""
    if read.won(game):
        return []
    found = [energy_short(game, route)]
    found += [body_lost(game, s) for s in route.of_kind("body")]
    found += [switch_out_of_reach(game, s) for s in route.of_kind("target")]
    return [f for f in found if f]


# ------------------------------------------------------------------ energy
def _shot_cost(game) -> float | None:
    """The cheapest shot: 0 with rounds in a gun, None without a gun."""
    costs = []
    for k, s in enumerate(read.weapons(game)):
        if s.kind == "gun":
            costs.append(0.0 if read.rounds(game, k) > 0 else s.cost_milli / 1000.0)
    return min(costs) if costs else None


def _beyond_bullets(game, t) -> bool:
    """Is the switch ``t`` out of every bullet's swing from every w the player can stand at?"""
    lo, hi = read.w_range(game)
    gap = max(0.0, t.center[3] - hi, lo - t.center[3])
    return not any(gap <= s.amplitude + s.size + t.radius for s in read.weapons(game) if s.kind == "gun")


def _reach_cost(game, t) -> tuple[float, str] | None:
    """The least a switch beyond the bullets costs to bring within reach (a blast, or a tick of
    the frustum camera), or None when a bullet reaches it as it is."""
    if not _beyond_bullets(game, t):
        return None
    anchored = read.target_spec(game, t.id).anchored
    ways = [(s.cost_milli / 1000.0, "a blast") for s in read.weapons(game) if s.kind == "blast" and not anchored]
    cam = game.level.camera
    if cam.frustum:
        ways.append((cam.frustum_cost_milli / 60000.0, "the frustum camera"))
    return min(ways) if ways else None


def energy_needed(game, route) -> tuple[float, list[str]]:
    """What the route's steps not yet done cost at the least, and what they are."""
    need, what = 0.0, []
    shot = _shot_cost(game) or 0.0
    open_targets = {t.name for t in read.targets(game)}
    for s in route.of_kind("target"):
        if s.name in open_targets:
            need += shot
            what.append(f"a shot at '{s.name}'")
            extra = _reach_cost(game, next(t for t in read.targets(game) if t.name == s.name))
            if extra:
                need += extra[0]
                what.append(extra[1])
    alive = {f.name: f for f in read.foes(game)}
    for s in route.of_kind("enemy"):
        if s.info.get("opens") and s.name in alive:
            need += shot * alive[s.name].health
            what.append(f"{alive[s.name].health} hits on '{s.name}'")
    for s in route.of_kind("manipulate"):
        h = next((h for h in read.handles(game) if h.name == s.name), None)
        spec = next((m for m in game.level.manipulables if m.object == s.name), None)
        if h is not None and spec is not None:
            left = sum(abs(a - h.angles.get(p, 0.0)) for p, a in s.info["angles"].items())
            if left > 0:
                need += left * spec.cost_milli / 1000.0
                what.append(f"{left:g} degrees of '{s.name}'")
    _, _, wr = read.goal(game)
    w = float(read.feet(game)[3])
    if wr is not None and not wr[0] <= w <= wr[1]:
        need += min(abs(w - wr[0]), abs(w - wr[1])) * read.w_cost(game)
        what.append("the way along w to the goal")
    return need, what


def refillable(game) -> bool:
    """Could the bar still fill: a crystal lying or growing back, or loot the bar can free?"""
    if read.crystals(game) or read.regrowing(game):
        return True
    bar = read.energy(game) or 0.0
    shot = _shot_cost(game)
    if shot == 0.0:
        return any(f.loot for f in read.foes(game))
    return bar > 0 and any(f.loot for f in read.foes(game))


def energy_short(game, route) -> str | None:
    bar = read.energy(game)
    if bar is None or refillable(game):
        return None
    need, what = energy_needed(game, route)
    if need <= bar + 1e-9:
        return None
    return f"energy: {bar:g} left and nothing refills it, but the route still needs {need:g} ({', '.join(what)})"


# ------------------------------------------------------------------ bodies
def _overlaps(lo, hi, boxes) -> np.ndarray:
    """Which of the boxes ``lo, hi (..., 3)`` meet any of ``boxes (k, 2, 3)`` (NaN rows: none)."""
    if len(boxes) == 0:
        return np.zeros(lo.shape[:-1], bool)
    a = (lo[..., None, :] < boxes[:, 1]) & (hi[..., None, :] > boxes[:, 0])
    return np.any(np.all(a, axis=-1), axis=-1)


def _grid(boxes, origin) -> tuple[np.ndarray, np.ndarray]:
    """Cell centres in x and z over the level's boxes, one of them exactly at ``origin``."""
    lo = np.nanmin(boxes[:, 0], axis=0)
    hi = np.nanmax(boxes[:, 1], axis=0)
    axes = []
    for a, o in ((0, origin[0]), (2, origin[2])):
        k0, k1 = int(np.floor((lo[a] - o) / CELL)), int(np.ceil((hi[a] - o) / CELL))
        axes.append(o + CELL * np.arange(min(k0, 0), max(k1, 0) + 1))
    return axes[0], axes[1]


def _fits(boxes, xs, zs, y0: float, y1: float, half: np.ndarray) -> np.ndarray:
    """Where a box ``2 half`` wide in x and z and spanning ``y0..y1`` fits, ``(nx, nz)``."""
    c = np.stack(np.meshgrid(xs, zs, indexing="ij"), axis=-1)
    lo = np.concatenate([c[..., :1] - half[0], np.full(c.shape[:2] + (1,), y0), c[..., 1:] - half[1]], axis=-1)
    hi = np.concatenate([c[..., :1] + half[0], np.full(c.shape[:2] + (1,), y1), c[..., 1:] + half[1]], axis=-1)
    return ~_overlaps(lo, hi, boxes)


def pushable_region(game, body, boxes) -> tuple[np.ndarray, tuple]:
    """Cells the body can be pushed to from where it is: ``(nx, nz)`` bool and the grid."""
    xs, zs = _grid(boxes, body.center)
    half = body.radius / 2.0  # a hypercube's half edge (its reach is twice that)
    bottom = body.center[1] - half
    # A centimetre less all round: resting contact leaves bodies a hair inside what they touch.
    body_ok = _fits(boxes, xs, zs, bottom + 0.02, bottom + 2 * half, np.array([half, half]) - SLACK)
    player = np.array([read.HALF_WIDTH, read.HALF_WIDTH]) - SLACK
    man_ok = _fits(boxes, xs, zs, bottom + LEDGE, bottom + read.HEIGHT, player)
    gap = int(np.ceil((half + read.HALF_WIDTH + 0.01) / CELL))
    start = (int(np.argmin(np.abs(xs - body.center[0]))), int(np.argmin(np.abs(zs - body.center[2]))))
    seen = np.zeros_like(body_ok)
    seen[start] = True
    todo = [start]
    while todo:
        i, k = todo.pop()
        for di, dk in ((1, 0), (-1, 0), (0, 1), (0, -1)):
            ni, nk = i + di, k + dk
            bi, bk = i - di * gap, k - dk * gap  # where the player stands to push
            if not (0 <= ni < len(xs) and 0 <= nk < len(zs) and 0 <= bi < len(xs) and 0 <= bk < len(zs)):
                continue
            if seen[ni, nk] or not body_ok[ni, nk] or not man_ok[bi, bk]:
                continue
            seen[ni, nk] = True
            todo.append((ni, nk))
    return seen, (xs, zs)


def _touching(lo, hi, boxes, axis: int, sign: int) -> np.ndarray:
    """For boxes ``lo, hi (..., 3)``: which of ``boxes`` each touches (within 10 cm) on its
    ``sign`` side along ``axis``, ``(..., k)`` bool."""
    lo, hi = lo.copy(), hi.copy()
    (hi if sign > 0 else lo)[..., axis] += 0.1 * sign
    a = (lo[..., None, :] < boxes[:, 1]) & (hi[..., None, :] > boxes[:, 0])
    return np.all(a, axis=-1)


def _same_contacts(body, boxes, rest, gx, gz) -> np.ndarray:
    """Cells where the body leans on the same boxes, on the same sides, as where the route
    uses it (a crate at the foot of a ledge works anywhere along the ledge), ``(nx, nz)``."""
    half = body.radius / 2.0
    bottom = body.center[1] - half

    def box_at(x, z):
        lo = np.stack([x - half, np.full_like(x, bottom + 0.02), z - half], axis=-1)
        hi = np.stack([x + half, np.full_like(x, bottom + 2 * half), z + half], axis=-1)
        return lo, hi

    r_lo, r_hi = box_at(np.array(rest[0]), np.array(rest[2]))
    g_lo, g_hi = box_at(gx, gz)
    out = np.ones(gx.shape, bool)
    leans = False
    for axis in (0, 2):
        for sign in (1, -1):
            need = _touching(r_lo, r_hi, boxes, axis, sign) & ~_touching(r_lo, r_hi, boxes, axis, 0)
            if need.any():
                leans = True
                out &= np.any(_touching(g_lo, g_hi, boxes, axis, sign)[..., need], axis=-1)
    return out if leans else np.zeros(gx.shape, bool)


def body_lost(game, step) -> str | None:
    body = read.body_named(game, step.name)
    if body is None or step.info.get("rest") is None:
        return None
    boxes = game.colliders_at(float(body.center[3]))
    boxes = boxes[~np.isnan(boxes).any(axis=(1, 2))]
    if len(boxes) == 0:
        return None
    seen, (xs, zs) = pushable_region(game, body, boxes)
    gx, gz = np.meshgrid(xs, zs, indexing="ij")
    for where in (step.info["start"], step.info["rest"]):
        near = np.hypot(gx - where[0], gz - where[2]) <= 0.35
        if np.any(seen & near):
            return None
    if np.any(seen & _same_contacts(body, boxes, step.info["rest"], gx, gz)):
        return None
    c = body.center
    return (
        f"body: '{step.name}' at x={c[0]:.2f}, z={c[2]:.2f} can no longer be pushed back to its start "
        f"or to where the route uses it (x={step.info['rest'][0]:.2f}, z={step.info['rest'][2]:.2f})"
    )


# ------------------------------------------------------------------ switches
def switch_out_of_reach(game, step) -> str | None:
    t = next((t for t in read.targets(game) if t.name == step.name), None)
    if t is None:
        return None
    kinds = {s.kind for s in read.weapons(game)}
    if "blast" in kinds or game.level.camera.frustum:
        return None
    if not _beyond_bullets(game, t):
        return None
    lo, hi = read.w_range(game)
    return f"switch: '{step.name}' at w={t.center[3]:g} is beyond every bullet's swing from w in [{lo:g}, {hi:g}]"
