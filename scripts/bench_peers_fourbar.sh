#!/usr/bin/env bash
# kanesens against Simbody and MuJoCo on the four-bar of configs/four_bar.yaml (docs/peers.md,
# "Four-bar: Simbody and MuJoCo"). Uses the kanesens in KANESENS_BUILD_DIR (built there if
# missing) and builds the peers (-DKANESENS_PEERS=ON; libsimbody-dev, libmujoco-dev:
# KANESENS_PEERS=1 scripts/install-deps.sh) into PEERS_BUILD_DIR, then in ONE run:
#
#  1. RHS speed at the consistent initial state, alternating in every round: `kanesens bench rhs
#     --json` ("rhs_multipliers": tree RHS + multiplier solve; "rhs_embedding": RHS in the
#     independent speeds), simbody_fourbar_bench (realize(Stage::Acceleration), which includes
#     the multipliers) and mujoco_fourbar_bench (mj_forward, which includes the soft-constraint
#     solve). Agreement: kanesens eom's u̇ and λ at that state against Simbody's u̇ and
#     coupler-end force and MuJoCo's qacc and efc_force.
#  2. Time to accuracy over t in [0, 10]: error = max abs over the six states at t = 10 against
#     y_ref = kanesens adams, embedding, rtol 1e-14, atol 1e-16 (kanesens projects only with BDF,
#     so the multipliers formulation cannot be the Adams reference; the other tight solutions are
#     reported as its check). kanesens: bdf with multipliers + projection, adams with multipliers
#     + Baumgarte, adams with embedding (rtol swept, atol = rtol·1e-2); Simbody RK-Merson and
#     CPodes at accuracy = the same values; MuJoCo RK4 and Euler fixed-step dt sweep (no error
#     control). Tools alternate for every tolerance (dt); median of TTA_REPS, 1 once a run takes
#     > 2 s; a peer method is not run at tighter tolerances (smaller dt) once a run took > BUDGET s.
#
#   scripts/bench_peers_fourbar.sh [OUT_DIR]
#     env: ROUNDS=3 REPEAT=31 TTA_REPS=3 TOLS="1e-3 1e-4 ... 1e-12"
#          DTS="1e-2 3e-3 1e-3 3e-4 1e-4 3e-5 1e-5" BUDGET=20
#          KANESENS_BUILD_DIR=build PEERS_BUILD_DIR=build-peers KANESENS_PYTHON=/usr/bin/python3
# Writes OUT_DIR (default docs/peers) fourbar.md (tables), fourbar.json (all raw results) and
# fourbar_workprecision.png.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
out=${1:-$root/docs/peers}
build=${KANESENS_BUILD_DIR:-$root/build}
peers_build=${PEERS_BUILD_DIR:-$root/build-peers}
python=${KANESENS_PYTHON:-/usr/bin/python3}
rounds=${ROUNDS:-3}
repeat=${REPEAT:-31}
tta_reps=${TTA_REPS:-3}
tols=${TOLS:-"1e-3 1e-4 1e-5 1e-6 1e-7 1e-8 1e-9 1e-10 1e-11 1e-12"}
dts=${DTS:-"1e-2 3e-3 1e-3 3e-4 1e-4 3e-5 1e-5"}
budget=${BUDGET:-20}
scene=$root/configs/four_bar.yaml
work=$(mktemp -d /tmp/bench_peers_fourbar.XXXXXX)
mkdir -p "$out" "$work/raw"

kanesens=$build/kanesens
if [[ ! -x $kanesens ]]; then
  cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=Release >/dev/null
  cmake --build "$build" -j "${KANESENS_JOBS:-1}" --target kanesens >/dev/null
fi
cmake -S "$root" -B "$peers_build" -DKANESENS_PEERS=ON -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$peers_build" -j "${KANESENS_JOBS:-1}" --target simbody_fourbar_bench mujoco_fourbar_bench >/dev/null
simbody=$peers_build/apps/peers/simbody_fourbar_bench
mujoco=$peers_build/apps/peers/mujoco_fourbar_bench
load_start=$(cut -d' ' -f1-3 /proc/loadavg)

# 1. RHS speed, alternating.
for r in $(seq 1 "$rounds"); do
  echo "bench_peers_fourbar: RHS round $r/$rounds" >&2
  "$kanesens" bench rhs "$scene" --repeat "$repeat" --json >"$work/raw/kanesens_$r.json"
  "$simbody" --repeat "$repeat" >"$work/raw/simbody_$r.json"
  "$mujoco" --repeat "$repeat" >"$work/raw/mujoco_$r.json"
done
"$python" - "$kanesens" "$scene" "$work/raw" <<'PY' >"$work/raw/agree.json"
import json, subprocess, sys
import numpy as np
exe, scene, raw = sys.argv[1], sys.argv[2], sys.argv[3]
k, sb, mj = (json.load(open(f"{raw}/{x}_1.json")) for x in ("kanesens", "simbody", "mujoco"))
for key in ("rhs_multipliers", "rhs_embedding", "constrained_state"):
    if key not in k:
        sys.exit(f"bench_peers_fourbar: `kanesens bench rhs --json` has no \"{key}\" (constrained RHS at the "
                 "consistent initial state); use a kanesens built from main at or after 1b14907")
fmt = lambda xs: ",".join(repr(x) for x in xs)
eom = json.loads(subprocess.run([exe, "eom", scene, "--q=" + fmt(sb["q"]), "--u=" + fmt(sb["u"])],
                                check=True, capture_output=True, text=True).stdout)
dmax = lambda a, b: max(abs(x - y) for x, y in zip(a, b))
# MuJoCo's constraint model has no J̇q̇ term (it solves J q̈ = (1 − d) J q̈_free − d (b v + k r)),
# so its q̈ at a consistent state is the constrained q̈ with a zero bias: solve that from kanesens's
# M, f, A to show where MuJoCo's difference comes from.
M, f, A = (np.array(eom[x]) for x in ("mass_matrix", "forcing", "constraint_matrix"))
kkt = np.block([[M, -A.T], [A, np.zeros((len(A), len(A)))]])
no_bias = np.linalg.solve(kkt, np.r_[f, np.zeros(len(A))])
print(json.dumps({
    "state_diff_simbody_vs_kanesens": dmax(sb["q"] + sb["u"], k["constrained_state"]),
    "state_diff_mujoco_vs_kanesens": dmax(mj["qpos"] + mj["qvel"], k["constrained_state"]),
    "kanesens_udot": eom["udot"], "kanesens_multipliers": eom["multipliers"],
    "simbody_udot_diff": dmax(eom["udot"], sb["udot"]),
    "simbody_force_diff": dmax(eom["multipliers"], sb["coupler_end_force"]),
    "mujoco_qacc_diff": dmax(eom["udot"], mj["qacc"]),
    "mujoco_force_diff": dmax(eom["multipliers"], mj["efc_force"][:2]),
    "kanesens_no_bias_udot": list(no_bias[:3]), "kanesens_no_bias_multipliers": list(no_bias[3:]),
    "mujoco_qacc_diff_no_bias": dmax(no_bias[:3], mj["qacc"]),
    "mujoco_force_diff_no_bias": dmax(no_bias[3:], mj["efc_force"][:2]),
    "max_abs_udot": max(abs(x) for x in eom["udot"]), "max_abs_multiplier": max(abs(x) for x in eom["multipliers"]),
}))
PY

# 2. Time to accuracy, alternating the tools for every tolerance (every dt for MuJoCo).
"$python" - "$kanesens" "$simbody" "$mujoco" "$scene" "$work" "$tols" "$dts" "$tta_reps" "$budget" <<'PY'
import json, statistics, subprocess, sys
from pathlib import Path
kanesens, simbody, mujoco, scene, work = sys.argv[1:6]
work = Path(work)
tols, dts = [float(x) for x in sys.argv[6].split()], [float(x) for x in sys.argv[7].split()]
reps, budget = int(sys.argv[8]), float(sys.argv[9])
study = work / "four_bar_tta.yaml"
study.write_text(f"kanesens: 1\nscene: {scene}\ntime: {{end: 10.0, outputs: 2}}\n"
                 "solver: {method: bdf, rtol: 1.0e-8, atol: 1.0e-10, jacobian: exact, max_steps: 100000000,\n"
                 "         constraints: {formulation: multipliers, stabilization: projection}}\n"
                 "record: [states]\n")
# kanesens methods: (CVODES method, constraint formulation, stabilization).
KS = {"bdf-projection": ("bdf", "multipliers", "projection"), "adams-baumgarte": ("adams", "multipliers", "baumgarte"),
      "adams-embedding": ("adams", "embedding", "none")}

def ks(method, rtol):
    m, form, stab = KS[method]
    p = subprocess.run([kanesens, "simulate", str(study), "--format", "json", "--sens", "none",
                        "--set", f"solver.method={m}", "--set", f"solver.constraints.formulation={form}",
                        "--set", f"solver.constraints.stabilization={stab}",
                        "--set", f"solver.rtol={rtol!r}", "--set", f"solver.atol={rtol * 1e-2!r}"],
                       capture_output=True, text=True, check=True)
    o = json.loads(p.stdout)
    return {"time_s": o["stats"]["wall_seconds"], "y_end": o["states"][-1], "steps": o["stats"]["steps"],
            "rhs_evals": o["stats"]["rhs_evals"], "status": o.get("status", 0)}

def peer(cmd, keys):
    p = subprocess.run(cmd + ["--repeat", "1"], capture_output=True, text=True)
    if p.returncode != 0:
        return {"time_s": None, "y_end": None, "status": p.returncode, "message": p.stderr.strip()[-300:]}
    o = json.loads(p.stdout)
    return {"time_s": o["wall_seconds"], "y_end": o["q"] + o["u"], "status": 0, **{k: o[k] for k in keys}}

def sb(which, acc):
    return peer([simbody, "--integrate", which, "--accuracy", repr(acc)],
                ("steps", "realizations", "projections", "position_residual", "velocity_residual"))

def mj(which, dt):
    return peer([mujoco, "--integrate", which, "--dt", repr(dt)], ("steps", "position_residual", "velocity_residual"))

ref = ks("adams-embedding", 1e-14)["y_end"]
err = lambda y: max(abs(a - b) for a, b in zip(y, ref))
checks = {"adams-embedding rtol 1e-13": err(ks("adams-embedding", 1e-13)["y_end"]),
          "adams-baumgarte rtol 1e-14": err(ks("adams-baumgarte", 1e-14)["y_end"]),
          "bdf-projection rtol 1e-14": err(ks("bdf-projection", 1e-14)["y_end"])}

def sweep(settings, tools, run):
    """Every setting: all active tools alternately, TTA_REPS times; rows of medians."""
    rows, active = [], {t for t in tools if t[0] != "kanesens"}
    for x in settings:
        now = [t for t in tools if t[0] == "kanesens" or t in active]
        res = {t: [] for t in now}
        for rep in range(reps):
            for t in now:
                if rep > 0 and (res[t][0]["time_s"] is None or res[t][0]["time_s"] > 2.0):
                    continue
                res[t].append(run(t, x))
        for t in now:
            rs, ok = res[t], res[t][0]["y_end"] is not None
            row = {"tool": t[0], "method": t[1], "setting": x,
                   "time_s": statistics.median(r["time_s"] for r in rs) if ok else None,
                   "times_s": [r["time_s"] for r in rs], "error": err(rs[0]["y_end"]) if ok else None,
                   **{k: v for k, v in rs[0].items() if k not in ("time_s", "y_end")}}
            rows.append(row)
            print(f"bench_peers_fourbar: TTA {t[0]} {t[1]} {x:.0e} err={row['error']} time={row['time_s']}",
                  file=sys.stderr, flush=True)
            if t in active and (not ok or row["time_s"] > budget):
                active.discard(t)
    return rows

tol_tools = [("kanesens", "bdf-projection"), ("simbody", "rkm"), ("kanesens", "adams-baumgarte"),
             ("simbody", "cpodes"), ("kanesens", "adams-embedding")]
rows = sweep(tols, tol_tools, lambda t, x: ks(t[1], x) if t[0] == "kanesens" else sb(t[1], x))
rows += sweep(dts, [("mujoco", "rk4"), ("mujoco", "euler")], lambda t, x: mj(t[1], x))
json.dump({"rows": rows, "y_ref": ref, "reference_checks": checks}, open(work / "raw" / "tta.json", "w"), indent=1)
PY

# Tables, JSON and the work-precision plot.
"$python" - "$out" "$work" "$rounds" "$load_start" "$(git -C "$root" rev-parse --short HEAD)" \
  "$("$kanesens" --version | head -1)" <<'PY'
import datetime, json, math, os, platform, statistics, sys
out, work, rounds, load_start, git, ks_version = sys.argv[1], sys.argv[2], int(sys.argv[3]), sys.argv[4], sys.argv[5], sys.argv[6]
load = lambda f: json.load(open(f"{work}/raw/{f}.json"))
med = statistics.median
cpu = next((l.split(":", 1)[1].strip() for l in open("/proc/cpuinfo") if l.startswith("model name")), "?")
load_end = " ".join(open("/proc/loadavg").read().split()[:3])
k = [load(f"kanesens_{r}") for r in range(1, rounds + 1)]
s = [load(f"simbody_{r}") for r in range(1, rounds + 1)]
m = [load(f"mujoco_{r}") for r in range(1, rounds + 1)]
agree = load("agree")
rhs = {"kanesens multipliers": med([x["rhs_multipliers"]["median_ns"] for x in k]),
       "kanesens embedding": med([x["rhs_embedding"]["median_ns"] for x in k]),
       "Simbody realize(Acceleration)": med([x["realize_acceleration"]["median_ns"] for x in s]),
       "MuJoCo mj_forward": med([x["mj_forward"]["median_ns"] for x in m])}
sb_ns, mj_ns = rhs["Simbody realize(Acceleration)"], rhs["MuJoCo mj_forward"]
versions = f"Simbody {s[0]['simbody_version']}, MuJoCo {m[0]['mujoco_version'] / 100:.2f}"
L = [f"Date {datetime.date.today()}, commit {git} ({ks_version}), {versions}, {cpu}, nproc {os.cpu_count()}, "
     f"load average {load_start} (start) / {load_end} (end), {rounds} rounds; medians over rounds of medians over batches.",
     "", "RHS evaluations at the consistent initial state (q, u of configs/four_bar.yaml at t = 0):", "",
     "| program | median ns | eval/s | ratio kanesens multipliers / this | ratio kanesens embedding / this |",
     "|---|---:|---:|---:|---:|"]
for name, ns in rhs.items():
    L.append(f"| {name} | {ns:,.0f} | {1e9 / ns:,.0f} | {ns / rhs['kanesens multipliers']:.2f} | "
             f"{ns / rhs['kanesens embedding']:.2f} |")
a = agree
L += ["", f"Agreement at that state (max abs over the 3 accelerations, rad/s², and the 2 loop forces, N; "
      f"max abs u̇ {a['max_abs_udot']:.2f}, max abs λ {a['max_abs_multiplier']:.2f}):", "",
      "| against kanesens eom | u̇ | loop force (world x, y) |", "|---|---:|---:|",
      f"| Simbody u̇, force on the coupler end | {a['simbody_udot_diff']:.1e} | {a['simbody_force_diff']:.1e} |",
      f"| MuJoCo qacc, efc_force | {a['mujoco_qacc_diff']:.1e} | {a['mujoco_force_diff']:.1e} |",
      f"| MuJoCo against kanesens with the J̇u bias set to zero | {a['mujoco_qacc_diff_no_bias']:.1e} | "
      f"{a['mujoco_force_diff_no_bias']:.1e} |",
      "", f"Initial states: Simbody vs kanesens {a['state_diff_simbody_vs_kanesens']:.1e}, MuJoCo vs kanesens "
      f"{a['state_diff_mujoco_vs_kanesens']:.1e} (max abs over q, u)."]

tta = load("tta")
checks = tta["reference_checks"]
# The closest other tight solution (Adams, the other formulation, same tolerance) bounds what the
# reference resolves; errors below it are not measured.
resolved = min(checks.values())
targets = [1e-4, 1e-6, 1e-8, 1e-10]

def time_at(pts, e):
    """pts in sweep order (loosest first): (error, time); log-log interpolation at error e."""
    prev = None
    for error, t in pts:
        if error <= e:
            if prev is None:
                return t, "<="
            e0, t0 = prev
            if e0 == error:
                return t, "="
            w = (math.log(e) - math.log(e0)) / (math.log(error) - math.log(e0))
            return math.exp(math.log(t0) + w * (math.log(t) - math.log(t0))), "="
        prev = (error, t)
    return None, "not reached"

methods = [("simbody", "rkm", "Simbody RK-Merson"), ("simbody", "cpodes", "Simbody CPodes BDF"),
           ("mujoco", "rk4", "MuJoCo RK4 (fixed dt)"), ("mujoco", "euler", "MuJoCo Euler (fixed dt)"),
           ("kanesens", "bdf-projection", "kanesens BDF, multipliers + projection"),
           ("kanesens", "adams-baumgarte", "kanesens Adams, multipliers + Baumgarte"),
           ("kanesens", "adams-embedding", "kanesens Adams, embedding")]
def points(tool, method):
    rs = [r for r in tta["rows"] if (r["tool"], r["method"]) == (tool, method) and r["error"] is not None]
    return sorted(rs, key=lambda r: -r["setting"])
cell = lambda v: "—" if v[0] is None else ("≤ " if v[1] == "<=" else "") + f"{v[0] * 1e3:,.1f}"
L += ["", "Time to reach a final-time max abs error over the six states, t ∈ [0, 10] (ms; log-log interpolation "
      "on the tolerance sweep, on the dt sweep for MuJoCo; '≤' = the loosest setting already reaches it; '—' = not "
      f"reached in the sweep or budget; targets below {resolved:.0e}, the distance of the closest other tight kanesens "
      "solution from y_ref, are not resolved: 'n/r'). Ratio = fastest peer / fastest kanesens:", "",
      "| target | " + " | ".join(x[2] for x in methods) + " | ratio best peer / best kanesens |",
      "|---:|" + "---:|" * (len(methods) + 1)]
tta_table = []
for e in targets:
    vs = [time_at([(r["error"], r["time_s"]) for r in points(t, mt)], e) for t, mt, _ in methods]
    if e < resolved:
        L.append(f"| {e:.0e} | " + " | ".join("n/r" for _ in methods) + " | n/r |")
        tta_table.append({"target": e, "resolved": False})
        continue
    peers = [(v[0], lab) for v, (t, _, lab) in zip(vs, methods) if t != "kanesens" and v[0] is not None]
    kss = [(v[0], lab) for v, (t, _, lab) in zip(vs, methods) if t == "kanesens" and v[0] is not None]
    ratio = min(peers)[0] / min(kss)[0] if peers and kss else None
    label = f"{ratio:,.1f} ({min(peers)[1]} / {min(kss)[1]})" if ratio else "—"
    L.append(f"| {e:.0e} | " + " | ".join(cell(v) for v in vs) + f" | {label} |")
    tta_table.append({"target": e, "resolved": True, **{f"{t}_{mt}": v[0] for (t, mt, _), v in zip(methods, vs)},
                      "ratio_best_peer_over_best_kanesens": ratio})
L += ["", "Reference y_ref(10): kanesens Adams, embedding, rtol 1e-14, atol 1e-16. Max abs difference from it of: " +
      ", ".join(f"{name} {v:.1e}" for name, v in checks.items()) + "."]

L += ["", "MuJoCo fixed-step sweep (no error control; solref = (2·dt, 1), solimp = 0.9999): final-time error, "
      "wall time and the loop-closure residual at t = 10:", "",
      "| integrator | dt | steps | wall (s) | max abs error | position residual (m) | velocity residual (m/s) |",
      "|---|---:|---:|---:|---:|---:|---:|"]
for r in [r for r in tta["rows"] if r["tool"] == "mujoco"]:
    if r["error"] is None:
        L.append(f"| {r['method']} | {r['setting']:.0e} | | | failed | | |")
    else:
        L.append(f"| {r['method']} | {r['setting']:.0e} | {r['steps']:,} | {r['time_s']:.3f} | {r['error']:.1e} | "
                 f"{r['position_residual']:.1e} | {r['velocity_residual']:.1e} |")
L += ["", "Simbody and kanesens sweep (accuracy = rtol; kanesens atol = rtol·1e-2): final-time error and wall time "
      "(Simbody: also the constraint residual at t = 10):", "",
      "| tolerance | " + " | ".join(x[2] for x in methods if x[0] != "mujoco") + " |", "|---:|" + "---|" * 5]
for tol in sorted({r["setting"] for r in tta["rows"] if r["tool"] != "mujoco"}, reverse=True):
    cells = []
    for t, mt, _ in [x for x in methods if x[0] != "mujoco"]:
        r = next((r for r in tta["rows"] if (r["tool"], r["method"], r["setting"]) == (t, mt, tol)), None)
        if r is None:
            cells.append("")
        elif r["error"] is None:
            cells.append("failed")
        else:
            res = f", res {max(r['position_residual'], r['velocity_residual']):.0e}" if t == "simbody" else ""
            cells.append(f"{r['error']:.1e} in {r['time_s'] * 1e3:,.1f} ms{res}")
    L.append(f"| {tol:.0e} | " + " | ".join(cells) + " |")
table = "\n".join(L) + "\n"
open(f"{out}/fourbar.md", "w").write(table)
json.dump({"date": str(datetime.date.today()), "git": git, "kanesens_version": ks_version, "cpu": cpu,
           "nproc": os.cpu_count(), "loadavg_start": load_start, "loadavg_end": load_end,
           "platform": platform.platform(), "rounds": rounds, "rhs_median_ns": rhs, "agreement": agree,
           "rhs_raw": {"kanesens": k, "simbody": s, "mujoco": m}, "tta": tta, "tta_table": tta_table},
          open(f"{out}/fourbar.json", "w"), indent=1)

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
fig, ax = plt.subplots(figsize=(8.5, 5.6))
sty = {("simbody", "rkm"): ("tab:purple", "o", "-"), ("simbody", "cpodes"): ("tab:brown", "s", "-"),
       ("mujoco", "rk4"): ("tab:red", "^", ":"), ("mujoco", "euler"): ("tab:orange", "v", ":"),
       ("kanesens", "bdf-projection"): ("black", "D", "-"), ("kanesens", "adams-baumgarte"): ("tab:blue", "X", "--"),
       ("kanesens", "adams-embedding"): ("tab:gray", "P", "--")}
for t, mt, lab in methods:
    pts = points(t, mt)
    if pts:
        c, mk, ls = sty[(t, mt)]
        ax.loglog([max(r["error"], 1e-16) for r in pts], [r["time_s"] for r in pts], color=c, marker=mk, ls=ls, ms=5,
                  label=lab)
for e in targets:
    ax.axvline(e, color="0.85", lw=0.8, zorder=0)
ax.set_xlim(3e2, 1e-10)  # reversed: accuracy increases to the right
ax.axvspan(resolved, 1e-10, color="0.93", zorder=0)
ax.text(resolved * 0.8, 0.98, "below the reference's\nresolution", fontsize=7, color="0.4", va="top",
        transform=ax.get_xaxis_transform())
ax.grid(True, alpha=0.3)
ax.set_xlabel("final-time max abs error over the six states (t = 10)")
ax.set_ylabel("wall time per solve (s)")
ax.legend(fontsize=8, loc="lower right")
ax.set_title(f"Four-bar (configs/four_bar.yaml), t ∈ [0, 10]: kanesens vs {versions}\n{datetime.date.today()}, {cpu}, "
             f"nproc {os.cpu_count()}; tolerance sweep, MuJoCo dt sweep", fontsize=9)
fig.tight_layout()
fig.savefig(f"{out}/fourbar_workprecision.png", dpi=120)
print(table)
PY
