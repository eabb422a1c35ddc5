"""The Dask campaign runner: 300 queries on a 2-worker LocalCluster give, byte for byte, the
answers of one local `dalembert batch` run (the default work budget makes an answer
independent of the machine and its load); a worker killed mid-run still leaves every query
answered exactly once, in order."""

import json
import os
import random
import signal
import threading
import time

import pytest

distributed = pytest.importorskip("distributed")

from dalembert.campaign import CampaignError, _check, partition, run_campaign, run_local  # noqa: E402


def queries(n, seed=3):
    """Particle and knife queries of every single-step kind, a few flows, and a few lines
    that are refused (a wrong dimension, a key that does not exist, not JSON)."""
    rng = random.Random(seed)
    out = []
    for i in range(n):
        r = rng.random()
        if i % 50 == 7:
            out.append(json.dumps({"id": i, "cmd": "step", "scene": "particle",
                                   "q0": [0, 0], "q1": [0, 0, 0], "h": 0.5}))
        elif i % 50 == 19:
            out.append("not JSON at all")
        elif r < 0.6:
            q0 = [rng.uniform(-1, 1) for _ in range(3)]
            v = [rng.uniform(-1, 1), rng.uniform(0.2, 1), 0.0]
            v[2] = q0[1] * v[0]
            h = rng.choice([0.125, 0.25, 0.5])
            q1 = [a + h * b for a, b in zip(q0, v)]
            cmd = rng.choice(["step", "retract", "lagrangian"])
            out.append(json.dumps({"id": i, "cmd": cmd, "scene": "particle", "q0": q0,
                                   "q1": q1, "h": h}))
        else:
            out.append(json.dumps({"id": f"f{i}", "cmd": "flow", "scene": "knife",
                                   "q": [rng.uniform(-1, 1) for _ in range(3)],
                                   "u": [rng.uniform(-1, 1), rng.uniform(-1, 1)],
                                   "t": rng.uniform(0.5, 4)}))
    return out


@pytest.fixture(scope="module")
def cluster():
    from distributed import Client, LocalCluster
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                      dashboard_address=None, host="127.0.0.1") as c, Client(c) as client:
        yield client


def test_partition_covers_in_order():
    lines = [str(i) for i in range(10)]
    for k in (1, 3, 4, 10, 20):
        parts = partition(lines, k)
        assert sum(parts, []) == lines and all(parts)


def test_check_refuses_missing_extra_and_foreign_answers():
    lines = ['{"id": 1}', "", '{"id": 2}']
    good = ['{"id":1,"ok":{}}', '{"id":2,"error":{"code":2,"message":"x"}}']
    _check(lines, good)
    for bad in (good[:1], good + good[:1], ['{"id":1,"ok":{}}', '{"id":3,"ok":{}}'],
                ['{"id":1,"ok":{}}', 'oops'], ['{"id":1}', good[1]]):
        with pytest.raises(CampaignError):
            _check(lines, bad)


def test_300_queries_on_two_workers_equal_one_local_batch(cluster):
    lines = queries(300)
    local = run_local(lines)
    assert len(local) == 300
    assert any('"error"' in a for a in local) and any('"ok"' in a for a in local)
    got = run_campaign(lines, cluster, partitions=7)
    assert "\n".join(got).encode() == "\n".join(local).encode()


def test_a_worker_killed_mid_run_still_answers_every_query_once(cluster):
    # every tenth line also a knife flow to T = 50 (a few ms each), so that each partition
    # takes a while on any build
    lines = []
    for i, line in enumerate(queries(900, seed=4)):
        lines.append(line)
        if i % 10 == 0:
            lines.append(json.dumps({"id": 10000 + i, "cmd": "flow", "scene": "knife",
                                     "q": [0, 0, 0], "u": [0.8, 0.8], "t": 50}))
    local = run_local(lines)
    pids = cluster.run(os.getpid)
    where, victim = sorted(pids.items(), key=lambda kv: kv[1])[0]
    killed = threading.Event()

    def kill_soon():
        # the moment the victim holds a partition: the run is then surely under way (no
        # guess at how long it takes)
        end = time.monotonic() + 60
        while time.monotonic() < end and not cluster.processing(workers=[where]).get(where):
            time.sleep(0.001)
        os.kill(victim, signal.SIGKILL)
        killed.set()

    threading.Thread(target=kill_soon, daemon=True).start()
    # many small partitions, so that some are still to run when the worker dies
    got = run_campaign(lines, cluster, partitions=60)
    assert killed.is_set(), "the worker was killed only after the run had ended"
    assert got == local
    ids = [json.loads(a)["id"] for a in got]
    want = [json.loads(q)["id"] if q.startswith("{") else None for q in lines]
    assert ids == want


def test_dict_queries_come_back_as_answers(cluster):
    from dalembert import Answer, Oracle, OracleError

    dicts = [json.loads(line) for line in queries(60, seed=5) if line.startswith("{")]
    got = run_campaign(dicts, cluster, partitions=4)
    assert len(got) == len(dicts)
    with Oracle() as o:
        want = o.run([{k: v for k, v in d.items() if k != "id"} for d in dicts])
    for g, w in zip(got, want):
        assert type(g) is type(w) and (isinstance(g, OracleError) or type(g) is Answer)
        if isinstance(g, Answer):
            assert dict(g.items()) == dict(w.items())
        else:
            assert (g.code, g.message) == (w.code, w.message)
