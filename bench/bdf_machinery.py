"""How much of a BDF solve with sensitivities is the integrator's own work, and what that leaves
for the cost per added sensitivity however cheap the sensitivity passes become.

  bdf_machinery.py OUT.json EXE [--scenes a,b] [--repeat R] [--set key=value ...]
  bdf_machinery.py --table OUT.json

For each scene of sensitivity_cost.py, `kanesens simulate` with BDF, plain and with the scene's
six sensitivities: the time of a solve (median of R − 1 repeated solves after the first in one
process) and a sampled profile (Linux `perf record -e cpu-clock`, R solves and at least two
seconds of them). Each sample is
"integrator" when it lies in libsundials_cvodes (CVODES's steps, corrector, error test and
Nordsieck history), in the serial N_Vector operations that kanesens installs for it
(sim/solve/serial_vector_ops.cpp) or in Newton's dense solves (sim/solve/dense_lu_solver.cpp),
and "dynamics" otherwise (right-hand sides, sensitivity passes, Jacobians, outputs).

With t_p, t_s the plain and sensitivity solves, m_p, m_s their integrator shares, n_p, n_s their
steps and Ns the sensitivities:
  per added sensitivity          (t_s − t_p) / (Ns t_p)
  bound with free passes         (m_s t_s + (1 − m_p) t_p n_s / n_p − t_p) / (Ns t_p):
                                 the integrator's work as measured, the plain right-hand sides
                                 at the steps the sensitivities' error test takes, nothing for
                                 the sensitivity passes.
"""
from __future__ import annotations

import argparse
import os
import re
import subprocess
import sys
import tempfile

from common import load_json, provenance, table_or_usage, write_json
from sensitivity_cost import run, studies

DEFAULT_SCENES = ["arm_3d", "chain8_spatial", "chain4_planar", "rolling_disc", "four_bar_multipliers"]
INTEGRATOR_SYMBOLS = re.compile(r"sim::\(anonymous namespace\)::(op_\w+|linear_sum|scale|combination|"
                                r"weighted_square_sum\w*|solve)\b|partial_lu_impl")


def shares(exe, study, sens, extra, repeat):
    """The integrator's share of the profiled samples, and the samples counted."""
    with tempfile.TemporaryDirectory() as tmp:
        data = os.path.join(tmp, "perf.data")
        subprocess.run(["perf", "record", "-q", "-e", "cpu-clock", "-F", "10000", "-o", data, exe, "simulate", study,
                        "--set", "solver.method=bdf", "--sens", sens, "--repeat", str(repeat)] + extra,
                       check=True, capture_output=True)
        report = subprocess.run(["perf", "report", "-i", data, "--no-children", "--sort", "dso,symbol", "--stdio",
                                 "-F", "sample,dso,symbol"], check=True, capture_output=True, text=True).stdout
    integrator = total = 0
    for line in report.splitlines():
        m = re.match(r"\s*(\d+)\s+(\S+)\s+\[.\]\s+(.*)", line)
        if not m:
            continue
        n, dso, symbol = int(m.group(1)), m.group(2), m.group(3)
        total += n
        if "libsundials_cvodes" in dso or INTEGRATOR_SYMBOLS.search(symbol):
            integrator += n
    return integrator / total, total


def measure(out, exe, scenes, extra, repeat):
    result = {**provenance(), "repeat": repeat, "rows": []}
    with tempfile.TemporaryDirectory() as tmp:
        for name, study, sens, _ in studies(tmp, scenes):
            row = {"scene": name, "ns": len(sens.split(",")), "sensitivities": sens}
            for kind, s in (("plain", "none"), ("sens", sens)):
                t, stats = run(exe, study, "bdf", s, extra, repeat)
                steps = stats["steps"]
                # At least two seconds of solves in the profile: some ten thousand samples.
                share, samples = shares(exe, study, s, extra, max(repeat, int(2.0 / t) + 1))
                row[kind] = {"seconds": t, "steps": steps, "integrator_share": share, "samples": samples}
            result["rows"].append(row)
            print(name, f"{row['plain']['seconds'] * 1e3:.2f} / {row['sens']['seconds'] * 1e3:.2f} ms",
                  f"integrator {row['plain']['integrator_share']:.2f} / {row['sens']['integrator_share']:.2f}",
                  file=sys.stderr)
    write_json(out, result)


def per_added(row):
    p, s = row["plain"], row["sens"]
    return (s["seconds"] - p["seconds"]) / (row["ns"] * p["seconds"])


def bound_with_free_passes(row):
    p, s = row["plain"], row["sens"]
    floor = s["integrator_share"] * s["seconds"] + (1 - p["integrator_share"]) * p["seconds"] * s["steps"] / p["steps"]
    return (floor - p["seconds"]) / (row["ns"] * p["seconds"])


def table(path):
    r = load_json(path)
    print(f"BDF, one process per solve, each time the median of {r['repeat'] - 1} repeated solves after the first; "
          "integrator = CVODES and the vector operations and dense solves it calls, from a sampled profile.\n")
    print("| scene | Ns | plain solve (ms) | integrator share | with Ns sensitivities (ms) | integrator share | "
          "steps plain / sens | per added sensitivity | bound with free sensitivity passes |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|---:|")
    for row in r["rows"]:
        p, s = row["plain"], row["sens"]
        print(f"| {row['scene']} | {row['ns']} | {p['seconds'] * 1e3:.2f} | {p['integrator_share'] * 100:.0f} % | "
              f"{s['seconds'] * 1e3:.2f} | {s['integrator_share'] * 100:.0f} % | {p['steps']} / {s['steps']} | "
              f"{per_added(row):.2f}x | {bound_with_free_passes(row):.2f}x |")


if __name__ == "__main__":
    table_or_usage(sys.argv[1:], table, __doc__)
    parser = argparse.ArgumentParser(usage=__doc__)
    parser.add_argument("out")
    parser.add_argument("exe")
    parser.add_argument("--scenes", default=",".join(DEFAULT_SCENES))
    parser.add_argument("--repeat", type=int, default=101)
    parser.add_argument("--set", action="append", default=[])
    a = parser.parse_args()
    measure(a.out, a.exe, a.scenes.split(","), [w for kv in a.set for w in ("--set", kv)], a.repeat)
    table(a.out)
