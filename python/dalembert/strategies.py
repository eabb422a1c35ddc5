"""Hypothesis strategies of admissible inputs for any scene, built-in or posed (a dict),
mirroring the Rust generators of `dalembert::testing::strategies` (spec eq. (11.6)):
configurations where the scene passes its checks, pairs on M_h^{e,nh} from the exact
exponential map with their certified defect, pairs at a chosen distance from it, and the
extreme step sizes of the stability table.

Every pair is built from shrinkable inputs (q0, u0, h drawn by Hypothesis) through the
oracle: `q1` is the midpoint of the certified flow from (q0, u0) at h, and the defect is
what the oracle's retraction certifies for the float pair. So when Hypothesis shrinks a
failing example it shrinks q0, u0 and h, and the pair is rebuilt from them: a shrunk pair
is as admissible as the first. Starts the oracle cannot certify are rejected (filtered), not
answered, and each rejection is a Hypothesis event naming its cause (`refused (mass)`,
...), so `pytest --hypothesis-show-statistics` shows the filter rate.

`states(oracle, scene, q_bound, u_bound, t=T)` draws initial states (q, u) whose flow the
oracle certifies up to the horizon T; `pairs_on_manifold` and `pairs_near` take the same
`t=` so that their starts are certified that far too (not only for the one step h).

    from hypothesis import given
    from dalembert import Oracle
    from dalembert.strategies import pairs_on_manifold

    oracle = Oracle()
    @given(pairs_on_manifold(oracle, "knife", q_bound=1.0, u_bound=1.0, h=(0.05, 0.2)))
    def test_my_scheme(p):
        ...  # p.q0, p.u0, p.q1, p.h, p.defect (Intervals)
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, List, Mapping, NamedTuple, Optional, Tuple

from hypothesis import event
from hypothesis import strategies as st

from ._intervals import Interval
from ._oracle import Oracle, OracleError, Uncertified
from ._oracle import SceneLike as Scene

__all__ = [
    "Pair", "State", "states", "dimensions", "configurations", "pairs_on_manifold", "pairs_near",
    "extreme_steps", "large_configurations",
]


@dataclass(frozen=True)
class Pair:
    """A pair (q0, q1) with step h: `q1` is the float point of the exact motion from
    (q0, u0) at h (moved by a chosen distance for `pairs_near`), `defect` the oracle's
    certified enclosure of its distance parameter s to M_h^{e,nh} (k intervals)."""

    q0: List[float]
    u0: List[float]
    q1: List[float]
    h: float
    defect: List[Interval]


class State(NamedTuple):
    """An initial state (q, u) whose flow the oracle certified up to the horizon."""

    q: List[float]
    u: List[float]


def _refused(what: str, e: OracleError) -> None:
    """A rejected draw, reported in Hypothesis' statistics with its cause."""
    event(f"{what}: refused ({getattr(e, 'cause', None) or e.reason or 'code %s' % e.code})")


def dimensions(oracle: Oracle, scene: Scene, params: Optional[Mapping[str, float]] = None
               ) -> Tuple[int, int]:
    """(n, m): the scene's number of coordinates and of quasi-velocities (n - k), read from
    `dalembert scenes --json` (its `n` and `k`) for a built-in scene, from the dict of a
    posed one (its `coordinates` and `constraints`)."""
    if isinstance(scene, str):
        for s in oracle.scenes()["scenes"]:
            if s["name"] == scene:
                return int(s["n"]), int(s["n"]) - int(s["k"])
        raise ValueError(f"unknown scene {scene!r}")
    n = len(scene["coordinates"])
    return n, n - len(scene["constraints"])


def _floats(bound: float) -> st.SearchStrategy[float]:
    return st.floats(-bound, bound, allow_nan=False, allow_infinity=False, width=64)


def _admissible(oracle: Oracle, scene: Scene, params: Any, q: List[float], m: int) -> bool:
    """The scene passes its checks at q (spec (3.17)): a flow of length 0 from q answers."""
    try:
        oracle.flow(q, [0.0] * m, 0.0, scene=scene, params=params)
        return True
    except OracleError as e:
        _refused("configuration", e)
        return False


def configurations(oracle: Oracle, scene: Scene, bound: float,
                   params: Optional[Mapping[str, float]] = None) -> st.SearchStrategy[List[float]]:
    """Configurations in [-bound, bound]^n at which the scene passes the checks of spec eq.
    (3.17) (others are rejected). Shrinks toward the origin."""
    n, m = dimensions(oracle, scene, params)
    return st.lists(_floats(bound), min_size=n, max_size=n).filter(
        lambda q: _admissible(oracle, scene, params, q, m))


def _normal(oracle: Oracle, scene: Scene, params: Any, q: List[float], m: int
            ) -> Optional[List[float]]:
    """A unit vector orthogonal (in float) to D(q): the basis of D is read from flows of
    length 0 (v = E(q)^T e_i), and the coordinate axis farthest from D is orthogonalised
    against it (Gram-Schmidt). For one constraint this is the direction of its normal."""
    n = len(q)
    basis: List[List[float]] = []
    for i in range(m):
        e = [0.0] * m
        e[i] = 1.0
        v = [iv.mid for iv in oracle.flow(q, e, 0.0, scene=scene, params=params).v]
        for b in basis:
            d = sum(x * y for x, y in zip(v, b))
            v = [x - d * y for x, y in zip(v, b)]
        length = math.sqrt(sum(x * x for x in v))
        if not (length > 0 and math.isfinite(length)):
            return None
        basis.append([x / length for x in v])
    best: Optional[List[float]] = None
    best_len = 0.0
    for j in range(n):
        w = [0.0] * n
        w[j] = 1.0
        for b in basis:
            d = sum(x * y for x, y in zip(w, b))
            w = [x - d * y for x, y in zip(w, b)]
        length = math.sqrt(sum(x * x for x in w))
        if length > best_len:
            best, best_len = [x / length for x in w], length
    return best if best_len > 1e-8 else None


def _pair(oracle: Oracle, scene: Scene, params: Any, m: int, q0: List[float],
          u0: List[float], h: float, distance: float, t: Optional[float] = None
          ) -> Optional[Pair]:
    try:
        if t is not None and abs(t) > h:
            oracle.flow(q0, u0, t, scene=scene, params=params)  # certified to the horizon
        flow = oracle.flow(q0, u0, h, scene=scene, params=params)
        q1 = [iv.mid for iv in flow.q]
        if distance != 0.0:
            normal = _normal(oracle, scene, params, q1, m)
            if normal is None:
                return None
            q1 = [x + distance * nx for x, nx in zip(q1, normal)]
        r = oracle.retract(q0, q1, h, scene=scene, params=params)
    except OracleError as e:
        _refused("pair", e)
        return None
    return Pair(q0=q0, u0=u0, q1=q1, h=h, defect=list(r.defect))


def _pairs(oracle: Oracle, scene: Scene, q_bound: float, u_bound: float,
           h: Tuple[float, float], distance: float, params: Optional[Mapping[str, float]],
           t: Optional[float] = None) -> st.SearchStrategy[Pair]:
    n, m = dimensions(oracle, scene, params)
    inputs = st.tuples(
        configurations(oracle, scene, q_bound, params),
        st.lists(_floats(u_bound), min_size=m, max_size=m),
        st.floats(h[0], h[1], allow_nan=False, allow_infinity=False),
    )
    return inputs.map(
        lambda d: _pair(oracle, scene, params, m, d[0], d[1], d[2], distance, t)
    ).filter(lambda p: p is not None)  # type: ignore[return-value]


def pairs_on_manifold(oracle: Oracle, scene: Scene, q_bound: float, u_bound: float,
                      h: Tuple[float, float], params: Optional[Mapping[str, float]] = None,
                      *, t: Optional[float] = None) -> st.SearchStrategy[Pair]:
    """Pairs (q0, q1) on M_h^{e,nh} up to rounding: q1 is the midpoint of the certified
    exact exponential map from (q0, u0) at h (q0 in [-q_bound, q_bound]^n, u0 in
    [-u_bound, u_bound]^m, h in the closed range `h`), with the defect the oracle's
    retraction certifies for the float pair. Starts the oracle cannot certify are rejected
    (a Hypothesis event names each cause); with `t` (the horizon of the test), also starts
    whose flow is not certified up to t."""
    return _pairs(oracle, scene, q_bound, u_bound, h, 0.0, params, t)


def pairs_near(oracle: Oracle, scene: Scene, q_bound: float, u_bound: float,
               h: Tuple[float, float], distance: float,
               params: Optional[Mapping[str, float]] = None, *, t: Optional[float] = None
               ) -> st.SearchStrategy[Pair]:
    """As `pairs_on_manifold`, with q1 then moved by `distance` along a unit vector
    orthogonal to D(q1) (the constraint normal's direction when there is one constraint):
    pairs at a chosen distance from M_h^{e,nh}. The defect is certified for the moved pair."""
    return _pairs(oracle, scene, q_bound, u_bound, h, distance, params, t)


def states(oracle: Oracle, scene: Scene, q_bound: float, u_bound: float, *, t: float,
           params: Optional[Mapping[str, float]] = None) -> st.SearchStrategy[State]:
    """Initial states `State(q, u)` (q in [-q_bound, q_bound]^n, u in [-u_bound, u_bound]^m)
    whose flow the oracle certifies up to the horizon `t` (one flow query per draw). Draws
    it cannot certify are filtered out, each a Hypothesis event `states: refused (CAUSE)`
    and the others `states: certified to t`, so that the filter rate is in Hypothesis'
    statistics (`pytest --hypothesis-show-statistics`). Shrinks toward q = 0, u = 0."""
    if not (isinstance(t, (int, float)) and math.isfinite(t)):
        raise ValueError(f"t: expected a finite horizon, got {t!r}")
    n, m = dimensions(oracle, scene, params)

    def certified(s: State) -> bool:
        try:
            oracle.flow(s.q, s.u, float(t), scene=scene, params=params)
        except Uncertified as e:
            _refused("states", e)
            return False
        event("states: certified to t")
        return True

    return st.builds(State, st.lists(_floats(q_bound), min_size=n, max_size=n),
                     st.lists(_floats(u_bound), min_size=m, max_size=m)).filter(certified)


def extreme_steps() -> st.SearchStrategy[float]:
    """The step sizes of the stability table's extremes, smallest first (shrinks toward it)."""
    return st.sampled_from([1e-8, 1e-6, 1e-3, 0.1, 0.5, 1.0, 2.0])


def large_configurations(oracle: Oracle, scene: Scene, max_exponent: int,
                         params: Optional[Mapping[str, float]] = None
                         ) -> st.SearchStrategy[List[float]]:
    """Configurations with large coordinates: each component +-10^e, e in
    0..=max_exponent, at which the scene passes its checks."""
    n, m = dimensions(oracle, scene, params)
    comp = st.tuples(st.integers(0, max_exponent), st.booleans()).map(
        lambda t: -(10.0 ** t[0]) if t[1] else 10.0 ** t[0])
    return st.lists(comp, min_size=n, max_size=n).filter(
        lambda q: _admissible(oracle, scene, params, q, m))
