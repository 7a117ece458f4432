#!/usr/bin/env bash
# kanesens against Simbody on planar N-link chains (docs/peers.md). Builds kanesens and the
# Simbody peer (-DKANESENS_PEERS=ON; needs libsimbody-dev: KANESENS_PEERS=1
# scripts/install-deps.sh) into build/, then in ONE run:
#
#  1. RHS speed: for every round and every N, alternately `kanesens bench rhs` on the chain
#     (the scene of scripts/bench_rhs.sh: rods of mass 1, length 1, central inertia
#     diag(1/12, 1e-4, 1/12)) and `simbody_chain_bench N` (realize(Stage::Acceleration) after
#     writing q and u) at the same seeded random state; medians over batches, then over rounds.
#     Check: kanesens eom's u̇ at Simbody's state against Simbody's u̇.
#  2. Time to accuracy (TTA_NS, default "2 4 8"): t in [0, 10] from scripts/gen_chain.py's
#     initial state (q1 = 0.5, rest 0), kanesens simulate (bdf with the exact Jacobian, adams, dop853;
#     rtol swept, atol = rtol·1e-2) alternating with Simbody's RungeKuttaMersonIntegrator and
#     CPodesIntegrator (BDF/Newton, finite-difference Jacobian) at accuracy = the same values;
#     error = max abs over states of y(10) − y_ref(10), y_ref = kanesens adams at rtol 1e-14
#     (atol 1e-16; as scripts/bench_peers_sympy.py, which checks it against SciPy's DOP853).
#
#   scripts/bench_peers_simbody.sh [OUT_DIR]
#     env: NS="1 2 4 8 16 32" ROUNDS=3 REPEAT=31 TTA_NS="2 4 8" TTA_REPS=3
#          TOLS="1e-3 1e-4 ... 1e-14" BUDGET=20 (s: a Simbody integrator
#          whose run took longer is not run at tighter tolerances for that N)
# Writes OUT_DIR (default docs/peers) simbody.md (tables), simbody.json (all raw results) and
# simbody_workprecision.png.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
out=${1:-$root/docs/peers}
build=${KANESENS_BUILD_DIR:-$root/build}
python=${KANESENS_PYTHON:-/usr/bin/python3}
ns=${NS:-"1 2 4 8 16 32"}
rounds=${ROUNDS:-3}
repeat=${REPEAT:-31}
tta_ns=${TTA_NS:-"2 4 8"}
tta_reps=${TTA_REPS:-3}
tols=${TOLS:-"1e-3 1e-4 1e-5 1e-6 1e-7 1e-8 1e-9 1e-10 1e-11 1e-12 1e-13 1e-14"}
budget=${BUDGET:-20}
work=$(mktemp -d /tmp/bench_peers_simbody.XXXXXX)
mkdir -p "$out" "$work/scenes" "$work/raw"

cmake -S "$root" -B "$build" -DKANESENS_PEERS=ON >/dev/null
cmake --build "$build" -j "${KANESENS_JOBS:-1}" --target kanesens simbody_chain_bench >/dev/null
kanesens=$build/kanesens
simbody=$build/apps/peers/simbody_chain_bench
load_start=$(cut -d' ' -f1-3 /proc/loadavg)

# The benchmark chain of scripts/bench_rhs.sh (untilted).
write_chain() {  # N FILE
  "$python" - "$1" >"$2" <<'PY'
import sys
n = int(sys.argv[1])
print("kanesens: 1\nscene:\n  name: chain%d\n  gravity: [0, -9.81, 0]" % n)
print("  parameters: {m: 1.0, L: 1.0}\n  bodies:")
for i in range(1, n + 1):
    print('    - {name: link%d, mass: m, inertia: {xx: "m*L^2/12", yy: 1.0e-4, zz: "m*L^2/12"}}' % i)
print("  joints:")
for i in range(1, n + 1):
    parent = "ground" if i == 1 else "link%d" % (i - 1)
    pp = "0" if i == 1 else '"-L/2"'
    print('    - {name: j%d, type: revolute, parent: %s, child: link%d, axis: [0, 0, 1], '
          'parent_point: [0, %s, 0], child_point: [0, "L/2", 0]}' % (i, parent, i, pp))
PY
}
for n in $ns; do write_chain "$n" "$work/scenes/chain$n.yaml"; done

# 1. RHS speed, alternating.
for r in $(seq 1 "$rounds"); do
  for n in $ns; do
    echo "bench_peers_simbody: RHS round $r/$rounds, N = $n" >&2
    "$kanesens" bench rhs "$work/scenes/chain$n.yaml" --repeat "$repeat" --json >"$work/raw/kanesens_${n}_$r.json"
    "$simbody" "$n" --repeat "$repeat" >"$work/raw/simbody_${n}_$r.json"
  done
done
for n in $ns; do
  "$python" - "$kanesens" "$work/scenes/chain$n.yaml" "$work/raw/simbody_${n}_1.json" >"$work/raw/agree_$n.json" <<'PY'
import json, subprocess, sys
exe, scene, sb = sys.argv[1], sys.argv[2], json.load(open(sys.argv[3]))
fmt = lambda xs: ",".join(repr(x) for x in xs)
ks = json.loads(subprocess.run([exe, "eom", scene, "--q=" + fmt(sb["q"]), "--u=" + fmt(sb["u"])],
                               check=True, capture_output=True, text=True).stdout)
print(json.dumps({"max_abs_diff_udot": max(abs(a - b) for a, b in zip(ks["udot"], sb["udot"])),
                  "max_abs_udot": max(abs(x) for x in sb["udot"])}))
PY
done

# 2. Time to accuracy, alternating kanesens and Simbody for every N and tolerance.
"$python" - "$kanesens" "$simbody" "$work" "$tta_ns" "$tols" "$tta_reps" "$budget" <<'PY'
import json, statistics, subprocess, sys, time
from pathlib import Path
kanesens, simbody, work = sys.argv[1], sys.argv[2], Path(sys.argv[3])
ns, tols = [int(x) for x in sys.argv[4].split()], [float(x) for x in sys.argv[5].split()]
reps, budget = int(sys.argv[6]), float(sys.argv[7])
sys.path.insert(0, str(Path(kanesens).resolve().parent.parent / "scripts"))
from gen_chain import chain_yaml

def ks(study, method, rtol):
    p = subprocess.run([kanesens, "simulate", str(study), "--format", "json", "--set", f"solver.method={method}",
                        "--set", f"solver.rtol={rtol!r}", "--set", f"solver.atol={rtol * 1e-2!r}"],
                       capture_output=True, text=True, check=True)
    o = json.loads(p.stdout)
    return {"time_s": o["stats"]["wall_seconds"], "y_end": o["states"][-1], "steps": o["stats"]["steps"],
            "rhs_evals": o["stats"]["rhs_evals"], "status": o.get("status", 0)}

def sb(n, which, acc):
    # Stopped after 3 x BUDGET s: the BUDGET rule then drops the method for tighter accuracies.
    try:
        p = subprocess.run([simbody, str(n), "--integrate", which, "--accuracy", repr(acc), "--repeat", "1",
                            "--q0", "0.5", "--yy", "0"], capture_output=True, text=True, timeout=3 * budget)
    except subprocess.TimeoutExpired:
        return {"time_s": None, "y_end": None, "status": "timeout", "message": f"stopped after {3 * budget:g} s"}
    if p.returncode != 0:
        return {"time_s": None, "y_end": None, "status": p.returncode, "message": p.stderr.strip()[-300:]}
    o = json.loads(p.stdout)
    return {"time_s": o["wall_seconds"], "y_end": o["q"] + o["u"], "steps": o["steps"],
            "realizations": o["realizations"], "status": 0}

rows, refs = [], []
for n in ns:
    scene = work / "scenes" / f"tta_chain{n}.yaml"
    scene.write_text(chain_yaml(n))
    study = work / "scenes" / f"tta_chain{n}_study.yaml"
    study.write_text(f"kanesens: 1\nscene: {scene.name}\ntime: {{end: 10.0, outputs: 2}}\n"
                     "solver: {method: bdf, rtol: 1.0e-8, atol: 1.0e-10, jacobian: exact, max_steps: 100000000}\n"
                     "record: [states]\n")
    ref = ks(study, "adams", 1e-14)["y_end"]
    diff = lambda y: max(abs(a - b) for a, b in zip(y, ref))
    refs.append({"n": n, "y_ref": ref, "adams_1e-13_vs_ref": diff(ks(study, "adams", 1e-13)["y_end"]),
                 "bdf_1e-14_vs_ref": diff(ks(study, "bdf", 1e-14)["y_end"])})
    active = {"rkm", "cpodes"}
    for tol in tols:
        tools = [("kanesens", "bdf"), ("simbody", "rkm"), ("kanesens", "adams"), ("simbody", "cpodes"),
                 ("kanesens", "dop853")]
        tools = [t for t in tools if t[0] == "kanesens" or t[1] in active]
        res = {t: [] for t in tools}
        for rep in range(reps):
            for t in tools:
                if rep > 0 and (res[t][0]["time_s"] is None or res[t][0]["time_s"] > 2.0):
                    continue
                res[t].append(ks(study, t[1], tol) if t[0] == "kanesens" else sb(n, t[1], tol))
        for t in tools:
            rs = res[t]
            ok = rs[0]["y_end"] is not None
            row = {"n": n, "tool": t[0], "method": t[1], "tol": tol,
                   "time_s": statistics.median(r["time_s"] for r in rs) if ok else None,
                   "times_s": [r["time_s"] for r in rs],
                   "error": max(abs(a - b) for a, b in zip(rs[0]["y_end"], ref)) if ok else None,
                   **{k: rs[0].get(k) for k in ("steps", "rhs_evals", "realizations", "status", "message") if k in rs[0]}}
            rows.append(row)
            print(f"bench_peers_simbody: TTA N={n} {t[0]} {t[1]} tol={tol:.0e} err={row['error']} time={row['time_s']}",
                  file=sys.stderr, flush=True)
            if t[0] == "simbody" and (not ok or row["time_s"] > budget):
                active.discard(t[1])
json.dump({"rows": rows, "refs": refs}, open(work / "raw" / "tta.json", "w"), indent=1)
PY

# Tables, JSON and the work-precision plot.
"$python" - "$out" "$work" "$rounds" "$ns" "$load_start" "$(git -C "$root" rev-parse --short HEAD)" <<'PY'
import datetime, json, math, os, platform, statistics, subprocess, sys
out, work, rounds, ns = sys.argv[1], sys.argv[2], int(sys.argv[3]), [int(x) for x in sys.argv[4].split()]
load_start, git = sys.argv[5], sys.argv[6]
load = lambda f: json.load(open(f"{work}/raw/{f}.json"))
med = statistics.median
cpu = next((l.split(":", 1)[1].strip() for l in open("/proc/cpuinfo") if l.startswith("model name")), "?")
load_end = " ".join(open("/proc/loadavg").read().split()[:3])
rows, raw = [], {}
for n in ns:
    k = [load(f"kanesens_{n}_{r}") for r in range(1, rounds + 1)]
    s = [load(f"simbody_{n}_{r}") for r in range(1, rounds + 1)]
    rows.append({"n": n, "kanesens_rhs_ns": med([x["rhs"]["median_ns"] for x in k]),
                 "kanesens_mf_ns": med([x["mass_matrix_and_forcing"]["median_ns"] for x in k]),
                 "simbody_realize_ns": med([x["realize_acceleration"]["median_ns"] for x in s]),
                 "simbody_version": s[0]["simbody_version"], "agreement": load(f"agree_{n}")})
    raw[n] = {"kanesens": k, "simbody": s}
eps = lambda x: 1e9 / x
L = [f"Date {datetime.date.today()}, commit {git}, {cpu}, nproc {os.cpu_count()}, load average {load_start} "
     f"(start) / {load_end} (end), {rounds} rounds; medians over rounds of medians over batches.", "",
     "| N | kanesens RHS (eval/s) | kanesens M+f (eval/s) | Simbody realize(Acceleration) (eval/s) | "
     "ratio kanesens RHS / Simbody | max abs(u̇ kanesens − u̇ Simbody) | max abs u̇ |",
     "|---:|---:|---:|---:|---:|---:|---:|"]
for r in rows:
    L.append(f"| {r['n']} | {eps(r['kanesens_rhs_ns']):,.0f} | {eps(r['kanesens_mf_ns']):,.0f} | "
             f"{eps(r['simbody_realize_ns']):,.0f} | {r['simbody_realize_ns'] / r['kanesens_rhs_ns']:.1f} | "
             f"{r['agreement']['max_abs_diff_udot']:.1e} | {r['agreement']['max_abs_udot']:.1f} |")

tta = load("tta")
targets = [1e-4, 1e-6, 1e-8, 1e-10]

def time_at(pts, e):
    prev = None
    for tol, err, t in pts:
        if err <= e:
            if prev is None:
                return t, "<="
            e0, t0 = prev
            if e0 == err:
                return t, "="
            a = (math.log(e) - math.log(e0)) / (math.log(err) - math.log(e0))
            return math.exp(math.log(t0) + a * (math.log(t) - math.log(t0))), "="
        prev = (err, t)
    return None, "not reached"

tns = sorted({r["n"] for r in tta["rows"]})
methods = [("simbody", "rkm"), ("simbody", "cpodes"), ("kanesens", "bdf"), ("kanesens", "adams"), ("kanesens", "dop853")]
T = {}
for n in tns:
    for tool, m in methods:
        pts = sorted([(r["tol"], r["error"], r["time_s"]) for r in tta["rows"]
                      if r["n"] == n and r["tool"] == tool and r["method"] == m and r["error"] is not None],
                     key=lambda p: -p[0])
        for e in targets:
            T[(n, tool, m, e)] = time_at(pts, e)
cell = lambda v: "—" if v[0] is None else ("≤ " if v[1] == "<=" else "") + f"{v[0] * 1e3:,.2f}"
L += ["", "Time to reach a final-time max abs error, t ∈ [0, 10] (ms; log-log interpolation on the tolerance sweep; "
      "'≤' = the loosest tolerance already reaches it; '—' = not reached in the sweep or budget):", "",
      "| N | target | Simbody RK-Merson | Simbody CPodes BDF | kanesens BDF | kanesens Adams | kanesens DOP853 | "
      "ratio best Simbody / best kanesens |", "|---:|---:|---:|---:|---:|---:|---:|---:|"]
tta_table = []
for n in tns:
    for e in targets:
        vs = [T[(n, t, m, e)] for t, m in methods]
        s = [v[0] for v in vs[:2] if v[0] is not None]
        k = [v[0] for v in vs[2:] if v[0] is not None]
        ratio = f"{min(s) / min(k):,.1f}" if s and k else "—"
        tta_table.append({"n": n, "target": e, **{f"{t}_{m}": v[0] for (t, m), v in zip(methods, vs)},
                          "ratio_best": (min(s) / min(k)) if s and k else None})
        L.append(f"| {n} | {e:.0e} | " + " | ".join(cell(v) for v in vs) + f" | {ratio} |")
L += ["", "Reference y_ref(10): kanesens adams at rtol 1e-14 (atol 1e-16). Max abs difference from it of kanesens "
      "adams at rtol 1e-13 / bdf at rtol 1e-14: " +
      ", ".join(f"N = {r['n']}: {r['adams_1e-13_vs_ref']:.1e} / {r['bdf_1e-14_vs_ref']:.1e}" for r in tta["refs"]) + "."]
table = "\n".join(L) + "\n"
open(f"{out}/simbody.md", "w").write(table)
json.dump({"date": str(datetime.date.today()), "git": git, "cpu": cpu, "nproc": os.cpu_count(),
           "loadavg_start": load_start, "loadavg_end": load_end, "platform": platform.platform(),
           "rounds": rounds, "rhs_rows": rows, "rhs_raw": raw, "tta": tta, "tta_table": tta_table},
          open(f"{out}/simbody.json", "w"), indent=1)

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
fig, axes = plt.subplots(1, len(tns), figsize=(5.2 * len(tns), 4.6), sharey=True, squeeze=False)
sty = {("simbody", "rkm"): ("tab:purple", "o", "-", "Simbody RK-Merson"),
       ("simbody", "cpodes"): ("tab:brown", "s", "-", "Simbody CPodes BDF"),
       ("kanesens", "bdf"): ("black", "D", "-", "kanesens BDF"), ("kanesens", "adams"): ("tab:gray", "P", "--", "kanesens Adams"),
       ("kanesens", "dop853"): ("tab:olive", "*", "-.", "kanesens DOP853")}
for ax, n in zip(axes[0], tns):
    for key, (c, mk, ls, lab) in sty.items():
        pts = sorted([(r["tol"], r["error"], r["time_s"]) for r in tta["rows"] if r["n"] == n and
                      (r["tool"], r["method"]) == key and r["error"] is not None], key=lambda p: -p[0])
        if pts:
            ax.loglog([max(p[1], 1e-16) for p in pts], [p[2] for p in pts], color=c, marker=mk, ls=ls, ms=5, label=lab)
    for e in targets:
        ax.axvline(e, color="0.85", lw=0.8, zorder=0)
    ax.invert_xaxis()
    ax.grid(True, alpha=0.3)
    ax.set_title(f"planar {n}-link chain, t ∈ [0, 10]")
    ax.set_xlabel("final-time max abs error over states")
axes[0][0].set_ylabel("wall time per solve (s)")
axes[0][0].legend(fontsize=8, loc="upper left")
fig.suptitle(f"Work-precision: kanesens (CVODES) vs Simbody {rows[0]['simbody_version']} — {datetime.date.today()}, "
             f"{cpu}, nproc {os.cpu_count()}; tolerance sweep (kanesens atol = rtol·1e-2)", fontsize=9)
fig.tight_layout()
fig.savefig(f"{out}/simbody_workprecision.png", dpi=120)
print(table)
PY
