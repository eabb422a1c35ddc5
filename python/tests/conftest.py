"""pytest set-up of the Python side: one oracle per test session, and Hypothesis profiles
("ci": derandomized, a fixed number of examples and no deadline, so that a run replays
exactly; selected with HYPOTHESIS_PROFILE=ci, as .ci/run does)."""

import os

import pytest
from hypothesis import HealthCheck, settings

from dalembert import Oracle

settings.register_profile(
    "ci", derandomize=True, max_examples=25, deadline=None, print_blob=True, database=None,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much])
settings.register_profile(
    "dev", max_examples=25, deadline=None,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much])
settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE", "dev"))


@pytest.fixture(scope="session")
def oracle():
    o = Oracle()
    yield o
    assert o.close() == 0
