"""How manufacturing tolerances move the benchmark bicycle's stability: runs the Saltelli study
configs/whipple_tolerance_study.yaml (masses ±2 %, geometry ±1 mm, uniform) at each forward speed,
and reports per speed

  * the probability of self-stability, P(all eigenvalues have Re < 0) = P(modes.re0 < 0) (the
    eigenvalues are sorted by decreasing real part), over the design's A and B runs;
  * the distribution of the weave eigenvalue's real part (the eigenvalue with Im > 0) and its
    first and total Sobol' indices (kanesens_post.sobol: Saltelli 2010 / Jansen 1999, bootstrap
    95 % intervals);
  * the same from the exact eigenvalue sensitivities at the nominal bicycle (linear UQ:
    σ² = Σ (∂Re λ/∂p_i)² Var p_i, S_i = (∂Re λ/∂p_i)² Var p_i / σ²), a check of both.

    /usr/bin/python3 scripts/bicycle_tolerance.py [--kanesens build/kanesens] [--np 2]
        [--samples N] [--speeds 5.0 6.0] [--study FILE] [--out JSON]

writes docs/linearization/bicycle_tolerance.json by default (with the command, the kanesens
version and the study's tolerances).
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "python"))
from kanesens_post import io as kio  # noqa: E402
from kanesens_post import sobol  # noqa: E402

STUDY = "configs/whipple_tolerance_study.yaml"
OUT = ROOT / "docs" / "linearization" / "bicycle_tolerance.json"
ENV = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
           OMPI_MCA_rmaps_base_oversubscribe="1")


def run(exe, study, speed, samples, nproc, out):
    cmd = [exe, "run", str(study), "-o", str(out), "--set", f"v={speed!r}"]
    if samples:
        cmd += ["--samples", str(samples)]
    if nproc > 1:
        cmd = ["mpirun", "-np", str(nproc)] + cmd
    subprocess.run(cmd, check=True, capture_output=True, text=True, env=ENV)


def nominal(exe, study, speed):
    p = subprocess.run([exe, "simulate", str(study), "--set", f"v={speed!r}"], check=True,
                       capture_output=True, text=True, env=ENV)
    return json.loads(p.stdout)


def eigenvalue_count(names):
    k = 0
    while f"modes.re{k}" in names:
        k += 1
    return k


def weave(re, im):
    """Per row: the real part and index of the eigenvalue with Im > 0 (NaN, −1 if none)."""
    has = im > 1e-9
    k = np.where(has.any(axis=1), np.argmax(has, axis=1), -1)
    value = np.where(k >= 0, re[np.arange(len(k)), np.maximum(k, 0)], np.nan)
    return value, k


def analyze(ds, nom, speed, n_boot):
    des = kio.design(ds)
    count = eigenvalue_count(kio.output_names(ds))
    re = np.stack([np.asarray(kio.response(ds, f"modes.re{k}").values, float) for k in range(count)], 1)
    im = np.stack([np.asarray(kio.response(ds, f"modes.im{k}").values, float) for k in range(count)], 1)
    ab = np.isin(des.row, (0, 1)) & np.isfinite(re[:, 0])
    stable = re[ab, 0] < 0
    w, _ = weave(re, im)
    blocks, dropped = sobol.saltelli_blocks(des, w)
    ind = sobol.indices(blocks)
    boot = sobol.bootstrap(blocks, n_boot, seed=0)

    # Linear UQ from the exact sensitivities at the nominal bicycle.
    o, s = nom["outputs"], nom["output_sensitivities"]
    nre = np.array([o[f"modes.re{k}"] for k in range(count)])
    nim = np.array([o[f"modes.im{k}"] for k in range(count)])
    _, kw = weave(nre[None, :], nim[None, :])
    grad = np.array(s[f"modes.re{kw[0]}"])
    var = np.array([des.dists[n].variance() for n in des.names])
    lin_var = float(np.sum(grad ** 2 * var))
    wab = w[ab]
    return {
        "speed": speed,
        "runs": int(des.row.size),
        "failed_runs": int((~np.isfinite(re[:, 0])).sum()),
        "probability_self_stable": float(stable.mean()),
        "probability_from_runs": int(stable.size),
        "max_real_part": {"mean": float(re[ab, 0].mean()), "min": float(re[ab, 0].min()),
                          "max": float(re[ab, 0].max())},
        "weave_real_part": {"nominal": float(nre[kw[0]]), "mean": float(np.nanmean(wab)),
                            "std": float(np.nanstd(wab)), "min": float(np.nanmin(wab)),
                            "max": float(np.nanmax(wab)),
                            "std_linear": float(np.sqrt(lin_var))},
        "sobol": {"inputs": des.names, "base_points": int(blocks.shape[0]),
                  "base_points_dropped": dropped,
                  "S1": ind["S1"].tolist(), "ST": ind["ST"].tolist(),
                  "S1_ci": boot["S1_ci"].T.tolist(), "ST_ci": boot["ST_ci"].T.tolist(),
                  "bootstrap": n_boot,
                  "S_linear": (grad ** 2 * var / lin_var).tolist()},
        "weave_sensitivities_nominal": dict(zip(des.names, grad.tolist())),
    }


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--kanesens", default=str(ROOT / "build" / "kanesens"))
    ap.add_argument("--study", default=str(ROOT / STUDY))
    ap.add_argument("--np", type=int, default=2, dest="nproc")
    ap.add_argument("--samples", type=int, default=0, help="Saltelli base points (default: the study's)")
    ap.add_argument("--speeds", type=float, nargs="+", default=[5.0, 6.0])
    ap.add_argument("--bootstrap", type=int, default=200)
    ap.add_argument("--out", default=str(OUT))
    a = ap.parse_args(argv)
    version = subprocess.run([a.kanesens, "--version"], capture_output=True, text=True).stdout.strip()
    result = {"command": "scripts/bicycle_tolerance.py " + " ".join(sys.argv[1:] if argv is None else argv),
              "kanesens": version, "study": os.path.relpath(a.study, ROOT), "speeds": []}
    with tempfile.TemporaryDirectory() as tmp:
        for v in a.speeds:
            path = Path(tmp) / f"bicycle_{v}.h5"
            run(a.kanesens, a.study, v, a.samples, a.nproc, path)
            ds = kio.open_run(path)
            try:
                if "tolerances" not in result:
                    result["tolerances"] = {n: {"dist": d.kind, **d.params}
                                            for n, d in kio.design(ds).dists.items()}
                r = analyze(ds, nominal(a.kanesens, a.study, v), v, a.bootstrap)
            finally:
                ds.close()
            result["speeds"].append(r)
            top = np.argsort(r["sobol"]["ST"])[::-1][:3]
            print(f"v = {v} m/s: P(self-stable) = {r['probability_self_stable']:.4f} "
                  f"({r['probability_from_runs']} runs); weave Re = {r['weave_real_part']['mean']:.4f} "
                  f"± {r['weave_real_part']['std']:.4f} (linear {r['weave_real_part']['std_linear']:.4f}); "
                  "largest ST: " + ", ".join(f"{r['sobol']['inputs'][i]} {r['sobol']['ST'][i]:.3f}" for i in top))
    Path(a.out).parent.mkdir(parents=True, exist_ok=True)
    Path(a.out).write_text(json.dumps(result, indent=1) + "\n")
    print(f"wrote {a.out}")


if __name__ == "__main__":
    main()
