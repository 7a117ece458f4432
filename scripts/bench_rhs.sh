#!/usr/bin/env bash
# Right-hand-side speed of kanesens against MuJoCo's mj_forward on planar N-link chains
# (docs/benchmarks.md). Builds kanesens and the MuJoCo peer (-DKANESENS_PEERS=ON; needs
# libmujoco-dev: KANESENS_PEERS=1 scripts/install-deps.sh) into build-bench/, then, in one run,
# alternates for every N and every round: `kanesens bench rhs` on the chain, the MuJoCo bench
# on the same chain and state, and `kanesens bench rhs` on the chain with its last axis tilted
# 1e-3 rad out of the plane (which forces the general 3-D evaluation). Each program reports a
# median over batches; the table shows the median of those over the rounds.
#
#   scripts/bench_rhs.sh [OUT_DIR]      env: NS="1 2 4 8 16 32" ROUNDS=3 REPEAT=31
# Writes OUT_DIR/bench_rhs.md (markdown table) and OUT_DIR/bench_rhs.json (all raw results).
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
out=${1:-$root/out/bench}
build=${KANESENS_BUILD_DIR:-$root/build-bench}
python=${KANESENS_PYTHON:-/usr/bin/python3}
ns=${NS:-"1 2 4 8 16 32"}
rounds=${ROUNDS:-3}
repeat=${REPEAT:-31}
mkdir -p "$out/scenes" "$out/raw"

cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=Release -DKANESENS_PEERS=ON -DKANESENS_BUILD_TESTS=OFF >/dev/null
cmake --build "$build" -j "${KANESENS_JOBS:-1}" --target kanesens mujoco_chain_bench >/dev/null
kanesens=$build/kanesens
mujoco=$build/apps/peers/mujoco_chain_bench

# The benchmark chain, as in tests/support/test_scenes.hpp (chain_scene) and the MuJoCo peer.
write_chain() {  # N TILT FILE
  "$python" - "$1" "$2" >"$3" <<'PY'
import math, sys
n, tilt = int(sys.argv[1]), float(sys.argv[2])
print("kanesens: 1\nscene:\n  name: chain%d\n  gravity: [0, -9.81, 0]" % n)
print("  parameters: {m: 1.0, L: 1.0}\n  bodies:")
for i in range(1, n + 1):
    print('    - {name: link%d, mass: m, inertia: {xx: "m*L^2/12", yy: 1.0e-4, zz: "m*L^2/12"}}' % i)
print("  joints:")
for i in range(1, n + 1):
    axis = "[%.17g, 0, %.17g]" % (math.sin(tilt), math.cos(tilt)) if tilt and i == n else "[0, 0, 1]"
    parent = "ground" if i == 1 else "link%d" % (i - 1)
    pp = "0" if i == 1 else '"-L/2"'
    print('    - {name: j%d, type: revolute, parent: %s, child: link%d, axis: %s, '
          'parent_point: [0, %s, 0], child_point: [0, "L/2", 0]}' % (i, parent, i, axis, pp))
PY
}

for n in $ns; do
  write_chain "$n" 0 "$out/scenes/chain$n.yaml"
  write_chain "$n" 1e-3 "$out/scenes/chain${n}_tilted.yaml"
done

for r in $(seq 1 "$rounds"); do
  for n in $ns; do
    echo "bench_rhs: round $r/$rounds, N = $n" >&2
    "$kanesens" bench rhs "$out/scenes/chain$n.yaml" --repeat "$repeat" --json >"$out/raw/kanesens_${n}_$r.json"
    "$mujoco" "$n" --repeat "$repeat" >"$out/raw/mujoco_${n}_$r.json"
    "$kanesens" bench rhs "$out/scenes/chain${n}_tilted.yaml" --repeat "$repeat" --json >"$out/raw/tilted_${n}_$r.json"
  done
done

# Same equations? kanesens's u̇ at MuJoCo's state against MuJoCo's qacc.
for n in $ns; do
  "$python" - "$kanesens" "$out/scenes/chain$n.yaml" "$out/raw/mujoco_${n}_1.json" >"$out/raw/agree_$n.json" <<'PY'
import json, subprocess, sys
exe, scene, mj = sys.argv[1], sys.argv[2], json.load(open(sys.argv[3]))
fmt = lambda xs: ",".join(repr(x) for x in xs)
ks = json.loads(subprocess.run([exe, "eom", scene, "--q=" + fmt(mj["qpos"]), "--u=" + fmt(mj["qvel"])],
                               check=True, capture_output=True, text=True).stdout)
scale = max(1.0, max(abs(x) for x in mj["qacc"]))
print(json.dumps({"max_abs_diff_udot_qacc": max(abs(a - b) for a, b in zip(ks["udot"], mj["qacc"])),
                  "scale": scale}))
PY
done

"$python" - "$out" "$rounds" "$ns" <<'PY'
import datetime, json, platform, statistics, subprocess, sys
out, rounds, ns = sys.argv[1], int(sys.argv[2]), [int(x) for x in sys.argv[3].split()]
load = lambda f: json.load(open(f"{out}/raw/{f}.json"))
med = lambda xs: statistics.median(xs)
rows, raw = [], {}
for n in ns:
    k = [load(f"kanesens_{n}_{r}") for r in range(1, rounds + 1)]
    m = [load(f"mujoco_{n}_{r}") for r in range(1, rounds + 1)]
    t = [load(f"tilted_{n}_{r}") for r in range(1, rounds + 1)]
    row = {"n": n,
           "kanesens_rhs_ns": med([x["rhs"]["median_ns"] for x in k]),
           "kanesens_mf_ns": med([x["mass_matrix_and_forcing"]["median_ns"] for x in k]),
           "kanesens_jacobian_ns": med([x["jacobian_dual"]["median_ns"] for x in k]),
           "kanesens_3d_rhs_ns": med([x["rhs"]["median_ns"] for x in t]),
           "kanesens_3d_mf_ns": med([x["mass_matrix_and_forcing"]["median_ns"] for x in t]),
           "mujoco_forward_ns": med([x["mj_forward"]["median_ns"] for x in m]),
           "kanesens_path": k[0].get("path", "?"), "tilted_path": t[0].get("path", "?"),
           "agreement": load(f"agree_{n}")}
    rows.append(row)
    raw[n] = {"kanesens": k, "mujoco": m, "kanesens_tilted": t}
cpu = next((l.split(":", 1)[1].strip() for l in open("/proc/cpuinfo") if l.startswith("model name")), "?")
nproc = subprocess.run(["nproc"], capture_output=True, text=True).stdout.strip()
load_avg = open("/proc/loadavg").read().split()[:3]
eps = lambda ns_: 1e9 / ns_
lines = [f"Date {datetime.date.today()}, {cpu}, nproc {nproc}, load average at the end {' '.join(load_avg)}, "
         f"{rounds} rounds, medians over rounds of medians over batches.", "",
         "| N | kanesens RHS (eval/s) | kanesens M+f (eval/s) | MuJoCo mj_forward (eval/s) | "
         "speed ratio RHS : mj_forward | kanesens Dual Jacobian (µs) | 3-D path RHS (eval/s) | planar speedup | "
         "max abs(udot − qacc) |",
         "|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
for r in rows:
    lines.append(f"| {r['n']} | {eps(r['kanesens_rhs_ns']):,.0f} | {eps(r['kanesens_mf_ns']):,.0f} | "
                 f"{eps(r['mujoco_forward_ns']):,.0f} | {r['mujoco_forward_ns'] / r['kanesens_rhs_ns']:.2f} | "
                 f"{r['kanesens_jacobian_ns'] / 1e3:.2f} | {eps(r['kanesens_3d_rhs_ns']):,.0f} | "
                 f"{r['kanesens_3d_rhs_ns'] / r['kanesens_rhs_ns']:.2f} | "
                 f"{r['agreement']['max_abs_diff_udot_qacc']:.1e} |")
table = "\n".join(lines) + "\n"
open(f"{out}/bench_rhs.md", "w").write(table)
json.dump({"date": str(datetime.date.today()), "cpu": cpu, "nproc": nproc, "loadavg_end": load_avg,
           "platform": platform.platform(), "rounds": rounds, "rows": rows, "raw": raw},
          open(f"{out}/bench_rhs.json", "w"), indent=1)
print(table)
PY
