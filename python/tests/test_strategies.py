"""The Hypothesis strategies on a posed scene (the contact oscillator written as a dict,
spec chapter 10) and on built-in ones, and an example: a scheme written in Python validated
against the exact discrete flow over pairs on M_h^{e,nh}.

The scheme is a Stormer-Verlet step with DLA's midpoint discrete constraint (as in
examples/python/validate_scheme.py): on the contact oscillator (L = |qd|^2/2 - V,
V = (x^2 + y^2 + z^2 + eps x^2 z^2) / 2, constraint xd + y zd = 0)
    q2 = 2 q1 - q0 - h^2 grad V(q1) + c mu(q1),   mu((q1 + q2) / 2) . (q2 - q1) = 0,
explicit since mu = (1, 0, y) depends on y only. Its one-step error against the exact
discrete flow is O(h^3) (spec (7.9)): the property is |q2 - q2_exact| <= C h^3 with C = 2
for |q0| <= 0.5, |u0| <= 0.5 (the third derivatives of the motion there stay below 0.3 by
a hand estimate: |q| <= 1, |qd| <= 1, so each term of the derivatives is O(1 + eps)), and
the distance is certified by the oracle's enclosure of q2 and `distance` (rounded
outwards)."""

import math

from hypothesis import given, settings
from hypothesis import strategies as st

from dalembert import Interval, distance
from dalembert.strategies import (
    Pair, State, configurations, dimensions, extreme_steps, large_configurations, pairs_near,
    pairs_on_manifold, states,
)

EPS = 0.3
CONTACT = {
    "name": "contact-posed",
    "coordinates": ["x", "y", "z"],
    "parameters": {"eps": EPS},
    "potential": "(x*x + y*y + z*z + eps*x*x*z*z) / 2",
    "constraints": [[1, 0, "y"]],
    "free": ["y", "z"],
}


def scheme(q0, q1, h):
    x, y, z = q1
    grad = [x + EPS * x * z * z, y, z + EPS * x * x * z]
    w = [b - a - h * h * g for a, b, g in zip(q0, q1, grad)]  # q2 - q1 with c = 0
    ym = y + w[1] / 2                                        # (y1 + y2) / 2
    c = -(w[0] + ym * w[2]) / (1 + ym * y)                   # mu(ym) . (w + c mu(y)) = 0
    return [x + w[0] + c, y + w[1], z + w[2] + c * y]


def test_dimensions_of_posed_and_built_in_scenes(oracle):
    assert dimensions(oracle, CONTACT) == (3, 2)
    assert dimensions(oracle, "knife") == (3, 2)
    assert dimensions(oracle, "rolling-disk") == (4, 2)


@given(st.data())
def test_pairs_on_the_posed_manifold_have_a_certified_tiny_defect(oracle, data):
    p = data.draw(pairs_on_manifold(oracle, CONTACT, 0.5, 0.5, (0.01, 0.2)))
    assert isinstance(p, Pair) and len(p.q1) == 3 and len(p.defect) == 1
    assert all(isinstance(s, Interval) and s.mag() < 1e-12 for s in p.defect), p
    # the pair answers the exact step, whose point of M_h^{e,nh} is q1 up to the defect
    s = oracle.step(p.q0, p.q1, p.h, scene=CONTACT)
    assert distance(p.q1, s.q1).hi < 1e-11


@given(st.data())
def test_a_python_scheme_has_local_error_below_2_h_cubed(oracle, data):
    p = data.draw(pairs_on_manifold(oracle, CONTACT, 0.5, 0.5, (0.01, 0.2)))
    exact = oracle.step(p.q0, p.q1, p.h, scene=CONTACT).q2
    err = distance(scheme(p.q0, p.q1, p.h), exact)
    assert err.hi <= 2 * p.h ** 3, (p, err)


@given(st.data())
@settings(max_examples=10)
def test_pairs_near_are_off_the_manifold_by_about_the_distance(oracle, data):
    d = 1e-4
    p = data.draw(pairs_near(oracle, "knife", 1.0, 1.0, (0.05, 0.2), d))
    # the defect s is a distance parameter along the constraint normal: proved non-zero,
    # and of the size of the move (the knife's normal (sin, -cos, 0) is a unit vector)
    assert all(s.excludes_zero() for s in p.defect), p
    assert all(0.5 * d < s.mag() < 2 * d for s in p.defect), p


@given(st.data())
@settings(max_examples=10)
def test_configurations_and_large_ones_pass_the_scene_checks(oracle, data):
    q = data.draw(configurations(oracle, "rolling-disk", 1.0))
    assert len(q) == 4 and all(abs(x) <= 1 for x in q)
    big = data.draw(large_configurations(oracle, "knife", 6))
    assert all(math.log10(abs(x)) in range(7) for x in big)
    assert oracle.flow(big, [0.0, 0.0], 0.0, scene="knife").q[0].lo == big[0]


@given(extreme_steps())
def test_extreme_steps_are_the_stability_tables(h):
    assert h in (1e-8, 1e-6, 1e-3, 0.1, 0.5, 1.0, 2.0)


def test_states_are_certified_to_the_horizon_and_the_filter_rate_is_reported(oracle):
    # the knife-like posed unicycle's derived basis is singular at theta = +-pi/2: starts
    # with |theta| <= 1.5 and |w| <= 2 often reach it before t = 1, and are filtered
    unicycle = {"coordinates": ["x", "y", "theta"], "parameters": {"m": 2.0, "J": 0.75},
                "mass": [["m", 0, 0], [0, "m", 0], [0, 0, "J"]],
                "constraints": [["-sin(theta)", "cos(theta)", 0]], "free": ["x", "theta"]}
    seen, events = [], []

    @settings(max_examples=15, database=None, derandomize=True)
    @given(states(oracle, unicycle, 1.5, 2.0, t=1.0))
    def prop(s):
        assert isinstance(s, State) and len(s.q) == 3 and len(s.u) == 2
        seen.append(s)

    import hypothesis.control as control
    real = control.event

    def spy(value, payload=""):
        events.append(value)
        return real(value, payload)

    import dalembert.strategies as strategies
    strategies.event = spy
    try:
        prop()
    finally:
        strategies.event = real
    assert seen
    for q, u in seen:
        oracle.flow(q, u, 1.0, scene=unicycle)  # certified (raises otherwise)
    assert "states: certified to t" in events
    assert any(e.startswith("states: refused (") for e in events), events
