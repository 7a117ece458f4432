#!/usr/bin/env bash
# Runs every work-precision study of docs/workprecision.md and draws the diagrams:
#   scripts/run_workprecision.sh [PROBLEM ...]     # default: all; KANESENS=build/kanesens REPEAT=5
# Writes docs/workprecision/<problem>.json (kanesens bench workprecision --json) and .png.
set -euo pipefail
cd "$(dirname "$0")/.."
K=${KANESENS:-build/kanesens}
R=${REPEAT:-5}
OUT=docs/workprecision
mkdir -p "$OUT"
ALL="chain4 chain16 chain4_stiff chain4_stiff_swing double_pendulum_chaos double_pendulum_lyapunov spinning_top double_pendulum_long constrained_pendulum four_bar four_bar_embedding andrews rolling_disc"
T7=1e-4,1e-5,1e-6,1e-7,1e-8,1e-9,1e-10
# Non-stiff problems take their reference from DOP853 at rtol 1e-13 (a BDF reference is only
# good to ~1e-9 there, which would hide the tight end of the diagrams); the stiff chains keep BDF.
NS="--reference-method dop853"
run() {  # name, args...
  local name=$1; shift
  echo "== $name: $K bench workprecision $* --repeat $R --json" >&2
  "$K" bench workprecision "$@" --repeat "$R" --json > "$OUT/$name.json"
  /usr/bin/python3 scripts/plot_workprecision.py "$OUT/$name.json" -o "$OUT" >&2
}
for p in ${@:-$ALL}; do
  case $p in
    chain4) run chain4 configs/wp_chain4.yaml --tolerances $T7 $NS ;;
    chain16) run chain16 configs/wp_chain16.yaml --tolerances $T7 $NS ;;
    chain4_stiff) run chain4_stiff configs/wp_chain4_stiff.yaml --tolerances 1e-4,1e-6,1e-8 \
                    --rk4-steps 500,1000,2000,3000,4000,8000 ;;
    chain4_stiff_swing) run chain4_stiff_swing configs/wp_chain4_stiff_swing.yaml --tolerances $T7 \
                    --rk4-steps 200,1000,2000,3000,4000,8000,16000 ;;
    double_pendulum_chaos) run double_pendulum_chaos configs/wp_double_pendulum_chaos.yaml --tolerances $T7 \
                    --max-steps 200000 $NS ;;
    double_pendulum_lyapunov) run double_pendulum_lyapunov configs/wp_double_pendulum_lyapunov.yaml \
                    --tolerances 1e-6,1e-8,1e-10 --methods bdf-exact,adams-newton,dop853,rk4 --with-sens \
                    --reference-rtol 1e-12 $NS ;;
    spinning_top) run spinning_top configs/wp_spinning_top.yaml --tolerances $T7 --rk4-h-scale 0.01 $NS ;;
    double_pendulum_long) run double_pendulum_long configs/wp_double_pendulum_long.yaml \
                    --tolerances 1e-6,1e-7,1e-8,1e-9,1e-10 --methods bdf-exact,adams-newton,adams-functional,dop853,rk4 $NS ;;
    constrained_pendulum) run constrained_pendulum configs/wp_constrained_pendulum.yaml --tolerances $T7 $NS ;;
    # Closed loops and a nonholonomic contact: the four-bar with its sensitivities (c, m2) under
    # multipliers + projection and under embedding, Andrews' mechanism (0.03 s: DOP853 is not
    # stability-bound there, and a BDF reference floors the errors at ~1e-8), the rolling disc
    # (nonholonomic rows, Baumgarte; states only: its study's sensitivity, to the mass, is
    # identically 0 — every force scales with m — so its relative error would compare noise).
    four_bar) run four_bar configs/four_bar_study.yaml --tolerances $T7 $NS ;;
    four_bar_embedding) run four_bar_embedding configs/four_bar_study.yaml --tolerances $T7 $NS \
                    --set solver.constraints.formulation=embedding --set solver.constraints.stabilization=none ;;
    andrews) run andrews configs/andrews_study.yaml --tolerances $T7 $NS ;;
    rolling_disc) run rolling_disc configs/rolling_disc_study.yaml --tolerances $T7 $NS \
                    --methods bdf-exact,bdf-dq,adams-newton,adams-functional,dop853,rk4 ;;
    *) echo "unknown problem $p" >&2; exit 2 ;;
  esac
done
# Second views: deterministic work (RHS evaluations), energy drift, quaternion norm drift.
P="/usr/bin/python3 scripts/plot_workprecision.py"
for p in chain4 chain16 chain4_stiff_swing; do
  [ -f "$OUT/$p.json" ] && $P "$OUT/$p.json" -o "$OUT" --work rhs_evals_total --suffix _rhs >&2
done
[ -f "$OUT/double_pendulum_long.json" ] && $P "$OUT/double_pendulum_long.json" -o "$OUT" --error energy_drift --suffix _energy >&2
[ -f "$OUT/spinning_top.json" ] && $P "$OUT/spinning_top.json" -o "$OUT" --error quaternion_norm_drift --suffix _quaternion >&2
true
