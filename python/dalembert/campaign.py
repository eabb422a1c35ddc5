"""A campaign of `dalembert batch` queries run on Dask (`dask.distributed`): the same
function runs on a `LocalCluster` (tests, one machine) and on a scheduler address (a cluster).

    from dask.distributed import Client, LocalCluster
    from dalembert.campaign import run_campaign
    with LocalCluster(n_workers=2, threads_per_worker=1) as cluster, Client(cluster) as c:
        answers = run_campaign(lines, c)          # or run_campaign(lines, "tcp://host:8786")

The lines are split into contiguous partitions; each partition is answered by one
`dalembert batch` process on a worker (the binary installed with this package there, or
$DALEMBERT, or PATH; or `binary=`). The answers come back in input order, as the binary
printed them (a partition is preceded by blank lines, which `batch` skips, so that an error
names the line number of the whole input): with the default work budget (or `--work`) an answer does not depend on the
machine, its load or the partitioning, so the output is byte for byte that of one local
`dalembert batch` run on the same lines (`run_local`). Every answer is checked: one answer
per non-blank line, its `id` the line's own (null for a line that is not a JSON object with
an id). A partition whose process fails, or whose answers do not check, is retried
(`retries`); a worker lost mid-run has its partitions rerun by Dask. Blank lines are skipped,
as `batch` skips them.

Queries may also be dicts (as `Oracle.query` makes them, numpy arrays allowed; any `id`
key is replaced by the query's position, 1, 2, ...): then the answers are `Answer` objects,
or the `OracleError` of a query refused (returned in its place, not raised), as
`Oracle.run` gives them. Lines in, lines out; dicts in, answers out.
"""

from __future__ import annotations

import json
import subprocess
from typing import Any, List, Mapping, Optional, Sequence, Union, cast

from ._oracle import Answer, OracleError, ProtocolError, _line, _parse, _plain, find_binary

Query = Union[str, Mapping[str, Any]]

__all__ = ["CampaignError", "run_campaign", "run_local", "partition"]


class CampaignError(RuntimeError):
    """An answer is missing, extra, or not the answer to its line."""


def _expected_id(line: str) -> Any:
    try:
        obj = json.loads(line)
    except ValueError:
        return None
    return obj.get("id") if isinstance(obj, dict) else None


def _check(lines: Sequence[str], answers: Sequence[str]) -> None:
    queries = [line for line in lines if line.strip()]
    if len(answers) != len(queries):
        raise CampaignError(f"{len(queries)} queries but {len(answers)} answers")
    for i, (q, a) in enumerate(zip(queries, answers)):
        try:
            obj = json.loads(a)
        except ValueError:
            raise CampaignError(f"answer {i + 1} is not JSON: {a[:200]!r}") from None
        if not isinstance(obj, dict) or ("ok" in obj) == ("error" in obj):
            raise CampaignError(f"answer {i + 1} is not an answer: {a[:200]!r}")
        want = _expected_id(q)
        if obj.get("id") != want:
            raise CampaignError(
                f"answer {i + 1} has id {obj.get('id')!r}, its query {want!r}")


def _batch(lines: Sequence[str], binary: Optional[str], args: Sequence[str],
           first: int = 1) -> List[str]:
    """One `dalembert batch` process on `lines`, the first being line `first` of the whole
    input; its answer lines, checked. The lines are preceded by `first - 1` blank lines
    (skipped by `batch`, but counted), so that an error naming a line number names it as
    one run on the whole input would."""
    for line in lines:
        if "\n" in line:
            raise ValueError("a query line holds a newline")
    data = ("\n" * (first - 1) + "".join(line + "\n" for line in lines)).encode()
    out = subprocess.run([find_binary(binary), "batch", *args], input=data,
                         capture_output=True, check=False)
    if out.returncode != 0:
        raise CampaignError(f"dalembert batch exited {out.returncode}: "
                            f"{out.stderr.decode(errors='replace').strip()}")
    answers = out.stdout.decode().splitlines()
    _check(lines, answers)
    return answers


def _as_lines(queries: Sequence[Query]) -> Optional[List[Mapping[str, Any]]]:
    """None when every query is a line; the dicts when every query is a dict (ValueError
    for a mix, or anything else)."""
    if all(isinstance(q, str) for q in queries):
        return None
    if all(isinstance(q, Mapping) for q in queries):
        return list(queries)  # type: ignore[arg-type]
    for i, q in enumerate(queries):
        if not isinstance(q, (str, Mapping)):
            raise ValueError(f"queries[{i}]: a query is a line (str) or a dict, not "
                             f"{type(q).__name__}")
    raise ValueError("queries: all lines (str) or all dicts, not a mix")


def _encode(dicts: Sequence[Mapping[str, Any]]) -> List[str]:
    """The batch lines of query dicts, ids 1, 2, ... in order."""
    out = []
    for i, q in enumerate(dicts):
        cmd = str(q.get("cmd", ""))
        out.append(_line({k: _plain(k, v, cmd) for k, v in q.items() if v is not None},
                         i + 1).decode())
    return out


def _decode(dicts: Sequence[Mapping[str, Any]], answers: Sequence[str]
            ) -> List[Union[Answer, OracleError]]:
    out: List[Union[Answer, OracleError]] = []
    for i, (q, a) in enumerate(zip(dicts, answers)):
        v = _parse(a, i + 1, q.get("cmd"))
        if isinstance(v, ProtocolError):
            raise CampaignError(str(v))
        out.append(v)  # type: ignore[arg-type]
    return out


def run_local(lines: Sequence[Query], binary: Optional[str] = None,
              args: Sequence[str] = ()) -> List[Any]:
    """One local `dalembert batch` run: the answer lines, checked (or, for dict queries,
    their `Answer`s and `OracleError`s)."""
    dicts = _as_lines(lines)
    if dicts is None:
        return _batch(lines, binary, args)  # type: ignore[arg-type]
    return _decode(dicts, _batch(_encode(dicts), binary, args))


def partition(lines: Sequence[str], parts: int) -> List[List[str]]:
    """`lines` in `parts` contiguous pieces of nearly equal size (none empty)."""
    parts = max(1, min(parts, len(lines)))
    size, extra = divmod(len(lines), parts)
    out, start = [], 0
    for i in range(parts):
        end = start + size + (1 if i < extra else 0)
        out.append(list(lines[start:end]))
        start = end
    return out


def run_campaign(lines: Sequence[Query], client: Union[str, Any, None] = None, *,
                 partitions: Optional[int] = None, binary: Optional[str] = None,
                 args: Sequence[str] = (), retries: int = 3) -> List[Any]:
    """Answer `lines` (batch query lines, JSON text) on Dask: `client` is a
    `distributed.Client`, a scheduler address, or None for the current client.
    `partitions` defaults to 4 per worker thread; `args` are extra `dalembert batch` flags
    (e.g. ["--work", "1000000"]). Returns the answer lines in input order; for dict queries
    their `Answer`s (an `OracleError` in the place of a query refused)."""
    dicts = _as_lines(lines)
    if dicts is not None:
        return _decode(dicts, run_campaign(
            _encode(dicts), client, partitions=partitions, binary=binary, args=args,
            retries=retries))
    from distributed import Client, get_client

    lines = cast(Sequence[str], lines)

    own = None
    if client is None:
        client = get_client()
    elif isinstance(client, str):
        # distributed has no annotations on Client: an untyped call, on purpose
        client = own = Client(client)  # type: ignore[no-untyped-call]
    try:
        if not lines:
            return []
        if partitions is None:
            threads = sum(client.nthreads().values()) or 1
            partitions = 4 * threads
        pieces = partition(list(lines), partitions)
        firsts = [1 + sum(len(p) for p in pieces[:i]) for i in range(len(pieces))]
        n = len(pieces)
        futures = client.map(_batch, pieces, [binary] * n, [list(args)] * n, firsts,
                             retries=retries, pure=False)
        answers: List[str] = []
        for piece, got in zip(pieces, client.gather(futures)):
            _check(piece, got)
            answers.extend(got)
        _check(lines, answers)
        return answers
    finally:
        if own is not None:
            own.close()  # type: ignore[no-untyped-call]
