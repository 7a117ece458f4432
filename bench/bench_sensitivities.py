#!/usr/bin/python3
"""Cost of forward sensitivities and time per trajectory (docs/benchmarks.md, "Sensitivities").

    /usr/bin/python3 bench/bench_sensitivities.py [-k 5] [--kanesens build/kanesens] [--ns 2,8,32]
    env (defaults of the options): K KANESENS
    quick smoke test: bench/bench_sensitivities.py -k 1 --ns 2

1. The 4-link chain over 10 s at rtol 1e-8 with S = 0, 1, 3, 10 sensitivities: CVODES BDF with
   exact (dual numbers) and CVODES difference-quotient sensitivity right-hand sides, staggered
   corrector; and DOP853 (solver.method: dop853, sensitivities by its own stages, exact RHS).
2. Time per trajectory of the N-link chain (N = 2, 8, 32) at rtol 1e-8, no sensitivities.
Medians of K runs of `kanesens simulate` (stats.wall_seconds: the integration). Prints markdown
tables.
"""
from __future__ import annotations

import argparse
import json
import subprocess
import tempfile
from pathlib import Path

import common as c

SETS = ["none", "m", "m,L,c", "m,L,c,k,j1.q0,j2.q0,j3.q0,j4.q0,j1.u0,j2.u0"]


def study_text(scene) -> str:
    return (f"kanesens: 1\nscene: {scene}\ntime: {{end: 10.0, outputs: 101}}\n"
            "solver: {rtol: 1.0e-8, atol: 1.0e-10}\n")


def sensitivity_table(exe, study, k):
    def run(sens, rhs, method="bdf"):
        args = [exe, "simulate", study, "--set", f"solver.sensitivity.rhs={rhs}", "--set", f"solver.method={method}",
                "--sens", sens]
        walls, st = [], None
        for _ in range(k):
            d = json.loads(subprocess.run([str(a) for a in args], capture_output=True, text=True).stdout)
            if d["status"] != 1:
                return None, d
            walls.append(d["stats"]["wall_seconds"])
            st = d["stats"]
        return c.median(walls), st

    print("| method | S | sens RHS | median wall (ms) | wall / plain | per added sensitivity | steps | RHS evals | "
          "sens RHS evals | RHS evals for DQ |")
    print("|---|---:|---|---:|---:|---:|---:|---:|---:|---:|")
    for method, kinds in (("bdf", ("exact", "dq")), ("dop853", ("exact",))):
        base, bst = run("none", "exact", method)
        print(f"| {method} | 0 | — | {base * 1e3:.2f} | 1.00 | — | {bst['steps']} | {bst['rhs_evals']} | 0 | 0 |")
        for sens in SETS[1:]:
            S = len(sens.split(","))
            for rhs in kinds:
                w, st = run(sens, rhs, method)
                if w is None:
                    print(f"| {method} | {S} | {rhs} | failed: {st['message'].split(':')[0]} | | | | | | |")
                    continue
                print(f"| {method} | {S} | {rhs} | {w * 1e3:.2f} | {w / base:.2f} | {(w / base - 1) / S:.2f} | "
                      f"{st['steps']} | {st['rhs_evals']} | {st['sens_rhs_evals']} | {st['rhs_evals_for_sens']} |")


def trajectory_row(exe, study, k, n):
    walls = []
    for _ in range(k):
        d = c.run_json([exe, "simulate", study])
        walls.append(d["stats"]["wall_seconds"])
        st = d["stats"]
    print(f"| {n} | {c.median(walls) * 1e3:.1f} | {st['steps']} | {st['rhs_evals']} | {st['jac_evals']} |")


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("-k", type=int, default=int(c.env_default("K", 5)), help="runs per median")
    ap.add_argument("--kanesens", default=c.env_default("KANESENS", str(c.kanesens_exe(c.ROOT / "build"))))
    ap.add_argument("--ns", default="2 8 32", help="chain sizes of the time-per-trajectory table")
    a = ap.parse_args(argv)
    with tempfile.TemporaryDirectory() as tmp:
        work = Path(tmp)
        (work / "chain4.yaml").write_text(study_text(c.CONFIGS / "nlink_chain_4.yaml"))
        sensitivity_table(a.kanesens, work / "chain4.yaml", a.k)
        print()
        print("| N | median wall per trajectory (ms), 10 s, rtol 1e-8 | steps | RHS evals | Jacobians |")
        print("|---:|---:|---:|---:|---:|")
        for n in [int(x) for x in c.words(a.ns)]:
            (work / f"chain{n}.yaml").write_text(c.gen_chain_yaml(n, damper=0.01))
            (work / f"s{n}.yaml").write_text(study_text(f"chain{n}.yaml"))
            trajectory_row(a.kanesens, work / f"s{n}.yaml", a.k, n)


if __name__ == "__main__":
    main()
