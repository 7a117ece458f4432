"""`kanesens-post draw` and `animate` draw what is there: the positions read back from the drawn
artists (and the animation's frames) equal closed forms of the scenes' geometry, written here
independently of kanesens — the double pendulum's joints and tip at a given state, the four-bar's
pivots and closed loop, the rolling disc's contact on its plane — and the recorded poses.

Environment: KANESENS (kanesens executable), KANESENS_SOURCE_DIR (repository root).
"""
import os
import subprocess
import sys
from pathlib import Path

import h5py
import numpy as np
import pytest
import yaml

ROOT = Path(os.environ.get("KANESENS_SOURCE_DIR") or Path(__file__).resolve().parents[2])
PACKAGE_DIR = ROOT / "python"
sys.path.insert(0, str(PACKAGE_DIR))

from kanesens_post import draw, geometry  # noqa: E402


@pytest.fixture(scope="module")
def exe():
    path = os.environ.get("KANESENS")
    if not path:
        pytest.skip("KANESENS is not set (path of the kanesens executable); ctest sets it")
    return path


def post(*args):
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(filter(None, [str(PACKAGE_DIR),
                                                                    os.environ.get("PYTHONPATH")])))
    return subprocess.run([sys.executable, "-m", "kanesens_post", *map(str, args)],
                          capture_output=True, text=True, env=env)


def drawn(fig, gid):
    """The points of every artist with this gid, as an (n, 2) or (n, 3) array."""
    pts = []
    for ax in fig.axes:
        for line in ax.get_lines():
            if line.get_gid() == gid:
                data = line.get_data_3d() if hasattr(line, "get_data_3d") else line.get_data()
                pts.append(np.column_stack([np.asarray(d, float) for d in data]))
    assert pts, f"nothing drawn with gid {gid}"
    return np.vstack(pts)


def test_double_pendulum_at_a_given_state(exe, tmp_path):
    a, b = 0.7, -1.1
    geo = geometry.scene_geometry(ROOT / "configs/double_pendulum_uq.yaml",
                                  q=[f"shoulder={a}", f"elbow={b}"], sets=["L1=1.3"], kanesens=exe)
    fig = draw.draw(geo)
    assert draw.planar_view(geo) == 2 and fig.axes[0].name == "rectilinear"
    L1, L2 = 1.3, 1.0
    down = lambda th: np.array([np.sin(th), -np.cos(th)])  # noqa: E731 - hanging along -y at 0
    elbow, tip = L1 * down(a), L1 * down(a) + L2 * down(a + b)
    np.testing.assert_allclose(drawn(fig, "joint:shoulder")[-1], [0, 0], atol=1e-12)
    np.testing.assert_allclose(drawn(fig, "joint:elbow")[-1], elbow, atol=1e-12)
    np.testing.assert_allclose(drawn(fig, "point:tip")[0], tip, atol=1e-12)
    centers = drawn(fig, "body:rod2")
    assert np.min(np.linalg.norm(centers - (elbow + 0.5 * L2 * down(a + b)), axis=1)) < 1e-12
    # rod1 is a rod shape: its stick runs from end to end, L1 long
    rod1 = drawn(fig, "body:rod1")
    assert np.max(np.linalg.norm(rod1[:, None] - rod1[None], axis=2)) == pytest.approx(L1, abs=1e-12)
    png = tmp_path / "dp.png"
    r = post("draw", ROOT / "configs/double_pendulum.yaml", "--q", f"shoulder={a}", "--q",
             f"elbow={b}", "-o", png, "--kanesens", exe)
    assert r.returncode == 0, r.stderr
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and png.stat().st_size > 10000


def test_four_bar_pivots_and_closed_loop(exe):
    geo = geometry.scene_geometry(ROOT / "configs/four_bar.yaml", kanesens=exe)
    fig = draw.draw(geo)
    r, a = 0.2, 0.6  # crank upright at q0 (th1 = pi/2), rocker pivot at (a, 0)
    np.testing.assert_allclose(drawn(fig, "joint:crank")[-1], [0, 0], atol=1e-12)
    np.testing.assert_allclose(drawn(fig, "joint:coupler")[-1], [0, r], atol=1e-12)
    np.testing.assert_allclose(drawn(fig, "joint:rocker")[-1], [a, 0], atol=1e-12)
    loop = drawn(fig, "constraint:loop")
    assert np.linalg.norm(loop[0] - loop[1]) < 1e-9  # the loop closed at the initial state
    c, b = 0.7, 0.5
    assert np.linalg.norm(loop[0] - [0, r]) == pytest.approx(c, abs=1e-9)
    assert np.linalg.norm(loop[0] - [a, 0]) == pytest.approx(b, abs=1e-9)


def test_rolling_disc_is_3d_with_its_contact_on_the_plane(exe):
    geo = geometry.scene_geometry(ROOT / "configs/rolling_disc.yaml", kanesens=exe)
    fig = draw.draw(geo)
    assert draw.planar_view(geo) is None and fig.axes[0].name == "3d"
    rim = drawn(fig, "constraint:contact")
    center = geo["bodies"]["disc"]["position"]
    r = 1.0  # the scene's radius; the rim circle, then the center and the contact point
    contact = rim[-1]
    assert contact[2] == pytest.approx(0.0, abs=1e-9)  # the contact point on the plane z = 0
    assert np.linalg.norm(contact - center) == pytest.approx(r, abs=1e-12)
    np.testing.assert_allclose(np.linalg.norm(rim[:-2] - center, axis=1), r, rtol=1e-12)
    assert drawn(fig, "body:disc")[-1] == pytest.approx(center, abs=1e-12)


def test_animate_draws_the_recorded_poses(exe, tmp_path):
    study = {"kanesens": 1, "scene": str(ROOT / "configs/double_pendulum.yaml"),
             "time": {"end": 1.0, "outputs": 11},
             "sampling": {"method": "mc", "samples": 2, "seed": 1},
             "vary": {"L1": {"dist": "uniform", "low": 0.8, "high": 1.2}},
             "record": ["states", "poses"],
             "outputs": {"tip": {"type": "position", "body": "rod2", "point": [0, "-L2/2", 0]}}}
    path = tmp_path / "study.yaml"
    path.write_text(yaml.safe_dump(study))
    h5 = tmp_path / "run.h5"
    subprocess.run([exe, "run", str(path), "-o", str(h5)], check=True, capture_output=True)
    with h5py.File(h5) as f:
        bodies = [x.decode() if isinstance(x, bytes) else x for x in f["body"][()]]
        poses, states = f["poses"][1], f["states"][1]
        L1 = float(f["parameters"][1, 0])
        times = f["time"][()]
    geo = geometry.scene_geometry(ROOT / "configs/double_pendulum.yaml", sets=[f"L1={L1!r}"],
                                  kanesens=exe, study_outputs=study["outputs"])
    gif = tmp_path / "run.gif"
    frames, pictures = draw.animate(geo, times, poses, bodies, gif, max_frames=6)
    assert len(frames) == 6
    down = lambda th: np.array([np.sin(th), -np.cos(th), 0])  # noqa: E731
    for n, k in enumerate(frames):
        a, b = states[k, 0], states[k, 1]
        elbow = next(j for j in pictures[n]["joints"] if j["name"] == "elbow")
        np.testing.assert_allclose(elbow["child_point"], L1 * down(a), atol=1e-9)
        np.testing.assert_allclose(elbow["parent_point"], L1 * down(a), atol=1e-9)
        tip = pictures[n]["points"][0]["at"]
        np.testing.assert_allclose(tip, L1 * down(a) + 1.0 * down(a + b), atol=1e-9)
        for i, body in enumerate(bodies):
            np.testing.assert_allclose(pictures[n]["bodies"][body]["position"], poses[k, i, :3])
    from PIL import Image
    with Image.open(gif) as im:
        assert im.n_frames == 6
    r = post("animate", h5, "--sample", 1, "-o", tmp_path / "cli.gif", "--frames", 4,
             "--kanesens", exe)
    assert r.returncode == 0, r.stderr
    with Image.open(tmp_path / "cli.gif") as im:
        assert im.n_frames == 4


def test_bad_input_is_one_line_and_exit_2(exe, tmp_path):
    study = {"kanesens": 1, "scene": str(ROOT / "configs/simple_pendulum.yaml"),
             "time": {"end": 0.1, "outputs": 3}, "record": ["states"]}
    (tmp_path / "s.yaml").write_text(yaml.safe_dump(study))
    h5 = tmp_path / "noposes.h5"
    subprocess.run([exe, "run", str(tmp_path / "s.yaml"), "-o", str(h5)], check=True,
                   capture_output=True)
    cases = [("animate", h5, "--sample", 0, "--kanesens", exe),
             ("draw", tmp_path / "missing.yaml", "--kanesens", exe),
             ("draw", ROOT / "configs/double_pendulum.yaml", "--q", "shoulder", "--kanesens", exe),
             ("draw", ROOT / "configs/double_pendulum.yaml", "--set", "nope=1", "--kanesens", exe)]
    for args in cases:
        r = post(*args)
        assert r.returncode == 2, (args, r.stderr)
        assert len(r.stderr.strip().splitlines()) == 1 and not r.stdout, (args, r.stderr)
