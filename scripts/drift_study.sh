#!/usr/bin/env bash
# Constraint drift of the crank-rocker four-bar over 100 s with stabilization none / baumgarte /
# projection (rtol 1e-8): runs `kanesens simulate ... --format json` three times and writes
# docs/figures/constraint_drift.png and the markdown table printed at the end
# (docs/constraints.md, "Drift over a long run").
#
#   bash scripts/drift_study.sh [BUILD_DIR]      # default: build
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${1:-$root/build}"
kanesens="$build/apps/kanesens/kanesens"
[ -x "$kanesens" ] || kanesens="$build/kanesens"
[ -x "$kanesens" ] || { echo "kanesens not found under $build (build first)" >&2; exit 1; }
python="${KANESENS_PYTHON:-/usr/bin/python3}"
out="$root/out/drift"
mkdir -p "$out" "$root/docs/figures"
for s in none baumgarte projection; do
  "$kanesens" simulate "$root/configs/four_bar_drift_study.yaml" \
      --set solver.constraints.stabilization=$s --format json > "$out/$s.json"
done
"$python" - "$out" "$root/docs/figures/constraint_drift.png" <<'PY'
import json, sys
import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
out, png = sys.argv[1], sys.argv[2]
names = ["none", "baumgarte", "projection"]
runs = {s: json.load(open(f"{out}/{s}.json")) for s in names}
fig, axes = plt.subplots(1, 3, figsize=(14, 4.2))
print("| stabilization | max position residual (m) | max velocity residual (m/s) | max abs(E - E0) (J) | steps | RHS evals | wall (s) |")
print("|---|---|---|---|---|---|---|")
for s in names:
    r = runs[s]
    assert r["status"] == 1, (s, r["message"])
    t = np.array(r["time"])
    pos = np.array(r["constraint_residuals"]["position"])
    vel = np.array(r["constraint_residuals"]["velocity"])
    e = np.array(r["outputs"]["energy"])
    de = np.abs(e - e[0])
    st = r["stats"]
    print(f"| {s} | {pos.max():.1e} | {vel.max():.1e} | {de.max():.1e} | {st['steps']} | {st['rhs_evals']} | {st['wall_seconds']:.2f} |")
    floor = 1e-17
    axes[0].semilogy(t, np.maximum(pos, floor), label=s)
    axes[1].semilogy(t, np.maximum(vel, floor), label=s)
    axes[2].semilogy(t, np.maximum(de, floor), label=s)
for ax, title in zip(axes, ["position residual max|g(q)| (m)", "velocity residual max|A u| (m/s)", "energy drift |E(t) - E(0)| (J)"]):
    ax.set_title(title, fontsize=10)
    ax.set_xlabel("t (s)")
    ax.grid(True, which="major", alpha=0.3)
    ax.legend(fontsize=9)
fig.suptitle("Crank-rocker four-bar, 100 s, BDF rtol 1e-8 atol 1e-10 (configs/four_bar_drift_study.yaml)", fontsize=11)
fig.tight_layout()
fig.savefig(png, dpi=110)
print(f"\nfigure: {png}")
PY
