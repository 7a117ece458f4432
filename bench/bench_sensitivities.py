#!/usr/bin/python3
"""Cost of forward sensitivities and time per trajectory (docs/benchmarks.md, "Sensitivities").

    /usr/bin/python3 bench/bench_sensitivities.py [-k 5] [--kanesens build/kanesens] [--ns 2,8,32]
    env (defaults of the options): K KANESENS
    quick smoke test: bench/bench_sensitivities.py -k 1 --ns 2

1. The 4-link chain over 10 s at rtol 1e-8 with S = 0, 1, 3, 10 sensitivities: CVODES BDF with
   exact (dual numbers) and CVODES difference-quotient sensitivity right-hand sides, staggered
   corrector; and DOP853 (solver.method: dop853, sensitivities by its own stages, exact RHS).
2. Time per trajectory of the N-link chain (N = 2, 8, 32) at rtol 1e-8, no sensitivities.
Medians of K runs of `kanesens simulate` (stats.wall_seconds: the integration). Writes
bench/results/bench_sensitivities.json (--out); bench/make_tables.py makes the tables.
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


def sensitivity_rows(exe, study, k) -> list[dict]:
    def run(sens, rhs, method="bdf"):
        args = [exe, "simulate", study, "--set", f"solver.sensitivity.rhs={rhs}", "--set", f"solver.method={method}",
                "--sens", sens]
        walls, st = [], None
        for _ in range(k):
            d = json.loads(subprocess.run([str(a) for a in args], capture_output=True, text=True).stdout)
            if d["status"] != 1:
                return None, d, walls
            walls.append(d["stats"]["wall_seconds"])
            st = d["stats"]
        return c.median(walls), st, walls

    rows = []
    for method, kinds in (("bdf", ("exact", "dq")), ("dop853", ("exact",))):
        base, bst, walls = run("none", "exact", method)
        rows.append({"method": method, "S": 0, "sens_rhs": "—", "median_wall_s": base, "wall_s": walls,
                     "wall_over_plain": 1.0, "steps": bst["steps"], "rhs_evals": bst["rhs_evals"],
                     "sens_rhs_evals": 0, "rhs_evals_dq": 0})
        for sens in SETS[1:]:
            S = len(sens.split(","))
            for rhs in kinds:
                c.log("bench_sensitivities", f"{method} S={S} {rhs}")
                w, st, walls = run(sens, rhs, method)
                if w is None:
                    rows.append({"method": method, "S": S, "sens_rhs": rhs, "failed": st["message"].split(":")[0],
                                 "message": st["message"]})
                    continue
                rows.append({"method": method, "S": S, "sens_rhs": rhs, "median_wall_s": w, "wall_s": walls,
                             "wall_over_plain": w / base, "per_added": (w / base - 1) / S, "steps": st["steps"],
                             "rhs_evals": st["rhs_evals"], "sens_rhs_evals": st["sens_rhs_evals"],
                             "rhs_evals_dq": st["rhs_evals_for_sens"]})
    return rows


def trajectory_row(exe, study, k, n) -> dict:
    walls = []
    for _ in range(k):
        d = c.run_json([exe, "simulate", study])
        walls.append(d["stats"]["wall_seconds"])
        st = d["stats"]
    return {"n": n, "median_wall_s": c.median(walls), "wall_s": walls, "steps": st["steps"],
            "rhs_evals": st["rhs_evals"], "jacobians": st["jac_evals"]}


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("-k", type=int, default=int(c.env_default("K", 5)), help="runs per median")
    ap.add_argument("--kanesens", default=c.env_default("KANESENS", str(c.kanesens_exe(c.ROOT / "build"))))
    ap.add_argument("--ns", default="2 8 32", help="chain sizes of the time-per-trajectory table")
    ap.add_argument("--out", default=str(c.ROOT / "bench" / "results" / "bench_sensitivities.json"))
    a = ap.parse_args(argv)
    load_start = c.loadavg()
    with tempfile.TemporaryDirectory() as tmp:
        work = Path(tmp)
        (work / "chain4.yaml").write_text(study_text(c.CONFIGS / "nlink_chain_4.yaml"))
        rows = sensitivity_rows(a.kanesens, work / "chain4.yaml", a.k)
        chains = []
        for n in [int(x) for x in c.words(a.ns)]:
            (work / f"chain{n}.yaml").write_text(c.gen_chain_yaml(n, damper=0.01))
            (work / f"s{n}.yaml").write_text(study_text(f"chain{n}.yaml"))
            chains.append(trajectory_row(a.kanesens, work / f"s{n}.yaml", a.k, n))
    Path(a.out).write_text(json.dumps({**c.provenance(load_start), "runs_per_median": a.k,
                                       "study": "configs/nlink_chain_4.yaml, 10 s, 101 outputs, rtol 1e-8, atol 1e-10",
                                       "rows": rows, "chains": chains}, indent=1))
    c.log("bench_sensitivities", f"wrote {a.out}; tables: bench/make_tables.py")


if __name__ == "__main__":
    main()
