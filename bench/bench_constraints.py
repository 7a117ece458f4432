#!/usr/bin/python3
"""Constrained systems at rtol 1e-8 (docs/benchmarks.md, "Constraints").

    /usr/bin/python3 bench/bench_constraints.py [-k 5] [--kanesens build/kanesens]
    env (defaults of the options): K KANESENS
    quick smoke test: bench/bench_constraints.py -k 1

The four-bar (3 s) and Andrews' mechanism (0.03 s), multipliers vs embedding, with and without
sensitivities; projection. Medians of K runs of `kanesens simulate` (wall_seconds = the
integration). Prints a markdown table.
"""
from __future__ import annotations

import argparse
import json
import subprocess

import common as c

CASES = [("four_bar_study.yaml", "c,m2"), ("andrews_study.yaml", "mom,c0")]


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("-k", type=int, default=int(c.env_default("K", 5)), help="runs per median")
    ap.add_argument("--kanesens", default=c.env_default("KANESENS", str(c.kanesens_exe(c.ROOT / "build"))))
    a = ap.parse_args(argv)
    print("| problem | formulation | sensitivities | median wall (ms) | steps | RHS evals | sens RHS evals | "
          "max abs(g) at outputs |")
    print("|---|---|---:|---:|---:|---:|---:|---:|")
    for study, sens in CASES:
        for form in ("multipliers", "embedding"):
            for s in ("none", sens):
                args = [a.kanesens, "simulate", str(c.CONFIGS / study), "--set", "solver.rtol=1e-8",
                        "--set", "solver.atol=1e-10", "--set", f"solver.constraints.formulation={form}",
                        "--set", "solver.constraints.stabilization=projection", "--sens", s]
                walls = []
                for _ in range(a.k):
                    d = json.loads(subprocess.run(args, capture_output=True, text=True).stdout)
                    walls.append(d["stats"]["wall_seconds"])
                st = d["stats"]
                g = max(x for x in d["constraint_residuals"]["position"] if x is not None)
                ns = 0 if s == "none" else len(s.split(","))
                print(f"| {study.replace('_study.yaml', '')} | {form} | {ns} | {c.median(walls) * 1e3:.1f} | "
                      f"{st['steps']} | {st['rhs_evals']} | {st['sens_rhs_evals']} | {g:.1e} |")


if __name__ == "__main__":
    main()
