#!/usr/bin/python3
"""Ensemble scaling and overheads (docs/benchmarks.md, "Ensemble").

    /usr/bin/python3 bench/bench_ensemble.py [--samples 2000] [--rounds 3] [--big 100000]
        [--ranks-many 8] [--kanesens build/kanesens]
    env (defaults of the options): SAMPLES ROUNDS BIG RANKS_MANY KANESENS
    quick smoke test: bench/bench_ensemble.py --samples 40 --rounds 1 --big 200 --ranks-many 3

 1. strong scaling 1 -> 2 ranks, SAMPLES samples of the 4-link chain
    (configs/chain4_scaling_study.yaml), ROUNDS alternating runs each, medians; efficiency =
    t1 / (2 t2); the run summary's split of rank time into integration, HDF5 writes and
    scheduling;
 2. throughput and file size for BIG samples on 2 ranks;
 3. scheduling/IO behaviour with many oversubscribed ranks (RANKS_MANY) — what the one-sided
    counter and independent writes cost when ranks outnumber cores.
Writes bench/results/bench_ensemble.json (--out); bench/make_tables.py makes the table.
"""
from __future__ import annotations

import argparse
import json
import os
import subprocess
import tempfile
from pathlib import Path

import common as c

STUDY = c.CONFIGS / "chain4_scaling_study.yaml"
MPI_ENV = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")


def mpirun(exe, np_, out, samples, prefix=()):
    cmd = [*prefix, "mpirun", "--oversubscribe", "-np", str(np_), str(exe), "run", str(STUDY), "--json",
           "--overwrite", "-o", str(out), "--samples", str(samples)]
    return subprocess.run(cmd, capture_output=True, text=True, env=MPI_ENV)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--samples", type=int, default=int(c.env_default("SAMPLES", 2000)))
    ap.add_argument("--rounds", type=int, default=int(c.env_default("ROUNDS", 3)))
    ap.add_argument("--big", type=int, default=int(c.env_default("BIG", 100000)))
    ap.add_argument("--ranks-many", type=int, default=int(c.env_default("RANKS_MANY", 8)))
    ap.add_argument("--kanesens", default=c.env_default("KANESENS", str(c.kanesens_exe(c.ROOT / "build"))))
    ap.add_argument("--out", default=str(c.ROOT / "bench" / "results" / "bench_ensemble.json"))
    a = ap.parse_args(argv)
    load_start = c.loadavg()
    n, big, many = a.samples, a.big, a.ranks_many

    with tempfile.TemporaryDirectory() as tmp:
        work = Path(tmp)

        def run(np_, name):
            p = mpirun(a.kanesens, np_, work / name, n)
            if p.returncode != 0:
                raise SystemExit(f"bench_ensemble: mpirun -np {np_} failed ({p.returncode}): {p.stderr.strip()}")
            return json.loads(p.stdout)

        one, two = [], []
        for _ in range(a.rounds):
            one.append(run(1, "r1.h5"))
            two.append(run(2, "r2.h5"))
        mn = run(many, "rm.h5")
        # Max RSS of one rank, as /usr/bin/time reports it for mpirun's children.
        p = mpirun(a.kanesens, 2, work / "big.h5", big,
                   prefix=["/usr/bin/time", "-f", "%e s wall, %M KiB max RSS (one rank)"])
        b = json.loads(p.stdout) if p.stdout.strip() else {}
        big_time = (p.stderr.strip().splitlines() or [""])[-1]
        size = (work / "big.h5").stat().st_size if (work / "big.h5").exists() else 0

    t1 = c.median(r["wall_seconds"] for r in one)
    t2 = c.median(r["wall_seconds"] for r in two)

    def shares(r):
        busy = r["compute_seconds"] + r["io_seconds"] + r["schedule_seconds"]
        return {"hdf5_percent": 100 * r["io_seconds"] / busy, "scheduling_percent": 100 * r["schedule_seconds"] / busy}

    rows = [{"ranks": 1, "samples": n, "median_wall_s": t1, "samples_per_s": n / t1, "efficiency": 1.0,
             **shares(one[0]), "wall_s": [r["wall_seconds"] for r in one]},
            {"ranks": 2, "samples": n, "median_wall_s": t2, "samples_per_s": n / t2, "efficiency": t1 / (2 * t2),
             **shares(two[0]), "wall_s": [r["wall_seconds"] for r in two]},
            {"ranks": many, "oversubscribed": True, "samples": n, "median_wall_s": mn["wall_seconds"],
             "samples_per_s": n / mn["wall_seconds"], "efficiency": None, **shares(mn), "wall_s": [mn["wall_seconds"]]}]
    big_row = {"ranks": 2, "samples": big, "wall_s": b.get("wall_seconds"), "samples_per_s": b.get("samples_per_second"),
               "file_bytes": size, "bytes_per_sample": size / big if big else None, "time_output": big_time,
               **(shares(b) if b else {})}
    Path(a.out).write_text(json.dumps({**c.provenance(load_start), "study": str(STUDY.relative_to(c.ROOT)),
                                       "rounds": a.rounds, "rows": rows, "big": big_row,
                                       "summaries": {"one": one, "two": two, "many": mn, "big": b}}, indent=1))
    c.log("bench_ensemble", f"wrote {a.out}; tables: bench/make_tables.py")


if __name__ == "__main__":
    main()
