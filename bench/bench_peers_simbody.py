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
    CPodesIntegrator (BDF/Newton, finite-difference Jacobian) at accuracy = the same values;
    error = max abs over states of y(10) − y_ref(10), y_ref = kanesens adams at rtol 1e-14
    (atol 1e-16; as bench/bench_peers_sympy.py, which checks it against SciPy's DOP853). A
    Simbody integrator whose run took longer than BUDGET s is not run at tighter tolerances
    for that N.

Writes OUT_DIR (default docs/peers) simbody.md (tables), simbody.json (all raw results) and
simbody_workprecision.png.
"""
from __future__ import annotations

import argparse
import datetime
import json
import os
import platform
import subprocess
import tempfile
from pathlib import Path

import common as c

WHO = "bench_peers_simbody"


def agreement(kanesens, scene, sb) -> dict:
    ks = c.run_json([kanesens, "eom", scene, "--q=" + c.fmt_list(sb["q"]), "--u=" + c.fmt_list(sb["u"])])
    return {"max_abs_diff_udot": max(abs(a - b) for a, b in zip(ks["udot"], sb["udot"])),
            "max_abs_udot": max(abs(x) for x in sb["udot"])}


def time_to_accuracy(kanesens, simbody, work: Path, ns, tols, reps, budget) -> dict:
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


def report(out: Path, raw: Path, rounds: int, ns, load_start: str, git: str) -> str:
    """Tables (simbody.md), all results (simbody.json) and the work-precision plot."""
    load = lambda f: c.load_json(raw / f"{f}.json")
    med = c.median
    cpu = c.cpu_model()
    load_end = " ".join(c.loadavg())
    rows, rhs_raw = [], {}
    for n in ns:
        k = [load(f"kanesens_{n}_{r}") for r in range(1, rounds + 1)]
        s = [load(f"simbody_{n}_{r}") for r in range(1, rounds + 1)]
        rows.append({"n": n, "kanesens_rhs_ns": med([x["rhs"]["median_ns"] for x in k]),
                     "kanesens_mf_ns": med([x["mass_matrix_and_forcing"]["median_ns"] for x in k]),
                     "simbody_realize_ns": med([x["realize_acceleration"]["median_ns"] for x in s]),
                     "simbody_version": s[0]["simbody_version"], "agreement": load(f"agree_{n}")})
        rhs_raw[n] = {"kanesens": k, "simbody": s}
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
    tns = sorted({r["n"] for r in tta["rows"]})
    methods = [("simbody", "rkm"), ("simbody", "cpodes"), ("kanesens", "bdf"), ("kanesens", "adams"),
               ("kanesens", "dop853")]
    T = {}
    for n in tns:
        for tool, m in methods:
            pts = sorted([(r["tol"], r["error"], r["time_s"]) for r in tta["rows"]
                          if r["n"] == n and r["tool"] == tool and r["method"] == m and r["error"] is not None],
                         key=lambda p: -p[0])
            for e in targets:
                T[(n, tool, m, e)] = c.time_at(pts, e)
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
    (out / "simbody.md").write_text(table)
    with open(out / "simbody.json", "w") as f:
        json.dump({"date": str(datetime.date.today()), "git": git, "cpu": cpu, "nproc": os.cpu_count(),
                   "loadavg_start": load_start, "loadavg_end": load_end, "platform": platform.platform(),
                   "rounds": rounds, "rhs_rows": rows, "rhs_raw": rhs_raw, "tta": tta, "tta_table": tta_table},
                  f, indent=1)
    plot(out / "simbody_workprecision.png", tta, tns, targets, rows[0]["simbody_version"], cpu)
    return table


def plot(png: Path, tta, tns, targets, simbody_version, cpu) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, len(tns), figsize=(5.2 * len(tns), 4.6), sharey=True, squeeze=False)
    sty = {("simbody", "rkm"): ("tab:purple", "o", "-", "Simbody RK-Merson"),
           ("simbody", "cpodes"): ("tab:brown", "s", "-", "Simbody CPodes BDF"),
           ("kanesens", "bdf"): ("black", "D", "-", "kanesens BDF"),
           ("kanesens", "adams"): ("tab:gray", "P", "--", "kanesens Adams"),
           ("kanesens", "dop853"): ("tab:olive", "*", "-.", "kanesens DOP853")}
    for ax, n in zip(axes[0], tns):
        for key, (col, mk, ls, lab) in sty.items():
            pts = sorted([(r["tol"], r["error"], r["time_s"]) for r in tta["rows"] if r["n"] == n and
                          (r["tool"], r["method"]) == key and r["error"] is not None], key=lambda p: -p[0])
            if pts:
                ax.loglog([max(p[1], 1e-16) for p in pts], [p[2] for p in pts], color=col, marker=mk, ls=ls, ms=5,
                          label=lab)
        for e in targets:
            ax.axvline(e, color="0.85", lw=0.8, zorder=0)
        ax.invert_xaxis()
        ax.grid(True, alpha=0.3)
        ax.set_title(f"planar {n}-link chain, t ∈ [0, 10]")
        ax.set_xlabel("final-time max abs error over states")
    axes[0][0].set_ylabel("wall time per solve (s)")
    axes[0][0].legend(fontsize=8, loc="upper left")
    fig.suptitle(f"Work-precision: kanesens (CVODES) vs Simbody {simbody_version} — {datetime.date.today()}, "
                 f"{cpu}, nproc {os.cpu_count()}; tolerance sweep (kanesens atol = rtol·1e-2)", fontsize=9)
    fig.tight_layout()
    fig.savefig(png, dpi=120)


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
    a = ap.parse_args(argv)
    out, ns = Path(a.out), [int(x) for x in c.words(a.ns)]
    out.mkdir(parents=True, exist_ok=True)
    work = Path(tempfile.mkdtemp(prefix="bench_peers_simbody."))
    (work / "scenes").mkdir()
    raw = work / "raw"
    raw.mkdir()

    c.cmake_build(a.build, ["kanesens", "simbody_chain_bench"], options=["-DKANESENS_PEERS=ON"], configure="always")
    kanesens, simbody = c.kanesens_exe(a.build), c.peer_exe(a.build, "simbody_chain_bench")
    load_start = " ".join(c.loadavg())
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
    tta = time_to_accuracy(kanesens, simbody, work, [int(x) for x in c.words(a.tta_ns)],
                           [float(x) for x in c.words(a.tols)], a.tta_reps, a.budget)
    with open(raw / "tta.json", "w") as f:
        json.dump(tta, f, indent=1)
    print(report(out, raw, a.rounds, ns, load_start, c.git_revision()))


if __name__ == "__main__":
    main()
