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
# "long": a fuzz campaign on a workstation (HYPOTHESIS_PROFILE=long): new examples, twenty times as many.
# tests/test_hardening.py scales its own example counts by `EXAMPLE_FACTOR`.
settings.register_profile("long", deadline=None, max_examples=2000,
                          suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much])
EXAMPLE_FACTOR = 20 if os.environ.get("HYPOTHESIS_PROFILE") == "long" else 1
settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE", "ci"))
