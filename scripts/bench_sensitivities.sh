#!/usr/bin/env bash
# Cost of forward sensitivities and time per trajectory (docs/benchmarks.md, "Sensitivities").
# 1. The 4-link chain over 10 s at rtol 1e-8 with S = 0, 1, 3, 10 sensitivities: CVODES BDF with
#    exact (dual numbers) and CVODES difference-quotient sensitivity right-hand sides, staggered
#    corrector; and DOP853 (solver.method: dop853, sensitivities by its own stages, exact RHS).
# 2. Time per trajectory of the N-link chain (N = 2, 8, 32) at rtol 1e-8, no sensitivities.
# Medians of K runs (default 5) from `kanesens simulate` stats (wall_seconds: the integration).
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
k=${K:-5}
py=${KANESENS_PYTHON:-/usr/bin/python3}
exe=${KANESENS:-$root/build/kanesens}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cat > "$work/chain4.yaml" <<YAML
kanesens: 1
scene: $root/configs/nlink_chain_4.yaml
time: {end: 10.0, outputs: 101}
solver: {rtol: 1.0e-8, atol: 1.0e-10}
YAML
sets=("none" "m" "m,L,c" "m,L,c,k,j1.q0,j2.q0,j3.q0,j4.q0,j1.u0,j2.u0")
"$py" - "$exe" "$work/chain4.yaml" "$k" "${sets[@]}" <<'PY'
import json, statistics, subprocess, sys
exe, study, k, sets = sys.argv[1], sys.argv[2], int(sys.argv[3]), sys.argv[4:]
def run(sens, rhs, method="bdf"):
    args = [exe, "simulate", study, "--set", f"solver.sensitivity.rhs={rhs}", "--set", f"solver.method={method}",
            "--sens", sens]
    walls, st = [], None
    for _ in range(k):
        p = subprocess.run(args, capture_output=True, text=True)
        d = json.loads(p.stdout)
        if d["status"] != 1:
            return None, d
        walls.append(d["stats"]["wall_seconds"]); st = d["stats"]
    return statistics.median(walls), st
print("| method | S | sens RHS | median wall (ms) | wall / plain | per added sensitivity | steps | RHS evals | sens RHS evals | RHS evals for DQ |")
print("|---|---:|---|---:|---:|---:|---:|---:|---:|---:|")
for method, kinds in (("bdf", ("exact", "dq")), ("dop853", ("exact",))):
    base, bst = run("none", "exact", method)
    print(f"| {method} | 0 | — | {base*1e3:.2f} | 1.00 | — | {bst['steps']} | {bst['rhs_evals']} | 0 | 0 |")
    for sens in sets[1:]:
        S = len(sens.split(","))
        for rhs in kinds:
            w, st = run(sens, rhs, method)
            if w is None:
                print(f"| {method} | {S} | {rhs} | failed: {st['message'].split(':')[0]} | | | | | | |")
                continue
            print(f"| {method} | {S} | {rhs} | {w*1e3:.2f} | {w/base:.2f} | {(w/base-1)/S:.2f} | {st['steps']} | "
                  f"{st['rhs_evals']} | {st['sens_rhs_evals']} | {st['rhs_evals_for_sens']} |")
PY
echo
echo "| N | median wall per trajectory (ms), 10 s, rtol 1e-8 | steps | RHS evals | Jacobians |"
echo "|---:|---:|---:|---:|---:|"
for n in 2 8 32; do
  "$py" "$root/scripts/gen_chain.py" "$n" --damper 0.01 > "$work/chain$n.yaml"
  cat > "$work/s$n.yaml" <<YAML
kanesens: 1
scene: chain$n.yaml
time: {end: 10.0, outputs: 101}
solver: {rtol: 1.0e-8, atol: 1.0e-10}
YAML
  "$py" - "$exe" "$work/s$n.yaml" "$k" "$n" <<'PY'
import json, statistics, subprocess, sys
exe, study, k, n = sys.argv[1:5]
walls = []
for _ in range(int(k)):
    d = json.loads(subprocess.run([exe, "simulate", study], check=True, capture_output=True, text=True).stdout)
    walls.append(d["stats"]["wall_seconds"]); st = d["stats"]
print(f"| {n} | {statistics.median(walls)*1e3:.1f} | {st['steps']} | {st['rhs_evals']} | {st['jac_evals']} |")
PY
done
