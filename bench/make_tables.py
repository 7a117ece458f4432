#!/usr/bin/python3
"""The benchmark pages' tables and figures, from the committed result JSON.

    /usr/bin/python3 bench/make_tables.py            # rewrite the tables in the docs and the figures
    /usr/bin/python3 bench/make_tables.py --check    # exit 1 if a table in the docs differs (no writes)
    /usr/bin/python3 bench/make_tables.py --list     # which table comes from which JSON

A table in one of the pages of DOCS below (docs/benchmarks.md,
docs/explanation/performance-record.md, docs/peers.md, ...) sits between
`<!-- table: NAME -->` and `<!-- /table -->`; NAME is a key of TABLES below, whose function
makes the markdown from one JSON file written by one driver run (the file names the command
that made it). Figures (PNG) are drawn from the same files; --check compares tables only.
"""
from __future__ import annotations

import argparse
import contextlib
import io
import json
import re
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
sys.path.insert(0, str(HERE))

DOCS = [ROOT / "docs" / "benchmarks.md", ROOT / "docs" / "peers.md", ROOT / "docs" / "workprecision.md",
        ROOT / "docs" / "explanation" / "stability.md", ROOT / "docs" / "explanation" / "constraints.md",
        ROOT / "docs" / "explanation" / "solvers.md", ROOT / "docs" / "explanation" / "sparsity.md",
        ROOT / "docs" / "explanation" / "performance-record.md"]
RESULTS = HERE / "results"
PEERS = ROOT / "docs" / "peers"
WP = ROOT / "docs" / "workprecision"
TARGETS = [1e-4, 1e-6, 1e-8, 1e-10]
MARK = re.compile(r"(<!-- table: ([\w.-]+) -->\n)(.*?)(<!-- /table -->)", re.S)


def load(path: Path):
    return json.loads(path.read_text())


def rel(path: Path) -> str:
    return str(path.relative_to(ROOT))


def md(header, rows, align=None) -> str:
    align = align or ["---:"] * len(header)
    out = ["| " + " | ".join(header) + " |", "|" + "|".join(align) + "|"]
    out += ["| " + " | ".join(str(c) for c in r) + " |" for r in rows]
    return "\n".join(out) + "\n"


def source(path: Path) -> str:
    d = load(path)
    cmd = d.get("command") or d.get("meta", {}).get("command")
    return f"\n<sub>From `{rel(path)}`" + (f" (`{cmd}`)" if cmd else "") + ".</sub>\n"


def printed(fn, *args) -> str:
    buf = io.StringIO()
    with contextlib.redirect_stdout(buf):
        fn(*args)
    return buf.getvalue().strip() + "\n"


def time_at(points, target):
    """Time to reach error <= target on a sweep [(setting, err, time)] ordered loose -> tight
    (log-log interpolation; as bench/common.py)."""
    import common
    return common.time_at(points, target)


def tta_cell(v) -> str:
    return "—" if v[0] is None else ("≤ " if v[1] == "<=" else "") + f"{v[0] * 1e3:,.1f}"


# --- docs/benchmarks.md ---------------------------------------------------------------------

RHS = RESULTS / "bench_rhs.json"


def paired_ratio(raw: dict, mujoco: str, kanesens: str) -> float:
    """The median over rounds of MuJoCo's time / kanesens's in that round (the two programs run
    back to back, so a slow spell of the machine that spans one round hits both)."""
    import statistics
    return statistics.median(m["mj_forward"]["median_ns"] / k["rhs"]["median_ns"]
                             for m, k in zip(raw[mujoco], raw[kanesens]))


def rhs_mujoco():
    d = load(RHS)
    rows = []
    for r in d["rows"]:
        raw = d["raw"][str(r["n"])]
        rows.append([r["n"], f"{r['kanesens_spatial_rhs_ns']:,.0f}", f"{r['mujoco_spatial_forward_ns']:,.0f}",
                     f"**{paired_ratio(raw, 'mujoco_spatial', 'kanesens_spatial'):.2f}**",
                     f"{r['kanesens_rhs_ns']:,.0f}", f"{r['mujoco_forward_ns']:,.0f}",
                     f"{paired_ratio(raw, 'mujoco', 'kanesens'):.2f}",
                     f"{r['agreement_spatial']['max_abs_diff_udot_qacc']:.1e}"])
    return md(["N", "kanesens general 3-D RHS, spatial chain (ns)", "MuJoCo mj_forward, spatial chain (ns)",
               "ratio, 3-D path", "kanesens planar RHS, planar chain (ns)", "MuJoCo mj_forward, planar chain (ns)",
               "ratio, planar path", "max abs(u̇ − qacc), spatial"], rows) + source(RHS)


def rhs_paths():
    d = load(RHS)
    rows = []
    for r in d["rows"]:
        rows.append([r["n"], f"{r['kanesens_rhs_ns']:,.0f}", f"{r['kanesens_3d_rhs_ns']:,.0f}",
                     f"{r['kanesens_3d_rhs_ns'] / r['kanesens_rhs_ns']:.2f}", f"{r['kanesens_mf_ns']:,.0f}",
                     f"{r['kanesens_3d_mf_ns']:,.0f}", f"{r['kanesens_3d_mf_ns'] / r['kanesens_mf_ns']:.2f}",
                     f"{r['kanesens_jacobian_ns'] / 1e3:.2f}"])
    return md(["N", "planar RHS (ns)", "3-D RHS, tilted chain (ns)", "3-D / planar", "planar M+f (ns)",
               "3-D M+f, tilted chain (ns)", "3-D / planar", "Dual Jacobian, planar (µs)"], rows) + source(RHS)


def driver_table(module: str, json_name: str, fn: str = "table") -> str:
    """What the driver `module` prints with its `fn` from RESULTS/json_name, and the source line."""
    import importlib
    path = RESULTS / json_name
    return printed(getattr(importlib.import_module(module), fn), path) + source(path)


def dense_lu_solve():
    p = RESULTS / "dense_lu_solve.json"
    d = load(p)
    rows = [[r["n"], f"{r['sundials_dense_ns']:.0f}", f"{r['kanesens_dense_lu_ns']:.0f}",
             f"{r['sundials_dense_ns'] / r['kanesens_dense_lu_ns']:.1f}", f"{r['eigen_partial_piv_lu_direct_ns']:.0f}"]
            for r in d["rows"]]
    return (f"Median over {d['rounds']} alternating rounds of one solve with a factored n×n matrix (ns).\n\n" +
            md(["n", "SUNLinSol_Dense", "kanesens (PartialPivLU's factors, substitutions by hand)", "speed-up",
               "PartialPivLU's solve called directly"], rows) +
            source(p))


def sensitivity_cost_evaluations():
    return driver_table("sensitivity_cost", "sensitivity_cost_current.json", "evaluations")


def sensitivity_cost_summary():
    """Per added sensitivity and the Jacobian's cost, each scene from the newest run that has it:
    on AVX-512 sensitivity_cost_value_rhs (sensitivity_cost_stacked for the scenes it left out),
    on AVX2 sensitivity_cost_avx2_current (sensitivity_cost_avx2 for any it left out) and the
    instruction table of that processor."""
    import sensitivity_cost
    import sensitivity_instructions

    def native(name, rate):
        return {(r["scene"], r["method"]): rate(r) for r in load(RESULTS / name)["rows"] if r["exe"] == "native"}
    avx512 = {**native("sensitivity_cost_stacked.json", sensitivity_cost.per_added),
              **native("sensitivity_cost_value_rhs.json", sensitivity_cost.per_added)}
    avx2 = {**native("sensitivity_cost_avx2.json", sensitivity_cost.per_added),
            **native("sensitivity_cost_avx2_current.json", sensitivity_cost.per_added)}
    instructions = native("sensitivity_instructions_avx2.json", sensitivity_instructions.per_added)

    def pair(rates, scene):
        v = [rates.get((scene, m)) for m in ("bdf", "dop853")]
        return None if None in v else " / ".join(f"{x:.2f}×" for x in v)

    def avx2_cell(scene):
        time, count = pair(avx2, scene), pair(instructions, scene)
        return f"{time} ({count or '—'})" if time else "—"

    def jacobian(name):
        v = [r["jacobian_over_rhs"] for r in load(RESULTS / name)["rows"] if r["exe"] == "native" and 6 <= r["nstate"] <= 20]
        return f"{min(v):.1f}–{max(v):.1f}×"
    scenes = [("arm_3d", "3-D arm (5 DOF, a universal joint)"), ("chain8_spatial", "8-link spatial chain"),
              ("chain4_planar", "planar 4-link chain"), ("four_bar_multipliers", "four-bar with multipliers"),
              ("rolling_disc", "rolling disc in steady turning (multipliers)"),
              ("rolling_disc_wobbling", "rolling disc, wobbling (multipliers)"), ("andrews", "Andrews' mechanism")]
    rows = [[label, "≤ 0.4×", pair(avx512, scene) or "—", avx2_cell(scene)] for scene, label in scenes]
    rows.append(["the exact Jacobian, in right-hand sides, at 6–20 states", "≤ 6×", jacobian("jacobian_cost_current.json"),
                 jacobian("jacobian_cost_avx2.json")])
    return ("Per added sensitivity with six sensitivities (minimum of the interleaved runs; on AVX2 also in "
            "instructions, which do not depend on the machine's load), and the Jacobian as the solvers get it "
            "(median), built for the machine (`native`).\n\n" +
            md(["six sensitivities of", "goal", "AVX-512: BDF / DOP853", "AVX2: BDF / DOP853, time (instructions)"],
               rows, ["---", "---", "---", "---"]) +
            "\n<sub>From `bench/results/`: AVX-512 `sensitivity_cost_value_rhs.json` (the planar chain "
            "`sensitivity_cost_stacked.json`) and `jacobian_cost_current.json`; AVX2 `sensitivity_cost_avx2_current.json`, "
            "`sensitivity_instructions_avx2.json` and `jacobian_cost_avx2.json` (each command is under its own "
            "table). —: not measured (no AVX-512 processor was at hand for the wobbling disc; valgrind 3.19 cannot "
            "decode an AVX instruction of the articulated-body recursion, which the 8-link chain's plain solve "
            "takes).</sub>\n")


def sensitivity_corrector_stacked():
    return driver_table("sensitivity_corrector", "sensitivity_corrector_stacked.json", "stacked_summary")


def sensitivity_corrector():
    return driver_table("sensitivity_corrector", "sensitivity_corrector.json", "summary")


def outputs_cost():
    p = RESULTS / "outputs_cost.json"
    d = load(p)
    names = {"plain": "none", "cheap outputs": "positions, kinetic energy, an expression, a value at the end",
             "all outputs": "the above plus velocity, acceleration, a joint load and an integral of its power"}
    rows = [[names.get(k, k), f"{v * 1e3:.1f}", f"{d['ratio_to_plain'][k]:.2f}"] for k, v in d["median_seconds"].items()]
    return md(["outputs", "median wall time (ms)", "ratio to no outputs"], rows, ["---", "---:", "---:"]) + source(p)


def newton_sweep():
    """Dense vs matrix-free Newton on the N four-bar and a chain (explanation/solvers.md)."""
    p = RESULTS / "newton_sweep.json"
    rows = []
    for c in load(p)["cases"]:
        s = c["solvers"]
        de, kr, kd = s["dense"], s["krylov"], s["krylov_dq"]
        if c["family"] == "n_four_bar":
            name, err = "N four-bar", lambda r: f"{r['error_vs_exact']:.1e}"
            errors = f"{err(de)} / {err(kr)}"
        else:
            name, errors = "chain", f"— / {kr['max_difference_vs_dense']:.1e}"
        rows.append([name, c["n"], c["states"], f"{de['wall_seconds_median']:.3g}", f"{kr['wall_seconds_median']:.3g}",
                     f"{kr['wall_ratio_vs_dense']:.2f}", f"{kd['wall_ratio_vs_dense']:.2f}", de["jac_evals"],
                     kr["jtimes_evals"], f"{de['steps']} / {kr['steps']}", errors])
    return md(["mechanism", "N", "states", "dense s", "krylov s", "krylov / dense", "krylov (`jacobian: dq`) / dense",
               "dense J", "krylov J v", "steps dense / krylov", "error dense / krylov"], rows,
              ["---"] + ["---:"] * 10) + source(p)


def newton_stiff():
    """Matrix-free Newton on chains with stiff joints, and what auto chose (explanation/solvers.md)."""
    p = RESULTS / "newton_sweep_stiff.json"
    rows = []
    for c in load(p)["cases"]:
        de, kr, au = c["solvers"]["dense"], c["solvers"]["krylov"], c["solvers"]["auto"]
        rows.append([f"{c['spring']:g}", f"{c['damper']:g}", f"{de['steps']} / {kr['steps']}",
                     f"{de['nonlin_conv_fails']} / {kr['nonlin_conv_fails']}", kr["jtimes_evals"],
                     f"{kr['wall_ratio_vs_dense']:.2f}", au["linear_solver"]])
    return md(["k (N m/rad)", "c (N m s/rad)", "steps dense / krylov", "Newton failures dense / krylov",
               "krylov J v", "krylov / dense (time)", "auto chose"], rows, ["---:"] * 6 + ["---"]) + source(p)


def sensitivities_table():
    p = RESULTS / "bench_sensitivities.json"
    d = load(p)
    rows = []
    for r in d["rows"]:
        if r.get("failed"):
            rows.append([r["method"], r["S"], r["sens_rhs"], f"failed: {r['failed']}", "", "", "", "", "", ""])
            continue
        rows.append([r["method"], r["S"], r["sens_rhs"], f"{r['median_wall_s'] * 1e3:.2f}", f"{r['wall_over_plain']:.2f}",
                     "—" if r["S"] == 0 else f"{r['per_added']:.2f}", r["steps"], r["rhs_evals"], r["sens_rhs_evals"],
                     r["rhs_evals_dq"]])
    t1 = md(["method", "S", "sens RHS", "median wall (ms)", "wall / plain", "per added sensitivity", "steps",
             "RHS evals", "sens RHS evals", "RHS evals for DQ"], rows, ["---", "---:", "---"] + ["---:"] * 7)
    rows = [[r["n"], f"{r['median_wall_s'] * 1e3:.1f}", r["steps"], r["rhs_evals"], r["jacobians"]] for r in d["chains"]]
    t2 = md(["N", "median wall per trajectory (ms)", "steps", "RHS evals", "Jacobians"], rows)
    return t1 + "\n" + t2 + source(p)


def constraints_table():
    p = RESULTS / "bench_constraints.json"
    d = load(p)
    rows = [[r["problem"], r["formulation"], r["sensitivities"], f"{r['median_wall_s'] * 1e3:.1f}", r["steps"],
             r["rhs_evals"], r["sens_rhs_evals"], f"{r['max_abs_g']:.1e}"] for r in d["rows"]]
    return md(["problem", "formulation", "sensitivities", "median wall (ms)", "steps", "RHS evals", "sens RHS evals",
               "max abs(g) at outputs"], rows, ["---", "---"] + ["---:"] * 6) + source(p)


def ensemble_table():
    p = RESULTS / "bench_ensemble.json"
    d = load(p)
    rows = []
    for r in d["rows"]:
        rows.append([r["ranks"] if not r.get("oversubscribed") else f"{r['ranks']} (oversubscribed)", r["samples"],
                     f"{r['median_wall_s']:.2f}", f"{r['samples_per_s']:.0f}",
                     "—" if r.get("efficiency") is None else f"{r['efficiency']:.2f}",
                     f"{r['hdf5_percent']:.2f} %", f"{r['scheduling_percent']:.2f} %"])
    b = d.get("big")
    if b and b.get("wall_s"):
        rows.append([b["ranks"], b["samples"], f"{b['wall_s']:.2f} (one run)", f"{b['samples_per_s']:.0f}", "—",
                     f"{b['hdf5_percent']:.2f} %", f"{b['scheduling_percent']:.2f} %"])
    return md(["ranks", "samples", "median wall (s)", "samples/s", "efficiency t1 / (R tR)",
               "rank time in HDF5 writes", "rank time in scheduling"], rows) + \
        (f"\nFile size at {b['samples']} samples: {b['file_bytes'] / 1e6:.1f} MB ({b['bytes_per_sample']:.0f} bytes per "
         f"sample); `/usr/bin/time`: {b['time_output']}.\n" if b and b.get("file_bytes") else "") + source(p)


# --- docs/peers.md --------------------------------------------------------------------------

SYMPY = PEERS / "sympy_scipy.json"
SIMBODY = PEERS / "simbody.json"
FB_SYMPY = PEERS / "fourbar_sympy_scipy.json"
FOURBAR = PEERS / "fourbar.json"
SB_LABEL = {"rkm": "RK-Merson", "rkf": "RK-Feldberg", "rk3": "RK3", "verlet": "Verlet", "cpodes": "CPodes BDF",
            "cpodes-adams": "CPodes Adams", "cpodes-adams-newton": "CPodes Adams/Newton"}
KS_LABEL = {"bdf": "BDF", "adams": "Adams", "dop853": "DOP853"}


def sympy_derivation():
    d = load(SYMPY)
    rows = [[r["n"], f"{r['build_model_wall_s']:.2f}", f"{r['kanes_equations_wall_s']:.2f}", f"{r['lambdify_wall_s']:.2f}",
             f"{r['total_wall_s']:.2f}", f"{r['total_cpu_s']:.2f}", f"{r['count_ops_M_f']:,}"] for r in d["derivation"]]
    return md(["N", "build_model (s)", "kanes_equations (s)", "lambdify, cse (s)", "total wall (s)", "total CPU (s)",
               "count_ops(M, f)"], rows) + source(SYMPY)


def sympy_reference():
    d = load(SYMPY)
    rr, cr = d["meta"]["ref_rtol"], d["meta"]["check_rtol"]
    rows = [[c["n"], f"{c['kanesens_adams_check_vs_ref']:.1e}", f"{c['kanesens_bdf_ref_rtol_vs_ref']:.1e}",
             f"{c['scipy_dop853_check_vs_ref']:.1e}", f"{max(abs(x) for x in c['y_ref']):.2f}"]
            for c in d["reference_check"]]
    return md(["N", f"kanesens Adams rtol {cr:.0e}", f"kanesens BDF rtol {rr:.0e}", f"SciPy DOP853 rtol {cr:.0e}",
               "max abs y_ref"], rows) + source(SYMPY)


def sympy_tta():
    import bench_peers_sympy as m
    d = load(SYMPY)
    T = {(t["n"], t["tool"], t["method"], t["target"]): t for t in d["targets"]}
    scipy_methods = [s for s in m.SCIPY_METHODS if any(k[1] == "scipy" and k[2] == s for k in T)]
    ks_methods = [s for s in m.KANESENS_METHODS if any(k[1] == "kanesens" and k[2] == s for k in T)]
    cell = lambda t: "—" if t is None or t["time_s"] is None else \
        ("≤ " if t["how"] == "<=" else "") + f"{t['time_s'] * 1e3:,.1f}"
    rows = []
    for n in sorted({k[0] for k in T}):
        for e in TARGETS:
            cs = [T.get((n, "scipy", s, e)) for s in scipy_methods] + [T.get((n, "kanesens", s, e)) for s in ks_methods]
            sv = [(c["time_s"], c["method"]) for c in cs[:len(scipy_methods)] if c and c["time_s"] is not None]
            kv = [(c["time_s"], KS_LABEL[c["method"]]) for c in cs[len(scipy_methods):] if c and c["time_s"] is not None]
            ratio = f"**{min(sv)[0] / min(kv)[0]:,.0f}** ({min(sv)[1]} / {min(kv)[1]})" if sv and kv else "—"
            a, b = T.get((n, "scipy", "DOP853", e)), T.get((n, "kanesens", "dop853", e))
            r2 = f"{a['time_s'] / b['time_s']:,.0f}" if a and b and a["time_s"] and b["time_s"] else "—"
            rows.append([n, f"{e:.0e}"] + [cell(c) for c in cs] + [ratio, r2])
    return md(["N", "target"] + [f"SciPy {s}" for s in scipy_methods] + [f"kanesens {KS_LABEL[s]}" for s in ks_methods]
              + ["best SciPy / best kanesens", "SciPy DOP853 / kanesens DOP853"], rows) + source(SYMPY)


def simbody_rhs():
    d = load(SIMBODY)
    rows = [[r["n"], f"{r['kanesens_rhs_ns']:,.0f}", f"{r['kanesens_mf_ns']:,.0f}", f"{r['simbody_realize_ns']:,.0f}",
             f"**{r['simbody_realize_ns'] / r['kanesens_rhs_ns']:.1f}**", f"{r['agreement']['max_abs_diff_udot']:.1e}",
             f"{r['agreement']['max_abs_udot']:.1f}"] for r in d["rhs_rows"]]
    return md(["N", "kanesens RHS (ns)", "kanesens M+f (ns)", "Simbody realize(Acceleration) (ns)",
               "Simbody / kanesens RHS", "max abs(u̇ kanesens − u̇ Simbody)", "max abs u̇"], rows) + source(SIMBODY)


def _sweeps(rows, key_fn):
    """{(n, tool, method): [(tol, err, time)] loose -> tight} of the runs with an error."""
    out = {}
    for r in rows:
        if r.get("error") is None or r.get("time_s") is None:
            continue
        out.setdefault(key_fn(r), []).append((r["tol"], r["error"], r["time_s"]))
    return {k: sorted(v, key=lambda p: -p[0]) for k, v in out.items()}


def simbody_tta():
    d = load(SIMBODY)
    rows = d["tta"]["rows"]
    integrators = d.get("integrators") or ["rkm", "cpodes"]
    S = _sweeps(rows, lambda r: (r["n"], r["tool"], r["method"]))
    out = []
    for n in sorted({r["n"] for r in rows}):
        for e in TARGETS:
            sv = {m: time_at(S.get((n, "simbody", m), []), e) for m in integrators}
            kv = {m: time_at(S.get((n, "kanesens", m), []), e) for m in ("bdf", "adams", "dop853")}
            sb = [(v[0], m) for m, v in sv.items() if v[0] is not None]
            kb = [(v[0], m) for m, v in kv.items() if v[0] is not None]
            best = f"{SB_LABEL[min(sb)[1]]}" if sb else "—"
            ratio = f"**{min(sb)[0] / min(kb)[0]:,.0f}**" if sb and kb else "—"
            out.append([n, f"{e:.0e}"] + [tta_cell(sv[m]) for m in integrators] + [best]
                       + [tta_cell(kv[m]) for m in ("bdf", "adams", "dop853")] + [ratio])
    return md(["N", "target"] + [f"Simbody {SB_LABEL[m]}" for m in integrators] + ["best Simbody"]
              + ["kanesens BDF", "kanesens Adams", "kanesens DOP853", "best Simbody / best kanesens"], out,
              ["---:", "---:"] + ["---:"] * len(integrators) + ["---"] + ["---:"] * 4) + source(SIMBODY)


def simbody_reference():
    d = load(SIMBODY)
    rows = [[r["n"], f"{r['adams_1e-13_vs_ref']:.1e}", f"{r['bdf_1e-14_vs_ref']:.1e}"] for r in d["tta"]["refs"]]
    return md(["N", "kanesens Adams rtol 1e-13", "kanesens BDF rtol 1e-14"], rows) + source(SIMBODY)


def _fb_label(k):
    import fourbar_kanesens as fk
    return fk.label(k)


def fourbar_sympy_derivation():
    d = load(FB_SYMPY)["derivation"]
    rows = [[name, f"{d[k + '_wall_s']:.3f}", f"{d[k + '_cpu_s']:.3f}"]
            for k, name in (("build", "build (frames, points, bodies, KanesMethod)"),
                            ("kanes_equations", "kanes_equations"), ("lambdify", "lambdify (cse)"), ("total", "total"))]
    return md(["stage", "wall (s)", "CPU (s)"], rows, ["---", "---:", "---:"]) + \
        f"\ncount_ops(M, f) = {d['count_ops_M_f']:,}.\n" + source(FB_SYMPY)


def fourbar_sympy_tight():
    c = load(FB_SYMPY)["reference_check"]
    rows = [[("kanesens " + _fb_label(r["method"])) if r["tool"] == "kanesens" else "SciPy " + r["method"],
             f"{r['rtol']:.0e}", f"{r['error']:.1e}", f"{r['g_end']:.1e}", f"{r['time_s']:.2f}"] for r in c["tight"]]
    return md(["solution", "rtol", "max abs (y − y_ref)", "\\|g\\| at t = 10", "time (s)"], rows,
              ["---"] + ["---:"] * 4) + source(FB_SYMPY)


def fourbar_sympy_tta():
    import bench_peers_fourbar_sympy as m
    d = load(FB_SYMPY)
    kv = d["meta"]["kanesens_variants"]
    T = {(t["tool"], t["method"], t["target"]): t for t in d["targets"]}
    rows = []
    for e in TARGETS:
        cs = [T.get(("scipy", s, e)) for s in m.SCIPY_METHODS] + [T.get(("kanesens", k, e)) for k in kv]
        ns = len(m.SCIPY_METHODS)
        sv = [(x["time_s"], x["method"]) for x in cs[:ns] if x and x["time_s"] is not None]
        kt = [(x["time_s"], _fb_label(x["method"])) for x in cs[ns:] if x and x["time_s"] is not None]
        ratio = f"**{min(sv)[0] / min(kt)[0]:,.0f}** ({min(sv)[1]} / {min(kt)[1]})" if sv and kt else "—"
        rows.append([f"{e:.0e}"] + [m.ms(x) for x in cs] + [ratio])
    return md(["target"] + [f"SciPy {s}" for s in m.SCIPY_METHODS] + ["kanesens " + _fb_label(k) for k in kv]
              + ["best SciPy / best kanesens"], rows) + source(FB_SYMPY)


def fourbar_rhs():
    d = load(FOURBAR)
    rhs = d["rhs_median_ns"]
    base = rhs["kanesens multipliers"]
    rows = [[name, f"{ns:,.0f}", f"{ns / base:.2f}"] for name, ns in rhs.items()]
    return md(["program", "median ns per evaluation", "ratio to kanesens multipliers"], rows,
              ["---", "---:", "---:"]) + source(FOURBAR)


def fourbar_agreement():
    a = load(FOURBAR)["agreement"]
    rows = [["Simbody u̇, force on the coupler end", f"{a['simbody_udot_diff']:.1e}", f"{a['simbody_force_diff']:.1e}"],
            ["MuJoCo qacc, efc_force", f"{a['mujoco_qacc_diff']:.1e}", f"{a['mujoco_force_diff']:.1e}"],
            ["MuJoCo against kanesens with the J̇u bias set to zero", f"{a['mujoco_qacc_diff_no_bias']:.1e}",
             f"{a['mujoco_force_diff_no_bias']:.1e}"],
            ["(scale: max abs u̇, max abs λ of kanesens)", f"{a['max_abs_udot']:.2f}", f"{a['max_abs_multiplier']:.2f}"]]
    return md(["against kanesens eom at the initial state", "u̇ (rad/s²)", "loop force (N)"], rows,
              ["---", "---:", "---:"]) + source(FOURBAR)


def _fourbar_methods(tta):
    seen = []
    for tool in ("simbody", "mujoco"):
        for r in tta["rows"]:
            if r["tool"] == tool and (tool, r["method"]) not in seen:
                seen.append((tool, r["method"]))
    return seen + [("kanesens", k) for k in tta["kanesens_variants"]]


def fourbar_tta():
    tta = load(FOURBAR)["tta"]
    methods = _fourbar_methods(tta)
    pts = {m: sorted([(r["setting"], r["error"], r["time_s"]) for r in tta["rows"]
                      if (r["tool"], r["method"]) == m and r["error"] is not None], key=lambda p: -p[0])
           for m in methods}
    rows = []
    for e in TARGETS:
        vs = {m: time_at(pts[m], e) for m in methods}
        peer = [(v[0], m) for m, v in vs.items() if m[0] != "kanesens" and v[0] is not None]
        ks = [(v[0], m) for m, v in vs.items() if m[0] == "kanesens" and v[0] is not None]
        ratio = f"**{min(peer)[0] / min(ks)[0]:,.0f}**" if peer and ks else "—"
        best = _fourbar_method_label(min(peer)[1]) if peer else "—"
        rows.append([f"{e:.0e}"] + [tta_cell(vs[m]) for m in methods] + [best, ratio])
    return md(["target"] + [_fourbar_method_label(m) for m in methods] + ["best peer", "best peer / best kanesens"],
              rows, ["---:"] * (len(methods) + 1) + ["---", "---:"]) + source(FOURBAR)


def _fourbar_method_label(m):
    tool, name = m
    if tool == "simbody":
        return "Simbody " + SB_LABEL.get(name, name)
    if tool == "mujoco":
        return f"MuJoCo {'RK4' if name == 'rk4' else name} (fixed dt)"
    return "kanesens " + _fb_label(name)


def fourbar_mujoco():
    tta = load(FOURBAR)["tta"]
    rows = []
    for r in sorted([r for r in tta["rows"] if r["tool"] == "mujoco"], key=lambda r: (r["method"], -r["setting"])):
        ok = r.get("error") is not None
        rows.append([r["method"], f"{r['setting']:.0e}", f"{r['steps']:,}" if ok else "", f"{r['time_s']:.3f}" if ok else "",
                     f"{r['error']:.1e}" if ok else "failed", f"{r['position_residual']:.1e}" if ok else ""])
    return md(["integrator", "dt", "steps", "wall (s)", "max abs error at t = 10", "loop position residual (m)"],
              rows, ["---"] + ["---:"] * 5) + source(FOURBAR)


def peers_summary():
    """One line per peer and problem: the ratios of the tables above, from the same JSON."""
    rows = []
    d = load(RHS)
    rhs = d["rows"]
    sp = [paired_ratio(d["raw"][str(r["n"])], "mujoco_spatial", "kanesens_spatial") for r in rhs]
    pl = [paired_ratio(d["raw"][str(r["n"])], "mujoco", "kanesens") for r in rhs]
    ns = [r["n"] for r in rhs]
    rows.append(["MuJoCo mj_forward", f"chain N = {ns[0]} … {ns[-1]}",
                 f"general 3-D path {min(sp):.1f}–{max(sp):.1f}× (planar path {min(pl):.1f}–{max(pl):.1f}×)",
                 "fixed step, no error control", "bench/results/bench_rhs.json"])
    sb = load(SIMBODY)
    r = [x["simbody_realize_ns"] / x["kanesens_rhs_ns"] for x in sb["rhs_rows"]]
    tta = [_ratio_from_cell(c) for c in _table_column(simbody_tta(), -1)]
    tta = [x for x in tta if x is not None]
    rows.append(["Simbody realize(Acceleration), best of its integrators per target", "chain N = 2, 4, 8",
                 f"{min(r):.0f}–{max(r):.0f}× (planar path)",
                 f"{min(tta):,.0f}–{max(tta):,.0f}×" if tta else "—", rel(SIMBODY)])
    sy = [_ratio_from_cell(c) for c in _table_column(sympy_tta(), -2)]
    sy = [x for x in sy if x is not None]
    rows.append(["SymPy KanesMethod + SciPy solve_ivp, best method per target", "chain N = 2, 4, 8", "—",
                 f"{min(sy):,.0f}–{max(sy):,.0f}×" if sy else "—", rel(SYMPY)])
    fs = [_ratio_from_cell(c) for c in _table_column(fourbar_sympy_tta(), -1)]
    fs = [x for x in fs if x is not None]
    rows.append(["SymPy KanesMethod + SciPy solve_ivp", "four-bar", "—",
                 f"{min(fs):,.0f}–{max(fs):,.0f}×" if fs else "—", rel(FB_SYMPY)])
    rr = load(FOURBAR)["rhs_median_ns"]
    k = rr["kanesens multipliers"]
    ft = [_ratio_from_cell(c) for c in _table_column(fourbar_tta(), -1)]
    ft = [x for x in ft if x is not None]
    rows.append(["Simbody, MuJoCo", "four-bar",
                 ", ".join(f"{p.split()[0]} {v / k:.0f}×" for p, v in rr.items() if not p.startswith("kanesens")),
                 f"{min(ft):,.0f}–{max(ft):,.0f}× (best peer)" if ft else "—", rel(FOURBAR)])
    return md(["peer", "problem", "RHS time, peer / kanesens", "time to the same error (targets 1e-4 … 1e-10 that both reach), peer / kanesens", "data"],
              rows, ["---"] * 5)


# --- docs/workprecision.md -----------------------------------------------------------------

def wp_summary():
    """Per problem: the fastest method to reach a final-time relative error, from docs/workprecision/*.json."""
    import run_workprecision as rw
    targets = [1e-4, 1e-6, 1e-8]
    rows = []
    for name in rw.PROBLEMS:
        p = WP / f"{name}.json"
        if not p.exists():
            continue
        d = load(p)
        ref = d.get("reference", {})
        refd = f"{ref['row'].get('method', 'bdf-exact')} rtol {ref['row']['rtol']:.0e}" if ref.get("kind") == "computed" \
            else "file"
        runs = [r for r in d["rows"] if not r.get("skipped")]
        methods = list(dict.fromkeys(r["method"] for r in runs))
        ok = lambda r: r["ok"] and r.get("final_rel_error") is not None and 0 < r["final_rel_error"] <= 10
        sweeps = {}
        for m in methods:
            rs = [r for r in runs if r["method"] == m and ok(r)]
            key = (lambda r: -(r.get("h") or 0)) if m == "rk4" else (lambda r: -(r.get("tol") or 0))
            sweeps[m] = [(0, r["final_rel_error"], r["wall_seconds"]) for r in sorted(rs, key=key)]
        cells = []
        for e in targets:
            best = [(t[0], m) for m in methods for t in [time_at(sweeps[m], e)] if t[0] is not None]
            cells.append(f"{min(best)[1]} ({min(best)[0] * 1e3:,.1f})" if best else "none")
        failed = sum(1 for r in runs if not ok(r))
        rows.append([f"[{name}](#{name})", refd] + cells + [failed])
    return md(["problem", "reference", "fastest to 1e-4 (ms)", "fastest to 1e-6 (ms)", "fastest to 1e-8 (ms)",
               "failed or diverged runs"], rows, ["---", "---"] + ["---"] * 3 + ["---:"]) + \
        "\n<sub>From `docs/workprecision/*.json` (each records its command); final-time max relative error, " \
        "interpolated log-log along each method's sweep.</sub>\n"


# --- docs/explanation/stability.md ---------------------------------------------------------

def _wp(name):
    return WP / f"{name}.json"


def _wp_source(name) -> str:
    d = load(_wp(name))
    return f"\n<sub>From `{rel(_wp(name))}` (`{d['harness_command']}`); reference {_wp_ref(d)}.</sub>\n"


def _wp_ref(d) -> str:
    r = d.get("reference", {})
    return f"{r['row']['method']} at rtol {r['row']['rtol']:.0e}" if r.get("kind") == "computed" else "from a file"


def _e(v) -> str:
    return "—" if v is None else f"{v:.1e}"


def _status(r) -> str:
    """'ok' or the failure's code and time (e.g. RK4_NONFINITE at t = 0.05)."""
    if r["ok"]:
        return "ok"
    code = r["message"].split(":")[0].split(" at t = ")[0] or str(r["status"])
    return code + (f" at t = {r['t_fail']:.3g}" if r.get("t_fail") is not None else "")


def _pivot(name, cell, methods=None, corner="method \\ tol") -> str:
    """Methods by row, tolerances by column (the adaptive methods' sweep); cell(row) -> text."""
    rows = [r for r in load(_wp(name))["rows"] if r["method"] != "rk4"]
    methods = methods or list(dict.fromkeys(r["method"] for r in rows))
    tols = sorted({r["tol"] for r in rows}, reverse=True)
    at = {(r["method"], r["tol"]): r for r in rows}
    body = []
    for m in methods:
        body.append([f"`{m}`"] + [("skipped" if at[m, t].get("skipped") else cell(at[m, t]) if at[m, t]["ok"]
                                   else _status(at[m, t])) if (m, t) in at else "" for t in tols])
    return md([corner] + [f"{t:.0e}" for t in tols], body, ["---"] + ["---:"] * len(tols))


def _rk4(name, extra=None) -> str:
    """RK4 by step size: steps, RHS evaluations, outcome, and an extra column (title, row -> text)."""
    rows = sorted((r for r in load(_wp(name))["rows"] if r["method"] == "rk4"), key=lambda r: -r["h"])
    head = ["RK4 h (s)", "steps", "RHS evaluations", "final rel. error or failure"] + ([extra[0]] if extra else [])
    body = [[f"{r['h']:.2g}", f"{r['steps']:,}", f"{r['rhs_evals_total']:,}",
             _e(r["final_rel_error"]) if r["ok"] else _status(r)] + ([extra[1](r) if r["ok"] else "—"] if extra else [])
            for r in rows]
    return md(head, body)


def _sweep_tables(name, title, cell, rk4_extra=None) -> str:
    """`title`, the adaptive methods' _pivot of `cell`, the RK4 table and the source line."""
    return title + ":\n\n" + _pivot(name, cell) + "\n" + _rk4(name, rk4_extra) + _wp_source(name)


def _steps_err(r) -> str:
    return f"{r['steps']:,} / {_e(r['final_rel_error'])}"


def _rows_ok(name, method):
    return [r for r in load(_wp(name))["rows"] if r["method"] == method and r["ok"] and not r.get("skipped")]


def _span(vals, fmt="{:,.0f}", sep="–") -> str:
    lo, hi = min(vals), max(vals)
    return fmt.format(lo) if fmt.format(lo) == fmt.format(hi) else fmt.format(lo) + sep + fmt.format(hi)


def stab_summary():
    """The atlas at a glance: one row per failure mode, every figure from the JSON of its section."""
    import statistics
    sw = "chain4_stiff_swing"
    loose = [1e-4, 1e-5, 1e-6]
    bdf = {r["tol"]: r for r in _rows_ok(sw, "bdf-exact")}
    ratio = lambda m: [r["steps"] / bdf[r["tol"]]["steps"] for r in _rows_ok(sw, m) if r["tol"] in loose]
    eig = load(RESULTS / "chain4_stiff_swing_eigenvalues.json")["eigenvalues"]
    h_max = 2.83 / max((a * a + b * b) ** 0.5 for a, b in eig)
    ex = "chain4_stiff"
    rk4_ok = max(r["h"] for r in _rows_ok(ex, "rk4"))
    lg = "double_pendulum_long"
    e_bdf = {r["tol"]: r["energy_drift"] for r in _rows_ok(lg, "bdf-exact")}
    less = lambda m: [e_bdf[r["tol"]] / r["energy_drift"] for r in _rows_ok(lg, m)]
    ly = load(_wp("double_pendulum_lyapunov"))
    rates = [r["sens_growth_rate"] for r in ly["rows"] if r["ok"]] + [ly["reference"]["row"]["sens_growth_rate"]]
    top = "spinning_top"
    q = lambda *ms: max(r["quaternion_norm_drift"] / r["rtol"] for m in ms for r in _rows_ok(top, m))
    cp = load(_wp("constrained_pendulum"))
    g = max(r["constraint_position_residual"] for r in cp["rows"] if r["ok"] and not r.get("skipped"))
    rows = [
        ["stiffness", f"`bench/configs/wp_{sw}.yaml`",
         f"RK4 for h > {h_max:.1e} (blow-up); Adams needs {_span(ratio('adams-newton') + ratio('adams-functional'))}× BDF's "
         f"steps, DOP853 {_span(ratio('dop853'))}× (stability-bound; tol 1e-4…1e-6)",
         f"BDF: {_span([bdf[t]['steps'] for t in loose])} steps (tol 1e-4…1e-6)", "`test_stability_stiff.py`"],
        ["excited stiff modes", f"`bench/configs/wp_{ex}.yaml`",
         f"nobody gets large steps (BDF {_span([r['steps'] for r in _rows_ok(ex, 'bdf-exact')])} steps in 1 s)",
         f"RK4 stable from h = {rk4_ok:.1e}; DOP853 fewest steps ({_span([r['steps'] for r in _rows_ok(ex, 'dop853')])})",
         "(documented, no test)"],
        ["long-horizon energy drift", f"`bench/configs/wp_{lg}.yaml`", "BDF loses energy monotonically",
         f"Adams: {_span(less('adams-newton'))}× less drift; DOP853 {_span(less('dop853'))}× less; RK4 down to "
         f"{min(r['energy_drift'] for r in _rows_ok(lg, 'rk4')):.1e}", "`test_stability_energy.py`"],
        ["chaos", "`bench/configs/wp_double_pendulum_chaos.yaml`, `bench/configs/wp_double_pendulum_lyapunov.yaml`",
         "every trajectory past ~10 s; DQ sensitivities at tol ≤ 1e-9",
         f"the growth rate of ‖S‖: λ ≈ {statistics.mean(rates):.1f} 1/s", "`test_stability_chaos.py`"],
        ["quaternion norm drift", f"`bench/configs/wp_{top}.yaml`", "— (bounded)",
         f"\\|q\\| − 1 ≤ {q('bdf-exact', 'bdf-dq'):.2g}·rtol (BDF), ≤ {q('adams-newton', 'adams-functional'):.2g}·rtol (Adams), "
         f"≤ {q('dop853'):.2g}·rtol (DOP853), not growing", "`test_stability_quaternion.py`"],
        ["constraint drift", "`bench/configs/wp_constrained_pendulum.yaml`",
         "Adams cannot project (BDF and DOP853 do); DQ sensitivities at 1e-10",
         f"max \\|g\\| ≤ {g:.1e} for every method that runs", "`test_bench_workprecision.py`"],
    ]
    return md(["failure mode", "config", "fails", "survives", "test"], rows, ["---"] * 5) + \
        "\n<sub>From the JSON of the sections below.</sub>\n"


def stab_swing_modes():
    """Stiff swinging chain: the Jacobian's eigenvalues at the start, damping ratios, RK4's step limit."""
    path = RESULTS / "chain4_stiff_swing_eigenvalues.json"
    d = load(path)
    body = []
    for re_, im in sorted((e for e in d["eigenvalues"] if e[1] > 0), key=lambda e: e[1]):
        mag = (re_ * re_ + im * im) ** 0.5
        body.append([f"{re_:.3g} ± {im:,.0f}i" if abs(re_) > 1e-6 else f"0 ± {im:.3g}i", f"{mag:,.0f}" if mag > 10 else f"{mag:.2f}",
                     f"{-re_ / mag:.3f}" if abs(re_) > 1e-6 else "0", f"{2 * 3.141592653589793 / im:.3g}", f"{2.83 / mag:.2g}"])
    return (md(["eigenvalue (1/s)", "\\|λ\\| (1/s)", "damping ratio ζ", "period (s)", "RK4 stable for h < 2.83/\\|λ\\| (s)"], body)
            + f"\n<sub>From `{rel(path)}` (`{d['command']}`).</sub>\n")


def stab_stiff_swing():
    """Stiff swinging chain: steps / final error per method and tolerance; RK4 by step size."""
    return _sweep_tables("chain4_stiff_swing", "Steps / final relative error", _steps_err)


def stab_stiff_excited():
    """Chain with excited stiff modes: steps / final error; RK4 by step size."""
    return _sweep_tables("chain4_stiff", "Steps / final relative error", _steps_err)


def stab_energy():
    """Long double pendulum: max |E(t) - E(0)| (and steps) per method and tolerance; RK4 by step size."""
    return _sweep_tables("double_pendulum_long", "max \\|E(t) − E(0)\\| (J) / E(end) − E(0) / steps",
                         lambda r: f"{_e(r['energy_drift'])} / {r['energy_drift_final']:+.1e} / {r['steps']:,}",
                         ("max \\|E(t) − E(0)\\| (J)", lambda r: _e(r["energy_drift"])))


def stab_chaos():
    """Chaotic double pendulum over 10 s: final relative error of the state (and of the sensitivities)."""
    cell = lambda r: _e(r["final_rel_error"]) + (f" (S: {_e(r['sens_final_rel_error'])})" if r["with_sens"] else "")
    return _sweep_tables("double_pendulum_chaos", "Final relative error at 10 s (sensitivity rows: state (sensitivities))",
                         cell)


def stab_lyapunov():
    """Chaotic double pendulum over 100 s with sensitivities: errors, ||S(100)||, growth rates."""
    n = "double_pendulum_lyapunov"
    d = load(_wp(n))
    rows = [r for r in d["rows"] if r["ok"]]
    key = lambda r: (r["method"], -(r["h"] or 0) if r["method"] == "rk4" else -r["tol"])
    body = [[f"`{r['method']}`", f"h {r['h']:.2g}" if r["method"] == "rk4" else f"{r['tol']:.0e}",
             _e(r["final_rel_error"]), f"{r['sens_norm_final']:.0e}", f"{r['sens_growth_rate']:.2f}",
             f"{r['sens_growth_slope']:.2f}"] for r in sorted(rows, key=key)]
    rates = [r["sens_growth_rate"] for r in rows]
    ref = d["reference"]["row"]
    if ref.get("sens_growth_rate") is not None:
        body.append([f"reference (`{ref['method']}`)", f"{ref['rtol']:.0e}", "—", f"{ref['sens_norm_final']:.0e}",
                     f"{ref['sens_growth_rate']:.2f}", f"{ref['sens_growth_slope']:.2f}"])
        rates.append(ref["sens_growth_rate"])
    import statistics
    return (md(["method", "tol", "final rel. error", "‖S(100)‖_F", "ln(‖S(100)‖/‖S(0)‖)/100 (1/s)",
                "slope of ln ‖S‖ over 50–100 s (1/s)"], body, ["---", "---:", "---:", "---:", "---:", "---:"])
            + f"\nGrowth rate over the {len(rates)} runs: mean {statistics.mean(rates):.2f} 1/s, standard deviation "
              f"{statistics.stdev(rates):.2f}, range {min(rates):.2f} … {max(rates):.2f}.\n" + _wp_source(n))


def stab_quaternion():
    """Spinning top: max | |q| - 1 | per method and tolerance (and as a multiple of rtol); RK4 by step size."""
    return _sweep_tables("spinning_top", "max \\| \\|q\\| − 1 \\| over 10 s (÷ rtol)",
                         lambda r: f"{_e(r['quaternion_norm_drift'])} ({r['quaternion_norm_drift'] / r['rtol']:.2g})",
                         ("max \\| \\|q\\| − 1 \\|", lambda r: _e(r["quaternion_norm_drift"])))


def stab_constrained():
    """Constrained pendulum: max |g| / final error per method and tolerance (sensitivity rows: error of S)."""
    def cell(r):
        s = f"{_e(r['constraint_position_residual'])} / {_e(r['final_rel_error'])}"
        return s + (f" / S {_e(r['sens_final_rel_error'])} ({r['steps']:,} steps)" if r["with_sens"] else "")
    return _sweep_tables("constrained_pendulum",
                         "max \\|g\\| (m) / final relative error (sensitivity rows: / error of the sensitivities)", cell,
                         ("max \\|g\\| (m)", lambda r: _e(r["constraint_position_residual"])))


# --- docs/explanation/constraints.md ----------------------------------------------------------

DRIFT = RESULTS / "drift_study.json"
CHOICE = HERE / "constraints_choice.json"


def constraint_drift():
    """Crank-rocker four-bar over 100 s per stabilization: residuals, energy drift, cost."""
    d = load(DRIFT)
    rows = [[r["stabilization"], f"{r['max_position_residual']:.1e}", f"{r['max_velocity_residual']:.1e}",
             f"{r['max_energy_drift']:.1e}", f"{r['max_energy_drift'] / r['energy_initial']:.1e}", f"{r['steps']:,}",
             f"{r['rhs_evals']:,}", f"{r['wall_seconds']:.2f}"] for r in d["rows"]]
    proj = next(r for r in d["rows"] if r["stabilization"] == "projection")
    return (md(["stabilization", "max position residual (m)", "max velocity residual (m/s)", "max \\|E − E0\\| (J)",
                "max \\|E − E0\\|/E0", "steps", "RHS evals", "wall (s)"], rows, ["---"] + ["---:"] * 7)
            + f"\nE0 = {proj['energy_initial']:.1f} J; the crank turns {proj['crank_revolutions']:,.0f} times in the 100 s "
              "(projection run).\n"
            + f"\n<sub>From `{rel(DRIFT)}` (`{d['command']}`, one run each; wall times on a shared 2-core machine).</sub>\n")


def _choice_rows(rows):
    out = []
    for r in rows:
        status = "" if r["status"] == 1 else f" (failed: {r['message'][:60]})"
        out.append([r["case"], r["method"], r["formulation"], r["stabilization"], f"{r['error']:.1e}{status}",
                    f"{r['energy_drift']:.1e}", f"{r['position_residual']:.1e}", r["steps"], r["rhs_evals"],
                    r["repartitions"], f"{1e3 * r['wall_median']:.1f}"])
    return md(["case", "method", "formulation", "stabilization", "error", "energy drift (rel.)",
               "max contact/position residual", "steps", "RHS evals", "repartitions", "wall (ms, median)"],
              out, ["---"] * 11)


def constraints_choice():
    """Embedding or multipliers: accuracy, residuals and cost on the constrained examples."""
    d = load(CHOICE)
    return _choice_rows(d["choice"]) + f"\n<sub>From `{rel(CHOICE)}` (`{d['command']}`).</sub>\n"


def contact_drift():
    """Contact-height drift of the two-wheeler and the rolling disc per stabilization."""
    d = load(CHOICE)
    cases = list(dict.fromkeys(r["case"] for r in d["drift"]))
    stabs = list(dict.fromkeys(r["stabilization"] for r in d["drift"]))
    at = {(r["case"], r["stabilization"]): r for r in d["drift"]}
    rows = [[c] + [f"{at[c, s]['position_residual']:.1e} m" if at[c, s]["status"] == 1 else "failed" for s in stabs]
            for c in cases]
    return (md(["scene"] + stabs, rows, ["---"] * (1 + len(stabs)))
            + f"\n<sub>From `{rel(CHOICE)}` (`{d['command']}`).</sub>\n")


def _us(v) -> str:
    return f"{v:,.0f}" if v >= 100 else f"{v:.1f}"


def scaling_sweep():
    """N four-bar: constrained and embedding RHS and the exact Jacobian, dense (before) and sparse (after)."""
    p = RESULTS / "scaling_sweep.json"
    d = load(p)
    by = {(r["n"], r["build"]): r for r in d["rhs"] if r["family"] == "n_four_bar"}
    kinds = ["rhs_multipliers", "rhs_embedding", "mass_matrix_and_forcing", "jacobian"]
    rows = []
    for n in sorted({n for n, _ in by}):
        a, b = by.get((n, "after")), by.get((n, "before"))
        cells = [f"{n} ({a['nu']})"]
        for k in kinds:
            before = _us(b[k + "_us"]) if b else "—"
            cells.append(f"{before} → {_us(a[k + '_us'])}")
        rows.append(cells)
    g = d["growth_per_doubling_20_to_80"]
    rows.append(["growth per doubling, N = 20 → 80"] + [f"{g[k]:.1f}×" for k in kinds])
    return (md(["N (speeds)", "constrained RHS", "embedding RHS", "M and f", "exact Jacobian"], rows,
               ["---", "---:", "---:", "---:", "---:"])
            + f"\n<sub>Median µs per evaluation, dense solves → sparse solves; from `{rel(p)}` (`{d['provenance']['command']}`).</sub>\n")


def newton(s):
    """Newton's linear solver of a study row and its work: dense Jacobians or products J v."""
    ls = s.get("linear_solver", "dense")
    if ls == "none" or s["method"] == "dop853":  # explicit: no Newton iteration
        return "—"
    if ls == "krylov":
        return f"krylov, {s.get('jtimes_evals', 0):,} J v"
    return f"dense, {s['jac_evals']} Jacobians"


def scaling_study():
    """The 20-second N = 40 study: wall time, steps and error against the exact solution."""
    p = RESULTS / "scaling_sweep.json"
    d = load(p)
    solves = {"before": "dense", "after": "sparse"}  # the build without the sparse solves, and this one
    rows = [[s["method"], solves[s["build"]], f"{s['wall_seconds']:.2f}", f"{s['steps']:,}", f"{s['rhs_evals']:,}",
             newton(s), f"{s['max_error_crank0_q']:.1e}"] for s in d["studies"]]
    rows.sort(key=lambda r: (r[0], r[1] != "dense"))
    s0 = d["studies"][0]
    return (md(["method", "solves", "median wall time (s)", "steps", "RHS", "Newton's linear solver", "max error of crank0.q"], rows,
               ["---", "---", "---:", "---:", "---:", "---:", "---:"])
            + f"\n<sub>N = {s0['n']}, {s0['end']:g} s, rtol {s0['rtol']:g}, projection; from `{rel(p)}`.</sub>\n")


def _table_column(table: str, col: int):
    lines = [l for l in table.splitlines() if l.startswith("|")][2:]
    return [l.strip("|").split("|")[col].strip() for l in lines]


def _ratio_from_cell(cell: str):
    m = re.match(r"\**([\d,.]+)", cell)
    return float(m.group(1).replace(",", "")) if m else None


# The tables that are one driver's table() of one JSON file: name → (driver module, JSON file).
DRIVER_TABLES = {
    "jacobian_cost": ("jacobian_cost", "jacobian_cost.json"),
    "articulated_crossover": ("articulated_crossover", "articulated_crossover.json"),
    "sensitivity_cost": ("sensitivity_cost", "sensitivity_cost.json"),
    "sensitivity_cost_few": ("sensitivity_cost", "sensitivity_cost_few.json"),
    "sensitivity_cost_jacobian": ("sensitivity_cost", "sensitivity_cost_jacobian.json"),
    "sensitivity_cost_few_constrained": ("sensitivity_cost", "sensitivity_cost_few_constrained.json"),
    "sensitivity_cost_constants": ("sensitivity_cost", "sensitivity_cost_constants.json"),
    "sensitivity_cost_residual": ("sensitivity_cost", "sensitivity_cost_residual.json"),
    "sensitivity_cost_dense_lu": ("sensitivity_cost", "sensitivity_cost_dense_lu.json"),
    "sensitivity_cost_dense_solve": ("sensitivity_cost", "sensitivity_cost_dense_solve.json"),
    "sensitivity_cost_matrix_ops": ("sensitivity_cost", "sensitivity_cost_matrix_ops.json"),
    "sensitivity_cost_closed_form": ("sensitivity_cost", "sensitivity_cost_closed_form.json"),
    "bdf_machinery": ("bdf_machinery", "bdf_machinery.json"),
    "sensitivity_cost_planar_recursion": ("sensitivity_cost", "sensitivity_cost_planar_recursion.json"),
    "jacobian_cost_arch": ("jacobian_cost", "jacobian_cost_arch.json"),
    "sensitivity_cost_arch": ("sensitivity_cost", "sensitivity_cost_arch.json"),
    "jacobian_cost_width6": ("jacobian_cost", "jacobian_cost_width6.json"),
    "sensitivity_cost_width6": ("sensitivity_cost", "sensitivity_cost_width6.json"),
    "jacobian_cost_gradient": ("jacobian_cost", "jacobian_cost_gradient.json"),
    "sensitivity_cost_gradient": ("sensitivity_cost", "sensitivity_cost_gradient.json"),
    "jacobian_cost_current": ("jacobian_cost", "jacobian_cost_current.json"),
    "sensitivity_cost_current": ("sensitivity_cost", "sensitivity_cost_current.json"),
    "sensitivity_cost_stacked": ("sensitivity_cost", "sensitivity_cost_stacked.json"),
    "sensitivity_cost_after_stacking": ("sensitivity_cost", "sensitivity_cost_after_stacking.json"),
    "sensitivity_cost_recorded_passes": ("sensitivity_cost", "sensitivity_cost_recorded_passes.json"),
    "sensitivity_cost_value_rhs": ("sensitivity_cost", "sensitivity_cost_value_rhs.json"),
    "sensitivity_cost_avx2": ("sensitivity_cost", "sensitivity_cost_avx2.json"),
    "sensitivity_cost_avx2_current": ("sensitivity_cost", "sensitivity_cost_avx2_current.json"),
    "sensitivity_instructions_avx2": ("sensitivity_instructions", "sensitivity_instructions_avx2.json"),
    "jacobian_cost_avx2": ("jacobian_cost", "jacobian_cost_avx2.json"),
    "sensitivity_cost_value_in_pack": ("sensitivity_cost", "sensitivity_cost_value_in_pack.json"),
    "sensitivity_cost_reciprocal_pivots": ("sensitivity_cost", "sensitivity_cost_reciprocal_pivots.json"),
    "sensitivity_cost_row_sums": ("sensitivity_cost", "sensitivity_cost_row_sums.json"),
    "sensitivity_cost_member_copies": ("sensitivity_cost", "sensitivity_cost_member_copies.json"),
    "sensitivity_cost_fused": ("sensitivity_cost", "sensitivity_cost_fused.json"),
    "sensitivity_cost_two": ("sensitivity_cost", "sensitivity_cost_two.json"),
    "sensitivity_cost_control": ("sensitivity_cost", "sensitivity_cost_control.json"),
    "dop853_step_control": ("dop853_step_control", "dop853_step_control.json"),
    "sensitivity_cost_vector_ops": ("sensitivity_cost", "sensitivity_cost_vector_ops.json"),
    "sensitivity_cost_no_error_control": ("sensitivity_cost", "sensitivity_cost_no_error_control.json"),
    "multitangent": ("multitangent_table", "multitangent_kernels.json"),
    "multitangent_avx2": ("multitangent_table", "multitangent_kernels_avx2.json"),
}

TABLES = {
    "rhs_mujoco": rhs_mujoco, "rhs_paths": rhs_paths,
    "dense_lu_solve": dense_lu_solve,
    "sensitivity_cost_evaluations": sensitivity_cost_evaluations, "sensitivity_corrector_stacked": sensitivity_corrector_stacked,
    "sensitivity_cost_summary": sensitivity_cost_summary, "outputs_cost": outputs_cost,
    "sensitivity_corrector": sensitivity_corrector,
    "newton_sweep": newton_sweep, "newton_stiff": newton_stiff,
    "sensitivities": sensitivities_table, "constraints": constraints_table, "ensemble": ensemble_table,
    "peers_summary": peers_summary,
    "sympy_derivation": sympy_derivation, "sympy_reference": sympy_reference, "sympy_tta": sympy_tta,
    "simbody_rhs": simbody_rhs, "simbody_tta": simbody_tta, "simbody_reference": simbody_reference,
    "fourbar_sympy_derivation": fourbar_sympy_derivation, "fourbar_sympy_tight": fourbar_sympy_tight,
    "fourbar_sympy_tta": fourbar_sympy_tta, "fourbar_rhs": fourbar_rhs, "fourbar_agreement": fourbar_agreement, "fourbar_tta": fourbar_tta,
    "fourbar_mujoco": fourbar_mujoco, "wp_summary": wp_summary,
    "stab_summary": stab_summary, "stab_swing_modes": stab_swing_modes, "stab_stiff_swing": stab_stiff_swing, "stab_stiff_excited": stab_stiff_excited, "stab_energy": stab_energy,
    "stab_chaos": stab_chaos, "stab_lyapunov": stab_lyapunov, "stab_quaternion": stab_quaternion,
    "stab_constrained": stab_constrained,
    "constraint_drift": constraint_drift, "constraints_choice": constraints_choice, "contact_drift": contact_drift,
    "scaling_sweep": scaling_sweep, "scaling_study": scaling_study,
}
TABLES.update({name: (lambda m=m, j=j: driver_table(m, j)) for name, (m, j) in DRIVER_TABLES.items()})


def render(text: str, missing: list) -> str:
    def sub(m):
        name = m.group(2)
        if name not in TABLES:
            missing.append(name)
            return m.group(0)
        return m.group(1) + TABLES[name]() + m.group(4)
    return MARK.sub(sub, text)


# --- figures --------------------------------------------------------------------------------

def figures() -> list[Path]:
    import figures as f
    return f.draw_all()


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--check", action="store_true", help="compare the docs' tables with the JSON; write nothing")
    ap.add_argument("--no-figures", action="store_true", help="rewrite the tables only")
    ap.add_argument("--list", action="store_true")
    ap.add_argument("--docs", nargs="*", default=[str(p) for p in DOCS], help=argparse.SUPPRESS)
    a = ap.parse_args(argv)
    if a.list:
        for name, fn in TABLES.items():
            print(name, fn.__doc__.strip().splitlines()[0] if fn.__doc__ else "")
        return 0
    bad, missing, seen = [], [], 0
    for doc in map(Path, a.docs):
        old = doc.read_text()
        seen += len(MARK.findall(old))
        new = render(old, missing)
        if new != old:
            if a.check:
                import difflib
                sys.stdout.writelines(difflib.unified_diff(old.splitlines(True), new.splitlines(True), str(doc),
                                                           "generated from the JSON"))
                bad.append(doc)
            else:
                doc.write_text(new)
                print(f"updated {rel(doc) if doc.is_relative_to(ROOT) else doc}")
    if missing:
        print("unknown tables: " + ", ".join(missing), file=sys.stderr)
        return 1
    if a.check:
        if bad:
            print("tables differ from bench/make_tables.py's output: " + ", ".join(map(str, bad)), file=sys.stderr)
            return 1
        print(f"{seen} tables match their JSON")
        return 0
    if not a.no_figures:
        for p in figures():
            print(f"drew {rel(p)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
