#!/usr/bin/python3
"""Speed against accuracy on the four-bar: kanesens vs SymPy KanesMethod + SciPy solve_ivp (docs/peers.md).

    /usr/bin/python3 bench/bench_peers_fourbar_sympy.py [--out docs/peers]
        [--kanesens build/kanesens] [--budget 20] [--reps 3] [--rtols 1e-3,...,1e-14]
    quick smoke test: ... --out /tmp/fourbar_sympy --rtols 1e-4,1e-6 --reps 1

The problem: the crank-rocker of configs/four_bar.yaml (crank upright at 6 rad/s, gravity −y,
conservative), integrated over t in [0, 10]; the crank goes round 16.6 times (q1: 1.57 -> 105.6).

* Derivation: tests/sympy/four_bar_kane.py, the four-bar written by hand in SymPy (same
  coordinates as kanesens: q1 crank, q2 coupler relative to the crank, q3 rocker; independent
  speed u1, dependent u2, u3; loop closure as configuration constraints, its time derivative as
  velocity constraints): build (frames, points, bodies, KanesMethod), kanes_equations, then one
  sympy.lambdify(cse=True) function (q, u, p) -> (M, f). Wall and CPU time of each stage.
* SciPy: solve_ivp(method in RK45, DOP853, Radau, LSODA) on the full state [q1, q2, q3, u1, u2,
  u3] with y' = [u; solve(M, f)], M, f = KanesMethod's mass_matrix/forcing (the reduced
  equation for u1' stacked on the differentiated velocity constraints). This is what a PyDy
  user integrates (System/ODEFunctionGenerator take mass_matrix_full/forcing_full, all q and
  u); nothing pulls the state back onto g(q) = 0, A(q) u = 0, so the final-time residuals
  |g| and |A u| are recorded. rtol swept, atol = rtol * 1e-2 (SciPy raises rtol < 100 eps to
  2.2e-14, recorded as rtol_effective); Radau and LSODA use SciPy's finite-difference
  Jacobians. Time: wall time of the solve_ivp call.
* kanesens: `kanesens simulate` of a study with the same scene (bench/fourbar_kanesens.py),
  six (method, constraint treatment) variants: BDF + multipliers + projection (the default),
  Adams + multipliers + Baumgarte (CVODES projects only with BDF), Adams + embedding (state
  [q; u1], no stabilization), BDF + embedding + projection, and the explicit Runge–Kutta
  DOP853 (Dormand–Prince 8(5,3)) with embedding (no stabilization) and with multipliers +
  Baumgarte. A variant whose method this kanesens does not know (dop853 before it landed) is
  skipped with a note. Time: stats.wall_seconds (integrate() including the integrator's setup;
  process start-up and parsing excluded, as the derivation is for SciPy); process wall time
  recorded.
* Error: max over the six states of |y(10) − y_ref(10)|. The crank angle reaches 105.6 rad, so
  an absolute 1e-8 is a relative 1e-10: the sweep goes on to rtol 1e-14 to reach it. y_ref is
  independent of every integrator: tests/sympy/four_bar_quadrature.py (one degree of freedom
  and T + V conserved give u1 = sqrt(2 (E − V(q1)) / m(q1)) along the closed-form assembly, so
  t(q1) = ∫ dq1 / u1 is a quadrature, mpmath at 30 digits, solved for t = 10 by Newton; q2,
  q3, u2, u3 from the assembly and the velocity constraints). Reported beside it: every
  kanesens variant at rtol --ref-rtol (1e-14, atol 1e-16) and SciPy DOP853 at --check-rtol
  (1e-13), as their distances from y_ref.
* Alternation: for every tolerance the programs run one after the other (kanesens, SciPy,
  kanesens, ...), repeated --reps times (1 time once a run took more than 2 s); the median is
  kept. A SciPy method whose run took more than --budget seconds is not run at tighter
  tolerances.

Writes OUT/fourbar_sympy_scipy.json (every run, the command line); bench/make_tables.py makes
docs/peers.md's tables and OUT/fourbar_sympy_scipy_workprecision.png from it. Needs Debian's python3 (sympy, mpmath, scipy, numpy,
matplotlib).
"""

from __future__ import annotations

import argparse
import datetime
import json
import os
import platform
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import mpmath
import numpy as np
import scipy
import sympy as sp
from scipy.integrate import solve_ivp

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "tests" / "sympy"))
import four_bar_kane as fb  # noqa: E402
import four_bar_quadrature  # noqa: E402
import fourbar_kanesens as fk  # noqa: E402
from bench_peers_sympy import now  # noqa: E402  (the chain bench's conventions)
from common import interleaved, max_err, repeated_runs, time_at  # noqa: E402

SCIPY_METHODS = ["RK45", "DOP853", "Radau", "LSODA"]
# (method, formulation, stabilization), see fourbar_kanesens.LABELS.
KANESENS_VARIANTS = [("bdf", "multipliers", "projection"), ("adams", "multipliers", "baumgarte"),
                     ("adams", "embedding", "none"), ("bdf", "embedding", "projection"),
                     ("dop853", "embedding", "none"), ("dop853", "multipliers", "baumgarte")]
TARGETS = [1e-4, 1e-6, 1e-8, 1e-10]
T_END = 10.0


def derive():
    """The four-bar in KanesMethod, then lambdify; returns timings, (q, u, p) -> (M, f), model."""
    w0, c0 = now()
    model = fb.kane_model()
    w1, c1 = now()
    fb.equations(model)
    w2, c2 = now()
    fun = fb.lambdify(model)
    w3, c3 = now()
    ops = int(sp.count_ops(list(model["mass_matrix"]) + list(model["forcing"])))
    return ({"build_wall_s": w1 - w0, "kanes_equations_wall_s": w2 - w1, "lambdify_wall_s": w3 - w2,
             "total_wall_s": w3 - w0, "build_cpu_s": c1 - c0, "kanes_equations_cpu_s": c2 - c1,
             "lambdify_cpu_s": c3 - c2, "total_cpu_s": c3 - c0, "count_ops_M_f": ops}, fun, model)


def residuals(constraints, p, y):
    """max |g(q)| and max |A(q) u| at the state y = [q; u]."""
    g, A = constraints(y[:3], y[3:], p)
    return (float(np.max(np.abs(np.asarray(g, dtype=float)))),
            float(np.max(np.abs(np.asarray(A, dtype=float) @ y[3:]))))


def scipy_run(fun, constraints, p, y0, method, rtol, atol):
    def rhs(_t, y):
        M, f = fun(y[:3], y[3:], p)
        return np.concatenate([y[3:], np.linalg.solve(np.asarray(M, dtype=float),
                                                      np.asarray(f, dtype=float).reshape(3))])
    t0 = time.perf_counter()
    sol = solve_ivp(rhs, (0.0, T_END), y0, method=method, rtol=rtol, atol=atol)
    dt = time.perf_counter() - t0
    y_end = sol.y[:, -1]
    g_end, v_end = residuals(constraints, p, y_end)
    return {"time_s": dt, "y_end": y_end.tolist(), "status": int(sol.status), "message": sol.message,
            "nfev": int(sol.nfev), "njev": int(sol.njev), "nlu": int(sol.nlu), "g_end": g_end, "Au_end": v_end}


def kanesens_run(exe, study, variant, rtol, atol):
    out = fk.simulate(exe, study, variant, rtol, atol)
    st, res = out["stats"], out["constraint_residuals"]
    return {"time_s": st["wall_seconds"], "process_wall_s": out["process_wall_s"], "y_end": out["states"][-1],
            "y0": out["states"][0], "status": out.get("status", 0), "message": out.get("message", ""),
            "nfev": st.get("rhs_evals"), "steps": st.get("steps"), "njev": st.get("jac_evals"),
            "g_end": res["position"][-1], "Au_end": res["velocity"][-1], "state_names": out["state_names"]}


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--out", default=str(ROOT / "docs" / "peers"))
    ap.add_argument("--kanesens", default=str(ROOT / "build" / "kanesens"))
    ap.add_argument("--budget", type=float, default=20.0, help="s; stop tightening a SciPy method after a run this long")
    ap.add_argument("--reps", type=int, default=3)
    ap.add_argument("--rtols", default="1e-3,1e-4,1e-5,1e-6,1e-7,1e-8,1e-9,1e-10,1e-11,1e-12,1e-13,1e-14")
    ap.add_argument("--ref-rtol", type=float, default=1e-14, help="kanesens check tolerance")
    ap.add_argument("--check-rtol", type=float, default=1e-13, help="SciPy DOP853 check tolerance")
    a = ap.parse_args()
    rtols = [float(x) for x in a.rtols.split(",")]
    out = Path(a.out)
    out.mkdir(parents=True, exist_ok=True)
    tmp = Path(tempfile.mkdtemp(prefix="bench_peers_fourbar_"))
    load_start = os.getloadavg()
    study = fk.write_study(tmp / "four_bar_study.yaml", T_END)
    variants = fk.available(a.kanesens, study, KANESENS_VARIANTS, "bench_peers_fourbar_sympy")

    print("deriving (KanesMethod + lambdify)", file=sys.stderr, flush=True)
    derivation, fun, model = derive()
    print(f"  {derivation}", file=sys.stderr, flush=True)
    constraints = fb.lambdify(model, ("closure", "velocity_matrix"))
    p = [fb.NOMINAL[k] for k in fb.PARAMETERS]

    print("reference: energy quadrature (tests/sympy/four_bar_quadrature.py)", file=sys.stderr, flush=True)
    w0 = time.perf_counter()
    y_ref, quad = four_bar_quadrature.state_at(T_END)
    quad["time_s"] = time.perf_counter() - w0
    ra, ca = a.ref_rtol, a.check_rtol
    checks = {"reference": f"energy quadrature (mpmath, {quad['dps']} digits)", "quadrature": quad, "y_ref": y_ref,
              "ref_rtol": ra, "check_rtol": ca, "tight": []}
    y0 = None
    for v in variants:
        r = kanesens_run(a.kanesens, study, v, ra, ra * 1e-2)
        if y0 is None:
            y0 = np.array(r["y0"], dtype=float)      # SciPy starts where kanesens starts, as in the chain bench
            checks["state_names"] = r["state_names"]
        checks["tight"].append({"tool": "kanesens", "method": fk.name(v), "rtol": ra, "time_s": r["time_s"],
                                "error": max_err(r["y_end"], y_ref), "y_end": r["y_end"], "g_end": r["g_end"]})
    dop = scipy_run(fun, constraints, p, y0, "DOP853", ca, ca * 1e-2)
    checks["tight"].append({"tool": "scipy", "method": "DOP853", "rtol": ca, "time_s": dop["time_s"],
                            "error": max_err(dop["y_end"], y_ref), "y_end": dop["y_end"], "g_end": dop["g_end"]})
    checks["y0"] = y0.tolist()
    checks["y0_vs_exact"] = max_err(y0, quad["y0"])
    for c in checks["tight"]:
        print(f"  {c['tool']} {c['method']} rtol {c['rtol']:g}: |y - y_quad| = {c['error']:.2e}, "
              f"|g| = {c['g_end']:.1e}, {c['time_s']:.2f} s", file=sys.stderr, flush=True)

    runs = []
    active = set(SCIPY_METHODS)
    for rtol in rtols:
        atol = rtol * 1e-2
        ks = [("kanesens", v) for v in variants]
        ss = [("scipy", m) for m in SCIPY_METHODS if m in active]
        order = interleaved(ks, ss)                  # kanesens BDF, RK45, kanesens Adams, DOP853, ...
        res = repeated_runs(order, a.reps, lambda t: kanesens_run(a.kanesens, study, t[1], rtol, atol)
                            if t[0] == "kanesens" else scipy_run(fun, constraints, p, y0, t[1], rtol, atol))
        for t in order:
            rs = res[t]
            name = fk.name(t[1]) if t[0] == "kanesens" else t[1]
            row = {"tool": t[0], "method": name, "rtol": rtol, "atol": atol,
                   "time_s": statistics.median(r["time_s"] for r in rs), "times_s": [r["time_s"] for r in rs],
                   "error": max_err(rs[0]["y_end"], y_ref), "g_end": rs[0]["g_end"], "Au_end": rs[0]["Au_end"],
                   "status": rs[0]["status"], "nfev": rs[0]["nfev"], "njev": rs[0]["njev"]}
            if t[0] == "scipy":
                row["rtol_effective"] = max(rtol, 100 * np.finfo(float).eps)
            if t[0] == "kanesens":
                row["process_wall_s"] = statistics.median(r["process_wall_s"] for r in rs)
                row["steps"] = rs[0]["steps"]
            runs.append(row)
            print(f"  {t[0]:8s} {name:28s} rtol={rtol:.0e} err={row['error']:.2e} |g|={row['g_end']:.1e} "
                  f"time={row['time_s']:.4g}s nfev={row['nfev']}", file=sys.stderr, flush=True)
            if t[0] == "scipy" and row["time_s"] > a.budget:
                active.discard(t[1])

    targets = []
    for tool, methods in (("scipy", SCIPY_METHODS), ("kanesens", [fk.name(v) for v in variants])):
        for m in methods:
            pts = sorted([(r["rtol"], r["error"], r["time_s"]) for r in runs
                          if r["tool"] == tool and r["method"] == m and r["status"] >= 0], key=lambda x: -x[0])
            for e in TARGETS:
                tt, how = time_at(pts, e)
                targets.append({"tool": tool, "method": m, "target": e, "time_s": tt, "how": how})

    cpu = next((l.split(":", 1)[1].strip() for l in open("/proc/cpuinfo") if l.startswith("model name")), "?")
    meta = {"date": str(datetime.date.today()), "cpu": cpu, "nproc": os.cpu_count(),
            "loadavg_start": load_start, "loadavg_end": os.getloadavg(), "platform": platform.platform(),
            "python": sys.version.split()[0], "sympy": sp.__version__, "scipy": scipy.__version__,
            "numpy": np.__version__, "mpmath": mpmath.__version__, "t_end": T_END, "rtols": rtols,
            "atol_factor": 1e-2, "reps": a.reps, "budget_s": a.budget,
            "kanesens_variants": [fk.name(v) for v in variants],
            "kanesens_variants_skipped": [fk.name(v) for v in KANESENS_VARIANTS if v not in variants],
            "git": subprocess.run(["git", "-C", str(ROOT), "rev-parse", "--short", "HEAD"],
                                  capture_output=True, text=True).stdout.strip(),
            "kanesens_version": subprocess.run([a.kanesens, "--version"], capture_output=True,
                                               text=True).stdout.splitlines()[0],
            "command": " ".join(sys.argv)}
    data = {"meta": meta, "derivation": derivation, "reference_check": checks, "runs": runs, "targets": targets}
    (out / "fourbar_sympy_scipy.json").write_text(json.dumps(data, indent=1))
    print(f"wrote {out / 'fourbar_sympy_scipy.json'}; tables and figure: bench/make_tables.py", file=sys.stderr)


def ms(t):
    return "—" if t is None or t["time_s"] is None else ("≤ " if t["how"] == "<=" else "") + f"{t['time_s'] * 1e3:,.1f}"


if __name__ == "__main__":
    main()
