"""Step policy of the fixed-step integrators: limits on the RK4 steps per forcing period."""

from __future__ import annotations

__all__ = ["MAX_STEPS", "MIN_STEPS"]

#: Fewest RK4 steps per forcing period a caller may ask for.
MIN_STEPS = 4
#: Most RK4 steps per forcing period: a model that needs more has a near-zero inertia or
#: a near-rigid element (its highest natural frequency is out of scale).
MAX_STEPS = 100_000
