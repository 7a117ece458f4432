#!/usr/bin/python3
"""Runs every work-precision study of docs/workprecision.md and draws the diagrams.

    /usr/bin/python3 bench/run_workprecision.py [PROBLEM ...] [--repeat 5] [--out docs/workprecision]
        [--build build] [--harness "CMD ..."] [--list]
    env: REPEAT (default of --repeat); KANESENS_WORKPRECISION (default of --harness)
    quick smoke test: bench/run_workprecision.py constrained_pendulum --repeat 1 --out /tmp/wp

PROBLEM: any of --list (default: all). For each, runs the work-precision harness
(`<harness> STUDY ARGS --repeat R --json`; harness default: `kanesens-workprecision` of the
build directory) into OUT/<problem>.json and draws OUT/<problem>.png (plot_workprecision.py);
then the second views: deterministic work (RHS evaluations), energy drift, quaternion norm
drift.
"""
from __future__ import annotations

import argparse
import contextlib
import json
import shlex
import subprocess
import sys
from pathlib import Path

import common as c
import plot_workprecision

T7 = "1e-4,1e-5,1e-6,1e-7,1e-8,1e-9,1e-10"
# Non-stiff problems take their reference from DOP853 at rtol 1e-13 (a BDF reference is only
# good to ~1e-9 there, which would hide the tight end of the diagrams); the stiff chains keep BDF.
NS = ["--reference-method", "dop853"]
# Studies relative to the repository root, where the harness runs (the JSON records the path).
WP, CF = c.BENCH_CONFIGS.relative_to(c.ROOT), c.CONFIGS.relative_to(c.ROOT)

# problem -> (study, harness arguments)
PROBLEMS = {
    "chain4": (WP / "wp_chain4.yaml", ["--tolerances", T7, *NS]),
    "chain16": (WP / "wp_chain16.yaml", ["--tolerances", T7, *NS]),
    "chain4_stiff": (WP / "wp_chain4_stiff.yaml", ["--tolerances", "1e-4,1e-6,1e-8",
                                                   "--rk4-steps", "500,1000,2000,3000,4000,8000"]),
    "chain4_stiff_swing": (WP / "wp_chain4_stiff_swing.yaml", ["--tolerances", T7,
                                                               "--rk4-steps", "200,1000,2000,3000,4000,8000,16000"]),
    "double_pendulum_chaos": (WP / "wp_double_pendulum_chaos.yaml", ["--tolerances", T7, "--max-steps", "200000", *NS]),
    "double_pendulum_lyapunov": (WP / "wp_double_pendulum_lyapunov.yaml",
                                 ["--tolerances", "1e-6,1e-8,1e-10", "--methods", "bdf-exact,adams-newton,dop853,rk4",
                                  "--with-sens", "--reference-rtol", "1e-12", *NS]),
    "spinning_top": (WP / "wp_spinning_top.yaml", ["--tolerances", T7, "--rk4-h-scale", "0.01", *NS]),
    "double_pendulum_long": (WP / "wp_double_pendulum_long.yaml",
                             ["--tolerances", "1e-6,1e-7,1e-8,1e-9,1e-10",
                              "--methods", "bdf-exact,adams-newton,adams-functional,dop853,rk4", *NS]),
    "constrained_pendulum": (WP / "wp_constrained_pendulum.yaml", ["--tolerances", T7, *NS]),
    # Closed loops and a nonholonomic contact: the four-bar with its sensitivities (c, m2) under
    # multipliers + projection and under embedding, Andrews' mechanism (0.03 s: DOP853 is not
    # stability-bound there, and a BDF reference floors the errors at ~1e-8), the rolling disc
    # (nonholonomic rows, Baumgarte; states only: its study's sensitivity, to the mass, is
    # identically 0 — every force scales with m — so its relative error would compare noise).
    "four_bar": (CF / "four_bar_study.yaml", ["--tolerances", T7, *NS]),
    "four_bar_embedding": (CF / "four_bar_study.yaml", ["--tolerances", T7, *NS,
                                                        "--set", "solver.constraints.formulation=embedding",
                                                        "--set", "solver.constraints.stabilization=none"]),
    "andrews": (CF / "andrews_study.yaml", ["--tolerances", T7, *NS]),
    "rolling_disc": (CF / "rolling_disc_study.yaml",
                     ["--tolerances", T7, *NS, "--methods", "bdf-exact,bdf-dq,adams-newton,adams-functional,dop853,rk4"]),
}
# Second views: (problems, plot_workprecision arguments)
VIEWS = [(["chain4", "chain16", "chain4_stiff_swing"], ["--work", "rhs_evals_total", "--suffix", "_rhs"]),
         (["double_pendulum_long"], ["--error", "energy_drift", "--suffix", "_energy"]),
         (["spinning_top"], ["--error", "quaternion_norm_drift", "--suffix", "_quaternion"])]


def plot(args) -> None:
    with contextlib.redirect_stdout(sys.stderr):  # the file names it wrote, as progress
        plot_workprecision.main(args)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("problems", nargs="*", help="problems to run (default: all)")
    ap.add_argument("--repeat", type=int, default=int(c.env_default("REPEAT", 5)))
    ap.add_argument("--out", default=str(c.ROOT / "docs" / "workprecision"))
    ap.add_argument("--build", default=str(c.ROOT / "build"), help="build directory of the harness")
    ap.add_argument("--harness", help="the harness command (default: $KANESENS_WORKPRECISION or "
                    f"<build>/{' '.join(c.WORKPRECISION)})")
    ap.add_argument("--list", action="store_true", help="print the problems and exit")
    a = ap.parse_args(argv)
    if a.list:
        print("\n".join(PROBLEMS))
        return 0
    unknown = [p for p in a.problems if p not in PROBLEMS]
    if unknown:
        print(f"unknown problem {unknown[0]}; known: {', '.join(PROBLEMS)}", file=sys.stderr)
        return 2
    harness = a.harness.split() if a.harness else c.workprecision_cmd(Path(a.build).resolve())
    out = Path(a.out).resolve()
    out.mkdir(parents=True, exist_ok=True)
    for name in a.problems or PROBLEMS:
        study, args = PROBLEMS[name]
        cmd = [*harness, str(study), *args, "--repeat", str(a.repeat), "--json"]
        print(f"== {name}: {' '.join(cmd)}", file=sys.stderr, flush=True)
        load_start = c.loadavg()
        res = json.loads(subprocess.run(cmd, stdout=subprocess.PIPE, check=True, cwd=c.ROOT, text=True).stdout)
        # What made this file: the harness command (from the repository root) and this driver's.
        res["harness_command"] = " ".join(shlex.quote(str(x)) for x in [Path(harness[0]).name, *harness[1:],
                                                                        str(study), *args, "--repeat", str(a.repeat),
                                                                        "--json"])
        res.update(c.provenance(load_start))
        (out / f"{name}.json").write_text(json.dumps(res, indent=1))
        plot([str(out / f"{name}.json"), "-o", str(out)])
    for names, args in VIEWS:
        for name in names:
            if (out / f"{name}.json").exists():
                plot([str(out / f"{name}.json"), "-o", str(out), *args])
    return 0


if __name__ == "__main__":
    sys.exit(main())
