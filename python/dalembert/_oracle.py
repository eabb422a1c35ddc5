"""One long-lived `dalembert batch` process per session, its queries as typed method calls.

Errors. An answer with an error raises `InputError` (code 2: invalid input) or `Uncertified`
(code 3: not certified, including past the budget, `reason == "budget"`); both are
`OracleError`s with `code`, `message`, `id`, `reason`, `cause` and `reached`, and an
`Uncertified` also has `at` (the stops of a `times` flow certified before the refusal). The
session goes on after either. A broken session (the process ended, an answer out of order or
not JSON) raises `ProtocolError`.

Answers are `Answer`s: dicts that also allow attribute access (`a.q2` is `a["q2"]`), with
each interval of the command's answer (spec/contract.md) turned into an `Interval`; other
values (`member`, `passed`, `stats`, `integrate`'s float rows) are as the JSON gives them.
`Answer.array(key)` gives the intervals of a key as a float64 numpy array of [lo, hi].

Throughput. Every query is buffered as soon as it is made and written to the process only
when an answer is needed (or the buffer is full); while a write waits for room in the pipe,
the process's answers are read into memory, so many queries in flight never block either
side: `Oracle.run(list)` and `Oracle.submit(...)` (one query at a time, answers collected
later with `.result()`) both pipeline; the plain methods (`step`, `flow`, ...) wait for their
answer. All of this runs in the calling thread (non-blocking writes and `select.poll`), so
an answer costs no hand-over between threads; where `select.poll` is missing (Windows) a
reader thread drains the output instead.
"""

from __future__ import annotations

import gc
import json
import os
import queue
import re
import select
import shutil
import subprocess
import sys
import sysconfig
import threading
from collections import deque
from typing import (
    Any, Deque, Dict, Iterable, Iterator, List, Mapping, Optional, Sequence, Union,
)

from ._intervals import Exact, Interval, to_array

__all__ = [
    "Oracle", "Answer", "Pending", "OracleError", "InputError", "Uncertified",
    "ProtocolError", "find_binary", "SceneLike", "Vector", "CAUSES",
]

Vector = Sequence[float]
#: A scene: a built-in name ("particle", "knife", ...) or a dict with the keys of a scene
#: file (spec chapter 10; a `dalembert.Scene` among them), sent inline in each query.
SceneLike = Union[str, Mapping[str, Any]]


class Answer(Mapping[str, Any]):
    """An `ok` answer: a read-only mapping whose keys are also attributes (`a.q2` is
    `a["q2"]`), each key's intervals made when the key is first read.

    An answer whose `ok` object is flat (no object inside it: step, retract, lagrangian,
    integrate; not flow, whose `stats` is an object) is kept as its line of text until a key
    is read, and then only that key's value is parsed: the key is found as the text
    `"key":`, which in a flat object can only be one of its own keys (a quote inside a JSON
    string is escaped). So an answer not yet read holds one string, not a tree of lists for
    the cyclic garbage collector to rescan, and one read costs what that key costs. A
    damaged answer body (which a working binary never prints) is a `ProtocolError` raised
    when the damaged key, or the whole answer (iteration, `len`), is read."""

    __slots__ = ("_raw", "_shape", "_done", "_text", "_at")

    def __init__(self, raw: Optional[Dict[str, Any]], shape: Optional[_Shape] = None,
                 text: Optional[str] = None, at: int = 0) -> None:
        self._raw = raw  # the parsed `ok` object; None while only the text is kept
        self._shape = shape or {}
        self._done: Dict[str, Any] = {}
        self._text = text  # the answer line, its flat `ok` object from index `at`
        self._at = at

    def _whole(self) -> Dict[str, Any]:
        """The parsed `ok` object (parsed now if only the text was kept)."""
        raw = self._raw
        if raw is None:
            text = self._text
            assert text is not None
            try:
                raw, end = _SCAN(text, self._at)
                if end != len(text) - 1 or type(raw) is not dict:
                    raise ValueError
            except (ValueError, StopIteration):
                raise ProtocolError(f"an answer that is not JSON: {text!r}") from None
            self._raw, self._text = raw, None
        return raw

    def _value(self, key: str) -> Any:
        """The parsed value of `key` (KeyError when absent)."""
        text = self._text
        if text is None or type(key) is not str or '"' in key or "\\" in key:
            return self._whole()[key]
        i = text.find('"' + key + '":', self._at)
        if i < 0:
            return self._whole()[key]  # absent (or a key written with escapes)
        try:
            v, end = _SCAN(text, i + len(key) + 3)
            if text[end] not in ",}":
                raise ValueError
        except (ValueError, StopIteration, IndexError):
            raise ProtocolError(f"an answer that is not JSON: {text!r}") from None
        return v

    def __getitem__(self, key: str) -> Any:
        done = self._done
        if key in done:
            return done[key]
        v = self._value(key)
        s = self._shape.get(key)
        if type(s) is int:
            v = _intervals(v, s)
        elif s is not None and type(v) is dict:
            v = Answer(v, s)
        done[key] = v
        return v

    def __getattr__(self, key: str) -> Any:
        if key[:1] == "_":
            raise AttributeError(key)
        try:
            return self[key]
        except KeyError:
            raise AttributeError(key) from None

    def __iter__(self) -> Iterator[str]:
        return iter(self._whole())

    def __len__(self) -> int:
        return len(self._whole())

    def __repr__(self) -> str:
        return f"Answer({dict(self.items())!r})"

    def array(self, key: str) -> Any:
        """The intervals under `key` as a float64 numpy array, last axis [lo, hi] (`(n, 2)`
        for a vector): float ends copied exactly, decimal ends rounded outward. Needs
        numpy."""
        return to_array(self[key])


#: The documented refusal causes (`OracleError.cause`; spec/contract.md, the `cause` key).
CAUSES = frozenset({"mass", "basis", "domain", "width", "steps", "work", "deadline", "proof",
                    "unbounded", "internal"})


class OracleError(Exception):
    """An error answer: `code` (2 or 3), `message` (the binary's text), `id`; for code 3 also
    `reason` ("budget", "no_proof", "unbounded", "undefined" or "internal"), `reached` (the
    time a flow had been proved up to, or None): contract E10; and `cause`, the one cause of
    the refusal, one of `CAUSES`: "mass" (the mass matrix not proved positive definite),
    "basis" (the derived basis singular), "domain" (an expression of the scene outside its
    domain), "width" (the enclosure grew too wide before any scene data failed: a higher
    `precision` may answer), "steps" (the step limit, `max_steps`), "work" (the work
    budget), "deadline", "proof" (a proof failed), "unbounded", "internal"; None for code 2
    or from a binary that does not name it."""

    def __init__(self, code: Optional[int], message: str, id: Any = None,
                 reason: Optional[str] = None, reached: Optional[float] = None,
                 cause: Optional[str] = None) -> None:
        super().__init__(f"code {code}: {message}")
        self.code, self.message, self.id = code, message, id
        self.reason, self.reached, self.cause = reason, reached, cause


class InputError(OracleError):
    """Code 2: invalid input (unknown scene or key, wrong dimension, non-finite number, ...)."""


class Uncertified(OracleError):
    """Code 3: the oracle could not certify (or ran past the query's budget). `at`: for a
    flow with `times`, the stops certified before the refusal (each an `Answer` with t, q,
    u, v, as in a whole answer's `at`); empty otherwise."""

    def __init__(self, *args: Any, **kw: Any) -> None:
        super().__init__(*args, **kw)
        self.at: List[Answer] = []

    @property
    def past_budget(self) -> bool:
        """A budget was spent (the work or the deadline, or more steps than allowed): a
        larger budget may answer."""
        return self.reason == "budget"


class ProtocolError(RuntimeError):
    """The session is broken: the process ended, or an answer is out of order or not JSON."""


# Where the intervals are in each command's answer: an int is a nesting depth (0 = I,
# 1 = [I], 2 = [[I]]; a null in a list stays None), a dict the shape of a nested object.
_Shape = Dict[str, Any]
_LADDER: _Shape = {"error": 1, "order": 1}
_SHAPES: Dict[str, _Shape] = {
    "flow": {"q": 1, "u": 1, "v": 1, "jacobian": 2},
    "retract": {"u0": 1, "v0": 1, "v1": 1, "defect": 1, "q1": 1},
    "step": {"q1": 1, "q2": 1, "p_minus": 1, "p_plus": 1},
    "lagrangian": {"l": 0, "defect": 1},
    "check": {"distance": 1, "max_distance": 0, "defect": 2, "energy_error": 1,
              "max_defect": 0},
    "order": {"local": _LADDER, "global": {"ladder": _LADDER}},
    "integrate": {},
}


# Answers are read by the JSON scanner called directly (`scan_once`, without `decode`'s
# checks for white space around the value), which gives what `json.loads` gives (floats
# correctly rounded, so each end is the f64 the binary printed); a line it does not read
# whole is handed to `_DECODE`, which gives the same value or the same error.
_DECODE = json.JSONDecoder().decode
_SCAN: Any = getattr(json.JSONDecoder(), "scan_once")
# An interval end printed as a decimal string (contract E18: answers computed with more than
# 53 bits), read as the exact `Exact` (a Decimal that mixes with floats) it writes.
_DECIMAL_END = re.compile(r"-?[0-9]+(\.[0-9]+)?(e-?[0-9]+)?")


def _end(x: Any) -> Any:
    """An interval end as the client keeps it: a JSON number as it is, a decimal string as
    its exact `Exact` (a Decimal); TypeError otherwise."""
    t = type(x)
    if t is float or t is int:
        return x
    if t is str and _DECIMAL_END.fullmatch(x):
        return Exact(x)
    raise TypeError(x)


def _pairs(value: List[Any]) -> List[Interval]:
    """`Interval`s from the [lo, hi] pairs of an answer; ValueError or TypeError when one is
    not an interval."""
    new = tuple.__new__
    # (the common case, float ends, in one comprehension; anything else below)
    out = [new(Interval, p) for p in value if type(p) is list and len(p) == 2
           and type(p[0]) is float and type(p[1]) is float and p[0] <= p[1]]
    if len(out) == len(value):
        return out
    out = []
    for p in value:
        if type(p) is not list or len(p) != 2:
            raise ValueError(p)
        lo, hi = _end(p[0]), _end(p[1])
        if not lo <= hi:
            raise ValueError(p)
        out.append(new(Interval, (lo, hi)))
    return out


def _intervals(value: Any, depth: int) -> Any:
    if value is None:
        return None
    try:
        if depth == 0:
            return _pairs([value])[0]
        if type(value) is not list:
            raise TypeError(value)
        if depth == 1 and None not in value:
            return _pairs(value)
    except (ValueError, TypeError):
        raise ProtocolError(f"expected intervals [lo, hi], got {value!r}") from None
    return [_intervals(v, depth - 1) for v in value]


def _answer(cmd: str, ok: Dict[str, Any]) -> Answer:
    if cmd == "flow" and "at" in ok:
        # dense output: one answer per stop, with keys t, q, u, v
        ok = {**ok, "at": [_answer("flow", stop) for stop in ok["at"]]}
    return Answer(ok, _SHAPES.get(cmd, {}))


def _error(err: Dict[str, Any], id: Any) -> OracleError:
    code, message = err.get("code"), err.get("message", "")
    cls: Any = {2: InputError, 3: Uncertified}.get(code, OracleError) \
        if isinstance(code, int) else OracleError
    e: OracleError = cls(code, message, id, err.get("reason"), err.get("reached"), err.get("cause"))
    stops = err.get("at")
    if isinstance(e, Uncertified) and isinstance(stops, list):
        e.at = [_answer("flow", stop) for stop in stops if isinstance(stop, dict)]
    return e


def _script_dirs() -> List[str]:
    dirs = [sysconfig.get_path("scripts")]
    try:
        dirs.append(sysconfig.get_path("scripts", f"{os.name}_user"))
    except KeyError:
        pass
    return [d for d in dirs if d]


def find_binary(binary: Optional[str] = None) -> str:
    """The `dalembert` binary: `binary` if given; else the one installed with this package
    (next to the interpreter's scripts: sysconfig's "scripts" path, or the user scheme's);
    else $DALEMBERT; else `dalembert` on PATH."""
    if binary:
        return binary
    exe = "dalembert.exe" if sys.platform == "win32" else "dalembert"
    for d in _script_dirs():
        p = os.path.join(d, exe)
        if os.path.isfile(p) and os.access(p, os.X_OK):
            return p
    found = os.environ.get("DALEMBERT") or shutil.which("dalembert")
    if not found:
        raise FileNotFoundError(
            "no dalembert binary: install this package with pip (it ships the binary), "
            "pass binary=, set $DALEMBERT or put `dalembert` on PATH")
    return found


class Pending:
    """A query sent and not yet answered (`Oracle.submit`): `result()` waits for its answer
    and returns the `Answer` or raises the `OracleError`."""

    __slots__ = ("_oracle", "id", "cmd", "_done", "_value")

    def __init__(self, oracle: "Oracle", id: Any, cmd: Optional[str]) -> None:
        self._oracle, self.id, self.cmd = oracle, id, cmd
        self._done = False
        self._value: Any = None

    def done(self) -> bool:
        return self._done

    def result(self) -> Answer:
        if not self._done:
            self._oracle._wait(self)
        if isinstance(self._value, BaseException):
            raise self._value
        return self._value  # type: ignore[no-any-return]

    def outcome(self) -> Union[Answer, OracleError]:
        """The `Answer`, or the `OracleError` returned (not raised)."""
        try:
            return self.result()
        except OracleError as e:
            return e


_FLUSH_BYTES = 1 << 16
_READ_BYTES = 1 << 16
_ENCODE = json.JSONEncoder(allow_nan=False, separators=(",", ":")).encode


def _numpy_default(value: Any) -> Any:
    """For `json`: a numpy array or scalar (anywhere in a query) as its list or number."""
    if hasattr(value, "tolist") and hasattr(value, "shape"):
        return value.tolist()
    raise TypeError(f"Object of type {type(value).__name__} is not JSON serializable")


# (the whole-query encoder of the slow path: numpy values nested in lists or dicts too)
_ENCODE_ANY = json.JSONEncoder(allow_nan=False, separators=(",", ":"),
                               default=_numpy_default).encode
# Whether the calling thread does all the pipe I/O itself (non-blocking writes, poll); a
# module-level switch so that the tests also run the reader-thread way used without poll.
_POLL = hasattr(select, "poll") and hasattr(os, "set_blocking")


# Each query is one line of JSON. Its floats are written with 17 significant digits
# ('%.17g'), which read back as the identical f64 (the contract reads each decimal as its
# nearest f64) and cost a third less than `repr`'s shortest form. The line is made by one
# %-format of a template kept per form of query (its keys, string values and vector
# lengths), instead of an encoder call per query; any other value (ints, bools, nested
# lists, inline scenes, numpy scalars) is a slot filled with its JSON from `json`, and a
# query with a key that is not a string, or a float that is not finite, is encoded by
# `json` whole (so NaN and infinity are refused as before). Keys that hold integers
# (`steps`, `order`, ...) keep floats in `repr` form, so that 4.0 stays a float there.
_FLOAT_SLOT = "%.17g"
_INT_KEYS = frozenset({"steps", "order", "rungs", "work", "precision", "max_steps"})
_TEMPLATES: Dict[Any, str] = {}
_is_integer = float.is_integer
# The kind of a slot for JSON text: an object of its own (True would equal the length 1 of
# a vector in the template's key).
_JSON_SLOT = object()


def _template(sig: Any) -> str:
    parts = ['{"id":%d']
    for i in range(0, len(sig), 2):
        key, kind = sig[i], sig[i + 1]
        if type(key) is not str:
            raise TypeError(key)
        head = "," + _ENCODE(key).replace("%", "%%") + ":"
        if kind is None:  # a float
            parts.append(head + _FLOAT_SLOT)
        elif kind is _JSON_SLOT:
            parts.append(head + "%s")
        elif type(kind) is int:  # a vector of `kind` floats
            parts.append(head + "[" + ",".join([_FLOAT_SLOT] * kind) + "]")
        else:  # a string, written into the template
            parts.append(head + _ENCODE(kind).replace("%", "%%"))
    parts.append("}")
    return "".join(parts)


def _line(query: Mapping[str, Any], id: int) -> bytes:
    """The JSON line of `query` with `"id": id` (any `id` key of the query replaced)."""
    if "id" in query:
        query = {k: v for k, v in query.items() if k != "id"}
    sig: List[Any] = []
    args: List[Any] = [id]
    try:
        for k, v in query.items():
            t = type(v)
            if t is float and k not in _INT_KEYS:
                sig += (k, None)
                args.append(v)
            elif t is list or t is tuple:
                try:  # float.is_integer takes floats only: a TypeError is a non-float
                    any(map(_is_integer, v))
                    sig += (k, len(v))
                    args += v
                except TypeError:
                    sig += (k, _JSON_SLOT)
                    args.append(_ENCODE(v))
            elif t is str:
                sig += (k, v)
            else:
                sig += (k, _JSON_SLOT)
                args.append(_ENCODE(v))
        key = tuple(sig)
        template = _TEMPLATES.get(key)
        if template is None:
            if len(_TEMPLATES) >= 1024:
                _TEMPLATES.clear()
            template = _TEMPLATES[key] = _template(key)
        text = template % tuple(args)
        if "inf" not in text and "nan" not in text:
            return text.encode()
    except (TypeError, ValueError):  # a key json turns into a string, or refuses
        pass
    q = dict(query)
    q["id"] = id
    try:
        return _ENCODE_ANY(q).encode()
    except ValueError as e:  # NaN or infinity: invalid input, as the contract says
        raise InputError(2, f"non-finite number in the query: {e}", id) from None


# The keys whose value is a vector (a 1-D array) or a matrix (rows; 2-D), for numpy input.
_VECTOR_KEYS = frozenset({"q", "u", "q0", "q1", "times", "t"})
_MATRIX_KEYS = frozenset({"q"})  # (for `check`, whose q is a trajectory: rows)


def _count(key: str, value: Any) -> int:
    """An integer >= 1 (a step limit, a work budget); ValueError naming `key` otherwise."""
    if isinstance(value, bool) or not float(value).is_integer() or value < 1:
        raise ValueError(f"{key}: expected an integer >= 1, got {value!r}")
    return int(value)


def _plain(key: str, value: Any, cmd: str = "") -> Any:
    """`value` with numpy arrays and scalars made lists and numbers (JSON's), the shape of
    an array checked against `key`: a vector key takes a 1-D array, `check`'s `q` a 2-D
    one (ValueError naming the key and the shape otherwise). Any other value is returned
    as it is."""
    t = type(value)
    if t is float or t is int or t is str or t is list or t is bool or value is None:
        return value
    shape = getattr(value, "shape", None)
    if shape is not None and hasattr(value, "tolist"):  # a numpy array or scalar
        want = 2 if (cmd == "check" and key in _MATRIX_KEYS) else (
            1 if key in _VECTOR_KEYS and not (key == "t" and len(shape) == 0) else None)
        if want is not None and len(shape) != want:
            what = "a vector (a 1-D array)" if want == 1 else "rows (a 2-D array)"
            raise ValueError(f"{key}: expected {what}, got an array of shape {tuple(shape)}")
        return value.tolist()
    if t is tuple:
        return [_plain(key, v) for v in value]
    if isinstance(value, Mapping) and t is not dict:
        return dict(value)
    return value


def _parse(line: Union[str, bytes], id: Any, cmd: Optional[str]
           ) -> Union[Answer, BaseException]:
    """The answer line to the query with `id` and `cmd`: its `Answer`, the `OracleError` of
    an error answer, or a `ProtocolError` (returned, not raised)."""
    if type(line) is str and type(id) is int and line[-2:] == "}}":
        # An `ok` answer to this id whose `ok` object is flat: kept as its text.
        head = '{"id":%d,"ok":{' % id
        if line.startswith(head) and line.find("{", len(head)) < 0:
            return Answer(None, _SHAPES.get(cmd or "", {}), line, len(head) - 1)
    try:
        text = line.decode() if isinstance(line, bytes) else line
        try:
            answer, end = _SCAN(text, 0)
            if end != len(text):
                raise ValueError
        except (ValueError, StopIteration):
            answer = _DECODE(text)
    except ValueError:  # UnicodeDecodeError and JSONDecodeError among them
        raw = line.encode() if isinstance(line, str) else line
        return ProtocolError(f"an answer that is not JSON: {raw!r}")
    if type(answer) is not dict or answer.get("id", ...) != id:
        return ProtocolError(f"answer {answer!r} is not the answer to id {id!r}")
    if "error" in answer:
        return _error(answer["error"], id)
    if "ok" not in answer:
        return ProtocolError(f"an answer without ok or error: {answer!r}")
    return _answer(cmd or "", answer["ok"])


class Oracle:
    """One `dalembert batch` process, kept for the life of the object (use `with`, or call
    `close()`). `scene` and `params` given here are the defaults of every query; a scene is
    a built-in name or a dict with the keys of a scene file (an inline scene). `work` (an
    integer, Taylor terms) and `deadline` (seconds) are the budget of every query that
    names none (`batch --work`, `--deadline`); with neither, the binary's default work
    budget applies, which answers the same on every machine (contract E14). `max_steps` (an
    integer >= 1) is the step limit of every validated flow that names none (`batch
    --max-steps`; the binary's default is 20000): a refusal with `cause == "steps"` may be
    answered with a larger one."""

    def __init__(self, binary: Optional[str] = None, scene: Optional[SceneLike] = None,
                 params: Optional[Mapping[str, float]] = None,
                 deadline: Optional[float] = None, work: Optional[int] = None,
                 jobs: Optional[int] = None, max_steps: Optional[int] = None) -> None:
        self.binary = find_binary(binary)
        args = [self.binary, "batch"]
        if jobs is not None:
            args += ["--jobs", str(int(jobs))]
        if deadline is not None:
            args += ["--deadline", repr(float(deadline))]
        if work is not None:
            args += ["--work", str(int(work))]
        if max_steps is not None:
            args += ["--max-steps", str(_count("max_steps", max_steps))]
        self.scene, self.params = scene, params
        self._p = subprocess.Popen(args, stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                                   bufsize=0)
        assert self._p.stdin is not None and self._p.stdout is not None
        self._in_fd, self._out_fd = self._p.stdin.fileno(), self._p.stdout.fileno()
        self._lines: Deque[Union[str, bytes]] = deque()
        self._rest = b""
        self._eof = False
        self._buf: List[bytes] = []
        self._buf_bytes = 0
        self._poll: Optional[Any] = None
        self._out: "queue.SimpleQueue[bytes]" = queue.SimpleQueue()
        self._reader: Optional[threading.Thread] = None
        if _POLL:
            os.set_blocking(self._in_fd, False)
            self._poll = select.poll()
            self._poll.register(self._in_fd, select.POLLOUT)
            self._poll.register(self._out_fd, select.POLLIN)
        else:
            self._reader = threading.Thread(target=self._read_all, daemon=True)
            self._reader.start()
        self._inflight: Deque[Pending] = deque()
        self._ended = False
        self._next = 0
        self.queries = 0

    # -- the queries -------------------------------------------------------------------
    def flow(self, q: Vector, u: Vector, t: Optional[float] = None, *,
             times: Optional[Vector] = None, order: Optional[int] = None,
             jacobian: Optional[bool] = None, precision: Optional[int] = None,
             max_steps: Optional[int] = None, **common: Any) -> Answer:
        """Exact state at time t from q with quasi-velocities u: keys q, u, v (, jacobian);
        with times=[t1, t2, ..] instead of t, key at (one answer per time: t, q, u, v).

        `precision` (bits, 53..1024; default 53): the answer is computed with intervals of
        that many significand bits (contract E18, E20), its interval ends then `Exact`
        numbers instead of floats; a flow refused with `cause == "width"` (the enclosure
        grew too wide) may be answered at 106. `max_steps`: this query's step limit (the
        session's, or 20000). A refusal after some of the `times` were certified raises
        `Uncertified` with those stops in its `at`."""
        return self.ask(self.query("flow", q=q, u=u, t=t, times=times, order=order,
                                   jacobian=jacobian, precision=precision,
                                   max_steps=max_steps, **common))

    def retract(self, q0: Vector, q1: Vector, h: float, **common: Any) -> Answer:
        """(q0, q1) onto M_h^{e,nh}: keys u0, v0, v1, defect, member, q1."""
        return self.ask(self.query("retract", q0=q0, q1=q1, h=h, **common))

    def step(self, q0: Vector, q1: Vector, h: float, **common: Any) -> Answer:
        """The exact discrete flow: keys q1 (the point of M_h^{e,nh}), q2, p_minus, p_plus."""
        return self.ask(self.query("step", q0=q0, q1=q1, h=h, **common))

    def lagrangian(self, q0: Vector, q1: Vector, h: float, **common: Any) -> Answer:
        """The exact discrete Lagrangian: keys l, defect."""
        return self.ask(self.query("lagrangian", q0=q0, q1=q1, h=h, **common))

    def integrate(self, q0: Vector, q1: Vector, h: float, steps: int, scheme: str = "dla",
                  **common: Any) -> Answer:
        """The built-in scheme's float trajectory: key q (rows of floats), p, energy, ..."""
        return self.ask(self.query("integrate", q0=q0, q1=q1, h=h, steps=steps,
                                   scheme=scheme, **common))

    def check(self, q: Sequence[Vector], h: Optional[float] = None, *,
              t: Optional[Vector] = None, tol: Optional[float] = None,
              defect_tol: Optional[float] = None, pairs: Optional[bool] = None,
              **common: Any) -> Answer:
        """Certified verdict on a trajectory q (rows) of step h, or at times t (one per
        row): keys distance, max_distance, defect, max_defect, energy_error, passed (False
        when the distance is proved beyond tol or a pair's defect beyond defect_tol).
        `precision=BITS` computes the exact discrete flow at that precision (contract E21;
        the figures stay float intervals)."""
        return self.ask(self.query("check", q=q, h=h, t=t, tol=tol, defect_tol=defect_tol,
                                   pairs=pairs, **common))

    def order(self, q: Vector, u: Vector, scheme: str = "dla", *, h: Optional[float] = None,
              rungs: Optional[int] = None, **common: Any) -> Answer:
        """Certified local and global order of DLA or MLA (the batch `order` query, the
        fields of `dalembert order --json`): keys scene, scheme, local {h, error, order},
        global {t, ladder {h, error, order}}; an order not proved is None."""
        return self.ask(self.query("order", q=q, u=u, scheme=scheme, h=h, rungs=rungs,
                                   **common))

    def scenes(self, scene: Optional[SceneLike] = None, *, scene_file: Optional[str] = None,
               params: Optional[Mapping[str, float]] = None) -> Dict[str, Any]:
        """What `dalembert scenes --json` prints, `{"scenes": [entry, ..]}`: each scene's
        coordinates, parameters, Lagrangian, constraints and basis of D (a derived basis
        written out as formulas). `scene`: a built-in name or an inline scene (a dict, e.g.
        a `Scene`), asked through the batch `scenes` query; `scene_file`: a scene file
        (TOML, or JSON by the extension `.json`); neither: every built-in scene (not the
        session's default scene). `params` override the scene's parameters."""
        if scene is not None and scene_file is not None:
            raise ValueError("scenes: give scene or scene_file, not both")
        if scene_file is not None or (params is None and not isinstance(scene, Mapping)):
            # a file, or built-in scenes: the command line (`scenes --json`)
            args = [self.binary, "scenes", "--json"]
            if scene_file is not None:
                args += ["--scene-file", os.fspath(scene_file)]
            for k, v in (params or {}).items():
                args += ["--param", f"{k}={float(v)!r}"]
            out = subprocess.run(args, capture_output=True, text=True)
            if out.returncode != 0:
                raise _error({"code": out.returncode, "message": out.stderr.strip()}, None)
            got: Dict[str, Any] = json.loads(out.stdout)
            if isinstance(scene, str):
                entries = [e for e in got["scenes"] if e.get("name") == scene]
                if not entries:
                    hint = " (a file is scene_file=...)" if scene.lower().endswith(
                        (".toml", ".json")) else ""
                    raise InputError(2, f"scene: unknown scene `{scene}` (the built-in "
                                     f"scenes: {', '.join(e['name'] for e in got['scenes'])})"
                                     f"{hint}")
                got = {"scenes": entries}
            return got
        q: Dict[str, Any] = {"cmd": "scenes"}
        if scene is not None:
            q["scene"] = dict(scene) if isinstance(scene, Mapping) else scene
        if params is not None:
            q["params"] = dict(params)
        a = self.ask(q)
        return {k: a[k] for k in a}

    # -- the protocol ------------------------------------------------------------------
    def query(self, cmd: str, *, scene: Optional[SceneLike] = None,
              params: Optional[Mapping[str, float]] = None, deadline: Optional[float] = None,
              work: Optional[int] = None, **keys: Any) -> Dict[str, Any]:
        """The query object (a dict) for `cmd`; None values are left out; numpy arrays
        and scalars become lists and numbers (a vector must be one-dimensional, `check`'s
        `q` two-dimensional: ValueError naming the key otherwise)."""
        q: Dict[str, Any] = {"cmd": cmd, "scene": scene if scene is not None else self.scene}
        q["params"] = params if params is not None else self.params
        q["deadline"] = deadline
        q["work"] = work
        q.update(keys)
        return {k: _plain(k, v, cmd) for k, v in q.items() if v is not None}

    def submit(self, query: Mapping[str, Any]) -> Pending:
        """Send one query (a dict without `id`, e.g. from `query`) without waiting: its
        answer is read when `.result()` is called. Queries sent this way are pipelined."""
        self._next += 1
        return self._send(_line(query, self._next), self._next, query.get("cmd"))

    def ask(self, query: Mapping[str, Any]) -> Answer:
        """Send one query (a dict without `id`), return its `Answer` or raise."""
        return self.submit(query).result()

    def ask_line(self, line: str) -> Answer:
        """Send one raw line as it is (tests, hand-written queries); its answer's id must be
        the line's own `id`, or null when the line has none or is not a JSON object."""
        if "\n" in line or not line.strip():
            raise ValueError("one non-blank line, without a newline")
        try:
            obj = json.loads(line)
        except ValueError:
            obj = None
        obj = obj if isinstance(obj, dict) else {}
        return self._send(line.encode(), obj.get("id"), obj.get("cmd")).result()

    def run(self, queries: Iterable[Mapping[str, Any]]) -> List[Union[Answer, OracleError]]:
        """Many queries at once (pipelined). Returns one item per query, in order: its
        `Answer` or the `OracleError` (not raised)."""
        # The answers kept alive here hold no reference cycles: the cyclic garbage collector
        # would only rescan them, again and again as they accumulate (about a sixth of this
        # method's time on 3,000 answers), so it is paused for the duration.
        was_enabled = gc.isenabled()
        gc.disable()
        try:
            pending = [self.submit(q) for q in queries]
            if pending:
                self._wait(pending[-1])  # every answer, in one loop
            out = [p._value for p in pending]
            for v in out:  # as `outcome()`: an OracleError is returned, the others raised
                if type(v) is not Answer and not isinstance(v, OracleError):
                    raise v
            return out
        finally:
            if was_enabled:
                gc.enable()

    def _send(self, line: bytes, id: Any, cmd: Optional[str]) -> Pending:
        if self._ended:
            raise ProtocolError("the batch process is closed")
        p = Pending(self, id, cmd)
        self.queries += 1
        self._inflight.append(p)
        self._buf.append(line)
        self._buf.append(b"\n")
        self._buf_bytes += len(line) + 1
        if self._buf_bytes >= _FLUSH_BYTES:
            self._flush()
        return p

    def _flush(self) -> None:
        if not self._buf:
            return
        data = b"".join(self._buf)
        self._buf, self._buf_bytes = [], 0
        view = memoryview(data)
        try:
            while view:
                if self._poll is None:  # blocking: the reader thread drains the output
                    n = os.write(self._in_fd, view)
                else:
                    try:
                        n = os.write(self._in_fd, view)
                    except BlockingIOError:
                        # The pipe is full: the process may be waiting for its own output
                        # to be read, so read that while waiting for room.
                        self._make_room()
                        continue
                view = view[n:]
        except OSError as e:  # BrokenPipeError among them: the process is gone
            raise ProtocolError(f"the batch process is gone: {e}") from None

    def _make_room(self) -> None:
        """Wait until the input pipe has room, reading the output that arrives meanwhile."""
        assert self._poll is not None
        for fd, _ in self._poll.poll():
            if fd == self._out_fd:
                self._take(os.read(self._out_fd, _READ_BYTES))

    def _read_all(self) -> None:
        # (without poll) whole chunks, not lines: one hand-over between the threads per chunk
        while True:
            chunk = os.read(self._out_fd, _READ_BYTES)
            self._out.put(chunk)
            if not chunk:
                break

    def _take(self, chunk: bytes) -> None:
        """Split a chunk of the output into answer lines (b"": the output ended)."""
        if not chunk:
            self._eof = True
            if self._poll is not None:
                self._poll.unregister(self._out_fd)
            if self._rest:
                self._lines.append(self._rest)
                self._rest = b""
            return
        data = self._rest + chunk if self._rest else chunk
        end = data.rfind(b"\n")
        if end < 0:
            self._rest = data
            return
        self._rest = data[end + 1:]
        whole = data[:end]
        try:  # the complete lines decoded at once (one call for many answers)
            self._lines.extend(whole.decode().split("\n"))
        except UnicodeDecodeError:  # each line decoded alone, by _result
            self._lines.extend(whole.split(b"\n"))

    def _next_line(self) -> Optional[Union[str, bytes]]:
        """The next answer line, None once the process's output has ended."""
        lines = self._lines
        while not lines:
            if self._eof:
                return None
            if self._reader is None:
                self._take(os.read(self._out_fd, _READ_BYTES))
            else:
                self._take(self._out.get())
        return lines.popleft()

    def _wait(self, target: Pending) -> None:
        self._flush()
        while not target._done:
            p = self._inflight.popleft()
            line = self._next_line()
            if line is None:
                self._inflight.appendleft(p)
                raise ProtocolError(f"the batch process ended (exit {self._p.poll()})")
            p._value = self._result(line, p)
            p._done = True

    @staticmethod
    def _result(line: Union[str, bytes], p: Pending) -> Union[Answer, BaseException]:
        return _parse(line, p.id, p.cmd)

    def close(self) -> int:
        """Answer what is in flight, end the input, wait for the process; its exit status
        (0 when all went well)."""
        if not self._ended:
            self._ended = True
            try:
                self._flush()
            except ProtocolError:
                pass
            if self._p.stdin and not self._p.stdin.closed:
                try:
                    self._p.stdin.close()
                except BrokenPipeError:
                    pass
            # The answers still to come are read now (kept for `.result()`), so that the
            # process never waits on a full output pipe while this waits for it to end.
            while self._reader is None and not self._eof:
                self._take(os.read(self._out_fd, _READ_BYTES))
        status = self._p.wait()
        if self._reader is not None:
            self._reader.join()
        if self._p.stdout:
            self._p.stdout.close()
        return status

    def __enter__(self) -> "Oracle":
        return self

    def __exit__(self, *exc: Any) -> None:
        self.close()
