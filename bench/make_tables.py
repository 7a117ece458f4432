#!/usr/bin/python3
"""The benchmark pages' tables and figures, from the committed result JSON.

    /usr/bin/python3 bench/make_tables.py            # rewrite the tables in the docs and the figures
    /usr/bin/python3 bench/make_tables.py --check    # exit 1 if a table in the docs differs (no writes)
    /usr/bin/python3 bench/make_tables.py --list     # which table comes from which JSON

A table in docs/benchmarks.md, docs/peers.md or docs/workprecision.md sits between
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

DOCS = [ROOT / "docs" / "benchmarks.md", ROOT / "docs" / "peers.md", ROOT / "docs" / "workprecision.md"]
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


def rhs_mujoco():
    d = load(RHS)
    rows = []
    for r in d["rows"]:
        rows.append([r["n"], f"{r['kanesens_spatial_rhs_ns']:,.0f}", f"{r['mujoco_spatial_forward_ns']:,.0f}",
                     f"**{r['mujoco_spatial_forward_ns'] / r['kanesens_spatial_rhs_ns']:.2f}**",
                     f"{r['kanesens_rhs_ns']:,.0f}", f"{r['mujoco_forward_ns']:,.0f}",
                     f"{r['mujoco_forward_ns'] / r['kanesens_rhs_ns']:.2f}",
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


def jacobian_cost():
    import jacobian_cost as m
    return printed(m.table, RESULTS / "jacobian_cost.json") + source(RESULTS / "jacobian_cost.json")


def sensitivity_cost():
    import sensitivity_cost as m
    return printed(m.table, RESULTS / "sensitivity_cost.json") + source(RESULTS / "sensitivity_cost.json")


def multitangent():
    import multitangent_table as m
    return printed(m.table, RESULTS / "multitangent_kernels.json") + source(RESULTS / "multitangent_kernels.json")


def outputs_cost():
    p = RESULTS / "outputs_cost.json"
    d = load(p)
    names = {"plain": "none", "cheap outputs": "positions, kinetic energy, an expression, a value at the end",
             "all outputs": "the above plus velocity, acceleration, a joint load and an integral of its power"}
    rows = [[names.get(k, k), f"{v * 1e3:.1f}", f"{d['ratio_to_plain'][k]:.2f}"] for k, v in d["median_seconds"].items()]
    return md(["outputs", "median wall time (ms)", "ratio to no outputs"], rows, ["---", "---:", "---:"]) + source(p)


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
    rhs = load(RHS)["rows"]
    sp = [r["mujoco_spatial_forward_ns"] / r["kanesens_spatial_rhs_ns"] for r in rhs]
    pl = [r["mujoco_forward_ns"] / r["kanesens_rhs_ns"] for r in rhs]
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


def _table_column(table: str, col: int):
    lines = [l for l in table.splitlines() if l.startswith("|")][2:]
    return [l.strip("|").split("|")[col].strip() for l in lines]


def _ratio_from_cell(cell: str):
    m = re.match(r"\**([\d,.]+)", cell)
    return float(m.group(1).replace(",", "")) if m else None


TABLES = {
    "rhs_mujoco": rhs_mujoco, "rhs_paths": rhs_paths, "jacobian_cost": jacobian_cost,
    "sensitivity_cost": sensitivity_cost, "multitangent": multitangent, "outputs_cost": outputs_cost,
    "sensitivities": sensitivities_table, "constraints": constraints_table, "ensemble": ensemble_table,
    "peers_summary": peers_summary,
    "sympy_derivation": sympy_derivation, "sympy_reference": sympy_reference, "sympy_tta": sympy_tta,
    "simbody_rhs": simbody_rhs, "simbody_tta": simbody_tta, "simbody_reference": simbody_reference,
    "fourbar_sympy_derivation": fourbar_sympy_derivation, "fourbar_sympy_tight": fourbar_sympy_tight,
    "fourbar_sympy_tta": fourbar_sympy_tta, "fourbar_rhs": fourbar_rhs, "fourbar_agreement": fourbar_agreement, "fourbar_tta": fourbar_tta,
    "fourbar_mujoco": fourbar_mujoco, "wp_summary": wp_summary,
}


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
