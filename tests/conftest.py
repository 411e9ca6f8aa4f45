import os

from hypothesis import HealthCheck, settings

# CI draws the same examples every run (derandomize), so that a red run can be reproduced and a green one
# means something; "explore" draws new ones (HYPOTHESIS_PROFILE=explore) to look for new counterexamples,
# which then become explicit tests.
settings.register_profile("ci", deadline=None, derandomize=True, database=None,
                          suppress_health_check=[HealthCheck.too_slow])
settings.register_profile("explore", deadline=None, max_examples=200,
                          suppress_health_check=[HealthCheck.too_slow])
settings.register_profile("dev", deadline=None, max_examples=20, suppress_health_check=[HealthCheck.too_slow])
settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE", "ci"))
