"""Test-wide settings: float32 everywhere (the library default) and a fixed hypothesis profile."""

import os

from hypothesis import HealthCheck, settings

# Compilation dominates small property tests; a few dozen examples per property is plenty and keeps CI fast.
settings.register_profile(
    "jaxmotion",
    max_examples=int(os.environ.get("JAXMOTION_HYPOTHESIS_EXAMPLES", "25")),
    deadline=None,
    derandomize=True,
    suppress_health_check=[HealthCheck.too_slow],
)
settings.load_profile("jaxmotion")
