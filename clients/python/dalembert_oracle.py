"""The dalembert oracle from Python: one `dalembert batch` process, queries as method calls.

Standard library only (CPython 3.9+). Import it by putting this directory on the path::

    import sys; sys.path.insert(0, "path/to/dalembert/clients/python")   # or PYTHONPATH
    from dalembert_oracle import Oracle, distance, observed_order

    with Oracle() as o:                     # binary: argument, $DALEMBERT, or `dalembert` on PATH
        s = o.step([0, 0, 0], [0.4, 0.4, 0.08], 0.5, scene="particle")
        print(s.q2[0], s.q2[0].lo, s.q2[0].hi)      # Interval(lo, hi), endpoints as printed

Soundness. Every bound the binary prints reaches the caller unchanged: JSON numbers are read
by Python's `json` (correctly rounded, so each endpoint is the f64 the binary printed) and
kept as they are in `Interval(lo, hi)`; nothing here rounds, re-computes or re-centres them.
The few bounds this module computes itself (`distance`, `quotient`, `observed_order`) round
outwards; their docstrings say how. `Interval.mid` is a point, not a bound.

Errors. An answer with an error raises `InputError` (code 2: invalid input) or `Uncertified`
(code 3: not certified, including past the time budget); both are `OracleError`s with
`code`, `message` and `id`. The session goes on after either. A broken session (the process
ended, an answer out of order or not JSON) raises `ProtocolError`.

The answers are `Answer`s: dicts that also allow attribute access (`a.q2` is `a["q2"]`), with
each interval of the command's answer (spec/contract.md) turned into an `Interval`; other
values (`member`, `passed`, `stats`, `integrate`'s float rows) are as the JSON gives them.
"""

import json
import math
import os
import shutil
import subprocess
import threading
from fractions import Fraction

__all__ = [
    "Oracle", "Interval", "Answer", "OracleError", "InputError", "Uncertified",
    "ProtocolError", "distance", "quotient", "observed_order", "down", "up", "find_binary",
]


class Interval:
    """A closed interval [lo, hi] as the oracle printed it: `lo` and `hi` are the JSON
    numbers, unchanged (never rounded, never recomputed). The exact value lies in it."""

    __slots__ = ("lo", "hi")

    def __init__(self, lo, hi):
        if not lo <= hi:
            raise ValueError(f"not an interval: [{lo!r}, {hi!r}]")
        self.lo, self.hi = lo, hi

    def __contains__(self, x):
        """Exact comparison: x may be an int, float, Fraction or Decimal."""
        return self.lo <= x <= self.hi

    def contains(self, x):
        return x in self

    def excludes_zero(self):
        return self.lo > 0 or self.hi < 0

    def width_up(self):
        """An upper bound on hi - lo (the float difference rounded up by one ulp)."""
        return up(self.hi - self.lo)

    @property
    def mid(self):
        """A float point inside the interval (round to nearest): a point, not a bound."""
        m = self.lo / 2 + self.hi / 2
        return min(max(m, self.lo), self.hi)

    def __iter__(self):
        return iter((self.lo, self.hi))

    def __eq__(self, other):
        return isinstance(other, Interval) and (self.lo, self.hi) == (other.lo, other.hi)

    def __hash__(self):
        return hash((self.lo, self.hi))

    def __repr__(self):
        return f"Interval({self.lo!r}, {self.hi!r})"


class Answer(dict):
    """An `ok` answer: a dict whose keys are also attributes."""

    def __getattr__(self, key):
        try:
            return self[key]
        except KeyError:
            raise AttributeError(key) from None


class OracleError(Exception):
    """An error answer: `code` (2 or 3), `message` (the binary's text), `id`; for code 3 also
    `reason` ("budget", "no_proof", "unbounded", "undefined" or "internal") and `reached`
    (the time a flow had been proved up to, or None): contract E10."""

    def __init__(self, code, message, id=None, reason=None, reached=None):
        super().__init__(f"code {code}: {message}")
        self.code, self.message, self.id = code, message, id
        self.reason, self.reached = reason, reached


class InputError(OracleError):
    """Code 2: invalid input (unknown scene or key, wrong dimension, non-finite number, ...)."""


class Uncertified(OracleError):
    """Code 3: the oracle could not certify (or ran past the query's time budget)."""

    @property
    def past_budget(self):
        """A budget was spent (the deadline, or more steps than allowed): more may answer."""
        return self.reason == "budget"


class ProtocolError(RuntimeError):
    """The session is broken: the process ended, or an answer is out of order or not JSON."""


# Nesting depth of the intervals in each command's answer: 0 = I, 1 = [I], 2 = [[I]].
_SHAPES = {
    "flow": {"q": 1, "u": 1, "v": 1, "jacobian": 2},
    "retract": {"u0": 1, "v0": 1, "v1": 1, "defect": 1, "q1": 1},
    "step": {"q1": 1, "q2": 1, "p_minus": 1, "p_plus": 1},
    "lagrangian": {"l": 0, "defect": 1},
    "check": {"distance": 1, "max_distance": 0, "defect": 2, "energy_error": 1,
              "max_defect": 0},
    "integrate": {},
}


def _intervals(value, depth):
    if depth == 0:
        if not (isinstance(value, list) and len(value) == 2):
            raise ProtocolError(f"expected an interval [lo, hi], got {value!r}")
        return Interval(value[0], value[1])
    return [_intervals(v, depth - 1) for v in value]


def _answer(cmd, ok):
    shape = _SHAPES.get(cmd, {})
    a = {k: _intervals(v, shape[k]) if k in shape else v for k, v in ok.items()}
    if cmd == "flow" and "at" in a:
        # dense output: one answer per stop, with keys t, q, u, v
        a["at"] = [_answer("flow", stop) for stop in a["at"]]
    return Answer(a)


def _error(err, id):
    code, message = err.get("code"), err.get("message", "")
    cls = {2: InputError, 3: Uncertified}.get(code, OracleError)
    return cls(code, message, id, err.get("reason"), err.get("reached"))


def find_binary(binary=None):
    """The binary: `binary` if given, else $DALEMBERT, else `dalembert` on PATH."""
    exe = binary or os.environ.get("DALEMBERT") or shutil.which("dalembert")
    if not exe:
        raise FileNotFoundError("no dalembert binary: pass binary=, set $DALEMBERT or PATH")
    return exe


class Oracle:
    """One `dalembert batch` process, kept for the life of the object (use `with`, or call
    `close()`). Each method sends one query line and reads one answer line, whose `id` must
    be the one sent. `scene` and `params` given here are the defaults of every query; a
    scene is a built-in name or a dict with the keys of a scene file (an inline scene)."""

    def __init__(self, binary=None, scene=None, params=None, deadline=None, jobs=None):
        args = [find_binary(binary), "batch"]
        if jobs is not None:
            args += ["--jobs", str(int(jobs))]
        if deadline is not None:
            args += ["--deadline", repr(float(deadline))]
        self.scene, self.params = scene, params
        self._p = subprocess.Popen(args, stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                                   text=True, encoding="utf-8")
        self._next = 0
        self.queries = 0

    # -- the queries -------------------------------------------------------------------
    def flow(self, q, u, t=None, *, times=None, order=None, jacobian=None, **common):
        """Exact state at time t from q with quasi-velocities u: keys q, u, v (, jacobian);
        with times=[t1, t2, ..] instead of t, key at (one answer per time: t, q, u, v)."""
        return self.ask(self.query("flow", q=q, u=u, t=t, times=times, order=order,
                                   jacobian=jacobian, **common))

    def retract(self, q0, q1, h, **common):
        """(q0, q1) onto M_h^{e,nh}: keys u0, v0, v1, defect, member, q1."""
        return self.ask(self.query("retract", q0=q0, q1=q1, h=h, **common))

    def step(self, q0, q1, h, **common):
        """The exact discrete flow: keys q1 (the point of M_h^{e,nh}), q2, p_minus, p_plus."""
        return self.ask(self.query("step", q0=q0, q1=q1, h=h, **common))

    def lagrangian(self, q0, q1, h, **common):
        """The exact discrete Lagrangian: keys l, defect."""
        return self.ask(self.query("lagrangian", q0=q0, q1=q1, h=h, **common))

    def integrate(self, q0, q1, h, steps, scheme="dla", **common):
        """The built-in scheme's float trajectory: key q (rows of floats), p, energy, ..."""
        return self.ask(self.query("integrate", q0=q0, q1=q1, h=h, steps=steps,
                                   scheme=scheme, **common))

    def check(self, q, h=None, *, t=None, tol=None, defect_tol=None, pairs=None, **common):
        """Certified verdict on a trajectory q (rows) of step h, or at times t (one per
        row): keys distance, max_distance, defect, max_defect, energy_error, passed (False
        when the distance is proved beyond tol or a pair's defect beyond defect_tol)."""
        return self.ask(self.query("check", q=q, h=h, t=t, tol=tol, defect_tol=defect_tol,
                                   pairs=pairs, **common))

    # -- the protocol ------------------------------------------------------------------
    def query(self, cmd, *, scene=None, params=None, deadline=None, **keys):
        """The query object (a dict) for `cmd`; None values are left out."""
        q = {"cmd": cmd, "scene": scene if scene is not None else self.scene}
        q["params"] = params if params is not None else self.params
        q["deadline"] = deadline
        q.update(keys)
        return {k: v for k, v in q.items() if v is not None}

    def ask(self, query):
        """Send one query (a dict without `id`), return its `Answer` or raise."""
        return self._result(self._exchange([dict(query)])[0])

    def ask_line(self, line):
        """Send one raw line as it is (tests, hand-written queries); its answer's id must be
        the line's own `id`, or null when the line has none or is not a JSON object."""
        if "\n" in line or not line.strip():
            raise ValueError("one non-blank line, without a newline")
        try:
            obj = json.loads(line)
        except ValueError:
            obj = None
        obj = obj if isinstance(obj, dict) else {}
        self.queries += 1
        self._write([line])
        return self._result((self._read(), obj.get("id"), obj.get("cmd")))

    def run(self, queries):
        """Many queries at once (pipelined: written by a thread while answers are read).
        Returns one item per query, in order: its `Answer` or the `OracleError` (not raised)."""
        out = []
        for item in self._exchange([dict(q) for q in queries]):
            try:
                out.append(self._result(item))
            except OracleError as e:
                out.append(e)
        return out

    def _exchange(self, queries):
        lines = []
        for q in queries:
            self._next += 1
            q["id"] = self._next
            try:
                lines.append(json.dumps(q, allow_nan=False))
            except ValueError as e:  # NaN or infinity: invalid input, as the contract says
                raise InputError(2, f"non-finite number in the query: {e}", self._next)
        self.queries += len(lines)
        if len(lines) == 1:
            self._write(lines)
            return [(self._read(), queries[0]["id"], queries[0]["cmd"])]
        writer = threading.Thread(target=self._write, args=(lines,), daemon=True)
        writer.start()
        answers = [(self._read(), q["id"], q["cmd"]) for q in queries]
        writer.join()
        return answers

    def _write(self, lines):
        try:
            self._p.stdin.write("".join(line + "\n" for line in lines))
            self._p.stdin.flush()
        except (BrokenPipeError, ValueError) as e:
            raise ProtocolError(f"the batch process is gone: {e}") from None

    def _read(self):
        line = self._p.stdout.readline()
        if not line:
            raise ProtocolError(f"the batch process ended (exit {self._p.poll()})")
        try:
            return json.loads(line)
        except ValueError:
            raise ProtocolError(f"an answer that is not JSON: {line!r}") from None

    @staticmethod
    def _result(item):
        answer, want, cmd = item
        if not isinstance(answer, dict) or answer.get("id", ...) != want:
            raise ProtocolError(f"answer {answer!r} is not the answer to id {want!r}")
        if "error" in answer:
            raise _error(answer["error"], want)
        if "ok" not in answer:
            raise ProtocolError(f"an answer without ok or error: {answer!r}")
        return _answer(cmd, answer["ok"])

    def close(self):
        """End the input; wait for the process; its exit status (0 when all went well)."""
        if self._p.stdin and not self._p.stdin.closed:
            try:
                self._p.stdin.close()
            except BrokenPipeError:
                pass
        status = self._p.wait()
        self._p.stdout.close()
        return status

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()


# -- certified arithmetic on the Python side ---------------------------------------------
#
# Python floats round to nearest: the result r of one +, -, *, / or abs of floats is the
# exact result rounded to the nearest f64, so the exact result lies between the floats next
# to r. `down(r)` and `up(r)` step one ulp outwards (math.nextafter, Python 3.9+), which turns
# each operation's rounded result into a certified bound.


def down(x):
    """The float below x (a lower bound on the exact result of the operation that gave x)."""
    return math.nextafter(x, -math.inf)


def up(x):
    """The float above x (an upper bound on the exact result of the operation that gave x)."""
    return math.nextafter(x, math.inf)


def _box(b):
    return b if isinstance(b, Interval) else Interval(b[0], b[1])


def distance(x, box):
    """Certified enclosure of |x - b|_inf for every b in the box (spec chapter 8,
    `distance`): an `Interval` with lo <= min over the box and hi >= max over the box.
    `x` is a sequence of floats, `box` a sequence of `Interval`s (or [lo, hi] pairs).
    Each subtraction is done in float and its result moved one ulp outwards with
    math.nextafter (`down`/`up`), since Python rounds to nearest; abs and max are exact."""
    lo = hi = 0.0
    for xi, b in _zip_same(x, box):
        b = _box(b)
        far = max(up(xi - b.lo), up(b.hi - xi))
        if xi < b.lo:
            near = down(b.lo - xi)
        elif xi > b.hi:
            near = down(xi - b.hi)
        else:
            near = 0.0
        lo, hi = max(lo, near, 0.0), max(hi, far)
    return Interval(lo, hi)


def _zip_same(a, b):
    a, b = list(a), list(b)
    if len(a) != len(b):
        raise ValueError(f"dimensions differ: {len(a)} and {len(b)}")
    return zip(a, b)


def quotient(a, b):
    """Certified a / b for intervals of positive numbers (b.lo > 0, a.lo >= 0): each
    endpoint divided in float and moved one ulp outwards (math.nextafter)."""
    a, b = _box(a), _box(b)
    if not (a.lo >= 0 and b.lo > 0):
        raise ValueError(f"quotient needs a >= 0 and b > 0: {a}, {b}")
    return Interval(max(0.0, down(a.lo / b.hi)), up(a.hi / b.lo))


# Observed order: a logarithm is not one rounded operation (math.log's error is not
# specified), so it is bounded here in exact rational arithmetic (fractions.Fraction) and
# the final bounds are rounded outwards to floats exactly.

def _ln_bounds(x):
    """Rationals lo <= ln(x) <= hi for a rational x > 0 (error below 2^-100)."""
    x = Fraction(x)
    if x <= 0:
        raise ValueError("ln of a non-positive number")
    k = x.numerator.bit_length() - x.denominator.bit_length()
    m = x / Fraction(2) ** k  # m in (1/2, 2)
    lo_m, hi_m = _atanh_series(m)
    lo_2, hi_2 = _LN2
    if k >= 0:
        return lo_m + k * lo_2, hi_m + k * hi_2
    return lo_m + k * hi_2, hi_m + k * lo_2


def _atanh_series(m):
    """ln m = 2 atanh(t), t = (m - 1) / (m + 1), |t| <= 1/3: partial sum and tail bound."""
    t = (m - 1) / (m + 1)
    t2, term, s = t * t, t, Fraction(0)
    for j in range(40):  # |t|^(2j+1) <= 3^-81 at the end
        s += term / (2 * j + 1)
        term *= t2
    tail = 2 * abs(term) / (81 * (1 - t2))  # sum of the remaining terms, bounded
    return 2 * s - tail, 2 * s + tail


_LN2 = _atanh_series(Fraction(2))


def _float_down(r):
    f = float(r)  # Fraction -> float is correctly rounded
    return down(f) if Fraction(f) > r else f


def _float_up(r):
    f = float(r)
    return up(f) if Fraction(f) < r else f


def observed_order(e_a, e_b, h_a, h_b):
    """Certified enclosure of log(e_a / e_b) / log(h_a / h_b) for the errors e_a at step
    h_a and e_b at h_b (intervals of positive numbers, h floats taken as exact): every
    order p with e_a / e_b = (h_a / h_b)^p for some e_a, e_b in the intervals lies in it.
    Logarithms are bounded in exact rational arithmetic, the result rounded outwards."""
    e_a, e_b = _box(e_a), _box(e_b)
    if not (e_a.lo > 0 and e_b.lo > 0):
        raise ValueError(f"no order: an error interval reaches 0 ({e_a}, {e_b})")
    if h_a == h_b or h_a <= 0 or h_b <= 0:
        raise ValueError("observed_order needs two different positive steps")
    num_lo = _ln_bounds(Fraction(e_a.lo) / Fraction(e_b.hi))[0]
    num_hi = _ln_bounds(Fraction(e_a.hi) / Fraction(e_b.lo))[1]
    den_lo, den_hi = _ln_bounds(Fraction(h_a) / Fraction(h_b))
    if den_lo <= 0 <= den_hi:
        raise ValueError("observed_order: log(h_a / h_b) not proved non-zero")
    qs = [n / d for n in (num_lo, num_hi) for d in (den_lo, den_hi)]
    return Interval(_float_down(min(qs)), _float_up(max(qs)))
