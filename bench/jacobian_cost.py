#!/usr/bin/python3
"""The exact Jacobian's cost in right-hand sides: `kanesens bench rhs --json` side by side.

  jacobian_cost.py OUT.json LABEL=EXE [LABEL=EXE ...] [--rounds K] [--scenes a,b]
  jacobian_cost.py --table OUT.json

For every scene and executable, K rounds (interleaved across executables) of `bench rhs`; each
round reports the median of its batches, and the figure is the median over rounds of
jacobian / rhs measured in the same round (`jacobian_dual`: one Dual pass per column, as before
multi-tangent passes; `jacobian`: what the solvers get, if the executable has it, by the method
it reports as `jacobian_method` (`whole_rhs` when it does not say); `jacobian_residual`: the
multi-tangent residual pass, where the executable took the closed form; `jacobian_whole_rhs`:
multi-tangent passes of the whole right-hand side, if the executable has both methods).
Scenes are looked up in configs/, then bench/configs/.
"""
import json
import os
import statistics
import subprocess
import sys

from common import load_json, table_or_usage

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), ".."))
SCENES = ["nlink_chain_4", "arm_3d", "spinning_top", "four_bar", "rolling_disc", "andrews", "nlink_chain_16"]


def scene_file(scene):
    path = os.path.join(ROOT, "configs", scene + ".yaml")
    return path if os.path.exists(path) else os.path.join(ROOT, "bench", "configs", scene + ".yaml")


def bench(exe, scene):
    p = subprocess.run([exe, "bench", "rhs", scene_file(scene), "--json", "--repeat", "11"],
                       check=True, capture_output=True, text=True)
    return json.loads(p.stdout)


def measure(out, exes, rounds, command, scenes=SCENES):
    rows = []
    for scene in scenes:
        runs = {label: [] for label, _ in exes}
        for _ in range(rounds):
            for label, exe in exes:
                runs[label].append(bench(exe, scene))
        for label, _ in exes:
            d = runs[label]
            row = {"scene": scene, "exe": label, "nstate": d[0]["nq"] + d[0]["nu"], "path": d[0]["path"],
                   "jacobian_method": d[0].get("jacobian_method", "whole_rhs"),
                   "rhs_ns": [r["rhs"]["median_ns"] for r in d]}
            for k in ("jacobian_dual", "jacobian", "jacobian_residual", "jacobian_whole_rhs", "jacobian_times"):
                if k in d[0]:
                    row[k + "_ns"] = [r[k]["median_ns"] for r in d]
                    row[k + "_over_rhs"] = statistics.median(r[k]["median_ns"] / r["rhs"]["median_ns"] for r in d)
            rows.append(row)
            print(scene, label, {k: round(v, 1) for k, v in row.items() if k.endswith("over_rhs")}, file=sys.stderr)
    with open(out, "w") as f:
        json.dump({"command": command, "rounds": rounds, "rows": rows}, f, indent=1)


def table(path):
    r = load_json(path)
    print(f"Median over {r['rounds']} interleaved rounds of (Jacobian time / RHS time), each from `kanesens bench rhs`.\n")
    residual_column = any("jacobian_residual_over_rhs" in row for row in r["rows"])
    print("| scene | states | path | build | RHS (ns) | Jacobian, one Dual pass per column | Jacobian, multi-tangent passes of the whole RHS |"
          + (" Jacobian, multi-tangent residual pass |" if residual_column else "")
          + " Jacobian as the solvers get it | method |")
    print("|---|---:|---|---|---:|---:|---:|" + ("---:|" if residual_column else "") + "---:|---|")

    def ratio(row, k):
        return f"{row[k + '_over_rhs']:.1f}x" if k + "_over_rhs" in row else "—"

    for row in r["rows"]:
        method = row.get("jacobian_method", "whole_rhs")
        whole = ratio(row, "jacobian_whole_rhs") if "jacobian_whole_rhs_over_rhs" in row else (
            ratio(row, "jacobian") if method == "whole_rhs" else "—")
        residual = ""
        if residual_column:
            residual = " " + (ratio(row, "jacobian_residual") if "jacobian_residual_over_rhs" in row else (
                ratio(row, "jacobian") if method == "residual" else "—")) + " |"
        print(f"| {row['scene']} | {row['nstate']} | {row['path']} | {row['exe']} | {statistics.median(row['rhs_ns']):.0f} | "
              f"{ratio(row, 'jacobian_dual')} | {whole} |{residual} {ratio(row, 'jacobian')} | {method} |")


if __name__ == "__main__":
    argv = sys.argv[1:]
    table_or_usage(argv, table, __doc__)
    rounds, exes, scenes = 5, [], SCENES
    i = 1
    while i < len(argv):
        if argv[i] == "--rounds":
            rounds = int(argv[i + 1]); i += 2
        elif argv[i] == "--scenes":
            scenes = argv[i + 1].split(","); i += 2
        else:
            exes.append(tuple(argv[i].split("=", 1))); i += 1
    measure(argv[0], exes, rounds, "/usr/bin/python3 bench/jacobian_cost.py " + " ".join(argv), scenes)
    table(argv[0])
