"""The design probe: does each level demand what it teaches, and can it never trap a player?

``across-dimensions probe [LEVEL...] [--json] [--workers N]`` runs a library of naive
strategies (:mod:`.strategies`) against each level through the headless simulation
(``Game(level).step(actions)``, nothing drawn), in worker processes (:mod:`.runner`):

- a strategy that avoids a mechanic the level declares in ``[design] needs``
  (:mod:`across_dimensions.world.design`) and still reaches the goal is a **bypass**;
- a run that ends with the level unwinnable by its intended route (the shipped replay's
  plan, :mod:`.route`), as one of the proofs of :mod:`.proofs` shows, is a **soft-lock**.

The strategies are bots (:mod:`.pilot`, :mod:`.skills`): they read the goal, crystals,
switches, crates and enemies from the game through :mod:`.read` (the one module that knows
where the game's systems keep their state) and steer, jump and aim at them.

Layering: above ``game`` and ``world``; never imports ``render`` or ``app`` (the command's
wiring lives in ``app.commands``).
"""

from .runner import probe

__all__ = ["probe"]
