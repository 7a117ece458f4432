"""Closed-loop example scenes (configs/four_bar.yaml, parallelogram_four_bar.yaml,
slider_crank.yaml) through `kanesens check`, `simulate` and `eom`.

Checks that can fail, each against something independent of the engine:
* loop closure: |g| and |A u| stay small (projection), the initial state needs no correction
  (the scenes give the closed-form assembly);
* T + V conserved (no damping, no drive);
* kinematics: the crank-rocker's crank turns fully and its rocker swings exactly between the
  Grashof limit angles (crank and coupler collinear, |OQ| = c ± r); the slider stays in
  [l − r, l + r]; the parallelogram's coupler does not rotate (rocker angle = crank angle);
* multipliers: Newton–Euler for one body written here (rocker about its pivot; slider along x),
  with λ = force on body_a (coupler / rod end) from body_b (rocker / slider), world x, y;
* sensitivities to a link length and a mass against central finite differences.

Environment: KANESENS (kanesens executable), KANESENS_SOURCE_DIR (repository root).
"""

import json
import math
import os
import subprocess
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(os.environ.get("KANESENS_SOURCE_DIR") or Path(__file__).resolve().parents[2])
CONFIGS = ROOT / "configs"
G = 9.81


def _exe() -> str:
    exe = os.environ.get("KANESENS")
    if not exe:
        pytest.skip("KANESENS is not set (path of the kanesens executable)")
    return exe


def simulate(study: str, *sets: str, sens: str = None) -> dict:
    cmd = [_exe(), "simulate", str(CONFIGS / study)]
    for s in sets:
        cmd += ["--set", s]
    if sens is not None:
        cmd += ["--sens", sens]
    p = subprocess.run(cmd, capture_output=True, text=True, timeout=60)
    assert p.returncode == 0, p.stderr
    d = json.loads(p.stdout)
    assert d["status"] == 1, d["message"]
    return d


def eom(scene: str, q, u) -> dict:
    cmd = [_exe(), "eom", str(CONFIGS / scene), "--q=" + ",".join(repr(float(x)) for x in q),
           "--u=" + ",".join(repr(float(x)) for x in u)]
    p = subprocess.run(cmd, capture_output=True, text=True, timeout=60)
    assert p.returncode == 0, p.stderr
    return json.loads(p.stdout)


def common_checks(d: dict, energy_rel: float, g_max: float, v_max: float) -> None:
    assert d["initial_correction"]["position"] < 1e-14
    assert d["initial_correction"]["velocity"] < 1e-13
    assert max(d["constraint_residuals"]["position"]) < g_max
    assert max(d["constraint_residuals"]["velocity"]) < v_max
    e = np.array(d["outputs"]["energy"])
    assert np.max(np.abs(e - e[0])) < energy_rel * abs(e[0])


@pytest.mark.parametrize("scene,rows", [("four_bar.yaml", "loop.x, loop.y"),
                                         ("parallelogram_four_bar.yaml", "loop.x, loop.y"),
                                         ("slider_crank.yaml", "pin.x, pin.y"),
                                         ("andrews.yaml", "g1, g2, g3, g4, g5, g6")])
def test_check_lists_constraint_rows(scene, rows):
    p = subprocess.run([_exe(), "check", str(CONFIGS / scene)], capture_output=True, text=True)
    assert p.returncode == 0, p.stderr
    assert "constraint rows: " + rows in p.stdout


def test_four_bar_crank_rocker():
    d = simulate("four_bar_study.yaml")
    common_checks(d, energy_rel=1e-6, g_max=1e-9, v_max=1e-7)
    y = np.array(d["states"])
    crank, rocker, crank_u = y[:, 0], y[:, 2], y[:, 3]
    assert np.all(crank_u > 0)                      # never stops: the crank turns fully ...
    assert crank[-1] - crank[0] > 4 * 2 * math.pi  # ... more than 4 times in 3 s
    # Grashof limits of the rocker: crank and coupler collinear, |OQ| = c ± r.
    r, c, b, a = 0.2, 0.7, 0.5, 0.6
    lim = [math.pi - math.acos((a * a + b * b - dd * dd) / (2 * a * b)) for dd in (c + r, c - r)]
    assert rocker.min() > lim[0] - 1e-9 and rocker.max() < lim[1] + 1e-9
    assert rocker.min() < lim[0] + 1e-3 and rocker.max() > lim[1] - 1e-3


def test_four_bar_inconsistent_speeds_keep_the_crank_speed():
    """Only the crank speed given (coupler, rocker speeds 0): the correction must keep the crank's
    6 rad/s (the first, driving speed) and solve for the other two, as for coordinates — and the
    sensitivity of the initial speeds to crank.u0 is (1, (w2 − w1)/w1, w3/w1)."""
    d = simulate("four_bar_study.yaml", "coupler.u0=0", "rocker.u0=0", "time.end=0.01", "time.outputs=2",
                 sens="crank.u0")
    r, c, b, a, th1, w1 = 0.2, 0.7, 0.5, 0.6, math.pi / 2, 6.0
    lpb = math.hypot(a - r * math.cos(th1), r * math.sin(th1))
    phi = math.atan2(-r * math.sin(th1), a - r * math.cos(th1)) + math.acos((c * c + lpb * lpb - b * b) / (2 * c * lpb))
    th3 = math.atan2(r * math.sin(th1) + c * math.sin(phi), r * math.cos(th1) + c * math.cos(phi) - a)
    w2 = -r * w1 * math.sin(th1 - th3) / (c * math.sin(phi - th3))
    w3 = r * w1 * math.sin(th1 - phi) / (b * math.sin(th3 - phi))
    u0 = d["states"][0][3:]
    assert u0[0] == w1
    assert u0[1] == pytest.approx(w2 - w1, rel=1e-12)
    assert u0[2] == pytest.approx(w3, rel=1e-12)
    assert d["initial_correction"]["velocity"] == pytest.approx(max(abs(w2 - w1), abs(w3)), rel=1e-12)
    s0 = [row[0] for row in d["sensitivities"][0]][3:]
    assert s0 == pytest.approx([1.0, (w2 - w1) / w1, w3 / w1], rel=1e-12)


def test_four_bar_multipliers_newton_euler_on_rocker():
    d = simulate("four_bar_study.yaml", "time.end=1", "time.outputs=11")
    m3, b, a = 1.5, 0.5, 0.6
    for k in (0, 5, 10):
        y = d["states"][k]
        e = eom("four_bar.yaml", y[:3], y[3:])
        lam = np.array(e["multipliers"])
        assert np.allclose(lam, d["multipliers"][k], rtol=1e-9, atol=1e-9)
        th3, alpha3 = y[2], e["udot"][2]
        # rocker about B: (m3 b²/3) α = −m3 g (b/2) cos θ3 + (Q − B) × F, F = −λ on the rocker
        torque = -m3 * G * b / 2 * math.cos(th3) + b * (math.cos(th3) * -lam[1] - math.sin(th3) * -lam[0])
        assert m3 * b * b / 3 * alpha3 == pytest.approx(torque, rel=1e-10, abs=1e-10)


def test_four_bar_sensitivities_vs_finite_differences():
    tight = ("solver.rtol=1e-12", "solver.atol=1e-14", "time.end=1", "time.outputs=11")
    d = simulate("four_bar_study.yaml", *tight)
    s = np.array(d["sensitivities"])[-1]  # states × (c, m2)
    ls = np.array(d["multiplier_sensitivities"])[-1]
    for j, (name, nominal, h) in enumerate((("c", 0.7, 1e-5), ("m2", 2.0, 1e-3))):
        hi = simulate("four_bar_study.yaml", *tight, f"{name}={nominal + h!r}")
        lo = simulate("four_bar_study.yaml", *tight, f"{name}={nominal - h!r}")
        fd = (np.array(hi["states"][-1]) - np.array(lo["states"][-1])) / (2 * h)
        fdl = (np.array(hi["multipliers"][-1]) - np.array(lo["multipliers"][-1])) / (2 * h)
        scale = np.max(np.abs(fd))
        assert np.max(np.abs(s[:, j] - fd)) < 2e-5 * scale, (name, s[:, j], fd)
        assert np.max(np.abs(ls[:, j] - fdl)) < 2e-5 * np.max(np.abs(fdl)), (name, ls[:, j], fdl)


def test_parallelogram_coupler_translates():
    d = simulate("parallelogram_four_bar_study.yaml")
    common_checks(d, energy_rel=1e-6, g_max=1e-9, v_max=1e-7)
    y = np.array(d["states"])
    assert np.max(np.abs(y[:, 0] + y[:, 1])) < 1e-8  # coupler absolute angle stays 0
    assert np.max(np.abs(y[:, 0] - y[:, 2])) < 1e-8  # rocker angle = crank angle
    assert -math.pi < y[:, 0].min() and y[:, 0].max() < 0  # stays away from the collinear positions


def test_slider_crank():
    d = simulate("slider_crank_study.yaml")
    common_checks(d, energy_rel=1e-6, g_max=1e-9, v_max=1e-7)
    y = np.array(d["states"])
    r, l, ms = 0.1, 0.35, 1.2
    assert np.all(y[:, 3] > 0) and y[-1, 0] - y[0, 0] > 2 * 2 * math.pi
    assert y[:, 2].min() > l - r - 1e-9 and y[:, 2].max() < l + r + 1e-9
    # slider along x: ms ẍ = force from the rod = −λ_x
    for k in (0, 50, 100, 200):
        e = eom("slider_crank.yaml", y[k, :3], y[k, 3:])
        assert ms * e["udot"][2] == pytest.approx(-e["multipliers"][0], rel=1e-10, abs=1e-10)
