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
Prints markdown tables.
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


def split(r) -> str:
    busy = r["compute_seconds"] + r["io_seconds"] + r["schedule_seconds"]
    return f'{100 * r["io_seconds"] / busy:.2f} % HDF5, {100 * r["schedule_seconds"] / busy:.2f} % scheduling'


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--samples", type=int, default=int(c.env_default("SAMPLES", 2000)))
    ap.add_argument("--rounds", type=int, default=int(c.env_default("ROUNDS", 3)))
    ap.add_argument("--big", type=int, default=int(c.env_default("BIG", 100000)))
    ap.add_argument("--ranks-many", type=int, default=int(c.env_default("RANKS_MANY", 8)))
    ap.add_argument("--kanesens", default=c.env_default("KANESENS", str(c.kanesens_exe(c.ROOT / "build"))))
    a = ap.parse_args(argv)
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
    print("| ranks | samples | median wall (s) | samples/s | efficiency | rank time in writes / scheduling |")
    print("|---:|---:|---:|---:|---:|---|")
    print(f"| 1 | {n} | {t1:.2f} | {n / t1:.0f} | 1.00 | {split(one[0])} |")
    print(f"| 2 | {n} | {t2:.2f} | {n / t2:.0f} | {t1 / (2 * t2):.2f} | {split(two[0])} |")
    tm = mn["wall_seconds"]
    print(f"| {many} (oversubscribed) | {n} | {tm:.2f} | {n / tm:.0f} | — | {split(mn)} |")
    print()
    print(f"{big} samples on 2 ranks: {b.get('wall_seconds', float('nan')):.1f} s wall, "
          f"{b.get('samples_per_second', float('nan')):.0f} samples/s, file {size / 1e6:.1f} MB "
          f"({size / big:.0f} bytes per sample); {big_time}; {split(b) if b else ''}")


if __name__ == "__main__":
    main()
