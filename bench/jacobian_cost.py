#!/usr/bin/python3
"""The exact Jacobian's cost in right-hand sides: `kanesens bench rhs --json` side by side.

  jacobian_cost.py OUT.json LABEL=EXE [LABEL=EXE ...] [--rounds K]
  jacobian_cost.py --table OUT.json

For every scene and executable, K rounds (interleaved across executables) of `bench rhs`; each
round reports the median of its batches, and the figure is the median over rounds of
jacobian / rhs measured in the same round (`jacobian_dual`: one Dual pass per column, as before
multi-tangent passes; `jacobian`: what the solvers get, if the executable has it).
"""
import json
import os
import statistics
import subprocess
import sys

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), ".."))
SCENES = ["nlink_chain_4", "arm_3d", "spinning_top", "four_bar", "rolling_disc", "andrews", "nlink_chain_16"]


def bench(exe, scene):
    p = subprocess.run([exe, "bench", "rhs", os.path.join(ROOT, "configs", scene + ".yaml"), "--json", "--repeat", "11"],
                       check=True, capture_output=True, text=True)
    return json.loads(p.stdout)


def measure(out, exes, rounds):
    rows = []
    for scene in SCENES:
        runs = {label: [] for label, _ in exes}
        for _ in range(rounds):
            for label, exe in exes:
                runs[label].append(bench(exe, scene))
        for label, _ in exes:
            d = runs[label]
            row = {"scene": scene, "exe": label, "nstate": d[0]["nq"] + d[0]["nu"], "path": d[0]["path"],
                   "rhs_ns": [r["rhs"]["median_ns"] for r in d]}
            for k in ("jacobian_dual", "jacobian"):
                if k in d[0]:
                    row[k + "_ns"] = [r[k]["median_ns"] for r in d]
                    row[k + "_over_rhs"] = statistics.median(r[k]["median_ns"] / r["rhs"]["median_ns"] for r in d)
            rows.append(row)
            print(scene, label, {k: round(v, 1) for k, v in row.items() if k.endswith("over_rhs")}, file=sys.stderr)
    with open(out, "w") as f:
        json.dump({"rounds": rounds, "rows": rows}, f, indent=1)


def table(path):
    with open(path) as f:
        r = json.load(f)
    print(f"Median over {r['rounds']} interleaved rounds of (Jacobian time / RHS time), each from `kanesens bench rhs`.\n")
    print("| scene | states | path | build | RHS (ns) | Jacobian, one Dual pass per column | Jacobian, blocked multi-tangent passes |")
    print("|---|---:|---|---|---:|---:|---:|")
    for row in r["rows"]:
        jd = f"{row['jacobian_dual_over_rhs']:.1f}x" if "jacobian_dual_over_rhs" in row else "—"
        jm = f"{row['jacobian_over_rhs']:.1f}x" if "jacobian_over_rhs" in row else "—"
        print(f"| {row['scene']} | {row['nstate']} | {row['path']} | {row['exe']} | {statistics.median(row['rhs_ns']):.0f} | {jd} | {jm} |")


if __name__ == "__main__":
    argv = sys.argv[1:]
    if len(argv) == 2 and argv[0] == "--table":
        table(argv[1])
        sys.exit(0)
    if len(argv) < 2:
        sys.exit(__doc__)
    rounds, exes = 5, []
    i = 1
    while i < len(argv):
        if argv[i] == "--rounds":
            rounds = int(argv[i + 1]); i += 2
        else:
            exes.append(tuple(argv[i].split("=", 1))); i += 1
    measure(argv[0], exes, rounds)
    table(argv[0])
