#!/usr/bin/python3
"""kanesens against Simbody and MuJoCo on the four-bar of configs/four_bar.yaml (docs/peers.md,
"Four-bar: Simbody and MuJoCo").

    /usr/bin/python3 bench/bench_peers_fourbar.py [OUT_DIR] [--rounds 3] [--repeat 31] [--tta-reps 3]
        [--tols "1e-3 1e-4 ... 1e-14"] [--dts "1e-2 3e-3 1e-3 3e-4 1e-4 3e-5 1e-5"] [--budget 20]
        [--build build] [--peers-build build-peers]
    env (defaults of the options): ROUNDS REPEAT TTA_REPS TOLS DTS BUDGET KANESENS_BUILD_DIR
        PEERS_BUILD_DIR KANESENS_JOBS
    quick smoke test (seconds, not for the docs):
        bench/bench_peers_fourbar.py /tmp/fourbar --rounds 1 --repeat 3 --tta-reps 1 --tols "1e-4 1e-6" --dts "1e-2 3e-3"

Uses the kanesens of the build directory (built there if missing) and builds the peers
(-DKANESENS_PEERS=ON; libsimbody-dev, libmujoco-dev: KANESENS_PEERS=1 tools/install-deps.sh)
into the peers build directory, then in ONE run:

 1. RHS speed at the consistent initial state, alternating in every round: `kanesens bench rhs
    --json` ("rhs_multipliers": tree RHS + multiplier solve; "rhs_embedding": RHS in the
    independent speeds), simbody_fourbar_bench (realize(Stage::Acceleration), which includes
    the multipliers) and mujoco_fourbar_bench (mj_forward, which includes the soft-constraint
    solve). Agreement: kanesens eom's u̇ and λ at that state against Simbody's u̇ and
    coupler-end force and MuJoCo's qacc and efc_force.
 2. Time to accuracy over t in [0, 10]: error = max abs over the six states at t = 10 against
    y_ref from energy conservation and a time quadrature (tests/sympy/four_bar_quadrature.py,
    mpmath at 30 digits; independent of every integrator). Each kanesens variant's solution at
    rtol 1e-14 is reported as a cross-check (its distance from y_ref). kanesens variants
    (bench/fourbar_kanesens.py): bdf with multipliers + projection, adams with multipliers +
    Baumgarte, adams with embedding, and the explicit Runge–Kutta dop853 (Dormand–Prince
    8(5,3)) with embedding and with multipliers + Baumgarte (skipped with a note by a kanesens
    without dop853); rtol swept, atol = rtol·1e-2. Simbody's integrators (--integrators:
    RK-Merson, RK-Feldberg, RK3, Verlet, CPodes BDF and Adams) at accuracy = the same values;
    MuJoCo RK4, semi-implicit Euler and implicit-in-velocity fixed-step dt sweep (no error
    control).
    Tools alternate for every tolerance (dt); median of TTA_REPS, 1 once a run takes > 2 s; a
    peer method is not run at tighter tolerances (smaller dt) once a run took > BUDGET s (so
    Simbody may stop before 1e-14).

Writes OUT_DIR (default docs/peers) fourbar.json (all raw results and the command line);
bench/make_tables.py makes docs/peers.md's tables and fourbar_workprecision.png from it.
"""
from __future__ import annotations

import argparse
import json
import subprocess
import sys
import tempfile
from pathlib import Path

import common as c
import fourbar_kanesens as fk

WHO = "bench_peers_fourbar"
SCENE = c.CONFIGS / "four_bar.yaml"
T_END = 10.0


def agreement(kanesens, raw: Path) -> dict:
    import numpy as np

    k, sb, mj = (c.load_json(raw / f"{x}_1.json") for x in ("kanesens", "simbody", "mujoco"))
    for key in ("rhs_multipliers", "rhs_embedding", "constrained_state"):
        if key not in k:
            sys.exit(f"{WHO}: `kanesens bench rhs --json` has no \"{key}\" (constrained RHS at the "
                     "consistent initial state); use a kanesens built from main at or after 1b14907")
    eom = c.run_json([kanesens, "eom", SCENE, "--q=" + c.fmt_list(sb["q"]), "--u=" + c.fmt_list(sb["u"])])
    dmax = lambda a, b: max(abs(x - y) for x, y in zip(a, b))
    # MuJoCo's constraint model has no J̇q̇ term (it solves J q̈ = (1 − d) J q̈_free − d (b v + k r)),
    # so its q̈ at a consistent state is the constrained q̈ with a zero bias: solve that from kanesens's
    # M, f, A to show where MuJoCo's difference comes from.
    M, f, A = (np.array(eom[x]) for x in ("mass_matrix", "forcing", "constraint_matrix"))
    kkt = np.block([[M, -A.T], [A, np.zeros((len(A), len(A)))]])
    no_bias = np.linalg.solve(kkt, np.r_[f, np.zeros(len(A))])
    return {
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
        "max_abs_udot": max(abs(x) for x in eom["udot"]),
        "max_abs_multiplier": max(abs(x) for x in eom["multipliers"]),
    }


def time_to_accuracy(kanesens, simbody, mujoco, work: Path, tols, dts, reps, budget, sb_integrators,
                     mj_integrators) -> dict:
    sys.path.insert(0, str(c.ROOT / "tests" / "sympy"))
    import four_bar_quadrature

    study = fk.write_study(work / "four_bar_tta.yaml", T_END)
    # kanesens variants (method, constraint formulation, stabilization); the dop853 ones are skipped
    # with a note by a kanesens that has no dop853.
    requested = [("bdf", "multipliers", "projection"), ("adams", "multipliers", "baumgarte"),
                 ("adams", "embedding", "none"), ("dop853", "embedding", "none"),
                 ("dop853", "multipliers", "baumgarte")]
    by_name = {fk.name(v): v for v in fk.available(kanesens, study, requested, WHO)}

    def ks(name, rtol):
        o = fk.simulate(kanesens, study, by_name[name], rtol, rtol * 1e-2)
        return {"time_s": o["stats"]["wall_seconds"], "y_end": o["states"][-1], "steps": o["stats"]["steps"],
                "rhs_evals": o["stats"]["rhs_evals"], "status": o.get("status", 0)}

    def peer(cmd, keys):
        # A peer run is stopped after 3 x BUDGET s (Simbody CPodes at accuracy 1e-14 ran > 3 min);
        # the row records it and the BUDGET rule drops that method for the tighter settings.
        try:
            p = subprocess.run([str(x) for x in cmd] + ["--repeat", "1"], capture_output=True, text=True,
                               timeout=3 * budget)
        except subprocess.TimeoutExpired:
            return {"time_s": None, "y_end": None, "status": "timeout",
                    "message": f"stopped after {3 * budget:g} s (3 x BUDGET)"}
        if p.returncode != 0:
            return {"time_s": None, "y_end": None, "status": p.returncode, "message": p.stderr.strip()[-300:]}
        o = json.loads(p.stdout)
        return {"time_s": o["wall_seconds"], "y_end": o["q"] + o["u"], "status": 0, **{k: o[k] for k in keys}}

    def sb(which, acc):
        return peer([simbody, "--integrate", which, "--accuracy", repr(acc)],
                    ("steps", "realizations", "projections", "position_residual", "velocity_residual"))

    def mj(which, dt):
        return peer([mujoco, "--integrate", which, "--dt", repr(dt)], ("steps", "position_residual", "velocity_residual"))

    # The reference: energy conservation and a time quadrature in mpmath, independent of every integrator.
    c.log(WHO, "reference, energy quadrature at t = 10")
    ref, quadrature = four_bar_quadrature.state_at(T_END)
    err = lambda y: c.max_err(y, ref)
    # Cross-checks, reported only: how far each kanesens variant's tightest solution is from it.
    checks = {name: err(ks(name, 1e-14)["y_end"]) for name in by_name}

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
                       "time_s": c.median(r["time_s"] for r in rs) if ok else None,
                       "times_s": [r["time_s"] for r in rs], "error": err(rs[0]["y_end"]) if ok else None,
                       **{k: v for k, v in rs[0].items() if k not in ("time_s", "y_end")}}
                rows.append(row)
                c.log(WHO, f"TTA {t[0]} {t[1]} {x:.0e} err={row['error']} time={row['time_s']}")
                if t in active and (not ok or row["time_s"] > budget):
                    active.discard(t)
        return rows

    # kanesens and Simbody interleaved: kanesens BDF, Simbody RK-Merson, kanesens Adams, Simbody CPodes, ...
    ks_tools = [("kanesens", name) for name in by_name]
    sb_tools = [("simbody", m) for m in sb_integrators]
    tol_tools = [t for i in range(max(len(ks_tools), len(sb_tools))) for t in ks_tools[i:i + 1] + sb_tools[i:i + 1]]
    rows = sweep(tols, tol_tools, lambda t, x: ks(t[1], x) if t[0] == "kanesens" else sb(t[1], x))
    rows += sweep(dts, [("mujoco", m) for m in mj_integrators], lambda t, x: mj(t[1], x))
    return {"rows": rows, "y_ref": ref, "quadrature": quadrature, "reference_checks": checks,
            "kanesens_variants": list(by_name),
            "kanesens_variants_skipped": [fk.name(v) for v in requested if fk.name(v) not in by_name]}


def report(out: Path, raw: Path, rounds: int, load_start, settings: dict) -> None:
    """All results in OUT_DIR/fourbar.json; bench/make_tables.py makes docs/peers.md's tables
    and fourbar_workprecision.png from it."""
    load = lambda f: c.load_json(raw / f"{f}.json")
    med = c.median
    k = [load(f"kanesens_{r}") for r in range(1, rounds + 1)]
    s = [load(f"simbody_{r}") for r in range(1, rounds + 1)]
    m = [load(f"mujoco_{r}") for r in range(1, rounds + 1)]
    rhs = {"kanesens multipliers": med([x["rhs_multipliers"]["median_ns"] for x in k]),
           "kanesens embedding": med([x["rhs_embedding"]["median_ns"] for x in k]),
           "Simbody realize(Acceleration)": med([x["realize_acceleration"]["median_ns"] for x in s]),
           "MuJoCo mj_forward": med([x["mj_forward"]["median_ns"] for x in m])}
    mjv = m[0]["mujoco_version"]  # mj_version(): 222 = 2.2.2
    with open(out / "fourbar.json", "w") as f:
        json.dump({**c.provenance(load_start), **settings, "simbody_version": s[0]["simbody_version"],
                   "mujoco_version": f"{mjv // 100}.{mjv // 10 % 10}.{mjv % 10}", "rounds": rounds,
                   "rhs_median_ns": rhs, "agreement": load("agree"), "rhs_raw": {"kanesens": k, "simbody": s, "mujoco": m},
                   "tta": load("tta")}, f, indent=1)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("out", nargs="?", default=str(c.ROOT / "docs" / "peers"), help="output directory")
    ap.add_argument("--rounds", type=int, default=int(c.env_default("ROUNDS", 3)))
    ap.add_argument("--repeat", type=int, default=int(c.env_default("REPEAT", 31)), help="batches per RHS program")
    ap.add_argument("--tta-reps", type=int, default=int(c.env_default("TTA_REPS", 3)))
    ap.add_argument("--tols", default=c.env_default("TOLS", "1e-3 1e-4 1e-5 1e-6 1e-7 1e-8 1e-9 1e-10 1e-11 1e-12 1e-13 1e-14"))
    ap.add_argument("--dts", default=c.env_default("DTS", "1e-2 3e-3 1e-3 3e-4 1e-4 3e-5 1e-5"))
    ap.add_argument("--budget", type=float, default=float(c.env_default("BUDGET", 20)),
                    help="s; a peer method is not run at tighter settings once a run took longer")
    ap.add_argument("--build", default=c.env_default("KANESENS_BUILD_DIR", str(c.ROOT / "build")))
    ap.add_argument("--peers-build", default=c.env_default("PEERS_BUILD_DIR", str(c.ROOT / "build-peers")))
    ap.add_argument("--integrators", default="rkm rkf rk3 verlet cpodes cpodes-adams",
                    help="Simbody integrators (bench/peers/simbody_integrators.hpp)")
    ap.add_argument("--mujoco-integrators", default="rk4 euler implicit")
    a = ap.parse_args(argv)
    out = Path(a.out)
    out.mkdir(parents=True, exist_ok=True)
    work = Path(tempfile.mkdtemp(prefix="bench_peers_fourbar."))
    raw = work / "raw"
    raw.mkdir()

    kanesens = c.kanesens_exe(a.build)
    if not kanesens.is_file():
        c.cmake_build(a.build, ["kanesens"], options=["-DCMAKE_BUILD_TYPE=Release"])
    c.cmake_build(a.peers_build, ["simbody_fourbar_bench", "mujoco_fourbar_bench"],
                  options=["-DKANESENS_PEERS=ON", "-DCMAKE_BUILD_TYPE=Release"])
    simbody = c.peer_exe(a.peers_build, "simbody_fourbar_bench")
    mujoco = c.peer_exe(a.peers_build, "mujoco_fourbar_bench")
    load_start = c.loadavg()

    # 1. RHS speed, alternating.
    for r in range(1, a.rounds + 1):
        c.log(WHO, f"RHS round {r}/{a.rounds}")
        c.write_json(raw / f"kanesens_{r}.json",
                     c.run_json([kanesens, "bench", "rhs", SCENE, "--repeat", a.repeat, "--json"]))
        c.write_json(raw / f"simbody_{r}.json", c.run_json([simbody, "--repeat", a.repeat]))
        c.write_json(raw / f"mujoco_{r}.json", c.run_json([mujoco, "--repeat", a.repeat]))
    c.write_json(raw / "agree.json", agreement(kanesens, raw))

    # 2. Time to accuracy, alternating the tools for every tolerance (every dt for MuJoCo).
    sbi, mji = c.words(a.integrators), c.words(a.mujoco_integrators)
    tta = time_to_accuracy(kanesens, simbody, mujoco, work, [float(x) for x in c.words(a.tols)],
                           [float(x) for x in c.words(a.dts)], a.tta_reps, a.budget, sbi, mji)
    with open(raw / "tta.json", "w") as f:
        json.dump(tta, f, indent=1)

    ks_version = subprocess.run([str(kanesens), "--version"], capture_output=True, text=True).stdout.splitlines()[0]
    report(out, raw, a.rounds, load_start, {"kanesens_version": ks_version, "repeat": a.repeat, "tta_reps": a.tta_reps,
                                            "budget_s": a.budget, "simbody_integrators": sbi, "mujoco_integrators": mji})
    c.log(WHO, f"wrote {out / 'fourbar.json'}; tables and figure: bench/make_tables.py")


if __name__ == "__main__":
    main()
