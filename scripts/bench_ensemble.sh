#!/usr/bin/env bash
# Ensemble scaling and overheads (docs/benchmarks.md, "Ensemble"):
#  1. strong scaling 1 -> 2 ranks, SAMPLES (default 2000) samples of the 4-link chain, ROUNDS
#     alternating runs each, medians; efficiency = t1 / (2 t2); the run summary's split of rank
#     time into integration, HDF5 writes and scheduling;
#  2. throughput and file size for BIG (default 100000) samples on 2 ranks;
#  3. scheduling/IO behaviour with many oversubscribed ranks (RANKS_MANY, default 8) — what the
#     one-sided counter and independent writes cost when ranks outnumber cores.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
exe="$root/build/kanesens"
study="$root/configs/chain4_scaling_study.yaml"
samples=${SAMPLES:-2000}; rounds=${ROUNDS:-3}; big=${BIG:-100000}; many=${RANKS_MANY:-8}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
run() { local np=$1; shift; mpirun --oversubscribe -np "$np" "$exe" run "$study" --json --overwrite "$@"; }
for r in $(seq "$rounds"); do
  run 1 -o "$work/r1.h5" --samples "$samples" >> "$work/np1.jsonl"
  run 2 -o "$work/r2.h5" --samples "$samples" >> "$work/np2.jsonl"
done
run "$many" -o "$work/rm.h5" --samples "$samples" >> "$work/npmany.jsonl"
/usr/bin/time -f "%e s wall, %M KiB max RSS (one rank)" mpirun --oversubscribe -np 2 "$exe" run "$study" --json --overwrite \
  -o "$work/big.h5" --samples "$big" > "$work/big.json" 2> "$work/big.time" || true
ls -l "$work/big.h5" | awk '{print $5}' > "$work/big.size"
/usr/bin/python3 - "$work" "$samples" "$big" "$many" <<'PY'
import json, statistics, sys, pathlib
w, n, big, many = pathlib.Path(sys.argv[1]), sys.argv[2], sys.argv[3], sys.argv[4]
def rows(name): return [json.loads(l) for l in (w / name).read_text().splitlines() if l.strip()]
one, two, mn = rows("np1.jsonl"), rows("np2.jsonl"), rows("npmany.jsonl")
t1 = statistics.median(r["wall_seconds"] for r in one); t2 = statistics.median(r["wall_seconds"] for r in two)
def split(r):
    busy = r["compute_seconds"] + r["io_seconds"] + r["schedule_seconds"]
    return f'{100*r["io_seconds"]/busy:.2f} % HDF5, {100*r["schedule_seconds"]/busy:.2f} % scheduling'
print(f"| ranks | samples | median wall (s) | samples/s | efficiency | rank time in writes / scheduling |")
print(f"|---:|---:|---:|---:|---:|---|")
print(f"| 1 | {n} | {t1:.2f} | {int(n)/t1:.0f} | 1.00 | {split(one[0])} |")
print(f"| 2 | {n} | {t2:.2f} | {int(n)/t2:.0f} | {t1/(2*t2):.2f} | {split(two[0])} |")
tm = mn[0]["wall_seconds"]
print(f"| {many} (oversubscribed) | {n} | {tm:.2f} | {int(n)/tm:.0f} | — | {split(mn[0])} |")
b = json.loads((w / "big.json").read_text()) if (w / "big.json").read_text().strip() else {}
size = int((w / "big.size").read_text() or 0)
print()
print(f"{big} samples on 2 ranks: {b.get('wall_seconds', float('nan')):.1f} s wall, "
      f"{b.get('samples_per_second', float('nan')):.0f} samples/s, file {size/1e6:.1f} MB "
      f"({size/int(big):.0f} bytes per sample); {(w/'big.time').read_text().strip().splitlines()[-1]}; {split(b) if b else ''}")
PY
