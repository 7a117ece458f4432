"""`kanesens linearize`: its JSON (coordinates, speeds, A, B, eigenvalues, eigenvectors) for the
Whipple bicycle against the benchmark of Meijaard et al. (2007) in tests/data/whipple_benchmark.txt
(eigenvalues from numpy's own eigensolver on the published M, C1, K0, K2), and its bad-input
contract: exit 2, one line on stderr, nothing on stdout."""
import json
import os
import subprocess
from pathlib import Path

import numpy as np
import pytest

SOURCE = Path(os.environ.get("KANESENS_SOURCE_DIR", Path(__file__).resolve().parents[2]))
BICYCLE = str(SOURCE / "configs" / "whipple_bicycle.yaml")


def kanesens(*args):
    exe = os.environ.get("KANESENS")
    if not exe:
        pytest.skip("KANESENS is not set (path of the kanesens executable)")
    return subprocess.run([exe, *args], capture_output=True, text=True)


def benchmark():
    data = {}
    for line in (SOURCE / "tests" / "data" / "whipple_benchmark.txt").read_text().splitlines():
        if line.startswith("#") or not line.strip():
            continue
        key, *vals = line.split()
        if key in ("M", "C1", "K0", "K2"):
            data[key] = np.array([float(x) for x in vals]).reshape(2, 2)
        elif key == "eig":
            data.setdefault("eig", {})[int(vals[0])] = [float(x) for x in vals[1:]]
    return data


@pytest.mark.parametrize("v", [2.0, 5.0, 8.0])
def test_bicycle_json_matches_published_matrices(v):
    p = kanesens("linearize", BICYCLE, "--set", f"v={v}", "--inputs", "Tphi,Tdelta", "--json")
    assert p.returncode == 0, p.stderr
    assert p.stderr == ""  # upright straight running is steady: no warning
    out = json.loads(p.stdout)
    assert out["coordinates"] == ["base.rx", "steer.q"]
    assert out["speeds"] == ["base.wx", "steer.u"]
    assert out["inputs"] == ["Tphi", "Tdelta"]
    assert set(out["dropped"]) == {"base.x", "base.y", "base.rz", "rear_hub.q", "front_hub.q", "rear_hub.u"}
    b = benchmark()
    Minv = np.linalg.inv(b["M"])
    A_ref = np.block([[np.zeros((2, 2)), np.eye(2)],
                      [-Minv @ (9.81 * b["K0"] + v**2 * b["K2"]), -v * Minv @ b["C1"]]])
    A, B = np.array(out["A"]), np.array(out["B"])
    assert np.max(np.abs(A - A_ref)) <= 1e-12 * np.max(np.abs(A_ref))
    assert np.max(np.abs(B - np.vstack([np.zeros((2, 2)), Minv]))) <= 1e-12 * np.max(np.abs(Minv))
    lam = np.array([complex(re, im) for re, im in out["eigenvalues"]])
    ref = np.linalg.eigvals(A_ref)
    for z in ref:
        assert np.min(np.abs(lam - z)) <= 1e-10 * np.max(np.abs(ref))
    # Sorted by decreasing real part, a conjugate pair with +Im first.
    assert all(lam[i].real >= lam[i + 1].real for i in range(len(lam) - 1))
    # Eigenvectors: A v = λ v, unit norm, in the order of the eigenvalues.
    for k, vec in enumerate(out["eigenvectors"]):
        x = np.array([complex(re, im) for re, im in vec])
        assert abs(np.linalg.norm(x) - 1) < 1e-13
        assert np.linalg.norm(A @ x - lam[k] * x) <= 1e-10 * max(1.0, abs(lam[k]))


def test_bicycle_table2_at_integer_speeds():
    b = benchmark()
    for v in (1, 4, 6, 9):
        out = json.loads(kanesens("linearize", BICYCLE, "--set", f"v={v}", "--json").stdout)
        lam = [complex(re, im) for re, im in out["eigenvalues"]]
        weave = [z for z in lam if z.imag > 1e-9][0]
        reals = sorted(z.real for z in lam if abs(z.imag) <= 1e-9)
        w_re, w_im, capsize, castering = b["eig"][v]
        got = [weave.real, weave.imag, reals[1], reals[0]]
        assert np.max(np.abs(np.array(got) - [w_re, w_im, capsize, castering])) <= 1e-12, (v, got)


def test_wheels_off_the_ground_are_brought_onto_it():
    # The rear frame given 0.2 m too high: the contacts' heights are corrected first (the rear
    # frame's height), and the linearization is the one about the consistent state.
    ref = json.loads(kanesens("linearize", BICYCLE, "--json").stdout)
    p = kanesens("linearize", BICYCLE, "--q=0,0,0.5,1,0,0,0,0,0,0", "--json")
    assert p.returncode == 0, p.stderr
    out = json.loads(p.stdout)
    assert abs(out["initial_correction"]["position"] - 0.2) < 1e-12
    assert out["constraint_residuals"]["position"] < 1e-12
    assert abs(out["q"][2] - 0.3) < 1e-12  # wheel centre at the radius rR
    assert np.max(np.abs(np.array(out["A"]) - np.array(ref["A"]))) <= 1e-12 * np.max(np.abs(ref["A"]))


def test_not_steady_state_warns():
    p = kanesens("linearize", str(SOURCE / "configs" / "double_pendulum.yaml"), "--json")
    assert p.returncode == 0, p.stderr
    assert "not steady" in p.stderr
    assert len(json.loads(p.stdout)["A"]) == 4


@pytest.mark.parametrize("args, key", [
    (["--inputs", "Tdelt"], "--inputs: unknown parameter 'Tdelt' (did you mean 'Tdelta'?)"),
    (["--inputs", "lam"], None),  # a parameter given by an expression is still a parameter
    (["--coordinates", "steer.q"], "--coordinates: 'base.rx' is independent and not ignorable"),
    (["--speeds", "base.wq"], "--speeds: unknown name 'base.wq'"),
    (["--q=0,0,50,1,0,0,0,0,0,0"], "cannot satisfy the position constraints"),
    (["--q=1,2"], "--q: expected 10 values"),
    (["--set", "mB=-1"], "mass"),
])
def test_bad_input_exits_2_with_one_line(args, key):
    p = kanesens("linearize", BICYCLE, *args)
    if key is None:
        assert p.returncode == 0, p.stderr
        return
    assert p.returncode == 2, (p.returncode, p.stderr)
    assert p.stdout == ""
    lines = p.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("kanesens: error: ") and key in lines[0], p.stderr
