#!/usr/bin/python3
"""Speed against accuracy: kanesens vs SymPy KanesMethod + SciPy solve_ivp (docs/peers.md).

    /usr/bin/python3 bench/bench_peers_sympy.py [--ns 2,4,8] [--out docs/peers]
        [--kanesens build/kanesens] [--budget 20] [--reps 3] [--rtols 1e-3,...,1e-11]

The problem: the planar N-link chain of scripts/gen_chain.py (uniform rods, revolute joints
about z, gravity -y, no springs or dampers, q0 = 0.5 rad on the first joint, everything else 0),
integrated over t in [0, 10].

* Derivation: tests/sympy/kane_reference.py turns the scene into KanesMethod's mass matrix M and
  forcing f (build_model + kane_equations), then sympy.lambdify(cse=True) makes one numpy
  function (q, u) -> (M, f). Wall and CPU time of each stage.
* SciPy: solve_ivp(method in RK45, DOP853, Radau, LSODA) with ydot = [u; solve(M, f)]
  (numpy.linalg.solve), rtol swept, atol = rtol * 1e-2; Radau and LSODA use SciPy's own
  finite-difference Jacobians. Time: wall time of the solve_ivp call.
* kanesens: `kanesens simulate` of a study with the same scene (method bdf with the exact
  Jacobian, adams, and the explicit dop853), --set solver.rtol=R --set solver.atol=R*1e-2; time: stats.wall_seconds
  (integrate() including CVODES setup; parsing and process start-up are excluded, as the
  lambdify is for SciPy). The process wall time is recorded too.
* Error: max over all states of |y(10) - y_ref(10)|, y_ref from kanesens adams at rtol 1e-14
  (atol 1e-16); it is checked against kanesens adams at rtol 1e-13, kanesens bdf at 1e-14 and
  SciPy DOP853 at 1e-13 (atol = rtol * 1e-2). (BDF at rtol 1e-13 is only good to ~1e-10 here,
  which is why the reference is Adams.)
* Alternation: for every N and tolerance, the programs run one after the other, repeated
  --reps times (1 time once a run took more than 2 s); the median is kept. A SciPy method whose
  run took more than --budget seconds is not run at tighter tolerances for that N.

Writes OUT/sympy_scipy.json (every run, the command line); bench/make_tables.py makes
docs/peers.md's tables and OUT/sympy_scipy_workprecision.png from it. Needs Debian's python3 (sympy, scipy, numpy, matplotlib).
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

import numpy as np
import scipy
import sympy as sp
from scipy.integrate import solve_ivp

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "tests" / "sympy"))
sys.path.insert(0, str(ROOT / "scripts"))
import kane_reference as kr  # noqa: E402
from common import interleaved, max_err, repeated_runs, time_at  # noqa: E402
from gen_chain import chain_yaml  # noqa: E402
from sympy.physics.mechanics import msubs  # noqa: E402

SCIPY_METHODS = ["RK45", "DOP853", "Radau", "LSODA"]
KANESENS_METHODS = ["bdf", "adams", "dop853"]
TARGETS = [1e-4, 1e-6, 1e-8, 1e-10]
T_END = 10.0


def now():
    return time.perf_counter(), time.process_time()


def derive(scene: Path) -> tuple[dict, object, int]:
    """KanesMethod on the scene, then lambdify; returns timings, f(q, u) -> (M, f), n."""
    w0, c0 = now()
    model = kr.build_model(scene)
    w1, c1 = now()
    kr.kane_equations(model)
    w2, c2 = now()
    n = len(model.u)
    qs, us = sp.symbols(f"qq0:{n}"), sp.symbols(f"uu0:{n}")
    sub = dict(zip(model.q, qs))
    sub.update(dict(zip(model.u, us)))
    sub[kr.T] = sp.Symbol("tt")
    M = msubs(model.mass_matrix, sub)
    f = msubs(model.forcing, sub)
    fun = sp.lambdify([qs, us], [M, f], modules="numpy", cse=True)
    w3, c3 = now()
    ops = int(sp.count_ops(list(M) + list(f)))
    return ({"build_model_wall_s": w1 - w0, "kanes_equations_wall_s": w2 - w1, "lambdify_wall_s": w3 - w2,
             "total_wall_s": w3 - w0, "total_cpu_s": c3 - c0, "count_ops_M_f": ops}, fun, n)


def scipy_run(fun, n, y0, method, rtol, atol):
    def rhs(_t, y):
        M, f = fun(y[:n], y[n:])
        return np.concatenate([y[n:], np.linalg.solve(np.asarray(M, dtype=float).reshape(n, n),
                                                      np.asarray(f, dtype=float).reshape(n))])
    t0 = time.perf_counter()
    sol = solve_ivp(rhs, (0.0, T_END), y0, method=method, rtol=rtol, atol=atol)
    dt = time.perf_counter() - t0
    return {"time_s": dt, "y_end": sol.y[:, -1].tolist(), "status": int(sol.status), "message": sol.message,
            "nfev": int(sol.nfev), "njev": int(sol.njev), "nlu": int(sol.nlu)}


def kanesens_run(exe, study, method, rtol, atol):
    cmd = [exe, "simulate", str(study), "--format", "json", "--set", f"solver.method={method}",
           "--set", f"solver.rtol={rtol!r}", "--set", f"solver.atol={atol!r}"]
    t0 = time.perf_counter()
    p = subprocess.run(cmd, capture_output=True, text=True)
    dt = time.perf_counter() - t0
    if p.returncode not in (0, 4):
        raise RuntimeError(f"{' '.join(cmd)} failed ({p.returncode}): {p.stderr}")
    out = json.loads(p.stdout)
    st = out["stats"]
    return {"time_s": st["wall_seconds"], "process_wall_s": dt, "y_end": out["states"][-1],
            "y0": out["states"][0], "status": out.get("status", 0), "message": out.get("message", ""),
            "nfev": st.get("rhs_evals"), "steps": st.get("steps"), "njev": st.get("jacobian_evals"),
            "state_names": out["state_names"]}


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--ns", default="2,4,8")
    ap.add_argument("--out", default=str(ROOT / "docs" / "peers"))
    ap.add_argument("--kanesens", default=str(ROOT / "build" / "kanesens"))
    ap.add_argument("--budget", type=float, default=20.0, help="s; stop tightening a SciPy method after a run this long")
    ap.add_argument("--reps", type=int, default=3)
    ap.add_argument("--rtols", default="1e-3,1e-4,1e-5,1e-6,1e-7,1e-8,1e-9,1e-10,1e-11,1e-12")
    ap.add_argument("--ref-rtol", type=float, default=1e-14)
    ap.add_argument("--check-rtol", type=float, default=1e-13, help="DOP853 and Adams check tolerance")
    a = ap.parse_args()
    ns = [int(x) for x in a.ns.split(",")]
    rtols = [float(x) for x in a.rtols.split(",")]
    out = Path(a.out)
    out.mkdir(parents=True, exist_ok=True)
    tmp = Path(tempfile.mkdtemp(prefix="bench_peers_sympy_"))
    load_start = os.getloadavg()
    runs, derivations, refchecks = [], [], []

    for n in ns:
        scene = tmp / f"chain{n}.yaml"
        scene.write_text(chain_yaml(n))
        study = tmp / f"chain{n}_study.yaml"
        study.write_text(f"kanesens: 1\nscene: {scene.name}\ntime: {{end: {T_END}, outputs: 2}}\n"
                         "solver: {method: bdf, rtol: 1.0e-8, atol: 1.0e-10, jacobian: exact, max_steps: 100000000}\n"
                         "record: [states]\n")
        print(f"N = {n}: deriving (KanesMethod + lambdify)", file=sys.stderr, flush=True)
        d, fun, nu = derive(scene)
        d["n"] = n
        derivations.append(d)
        print(f"  {d}", file=sys.stderr, flush=True)

        # Reference and its checks.
        ra, ca = a.ref_rtol, a.check_rtol
        ref = kanesens_run(a.kanesens, study, "adams", ra, ra * 1e-2)
        y0 = np.array(ref["y0"], dtype=float)
        chk = {"n": n, "ref": f"kanesens adams rtol {ra:g} atol {ra * 1e-2:g}", "state_names": ref["state_names"],
               "y0": y0.tolist(), "y_ref": ref["y_end"], "ref_time_s": ref["time_s"]}
        ad = kanesens_run(a.kanesens, study, "adams", ca, ca * 1e-2)
        chk["kanesens_adams_check_vs_ref"] = max_err(ad["y_end"], ref["y_end"])
        bd = kanesens_run(a.kanesens, study, "bdf", ra, ra * 1e-2)
        chk["kanesens_bdf_ref_rtol_vs_ref"] = max_err(bd["y_end"], ref["y_end"])
        dop = scipy_run(fun, nu, y0, "DOP853", ca, ca * 1e-2)
        chk["scipy_dop853_check_vs_ref"] = max_err(dop["y_end"], ref["y_end"])
        chk["scipy_dop853_time_s"] = dop["time_s"]
        chk["check_rtol"] = ca
        refchecks.append(chk)
        print(f"  reference check: adams {chk['kanesens_adams_check_vs_ref']:.2e}, bdf {chk['kanesens_bdf_ref_rtol_vs_ref']:.2e},"
              f" DOP853 {chk['scipy_dop853_check_vs_ref']:.2e} (DOP853 took {dop['time_s']:.1f} s)", file=sys.stderr, flush=True)
        y_ref = ref["y_end"]

        active = set(SCIPY_METHODS)
        for rtol in rtols:
            atol = rtol * 1e-2
            tools = [("kanesens", m) for m in KANESENS_METHODS] + [("scipy", m) for m in SCIPY_METHODS if m in active]
            # Alternate: kanesens bdf, RK45, kanesens adams, DOP853, ... in every repetition.
            order = interleaved([t for t in tools if t[0] == "kanesens"], [t for t in tools if t[0] == "scipy"])
            res = repeated_runs(order, a.reps, lambda t: kanesens_run(a.kanesens, study, t[1], rtol, atol)
                                if t[0] == "kanesens" else scipy_run(fun, nu, y0, t[1], rtol, atol))
            for t in order:
                rs = res[t]
                row = {"n": n, "tool": t[0], "method": t[1], "rtol": rtol, "atol": atol,
                       "time_s": statistics.median(r["time_s"] for r in rs), "times_s": [r["time_s"] for r in rs],
                       "error": max_err(rs[0]["y_end"], y_ref), "status": rs[0]["status"],
                       "nfev": rs[0]["nfev"], "njev": rs[0]["njev"]}
                if t[0] == "kanesens":
                    row["process_wall_s"] = statistics.median(r["process_wall_s"] for r in rs)
                    row["steps"] = rs[0]["steps"]
                runs.append(row)
                print(f"  N={n} {t[0]:8s} {t[1]:6s} rtol={rtol:.0e} err={row['error']:.2e} "
                      f"time={row['time_s']:.4g}s nfev={row['nfev']}", file=sys.stderr, flush=True)
                if t[0] == "scipy" and row["time_s"] > a.budget:
                    active.discard(t[1])

    # Time to reach each target accuracy.
    targets = []
    for n in ns:
        for tool, methods in (("scipy", SCIPY_METHODS), ("kanesens", KANESENS_METHODS)):
            for m in methods:
                pts = [(r["rtol"], r["error"], r["time_s"]) for r in runs
                       if r["n"] == n and r["tool"] == tool and r["method"] == m and r["status"] >= 0]
                pts.sort(key=lambda p: -p[0])
                for e in TARGETS:
                    t, how = time_at(pts, e)
                    targets.append({"n": n, "tool": tool, "method": m, "target": e, "time_s": t, "how": how})

    cpu = next((l.split(":", 1)[1].strip() for l in open("/proc/cpuinfo") if l.startswith("model name")), "?")
    meta = {"date": str(datetime.date.today()), "cpu": cpu, "nproc": os.cpu_count(),
            "loadavg_start": load_start, "loadavg_end": os.getloadavg(), "platform": platform.platform(),
            "python": sys.version.split()[0], "sympy": sp.__version__, "scipy": scipy.__version__,
            "numpy": np.__version__, "t_end": T_END, "rtols": rtols, "atol_factor": 1e-2,
            "ref_rtol": a.ref_rtol, "check_rtol": a.check_rtol, "reps": a.reps, "budget_s": a.budget,
            "git": subprocess.run(["git", "-C", str(ROOT), "rev-parse", "--short", "HEAD"],
                                  capture_output=True, text=True).stdout.strip(),
            "command": " ".join(sys.argv)}
    data = {"meta": meta, "derivation": derivations, "reference_check": refchecks, "runs": runs, "targets": targets}
    (out / "sympy_scipy.json").write_text(json.dumps(data, indent=1))
    print(f"wrote {out / 'sympy_scipy.json'}; tables and figure: bench/make_tables.py", file=sys.stderr)


if __name__ == "__main__":
    main()
