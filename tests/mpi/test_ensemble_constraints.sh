#!/usr/bin/env bash
# Constrained ensembles under MPI give bitwise identical files on 1 and 2 ranks: the knife-edge
# vehicle with the embedding re-choosing its independent speeds (bdf and dop853; every sample
# re-partitions), and the two-wheeled vehicle with sampled steer, every sample starting with both
# contacts on the ground; and the N four-bar (N = 30) with matrix-free Newton (linear_solver:
# krylov) and a sensitivity.
set -euo pipefail
: "${KANESENS:?path to the kanesens executable}"
source "$(dirname "$0")/common.sh"
run() { local np=$1 study=$2; shift 2; mpirun --allow-run-as-root --oversubscribe -np "$np" "$KANESENS" run "$study" "$@"; }
check() { "$KANESENS_PYTHON" "$here/check_ensemble.py" "$@"; }

for method in bdf dop853; do
  run 1 "$configs/knife_edge_study.yaml" -o "$work/k1_$method.h5" --set solver.method=$method
  run 2 "$configs/knife_edge_study.yaml" -o "$work/k2_$method.h5" --set solver.method=$method --chunk 1
  check status "$work/k1_$method.h5" 8 0 0
  check same "$work/k1_$method.h5" "$work/k2_$method.h5"
  check stat-at-least "$work/k1_$method.h5" repartitions 8
done

run 1 "$configs/two_wheeler_study.yaml" -o "$work/w1.h5"
run 2 "$configs/two_wheeler_study.yaml" -o "$work/w2.h5" --chunk 1
check status "$work/w1.h5" 8 0 0
check same "$work/w1.h5" "$work/w2.h5"
check initial-residual "$work/w1.h5" 1e-12
"$KANESENS_PYTHON" "$here/../../bench/n_four_bar.py" 30 --scene "$work/n_four_bar_30.yaml"
cat > "$work/n_four_bar_study.yaml" <<YAML
kanesens: 1
scene: $work/n_four_bar_30.yaml
time: {end: 0.3, outputs: 4}
solver: {method: bdf, linear_solver: krylov}
sampling: {method: mc, samples: 4, seed: 2}
vary:
  m: {dist: uniform, low: 0.9, high: 1.1}
sensitivities: [m]
YAML
run 1 "$work/n_four_bar_study.yaml" -o "$work/f1.h5"
run 2 "$work/n_four_bar_study.yaml" -o "$work/f2.h5" --chunk 1
check status "$work/f1.h5" 4 0 0
check same "$work/f1.h5" "$work/f2.h5"
echo "test_ensemble_constraints: ok"
