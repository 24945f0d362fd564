"""What the energy bar shows of energy just spent: a bright segment that waits, then sinks in.

Moving along w pays by the distance, a little every tick, so a drain is smooth and at 10 FPS
easy to miss: holding a w key "briefly" could empty the bar before the player saw a change. The
trail keeps the value from before the spending for :data:`GRACE_SECONDS` after the last spend,
then lets it sink at :data:`SINK_PER_SECOND` of the bar, so what a move cost is seen as it is
spent. Drawing only: wall-clock time in the window, never the simulation's state.
"""

from __future__ import annotations

from dataclasses import replace

#: Seconds the spent segment stays whole after the last spend before it starts to sink.
GRACE_SECONDS = 0.5
#: How fast it sinks once it does, in bars per second (a full bar's trail in under a second).
SINK_PER_SECOND = 1.2


class EnergyTrail:
    """The value the bar showed before the energy just spent, and how long since that spend."""

    def __init__(self):
        self.shown: float | None = None  # the top of the spent segment
        self.last = 0.0  # the value at the last update
        self.since = 0.0  # wall seconds since the value last fell

    def update(self, gauge, dt: float):
        """``gauge`` (an :class:`~across_dimensions.game.frame.EnergyGauge` or None) with its
        ``spent`` filled in, ``dt`` wall seconds after the last call."""
        if gauge is None:
            self.shown = None
            return None
        value = float(gauge.value)
        if self.shown is None or value >= self.shown:
            self.shown, self.last, self.since = value, value, 0.0
            return gauge
        self.since = 0.0 if value < self.last else self.since + dt  # spent again: the grace starts over
        self.last = value
        if self.since > GRACE_SECONDS:
            self.shown = max(value, self.shown - SINK_PER_SECOND * float(gauge.maximum) * dt)
        return replace(gauge, spent=self.shown - value)
