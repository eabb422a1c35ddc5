"""dalembert from Python: certified enclosures of exact discrete nonholonomic mechanics.

    import dalembert
    with dalembert.Oracle(scene="knife") as o:
        a = o.flow([0, 0, 0], [1, 0.5], 2.0)
        print(a.q[0], a.q[0].lo, a.q[0].hi)     # Interval(lo, hi): the exact value lies in it
        a.array("q")                           # (n, 2) float64 [lo, hi] (numpy installed)

`Oracle` keeps one `dalembert batch` process (the binary installed with this package; see
`find_binary`); `dalembert.strategies` has Hypothesis strategies of admissible inputs,
`dalembert.campaign` runs many queries on Dask. docs/python.md of the repository is the
guide.
"""

from ._intervals import (
    Exact, Interval, IntervalLike, distance, down, intervals, observed_order, quotient,
    to_array, up,
)
from ._oracle import (
    CAUSES, Answer, InputError, Oracle, OracleError, Pending, ProtocolError, SceneLike,
    Uncertified, Vector, find_binary,
)
from ._scene import Scene
from ._grade import Grade, WorkPrecision, WorkPrecisionRow, grade, work_precision

__all__ = [
    "Oracle", "Answer", "Pending", "Interval", "IntervalLike", "Scene", "SceneLike", "Vector",
    "CAUSES", "grade", "Grade", "work_precision", "WorkPrecision", "WorkPrecisionRow",
    "OracleError", "InputError", "Uncertified", "ProtocolError", "find_binary",
    "Exact", "distance", "quotient", "observed_order", "down", "up", "to_array", "intervals",
]

__version__ = "0.1.0"
