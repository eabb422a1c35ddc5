"""Pipelining: many queries in flight (more than a pipe holds, each way) are answered in
order and exactly as the same queries asked one at a time, with either way of doing the pipe
I/O (poll in the calling thread, or the reader thread used where poll is missing); a
`.result()` sends what is buffered before it waits; a session closed with answers unread
ends and keeps them; the binary answers a client that waits for each answer."""

import json
import os
import random
import select
import subprocess
import threading

import pytest

import dalembert._oracle as oracle_module
from dalembert import InputError, Oracle, find_binary

# 1,000 step queries are about 200 KiB of queries and 450 KiB of answers: more than a pipe
# buffer (64 KiB on Linux) either way, so neither side may wait for the other to read.
N = 1000


def step_queries(n, seed):
    rng = random.Random(seed)
    out = []
    for k in range(n):
        h = rng.uniform(0.05, 0.5)
        q0 = [rng.uniform(-1, 1) for _ in range(3)]
        v = [rng.uniform(-1, 1), rng.choice([-1, 1]) * rng.uniform(0.2, 1), 0.0]
        v[2] = q0[1] * v[0]
        q1 = [a + h * b for a, b in zip(q0, v)]
        q = {"cmd": "step", "scene": "particle", "q0": q0, "q1": q1, "h": h}
        if k % 97 == 13:
            q["q0"] = q0[:2]  # a wrong dimension: an error answer in its place
        out.append(q)
    return out


def same(a, b):
    """The same answer: equal Answers, or errors of the same type, code and message."""
    if isinstance(a, Exception) or isinstance(b, Exception):
        return type(a) is type(b) and (a.code, a.message) == (b.code, b.message)
    return dict(a) == dict(b)


def guarded(body, seconds=300):
    """Run body() on a thread; fail (instead of hanging the suite) if it has not finished
    within `seconds`."""
    out = {}

    def run():
        try:
            out["value"] = body()
        except BaseException as e:  # re-raised below, in the test's thread
            out["error"] = e

    t = threading.Thread(target=run, daemon=True)
    t.start()
    t.join(seconds)
    assert not t.is_alive(), f"no answer within {seconds} s: a deadlock"
    if "error" in out:
        raise out["error"]
    return out["value"]


@pytest.fixture(scope="module")
def reference():
    """The queries and their answers asked one at a time (a round trip each)."""
    qs = step_queries(N, seed=5)
    with Oracle() as o:
        answers = []
        for q in qs:
            try:
                answers.append(o.ask(q))
            except InputError as e:
                answers.append(e)
    assert sum(isinstance(a, InputError) for a in answers) == len(range(13, N, 97))
    return qs, answers


@pytest.fixture(params=["poll", "thread"])
def io_way(request, monkeypatch):
    if request.param == "poll" and not oracle_module._POLL:
        pytest.skip("no select.poll here")
    monkeypatch.setattr(oracle_module, "_POLL", request.param == "poll")
    return request.param


def test_a_list_in_flight_is_answered_in_order(reference, io_way):
    qs, ref = reference

    def body():
        with Oracle() as o:
            assert (o._reader is None) == (io_way == "poll")
            return o.run(qs)

    got = guarded(body)
    assert len(got) == N and all(same(a, b) for a, b in zip(got, ref))


def test_results_asked_last_first(reference, io_way):
    qs, ref = reference

    def body():
        with Oracle() as o:
            pend = [o.submit(q) for q in qs]
            last = pend[-1].outcome()  # sends every buffered query, reads every answer
            assert all(p.done() for p in pend)
            return [p.outcome() for p in pend[:-1]] + [last]

    got = guarded(body)
    assert all(same(a, b) for a, b in zip(got, ref))


def test_a_result_sends_the_buffered_queries_before_waiting(reference, io_way):
    qs, ref = reference

    def body():
        with Oracle() as o:
            p = o.submit(qs[0])
            assert o._buf, "a query is buffered until an answer is needed"
            return p.result()

    assert same(guarded(body, 60), ref[0])


def test_close_with_answers_unread_ends_and_keeps_them(reference, io_way):
    qs, ref = reference

    def body():
        o = Oracle()
        pend = [o.submit(q) for q in qs]
        assert o.close() == 0
        return [p.outcome() for p in pend]

    got = guarded(body)
    assert all(same(a, b) for a, b in zip(got, ref))


def read_line(proc, seconds=60):
    """One line of the process's output, or fail after `seconds` without one."""
    fd = proc.stdout.fileno()
    line = b""
    while not line.endswith(b"\n"):
        ready, _, _ = select.select([fd], [], [], seconds)
        assert ready, f"no answer within {seconds} s"
        chunk = os.read(fd, 1)
        assert chunk, "the output ended"
        line += chunk
    return json.loads(line)


@pytest.mark.skipif(not hasattr(select, "select") or os.name != "posix",
                    reason="select on pipes")
def test_the_binary_answers_each_line_before_waiting_for_the_next():
    """A client that sends a line (with a blank line after it, or two lines in one write)
    and waits gets every answer without sending more."""
    q = {"cmd": "step", "scene": "particle", "q0": [0.1, 0.2, 0.3], "q1": [0.5, 0.6, 0.55],
         "h": 0.3}
    line = lambda i: json.dumps({"id": i, **q}).encode() + b"\n"  # noqa: E731
    p = subprocess.Popen([find_binary(), "batch"], stdin=subprocess.PIPE,
                         stdout=subprocess.PIPE, bufsize=0)
    try:
        p.stdin.write(line(1))
        assert read_line(p)["id"] == 1
        p.stdin.write(line(2) + b"\n")
        assert read_line(p)["id"] == 2
        p.stdin.write(line(3) + line(4))
        assert [read_line(p)["id"] for _ in range(2)] == [3, 4]
        p.stdin.write(line(5)[:40])  # half a line: nothing to answer yet
        p.stdin.write(line(5)[40:])
        assert read_line(p)["id"] == 5
    finally:
        p.stdin.close()
        assert p.wait(60) == 0
        p.stdout.close()
