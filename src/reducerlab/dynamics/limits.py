"""The engine's limits and defaults as plain numbers (no imports), so that the command
line can show them in its options without importing numpy or scipy."""

__all__ = ["ACCURACY", "MAX_STEPS", "MIN_STEPS"]

#: Fewest RK4 steps per forcing period a caller may ask for.
MIN_STEPS = 4
#: Most RK4 steps per forcing period: a model that needs more has a near-zero inertia or
#: a near-rigid element (its highest natural frequency is out of scale).
MAX_STEPS = 100_000
#: Default target error of Poincaré points, relative to the motion's scale
#: (:func:`reducerlab.dynamics.accuracy.accurate_steps`).
ACCURACY = 1e-6
