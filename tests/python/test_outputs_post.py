"""Study outputs from `kanesens run` to kanesens-post, on a case with known answers.

One Saltelli run (N = 1024, P = 5) of a harmonic oscillator x'' = −(k/m) x with two scalar
outputs: x_end = x(T) = x0 cos ωT + (v0/ω) sin ωT (linear: S1 = ST, closed form from the input
variances), and the Ishigami function of three further parameters written as an output
expression (S1 = 0.3139, 0.4424, 0; ST = 0.5576, 0.4424, 0.2437; Ishigami & Homma 1990,
Saltelli et al. 2010). Checked: the Sobol' indices of both, DGSM from the recorded exact output
sensitivities (ν = E[(∂y/∂x)²] against the derivatives' closed forms at the sampled inputs),
linear UQ of the linear output, summary and plot of a scalar output, a series output (the
block's position) against the same quantity at the end, the command line's errors for names, and
the poses."""
import json
import math
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from kanesens_post import dgsm, linear_uq, sobol, summary
from kanesens_post.cli import main
from kanesens_post.io import design, open_run, output_names

PACKAGE_DIR = Path(__file__).resolve().parents[2] / "python"
T, OMEGA = 0.4, 2.0
STUDY = f"""kanesens: 1
scene:
  name: oscillator
  gravity: [0, 0, 0]
  parameters: {{m: 1.0, k: 4.0, x0: 0.0, v0: 0.0, x1: 0.0, x2: 0.0, x3: 0.0}}
  bodies:
    - {{name: block, mass: m, inertia: {{shape: point}}}}
  joints:
    - {{name: slider, type: prismatic, parent: ground, child: block, axis: [1, 0, 0],
       q0: x0, u0: v0, spring: {{k: k, rest: 0}}}}
time: {{end: {T}, outputs: 3}}
solver: {{rtol: 1.0e-10, atol: 1.0e-12}}
sampling: {{method: saltelli, samples: 1024, seed: 5, randomize: true}}
vary:
  x0: {{dist: uniform, low: -1.0, high: 1.0}}
  v0: {{dist: uniform, low: -1.0, high: 1.0}}
  x1: {{dist: uniform, low: -3.141592653589793, high: 3.141592653589793}}
  x2: {{dist: uniform, low: -3.141592653589793, high: 3.141592653589793}}
  x3: {{dist: uniform, low: -3.141592653589793, high: 3.141592653589793}}
sensitivities: [x0, v0, x1, x3]
record: [states, poses]
outputs:
  xs: {{type: position, body: block}}
  x_end: {{of: slider.q, at: end}}
  ishigami: {{expression: "sin(x1) + 7*sin(x2)^2 + 0.1*x3^4*sin(x1)"}}
"""


@pytest.fixture(scope="module")
def run_file(tmp_path_factory):
    exe = os.environ.get("KANESENS")
    if not exe:
        pytest.skip("KANESENS is not set (path of the kanesens executable)")
    d = tmp_path_factory.mktemp("outputs")
    (d / "known.yaml").write_text(STUDY)
    p = subprocess.run([exe, "run", str(d / "known.yaml"), "-o", str(d / "known.h5")],
                       capture_output=True, text=True)
    assert p.returncode == 0, p.stderr
    return d / "known.h5"


def linear_indices():
    c, s = math.cos(OMEGA * T), math.sin(OMEGA * T) / OMEGA
    var = 1.0 / 3.0  # U(−1, 1)
    total = c * c * var + s * s * var
    return c * c * var / total, s * s * var / total


def test_sobol_of_a_linear_scalar_output(run_file):
    ds = open_run(run_file)
    r = sobol.analyze(ds, design(ds), "x_end", n_boot=0)
    assert r["time"] is None and r["base_points"] == 1024
    s_x0, s_v0 = linear_indices()
    assert r["S1"][:2] == pytest.approx([s_x0, s_v0], abs=0.02), r["S1"]
    assert r["ST"][:2] == pytest.approx([s_x0, s_v0], abs=0.02), r["ST"]
    # x_end does not read x1, x2, x3: their runs give bitwise the same value.
    assert np.all(r["S1"][2:] == 0) and np.all(r["ST"][2:] == 0)


def test_sobol_of_the_ishigami_output(run_file):
    ds = open_run(run_file)
    r = sobol.analyze(ds, design(ds), "ishigami", n_boot=0)
    assert r["S1"] == pytest.approx([0, 0, 0.3139, 0.4424, 0.0], abs=0.03), r["S1"]
    assert r["ST"] == pytest.approx([0, 0, 0.5576, 0.4424, 0.2437], abs=0.03), r["ST"]


def test_dgsm_uses_the_exact_output_sensitivities(run_file):
    ds = open_run(run_file)
    x = dict(zip([str(p) for p in ds["parameter"].values], np.asarray(ds["parameters"].values).T))
    r = dgsm.analyze(ds, design(ds), "x_end")
    c, s = math.cos(OMEGA * T), math.sin(OMEGA * T) / OMEGA
    assert r["inputs"] == ["x0", "v0", "x1", "x3"] and r["inputs_without_sensitivity"] == ["x2"]
    assert r["nu"] == pytest.approx([c * c, s * s, 0, 0], rel=1e-8, abs=1e-15)
    r = dgsm.analyze(ds, design(ds), "ishigami")
    d1 = np.cos(x["x1"]) * (1 + 0.1 * x["x3"] ** 4)
    d3 = 0.4 * x["x3"] ** 3 * np.sin(x["x1"])
    assert r["nu"] == pytest.approx([0, 0, np.mean(d1 ** 2), np.mean(d3 ** 2)], rel=1e-12, abs=1e-15)


def test_linear_uq_of_a_linear_output_holds(run_file):
    ds = open_run(run_file)
    r = linear_uq.analyze(ds, design(ds), "x_end")
    assert r["time"] is None and r["holds"]
    assert r["variance_ratio"] == pytest.approx(1.0, abs=1e-3)


def test_summary_and_plot_of_a_scalar_output(run_file, tmp_path, capsys):
    ds = open_run(run_file)
    r = summary.output_statistics(ds, "ishigami")
    assert r["time"] is None and r["samples"] == 1024 * 7
    assert r["mean"][0] == pytest.approx(3.5, abs=0.15)  # E = a/2 = 3.5
    assert main(["summary", str(run_file), "--output", "ishigami", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["output"] == "ishigami"
    assert main(["plot", str(run_file), "--output", "ishigami", "--out", str(tmp_path / "h.png")]) == 0
    assert (tmp_path / "h.png").stat().st_size > 0
    assert main(["sobol", str(run_file), "--output", "ishigami", "--at", "0.1"]) == 2
    assert "one number per sample" in capsys.readouterr().err


def test_poses(run_file):
    ds = open_run(run_file)
    poses = ds["poses"]
    assert poses.dims == ("sample", "time", "body", "pose")
    assert list(ds["pose"].values) == ["x", "y", "z", "qw", "qx", "qy", "qz"]
    x = poses.sel(body="block", pose="x").values
    assert np.array_equal(x, ds["states"].sel(state="slider.q").values)
    assert np.all(poses.sel(body="block", pose="qw").values == 1)


def test_a_series_output_at_the_end_is_the_scalar_output(run_file):
    ds = open_run(run_file)
    assert sorted(output_names(ds)) == ["ishigami", "x_end", "xs.x", "xs.y", "xs.z"]
    assert list(ds["output"].values) == ["xs.x", "xs.y", "xs.z", "x_end", "ishigami"]
    assert ds["output_xs.x"].dims == ("sample", "time")
    assert ds["output_sensitivity_xs.x"].dims == ("sample", "time", "sensitivity")
    assert ds["output_sensitivity_x_end"].dims == ("sample", "sensitivity")
    assert np.array_equal(ds["output_xs.x"].values, ds["states"].sel(state="slider.q").values)
    assert np.allclose(ds["output_sensitivity_xs.x"].isel(time=-1).values,
                       ds["output_sensitivity_x_end"].values, rtol=1e-9, atol=1e-14)
    series = dgsm.analyze(ds, design(ds), "xs.x", at=T)
    scalar = dgsm.analyze(ds, design(ds), "x_end")
    assert series["time"] == pytest.approx(T) and series["nu"] == pytest.approx(scalar["nu"], rel=1e-9)
    r = sobol.analyze(ds, design(ds), "xs.x", over_time=True, n_boot=0)
    assert r["ST"].shape == (5, 3) and r["ST"][:2, -1] == pytest.approx(linear_indices(), abs=0.02)


@pytest.mark.parametrize("args, message", [
    (["sobol", "--output", "xs", "--at", "0.4"], "name one of its components: xs.x, xs.y, xs.z"),
    (["dgsm", "--output", "x_ned"], "no state or output named 'x_ned' (did you mean 'x_end'?)"),
    (["morris", "--output", "xs.x"], "'xs.x' is a series over time: give --at T"),
    (["linear-uq", "--output", "x_end", "--over-time"], "one number per sample"),
    (["dgsm", "--output", "slider.q", "--at", "0.4"], "no /sensitivities"),
])
def test_command_line_errors_name_the_outputs(run_file, capsys, args, message):
    assert main([args[0], str(run_file), *args[1:]]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and message in err, err


def test_command_line_on_outputs(run_file):
    """As a user runs it: text for a scalar output (no --at), JSON for a series at one time."""
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(
        filter(None, [str(PACKAGE_DIR), os.environ.get("PYTHONPATH")])))
    run = lambda *a: subprocess.run([sys.executable, "-m", "kanesens_post", *map(str, a)],
                                    capture_output=True, text=True, env=env)
    p = run("sobol", run_file, "--output", "ishigami", "--bootstrap", "0")
    assert p.returncode == 0, p.stderr
    assert p.stdout.startswith("Sobol' indices of ishigami: 1024 base points") and " at t = " not in p.stdout
    p = run("dgsm", run_file, "--output", "xs.x", "--at", T, "--json")
    assert p.returncode == 0, p.stderr
    r = json.loads(p.stdout)
    assert r["time"] == pytest.approx(T) and r["inputs_without_sensitivity"] == ["x2"]
