#!/usr/bin/env python3
"""Shard a campaign of `dalembert batch` queries over processes or machines, and merge.

    shard.py split QUERIES K DIR          DIR/shard-0000.jsonl .. : line i (from 1) goes to
                                          shard (i - 1) mod K; a line without "id" gets
                                          "id": i (inserted as text: the rest of the line is
                                          sent byte for byte); ids must be distinct
    shard.py merge QUERIES ANSWERS...     the answers of all shards, in the order of QUERIES,
                                          on stdout, each line as the binary printed it
    shard.py run QUERIES K [--binary B]   split, K `dalembert batch` processes, merge

Run the shards with any job runner, on one machine or many, e.g.
    python3 shard.py split queries.jsonl 8 shards
    ls shards/shard-*.jsonl | xargs -P 8 -I{} sh -c 'dalembert batch < {} > {}.out'
    # or: parallel 'dalembert batch < {} > {}.out' ::: shards/shard-*.jsonl   (GNU parallel)
    python3 shard.py merge queries.jsonl shards/*.out > answers.jsonl

`merge` checks, and exits 1 naming the problem when it fails: every answer line is an answer
(a JSON object with an "id" and exactly one of "ok" or "error"), every query's id is answered
exactly once, no answer is to an id that was not asked, and within each answer file the
answers come in the order of the queries (as `batch` prints them). Error answers (codes 2
and 3) are answers: they are merged like the others. Blank query lines are skipped, as
`batch` skips them. Standard library only.
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile
import time


class ShardError(Exception):
    pass


def _key(value):
    return json.dumps(value, sort_keys=True)


def _reject_duplicates(pairs):
    keys = [k for k, _ in pairs]
    if len(set(keys)) != len(keys):
        raise ShardError("a key repeated within one object")
    return dict(pairs)


def read_queries(path):
    """[(line number, line with an id, key of the id)] for the non-blank lines of the file."""
    out, seen = [], {}
    with open(path, encoding="utf-8") as f:
        for i, line in enumerate(f, 1):
            line = line.rstrip("\n").rstrip("\r")
            if not line.strip():
                continue
            try:
                obj = json.loads(line, object_pairs_hook=_reject_duplicates)
            except (ValueError, ShardError) as e:
                raise ShardError(f"{path}: line {i}: not a JSON object ({e})") from None
            if not isinstance(obj, dict):
                raise ShardError(f"{path}: line {i}: not a JSON object")
            if "id" not in obj:
                body = line.lstrip()[1:]
                sep = "" if body.lstrip().startswith("}") else ","
                line = f'{{"id":{i}{sep}{body}'
                obj["id"] = i
            key = _key(obj["id"])
            if key in seen:
                raise ShardError(f"{path}: line {i}: id {key} is also the id of line {seen[key]}")
            seen[key] = i
            out.append((i, line, key))
    return out


def split(queries, k, directory):
    os.makedirs(directory, exist_ok=True)
    paths = [os.path.join(directory, f"shard-{j:04}.jsonl") for j in range(k)]
    files = [open(p, "w", encoding="utf-8") for p in paths]
    try:
        for n, (_, line, _) in enumerate(queries):
            files[n % k].write(line + "\n")
    finally:
        for f in files:
            f.close()
    return paths


def merge(queries, answer_files, out):
    position = {key: n for n, (_, _, key) in enumerate(queries)}
    lines = [None] * len(queries)
    for path in answer_files:
        last = -1
        with open(path, encoding="utf-8") as f:
            for j, text in enumerate(f, 1):
                where = f"{path}: line {j}"
                try:
                    answer = json.loads(text)
                except ValueError:
                    raise ShardError(f"{where}: not an answer (not JSON)") from None
                if not (isinstance(answer, dict) and "id" in answer
                        and ("ok" in answer) != ("error" in answer)):
                    raise ShardError(f"{where}: not an answer: {text.strip()[:200]}")
                key = _key(answer["id"])
                if key not in position:
                    raise ShardError(f"{where}: an answer to id {key}, which no query has")
                n = position[key]
                if lines[n] is not None:
                    raise ShardError(f"{where}: a second answer to id {key}")
                if n <= last:
                    raise ShardError(f"{where}: id {key} out of the order of the queries")
                last, lines[n] = n, text.rstrip("\n")
    missing = [queries[n][0] for n, line in enumerate(lines) if line is None]
    if missing:
        raise ShardError(f"{len(missing)} queries have no answer (input lines "
                         f"{', '.join(map(str, missing[:10]))}{', ...' if len(missing) > 10 else ''})")
    for line in lines:
        out.write(line + "\n")
    return len(lines)


def run(queries, k, binary, directory, batch_args=()):
    paths = split(queries, k, directory)
    procs = []
    for p in paths:
        with open(p, "rb") as src, open(p + ".out", "wb") as dst:
            procs.append(subprocess.Popen([binary, "batch", *batch_args], stdin=src, stdout=dst))
    for p, proc in zip(paths, procs):
        if proc.wait() != 0:
            raise ShardError(f"dalembert batch on {p} exited with {proc.returncode}")
    return [p + ".out" for p in paths]


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    sub = ap.add_subparsers(dest="cmd", required=True)
    s = sub.add_parser("split")
    s.add_argument("queries"), s.add_argument("k", type=int), s.add_argument("dir")
    m = sub.add_parser("merge")
    m.add_argument("queries"), m.add_argument("answers", nargs="+")
    r = sub.add_parser("run")
    r.add_argument("queries"), r.add_argument("k", type=int)
    r.add_argument("--binary", default=os.environ.get("DALEMBERT", "dalembert"))
    r.add_argument("--dir", help="keep the shards and their answers here")
    a = ap.parse_args(argv)
    try:
        queries = read_queries(a.queries)
        if a.cmd in ("split", "run") and a.k < 1:
            raise ShardError("K must be at least 1")
        if a.cmd == "split":
            for p in split(queries, a.k, a.dir):
                print(p)
        elif a.cmd == "merge":
            n = merge(queries, a.answers, sys.stdout)
            print(f"merged {n} answers", file=sys.stderr)
        else:
            t = time.time()
            with tempfile.TemporaryDirectory() as tmp:
                outs = run(queries, a.k, a.binary, a.dir or tmp)
                n = merge(queries, outs, sys.stdout)
            print(f"{n} answers from {a.k} shards in {time.time() - t:.2f} s", file=sys.stderr)
    except (ShardError, OSError, UnicodeDecodeError) as e:
        print(f"error: {e}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
