#!/usr/bin/env bash
# Constrained systems at rtol 1e-8 (docs/benchmarks.md, "Constraints"): the four-bar (3 s) and
# Andrews' mechanism (0.03 s), multipliers vs embedding, with and without sensitivities;
# projection. Medians of K runs of `kanesens simulate` (wall_seconds = the integration).
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
K=${K:-5} /usr/bin/python3 - "$root/build/kanesens" "$root/configs" <<'PY'
import json, os, statistics, subprocess, sys
exe, cfg = sys.argv[1], sys.argv[2]
k = int(os.environ.get("K", "5"))
cases = [("four_bar_study.yaml", "c,m2"), ("andrews_study.yaml", "mom,c0")]
print("| problem | formulation | sensitivities | median wall (ms) | steps | RHS evals | sens RHS evals | max abs(g) at outputs |")
print("|---|---|---:|---:|---:|---:|---:|---:|")
for study, sens in cases:
    for form in ("multipliers", "embedding"):
        for s in ("none", sens):
            args = [exe, "simulate", f"{cfg}/{study}", "--set", "solver.rtol=1e-8", "--set", "solver.atol=1e-10",
                    "--set", f"solver.constraints.formulation={form}", "--set", "solver.constraints.stabilization=projection",
                    "--sens", s]
            walls = []
            for _ in range(k):
                p = subprocess.run(args, capture_output=True, text=True)
                d = json.loads(p.stdout)
                walls.append(d["stats"]["wall_seconds"])
            st = d["stats"]
            g = max(x for x in d["constraint_residuals"]["position"] if x is not None)
            ns = 0 if s == "none" else len(s.split(","))
            print(f"| {study.replace('_study.yaml','')} | {form} | {ns} | {statistics.median(walls)*1e3:.1f} | {st['steps']} | {st['rhs_evals']} | {st['sens_rhs_evals']} | {g:.1e} |")
PY
