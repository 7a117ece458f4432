#!/usr/bin/python3
"""kanesens against Simbody on planar N-link chains (docs/peers.md).

    /usr/bin/python3 bench/bench_peers_simbody.py [OUT_DIR] [--ns "1 2 4 8 16 32"] [--rounds 3] [--repeat 31]
        [--tta-ns "2 4 8"] [--tta-reps 3] [--tols "1e-3 1e-4 ... 1e-14"] [--budget 20] [--build build]
    env (defaults of the options): NS ROUNDS REPEAT TTA_NS TTA_REPS TOLS BUDGET KANESENS_BUILD_DIR
        KANESENS_JOBS
    quick smoke test (not for the docs):
        bench/bench_peers_simbody.py /tmp/simbody --ns 1,2 --rounds 1 --repeat 3 --tta-ns 2 --tta-reps 1 --tols 1e-4,1e-6

Builds kanesens and the Simbody peer (-DKANESENS_PEERS=ON; needs libsimbody-dev:
KANESENS_PEERS=1 tools/install-deps.sh) into the build directory, then in ONE run:

 1. RHS speed: for every round and every N, alternately `kanesens bench rhs` on the chain
    (the scene of bench/bench_rhs.py: rods of mass 1, length 1, central inertia
    diag(1/12, 1e-4, 1/12)) and `simbody_chain_bench N` (realize(Stage::Acceleration) after
    writing q and u) at the same seeded random state; medians over batches, then over rounds.
    Check: kanesens eom's u̇ at Simbody's state against Simbody's u̇.
 2. Time to accuracy (TTA_NS): t in [0, 10] from scripts/gen_chain.py's initial state
    (q1 = 0.5, rest 0), kanesens simulate (bdf with the exact Jacobian, adams, dop853; rtol
    swept, atol = rtol·1e-2) alternating with Simbody's RungeKuttaMersonIntegrator and
    its other integrators at accuracy = the same values;
    error = max abs over states of y(10) − y_ref(10), y_ref = kanesens adams at rtol 1e-14
    (atol 1e-16; as bench/bench_peers_sympy.py, which checks it against SciPy's DOP853). A
    Simbody integrator whose run took longer than BUDGET s is not run at tighter tolerances
    for that N.

Simbody's integrators (--integrators): RungeKuttaMerson, RungeKuttaFeldberg, RungeKutta3,
Verlet, CPodes BDF/Newton and CPodes Adams/functional (bench/peers/simbody_integrators.hpp).

Writes OUT_DIR (default docs/peers) simbody.json (all raw results and the command line);
bench/make_tables.py makes docs/peers.md's tables and simbody_workprecision.png from it.
"""
from __future__ import annotations

import argparse
import json
import subprocess
import tempfile
from pathlib import Path

import common as c

WHO = "bench_peers_simbody"


def agreement(kanesens, scene, sb) -> dict:
    ks = c.run_json([kanesens, "eom", scene, "--q=" + c.fmt_list(sb["q"]), "--u=" + c.fmt_list(sb["u"])])
    return {"max_abs_diff_udot": max(abs(a - b) for a, b in zip(ks["udot"], sb["udot"])),
            "max_abs_udot": max(abs(x) for x in sb["udot"])}


def time_to_accuracy(kanesens, simbody, work: Path, ns, tols, reps, budget, integrators) -> dict:
    def ks(study, method, rtol):
        o = c.run_json([kanesens, "simulate", study, "--format", "json", "--set", f"solver.method={method}",
                        "--set", f"solver.rtol={rtol!r}", "--set", f"solver.atol={rtol * 1e-2!r}"])
        return {"time_s": o["stats"]["wall_seconds"], "y_end": o["states"][-1], "steps": o["stats"]["steps"],
                "rhs_evals": o["stats"]["rhs_evals"], "status": o.get("status", 0)}

    def sb(n, which, acc):
        # Stopped after 3 x BUDGET s: the BUDGET rule then drops the method for tighter accuracies.
        try:
            p = subprocess.run([str(simbody), str(n), "--integrate", which, "--accuracy", repr(acc), "--repeat", "1",
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
        scene.write_text(c.gen_chain_yaml(n))
        study = work / "scenes" / f"tta_chain{n}_study.yaml"
        study.write_text(f"kanesens: 1\nscene: {scene.name}\ntime: {{end: 10.0, outputs: 2}}\n"
                         "solver: {method: bdf, rtol: 1.0e-8, atol: 1.0e-10, jacobian: exact, max_steps: 100000000}\n"
                         "record: [states]\n")
        ref = ks(study, "adams", 1e-14)["y_end"]
        diff = lambda y: max(abs(a - b) for a, b in zip(y, ref))
        refs.append({"n": n, "y_ref": ref, "adams_1e-13_vs_ref": diff(ks(study, "adams", 1e-13)["y_end"]),
                     "bdf_1e-14_vs_ref": diff(ks(study, "bdf", 1e-14)["y_end"])})
        active = set(integrators)
        for tol in tols:
            # Interleaved: kanesens, Simbody, kanesens, Simbody, ... per tolerance.
            ks_methods = ["bdf", "adams", "dop853"]
            tools = []
            for i in range(max(len(ks_methods), len(integrators))):
                if i < len(ks_methods):
                    tools.append(("kanesens", ks_methods[i]))
                if i < len(integrators):
                    tools.append(("simbody", integrators[i]))
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
                       "time_s": c.median(r["time_s"] for r in rs) if ok else None,
                       "times_s": [r["time_s"] for r in rs],
                       "error": max(abs(a - b) for a, b in zip(rs[0]["y_end"], ref)) if ok else None,
                       **{k: rs[0].get(k) for k in ("steps", "rhs_evals", "realizations", "status", "message")
                          if k in rs[0]}}
                rows.append(row)
                c.log(WHO, f"TTA N={n} {t[0]} {t[1]} tol={tol:.0e} err={row['error']} time={row['time_s']}")
                if t[0] == "simbody" and (not ok or row["time_s"] > budget):
                    active.discard(t[1])
    return {"rows": rows, "refs": refs}


def report(out: Path, raw: Path, rounds: int, ns, load_start, settings: dict) -> None:
    """All results in OUT_DIR/simbody.json; bench/make_tables.py turns them into docs/peers.md's
    tables and figure."""
    load = lambda f: c.load_json(raw / f"{f}.json")
    med = c.median
    rows, rhs_raw = [], {}
    for n in ns:
        k = [load(f"kanesens_{n}_{r}") for r in range(1, rounds + 1)]
        s = [load(f"simbody_{n}_{r}") for r in range(1, rounds + 1)]
        rows.append({"n": n, "kanesens_rhs_ns": med([x["rhs"]["median_ns"] for x in k]),
                     "kanesens_mf_ns": med([x["mass_matrix_and_forcing"]["median_ns"] for x in k]),
                     "simbody_realize_ns": med([x["realize_acceleration"]["median_ns"] for x in s]),
                     "simbody_version": s[0]["simbody_version"], "agreement": load(f"agree_{n}")})
        rhs_raw[n] = {"kanesens": k, "simbody": s}
    with open(out / "simbody.json", "w") as f:
        json.dump({**c.provenance(load_start), **settings, "rounds": rounds, "rhs_rows": rows,
                   "rhs_raw": rhs_raw, "tta": load("tta")}, f, indent=1)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("out", nargs="?", default=str(c.ROOT / "docs" / "peers"), help="output directory")
    ap.add_argument("--ns", default=c.env_default("NS", "1 2 4 8 16 32"), help="chain sizes of the RHS table")
    ap.add_argument("--rounds", type=int, default=int(c.env_default("ROUNDS", 3)))
    ap.add_argument("--repeat", type=int, default=int(c.env_default("REPEAT", 31)), help="batches per RHS program")
    ap.add_argument("--tta-ns", default=c.env_default("TTA_NS", "2 4 8"), help="chain sizes of the time to accuracy")
    ap.add_argument("--tta-reps", type=int, default=int(c.env_default("TTA_REPS", 3)))
    ap.add_argument("--tols", default=c.env_default("TOLS", "1e-3 1e-4 1e-5 1e-6 1e-7 1e-8 1e-9 1e-10 1e-11 1e-12 1e-13 1e-14"))
    ap.add_argument("--budget", type=float, default=float(c.env_default("BUDGET", 20)),
                    help="s; a Simbody integrator whose run took longer is not run at tighter tolerances for that N")
    ap.add_argument("--build", default=c.env_default("KANESENS_BUILD_DIR", str(c.ROOT / "build")))
    ap.add_argument("--integrators", default="rkm rkf rk3 verlet cpodes cpodes-adams",
                    help="Simbody integrators of the time to accuracy (bench/peers/simbody_integrators.hpp)")
    a = ap.parse_args(argv)
    out, ns = Path(a.out), [int(x) for x in c.words(a.ns)]
    out.mkdir(parents=True, exist_ok=True)
    work = Path(tempfile.mkdtemp(prefix="bench_peers_simbody."))
    (work / "scenes").mkdir()
    raw = work / "raw"
    raw.mkdir()

    c.cmake_build(a.build, ["kanesens", "simbody_chain_bench"], options=["-DKANESENS_PEERS=ON"], configure="always")
    kanesens, simbody = c.kanesens_exe(a.build), c.peer_exe(a.build, "simbody_chain_bench")
    load_start = c.loadavg()
    for n in ns:  # the benchmark chain of bench/bench_rhs.py (untilted)
        (work / "scenes" / f"chain{n}.yaml").write_text(c.chain_scene_yaml(n))

    # 1. RHS speed, alternating.
    for r in range(1, a.rounds + 1):
        for n in ns:
            c.log(WHO, f"RHS round {r}/{a.rounds}, N = {n}")
            c.write_json(raw / f"kanesens_{n}_{r}.json",
                         c.run_json([kanesens, "bench", "rhs", work / "scenes" / f"chain{n}.yaml", "--repeat", a.repeat,
                                     "--json"]))
            c.write_json(raw / f"simbody_{n}_{r}.json", c.run_json([simbody, n, "--repeat", a.repeat]))
    for n in ns:
        c.write_json(raw / f"agree_{n}.json",
                     agreement(kanesens, work / "scenes" / f"chain{n}.yaml", c.load_json(raw / f"simbody_{n}_1.json")))

    # 2. Time to accuracy, alternating kanesens and Simbody for every N and tolerance.
    integrators = c.words(a.integrators)
    tta = time_to_accuracy(kanesens, simbody, work, [int(x) for x in c.words(a.tta_ns)],
                           [float(x) for x in c.words(a.tols)], a.tta_reps, a.budget, integrators)
    with open(raw / "tta.json", "w") as f:
        json.dump(tta, f, indent=1)
    report(out, raw, a.rounds, ns, load_start,
           {"repeat": a.repeat, "tta_reps": a.tta_reps, "budget_s": a.budget, "integrators": integrators})
    c.log(WHO, f"wrote {out / 'simbody.json'}; tables and figure: bench/make_tables.py")


if __name__ == "__main__":
    main()
