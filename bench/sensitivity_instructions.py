#!/usr/bin/python3
"""Cost of forward sensitivities in instructions: callgrind counts of `kanesens simulate` with and
without Ns sensitivities, for machines whose load makes wall times too noisy to compare
(bench/sensitivity_cost.py measures the times).

  sensitivity_instructions.py OUT.json LABEL=EXE [LABEL=EXE ...] [--scenes a,b] [--methods m,n]
  sensitivity_instructions.py --table OUT.json

The scenes, studies and sensitivities are sensitivity_cost.py's. One solve's count is that of
`simulate --repeat 3` minus that of `--repeat 1`, halved: reading the study and building the
model drop out. Per added sensitivity = (I_sens − I_plain) / (Ns · I_plain). Counts are the same
on every run of a build; they do not weigh instructions by their cost (a vector multiply-add and
a scalar move count one each), so they rank two builds' work but are not times.
Needs valgrind (callgrind).
"""
import json
import os
import subprocess
import sys
import tempfile

from common import load_json, provenance, table_or_usage
from sensitivity_cost import SCENES, instruction_set, studies


def instructions(exe, study, method, sens, repeat):
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "callgrind.out")
        subprocess.run(["valgrind", "--tool=callgrind", f"--callgrind-out-file={out}", exe, "simulate", study,
                        "--set", f"solver.method={method}", "--sens", sens, "--repeat", str(repeat)],
                       check=True, capture_output=True, text=True)
        for line in open(out):
            if line.startswith("summary:") or line.startswith("totals:"):
                return int(line.split()[1])
    raise RuntimeError(f"{exe}: no callgrind total")


def per_solve(exe, study, method, sens):
    return (instructions(exe, study, method, sens, 3) - instructions(exe, study, method, sens, 1)) / 2


def measure(out, exes, scenes, methods_only):
    result = {"command": "/usr/bin/python3 bench/sensitivity_instructions.py " + " ".join(sys.argv[1:]),
              "machine": provenance(), "builds": {label: instruction_set(exe) for label, exe in exes}, "rows": []}
    with tempfile.TemporaryDirectory() as tmp:
        for name, study, sens, methods in studies(tmp, scenes):
            for method in [m for m in methods if not methods_only or m in methods_only]:
                for label, exe in exes:
                    row = {"scene": name, "method": method, "exe": label, "ns": len(sens.split(",")),
                           "sensitivities": sens, "plain": per_solve(exe, study, method, "none"),
                           "sens": per_solve(exe, study, method, sens)}
                    result["rows"].append(row)
                    print(name, method, label, f"{per_added(row):.2f}", file=sys.stderr)
    with open(out, "w") as f:
        json.dump(result, f, indent=1)


def per_added(row):
    return (row["sens"] - row["plain"]) / (row["ns"] * row["plain"])


def table(path):
    r = load_json(path)
    print("Instructions of one solve (callgrind); per added sensitivity = (I_sens − I_plain) / (Ns · I_plain). "
          + ", ".join(f"{label}: {isa}" for label, isa in r["builds"].items()) + ".\n")
    print("| scene | method | build | Ns | plain solve (M instructions) | with Ns sensitivities | per added sensitivity |")
    print("|---|---|---|---:|---:|---:|---:|")
    for row in r["rows"]:
        print(f"| {row['scene']} | {row['method']} | {row['exe']} | {row['ns']} | {row['plain']/1e6:.2f} | "
              f"{row['sens']/1e6:.2f} | {per_added(row):.2f}x |")


if __name__ == "__main__":
    argv = sys.argv[1:]
    table_or_usage(argv, table, __doc__)
    scenes, methods = list(SCENES), None
    out, exes = argv[0], []
    i = 1
    while i < len(argv):
        if argv[i] == "--scenes":
            scenes = argv[i + 1].split(","); i += 2
        elif argv[i] == "--methods":
            methods = argv[i + 1].split(","); i += 2
        else:
            label, exe = argv[i].split("=", 1)
            exes.append((label, exe)); i += 1
    measure(out, exes, scenes, methods)
