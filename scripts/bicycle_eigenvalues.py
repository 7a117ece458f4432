"""Eigenvalues of the benchmark bicycle (configs/whipple_bicycle.yaml) against forward speed, from
`kanesens linearize`, with Table 2 of Meijaard et al. (2007) (tests/data/whipple_benchmark.txt)
overlaid, and the weave and capsize speeds found by bisection on kanesens's eigenvalues.

    /usr/bin/python3 scripts/bicycle_eigenvalues.py [--kanesens build/kanesens]

writes docs/linearization/bicycle_eigenvalues.json (every eigenvalue, the speeds, the command
and the kanesens version) and docs/linearization/bicycle_eigenvalues.png.
"""
import argparse
import json
import subprocess
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
SCENE = "configs/whipple_bicycle.yaml"
OUT = ROOT / "docs" / "linearization"


def eigenvalues(exe, v):
    p = subprocess.run([exe, "linearize", SCENE, "--set", f"v={v!r}", "--json"], cwd=ROOT,
                       capture_output=True, text=True, check=True)
    return [complex(re, im) for re, im in json.loads(p.stdout)["eigenvalues"]]


def weave_real(exe, v):
    return max(z.real for z in eigenvalues(exe, v) if abs(z.imag) > 1e-9)


def capsize(exe, v):
    return max(z.real for z in eigenvalues(exe, v) if abs(z.imag) <= 1e-9)


def bisect(f, a, b, tol=1e-14):
    fa = f(a)
    while b - a > tol:
        c = 0.5 * (a + b)
        fc = f(c)
        if (fc > 0) == (fa > 0):
            a, fa = c, fc
        else:
            b = c
    return 0.5 * (a + b)


def table2():
    rows = {}
    for line in (ROOT / "tests" / "data" / "whipple_benchmark.txt").read_text().splitlines():
        if line.startswith("eig "):
            v, *vals = line.split()[1:]
            rows[int(v)] = [float(x) for x in vals]
    return rows


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--kanesens", default=str(ROOT / "build" / "kanesens"))
    args = ap.parse_args()
    exe = str(Path(args.kanesens).resolve())
    speeds = np.round(np.arange(0, 10.0001, 0.05), 10)
    eigs = [eigenvalues(exe, float(v)) for v in speeds]
    v_w = bisect(lambda v: weave_real(exe, v), 4.0, 4.5)
    v_c = bisect(lambda v: capsize(exe, v), 5.9, 6.2)
    ref = table2()
    version = subprocess.run([exe, "--version"], capture_output=True, text=True).stdout.splitlines()[0]
    OUT.mkdir(parents=True, exist_ok=True)
    record = {
        "command": f"kanesens linearize {SCENE} --set v=V --json",
        "script": "scripts/bicycle_eigenvalues.py",
        "kanesens": version,
        "speeds": speeds.tolist(),
        "eigenvalues": [[[z.real, z.imag] for z in e] for e in eigs],
        "weave_speed": v_w,
        "capsize_speed": v_c,
        "reference": {"source": "Meijaard, Papadopoulos, Ruina, Schwab (2007), Proc. R. Soc. A 463, Table 2",
                      "weave_speed": 4.29238253634110396, "capsize_speed": 6.02426201538835889},
    }
    (OUT / "bicycle_eigenvalues.json").write_text(json.dumps(record, indent=1) + "\n")

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(7, 4.5))
    re = np.array([[z.real for z in e] for e in eigs])
    im = np.array([[abs(z.imag) for z in e] for e in eigs])
    for k in range(re.shape[1]):
        ax.plot(speeds, re[:, k], ".", ms=2.5, color="C0", label="Re λ (kanesens)" if k == 0 else None)
        mask = im[:, k] > 1e-9
        ax.plot(speeds[mask], im[mask, k], ".", ms=2.5, color="C1", label="|Im λ| (kanesens)" if k == 0 else None)
    vs = sorted(ref)
    for v in vs:
        w_re, w_im, cap, cas = ref[v]
        reals = [w_re, -w_re, cas, -cas] if v == 0 else [w_re, cap, cas]
        ax.plot([v] * len(reals), reals, "o", mfc="none", color="k", ms=6,
                label="Table 2 (Meijaard et al. 2007)" if v == 0 else None)
        if w_im > 0:
            ax.plot(v, w_im, "o", mfc="none", color="k", ms=6)
    ax.axvspan(v_w, v_c, color="0.9", label=f"self-stable {v_w:.4f} < v < {v_c:.4f} m/s")
    ax.axhline(0, color="0.5", lw=0.5)
    ax.set_ylim(-10, 10)
    ax.set_xlabel("forward speed v (m/s)")
    ax.set_ylabel("eigenvalue (1/s)")
    ax.set_title("Whipple bicycle, benchmark parameters: weave, capsize, castering")
    ax.legend(loc="lower right", fontsize=8)
    fig.tight_layout()
    fig.savefig(OUT / "bicycle_eigenvalues.png", dpi=120)
    print(f"v_w = {v_w:.15f}, v_c = {v_c:.15f}")


if __name__ == "__main__":
    main()
