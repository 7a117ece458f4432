#!/usr/bin/python3
"""Constrained systems at rtol 1e-8 (docs/benchmarks.md, "Constraints").

    /usr/bin/python3 bench/bench_constraints.py [-k 5] [--kanesens build/kanesens]
    env (defaults of the options): K KANESENS
    quick smoke test: bench/bench_constraints.py -k 1

The four-bar (3 s) and Andrews' mechanism (0.03 s), multipliers vs embedding, with and without
sensitivities; projection. Medians of K runs of `kanesens simulate` (wall_seconds = the
integration). Writes bench/results/bench_constraints.json (--out); bench/make_tables.py makes
the table.
"""
from __future__ import annotations

import argparse
import json
import subprocess
from pathlib import Path

import common as c

CASES = [("four_bar_study.yaml", "c,m2"), ("andrews_study.yaml", "mom,c0")]


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("-k", type=int, default=int(c.env_default("K", 5)), help="runs per median")
    ap.add_argument("--kanesens", default=c.env_default("KANESENS", str(c.kanesens_exe(c.ROOT / "build"))))
    ap.add_argument("--out", default=str(c.ROOT / "bench" / "results" / "bench_constraints.json"))
    a = ap.parse_args(argv)
    load_start = c.loadavg()
    rows = []
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
                rows.append({"problem": study.replace("_study.yaml", ""), "formulation": form,
                             "sensitivities": 0 if s == "none" else len(s.split(",")), "sens": s,
                             "median_wall_s": c.median(walls), "wall_s": walls, "steps": st["steps"],
                             "rhs_evals": st["rhs_evals"], "sens_rhs_evals": st["sens_rhs_evals"], "max_abs_g": g})
    Path(a.out).write_text(json.dumps({**c.provenance(load_start), "runs_per_median": a.k, "rows": rows}, indent=1))
    c.log("bench_constraints", f"wrote {a.out}; tables: bench/make_tables.py")


if __name__ == "__main__":
    main()
