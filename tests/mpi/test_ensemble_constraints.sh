#!/usr/bin/env bash
# Constrained ensembles under MPI give bitwise identical files on 1 and 2 ranks: the knife-edge
# vehicle with the embedding re-choosing its independent speeds (bdf and dop853; every sample
# re-partitions), and the two-wheeled vehicle with sampled steer, every sample starting with both
# contacts on the ground.
set -euo pipefail
: "${KANESENS:?path to the kanesens executable}"
: "${KANESENS_PYTHON:=/usr/bin/python3}"
here=$(cd "$(dirname "$0")" && pwd)
configs="$here/../../configs"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
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
echo "test_ensemble_constraints: ok"
