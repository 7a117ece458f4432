"""Checks of the independent SymPy reference (tests/sympy/kane_reference.py) itself.

The fixtures that the C++ engine is compared with are only worth something if the reference
is right, so it is checked here against things neither implementation shares:
closed forms (compound pendulum, Euler's equations of a free body and of a top about its fixed
point, the cart + double pendulum mass matrix and static forces from hand-written
kinematics), the documented joint conventions (quaternion, universal, planar directions), and
the energy balance dE/dt = 0 along u' = M^-1 f for conservative versions of every example
scene (dE/dt = -c u^2 for a single damper).

Run: /usr/bin/python3 -m pytest -q tests/python/test_sympy_reference_selfcheck.py
"""

import math
import sys
from pathlib import Path

import numpy as np
import pytest

sympy = pytest.importorskip("sympy", reason="needs SymPy (use Debian's /usr/bin/python3)")
pytest.importorskip("yaml", reason="needs PyYAML (use Debian's /usr/bin/python3)")

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "tests" / "sympy"))
sys.path.insert(0, str(ROOT / "scripts"))
import kane_reference as kr  # noqa: E402
from gen_chain import chain_yaml  # noqa: E402

G = 9.81


def numeric(path, overrides=None):
    return kr.NumericModel(kr.build_model(ROOT / path if not Path(path).is_absolute() else path,
                                          overrides))


def rot_np(axis, angle):
    a = np.asarray(axis, float) / np.linalg.norm(axis)
    K = np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])
    return np.eye(3) + math.sin(angle) * K + (1 - math.cos(angle)) * K @ K


def quat_np(q):
    w, x, y, z = q
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                     [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                     [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])


def dcm_child_to_world(model, body_name, q):
    """R (child components -> world components) of a body at coordinates q, from SymPy."""
    body = next(b for b in model.bodies if str(b) == body_name)
    R = body.frame.dcm(model.N).T          # SymPy's B.dcm(N) maps N components to B components
    return np.array(R.subs(dict(zip(model.q, q))).evalf(), dtype=float)


# ----------------------------------------------------------------------------------------------
# Closed forms
# ----------------------------------------------------------------------------------------------

def test_simple_pendulum_closed_form():
    num = numeric("configs/simple_pendulum.yaml")
    m, L = 1.0, 1.0
    for q, u in [(0.3, 0.7), (-2.5, 1.9), (math.pi / 2, 0.0)]:
        out = num.evaluate(1.0, [q], [u])
        assert out["mass_matrix"][0, 0] == pytest.approx(m * L**2 / 3, rel=1e-14)
        assert out["forcing"][0] == pytest.approx(-m * G * L / 2 * math.sin(q), rel=1e-13, abs=1e-14)
        assert out["kinetic_energy"] == pytest.approx(0.5 * m * L**2 / 3 * u**2, rel=1e-14)
        assert out["potential_energy"] == pytest.approx(-m * G * L / 2 * math.cos(q), rel=1e-13)


def test_free_body_euler_equations():
    num = numeric("configs/free_body.yaml")
    I = np.diag([1.0, 2.0, 3.0])
    rng = np.random.default_rng(1)
    for _ in range(3):
        quat = rng.normal(size=4)
        quat /= np.linalg.norm(quat)
        q = list(rng.uniform(-1, 1, 3)) + list(quat)
        u = rng.uniform(-2, 2, 6)
        out = num.evaluate(0.0, q, u)
        w = u[3:]
        np.testing.assert_allclose(out["mass_matrix"], np.diag([1, 1, 1, 1, 2, 3]), atol=1e-14)
        # Euler: I w' = -w x I w, i.e. ((I2-I3) w2 w3, (I3-I1) w3 w1, (I1-I2) w1 w2)
        np.testing.assert_allclose(out["forcing"][:3], 0, atol=1e-14)
        np.testing.assert_allclose(out["forcing"][3:], -np.cross(w, I @ w), rtol=1e-13, atol=1e-14)
        assert out["kinetic_energy"] == pytest.approx(0.5 * u[:3] @ u[:3] + 0.5 * w @ I @ w)
        assert out["potential_energy"] == 0


def test_free_body_reference_values():
    """I = diag(1, 2, 3): 2E = 4 and |H|^2 = 10 at omega = (1, 0, 1)."""
    num = numeric("configs/free_body.yaml")
    out = num.evaluate(0.0, [0, 0, 0, 1, 0, 0, 0], [0, 0, 0, 1, 0, 1])
    assert 2 * out["kinetic_energy"] == pytest.approx(4.0, rel=1e-15)
    H = out["mass_matrix"][3:, 3:] @ np.array([1.0, 0, 1])
    assert H @ H == pytest.approx(10.0, rel=1e-15)


def test_spinning_top_euler_about_fixed_point():
    """I_O w' + w x I_O w = r x (m R^T g), with r = (0, 0, l) pivot -> mass center (body)."""
    num = numeric("configs/spinning_top.yaml")
    m, r, h, l = 0.5, 0.04, 0.01, 0.05
    It, Ia = m * (3 * r**2 + h**2) / 12, m * r**2 / 2
    I_O = np.diag([It + m * l**2, It + m * l**2, Ia])
    rvec = np.array([0, 0, l])
    rng = np.random.default_rng(2)
    for _ in range(4):
        quat = rng.normal(size=4)
        quat /= np.linalg.norm(quat)
        w = rng.uniform(-2, 2, 3)
        out = num.evaluate(0.0, list(quat), list(w))
        R = quat_np(quat)
        g_body = R.T @ np.array([0, 0, -G])
        np.testing.assert_allclose(out["mass_matrix"], I_O, rtol=1e-14, atol=1e-16)
        expected = -np.cross(w, I_O @ w) + np.cross(rvec, m * g_body)
        np.testing.assert_allclose(out["forcing"], expected, rtol=1e-12, atol=1e-14)
        z_cm = (R @ rvec)[2]
        assert out["potential_energy"] == pytest.approx(m * G * z_cm, rel=1e-13, abs=1e-15)


def test_cart_double_pendulum_mass_matrix_and_static_forces():
    """Hand-written kinematics: x cart, a = q1 (absolute), b = q1 + q2 (absolute)."""
    num = numeric("configs/cart_double_pendulum.yaml")
    mc, m1, L1, m2, L2 = 2.0, 0.5, 0.8, 0.4, 0.6
    F0, w, k_wall = 1.5, 2.0, 4.0
    # (the cart does not rotate, so its box inertia never enters)
    I1, I2 = m1 * L1**2 / 12, m2 * L2**2 / 12
    rng = np.random.default_rng(3)
    for _ in range(4):
        x, q1, q2 = rng.uniform(-3, 3, 3)
        t = rng.uniform(0, 10)
        a, b = q1, q1 + q2
        # Jacobians of the mass-center velocities (x, y) and angular rates w.r.t. (x', q1', q2')
        J1 = np.array([[1, L1 / 2 * math.cos(a), 0], [0, L1 / 2 * math.sin(a), 0]])
        J2 = np.array([[1, L1 * math.cos(a) + L2 / 2 * math.cos(b), L2 / 2 * math.cos(b)],
                       [0, L1 * math.sin(a) + L2 / 2 * math.sin(b), L2 / 2 * math.sin(b)]])
        Jc = np.array([[1, 0, 0], [0, 0, 0]])
        W1, W2 = np.array([0, 1, 0]), np.array([0, 1, 1])
        M = (mc * Jc.T @ Jc + m1 * J1.T @ J1 + m2 * J2.T @ J2
             + I1 * np.outer(W1, W1) + I2 * np.outer(W2, W2))
        out = num.evaluate(t, [x, q1, q2], [0, 0, 0])
        np.testing.assert_allclose(out["mass_matrix"], M, rtol=1e-13, atol=1e-15)
        # u = 0: no velocity terms, no damping: forcing = generalized applied forces
        f_grav = -G * (m1 * J1[1] + m2 * J2[1])
        f_push = F0 * math.sin(w * t) * np.array([1, 0, 0])
        f_wall = -k_wall * x * np.array([1, 0, 0])   # spring relaxed at x = 0 (rest = 5 = wall)
        np.testing.assert_allclose(out["forcing"], f_grav + f_push + f_wall, rtol=1e-12, atol=1e-13)
        pe = (-m1 * G * L1 / 2 * math.cos(a) - m2 * G * (L1 * math.cos(a) + L2 / 2 * math.cos(b))
              + 0.5 * k_wall * x**2)
        assert out["potential_energy"] == pytest.approx(pe, rel=1e-13)


# ----------------------------------------------------------------------------------------------
# Joint conventions of docs/reference/scene.md
# ----------------------------------------------------------------------------------------------

def _inline(tmp_path, text, name="s.yaml"):
    p = tmp_path / name
    p.write_text(text)
    return p


ONE_BODY = """kanesens: 1
scene:
  name: conv
  gravity: [0, 0, 0]
  bodies:
    - {{name: b, mass: 1.0, inertia: {{xx: 1, yy: 2, zz: 3}}}}
  joints:
    - {{name: j, type: {type}, parent: ground, child: b, {extra}
       parent_point: [0.1, 0.2, 0.3], child_point: [0.4, -0.5, 0.6]}}
"""


def test_quaternion_convention_matches_sympy_orientation():
    """SymPy's orient_quaternion == the documented child->parent rotation of (w, x, y, z)."""
    rng = np.random.default_rng(4)
    quat = rng.normal(size=4)
    quat /= np.linalg.norm(quat)
    m = kr.build_model(ROOT / "configs/spinning_top.yaml")
    np.testing.assert_allclose(dcm_child_to_world(m, "top", quat), quat_np(quat), atol=1e-14)
    # q' = 1/2 q (x) (0, w): R' = R [w]x (w in child components)
    w = np.array([0.3, -1.1, 0.7])
    num = kr.NumericModel(m)
    qd = num.qdot(quat, w)
    h = 1e-6
    Rdot = (quat_np(quat + h * qd) - quat_np(quat - h * qd)) / (2 * h)
    W = np.array([[0, -w[2], w[1]], [w[2], 0, -w[0]], [-w[1], w[0], 0]])
    np.testing.assert_allclose(Rdot, quat_np(quat) @ W, atol=1e-8)


def test_universal_joint_rotation(tmp_path):
    p = _inline(tmp_path, ONE_BODY.format(type="universal", extra="axes: [[1, 0, 0], [0, 1, 1]],"))
    m = kr.build_model(p)
    q = [0.7, -0.4]
    expected = rot_np([1, 0, 0], q[0]) @ rot_np([0, 1, 1], q[1])
    np.testing.assert_allclose(dcm_child_to_world(m, "b", q), expected, atol=1e-14)


def test_planar_joint_directions(tmp_path):
    """n = [0, 1, 1]: e1 = x, e2 = n x e1 = [0, 1, -1]/sqrt(2); n = x: e1 = y, e2 = z."""
    e1, e2 = kr.planar_directions(kr._unit([0, 1, 1]))
    np.testing.assert_allclose(np.array(e1, float).ravel(), [1, 0, 0], atol=1e-15)
    np.testing.assert_allclose(np.array(e2, float).ravel(), [0, 1 / math.sqrt(2), -1 / math.sqrt(2)],
                               atol=1e-15)
    e1, e2 = kr.planar_directions(kr._unit([1, 0, 0]))
    np.testing.assert_allclose(np.array(e1, float).ravel(), [0, 1, 0], atol=1e-15)
    np.testing.assert_allclose(np.array(e2, float).ravel(), [0, 0, 1], atol=1e-15)


@pytest.mark.parametrize("jtype,extra,q,trans,R", [
    ("revolute", "axis: [0, 0, 2],", [0.5], lambda q: np.zeros(3), lambda q: rot_np([0, 0, 1], q[0])),
    ("prismatic", "axis: [3, 0, 4],", [0.5], lambda q: q[0] * np.array([0.6, 0, 0.8]),
     lambda q: np.eye(3)),
    ("cylindrical", "axis: [1, 0, 1],", [0.5, 0.3],
     lambda q: q[1] * np.array([1, 0, 1]) / math.sqrt(2), lambda q: rot_np([1, 0, 1], q[0])),
    ("planar", "axis: [0, 1, 1],", [0.2, -0.3, 0.9],
     lambda q: q[0] * np.array([1, 0, 0]) + q[1] * np.array([0, 1, -1]) / math.sqrt(2),
     lambda q: rot_np([0, 1, 1], q[2])),
    ("free", "", [0.2, -0.3, 0.4, 0.5, 0.5, -0.5, 0.5],
     lambda q: np.array(q[:3]), lambda q: quat_np(q[3:])),
    ("weld", "", [], lambda q: np.zeros(3), lambda q: np.eye(3)),
])
def test_joint_placement(tmp_path, jtype, extra, q, trans, R):
    """Mass center = parent_point + translation(q) - R(q) child_point (world = parent here)."""
    p = _inline(tmp_path, ONE_BODY.format(type=jtype, extra=extra))
    m = kr.build_model(p)
    Rq = R(q)
    np.testing.assert_allclose(dcm_child_to_world(m, "b", q), Rq, atol=1e-14)
    body = m.bodies[0]
    pos = body.masscenter.pos_from(_world_origin(body.masscenter)).to_matrix(m.N)
    pos = np.array(pos.subs(dict(zip(m.q, q))).evalf(), float).ravel()
    expected = np.array([0.1, 0.2, 0.3]) + trans(q) - Rq @ np.array([0.4, -0.5, 0.6])
    np.testing.assert_allclose(pos, expected, atol=1e-14)


def _world_origin(point):
    """The Point named 'O' reachable from ``point`` through set_pos links."""
    seen, todo = set(), [point]
    while todo:
        p = todo.pop()
        if p.name == "O":
            return p
        seen.add(p)
        todo += [n for n in p._pos_dict if n not in seen]
    raise AssertionError("no world origin")


# ----------------------------------------------------------------------------------------------
# Energy balance: dE/dt along the equations of motion
# ----------------------------------------------------------------------------------------------

CONSERVATIVE = [
    ("configs/simple_pendulum.yaml", {}),
    ("configs/double_pendulum.yaml", {"k": 3.0}),
    ("chain5", {"c": 0.0}),
    ("configs/cart_double_pendulum.yaml", {"F0": 0.0, "c_cart": 0.0, "c_sh": 0.0, "c_wall": 0.0}),
    ("configs/arm_3d.yaml", {"c_sh": 0.0, "c_tele": 0.0, "b_wrist": 0.0, "tau0": 0.0,
                             "c_tip": 0.0}),
    ("configs/spinning_top.yaml", {}),
    ("configs/free_body.yaml", {}),
    ("tests/fixtures/scenes/cylindrical_planar.yaml",
     {"tau0": 0.0, "kq": 0.0, "cq": 0.0, "cpoke": 0.0, "fpoke": 0.0, "gpoke": 0.0, "c_link": 0.0}),
]


def _energy_rate(num, t, q, u):
    """Central difference of E = T + V along (q', u') = (N(q) u, M^-1 f)."""
    out = num.evaluate(t, q, u)
    ud = np.linalg.solve(out["mass_matrix"], out["forcing"])
    qd = num.qdot(q, u)
    h = 1e-6

    def E(s):
        o = num.evaluate(t, np.asarray(q) + s * qd, np.asarray(u) + s * ud)
        return o["kinetic_energy"] + o["potential_energy"]
    scale = max(1.0, abs(out["kinetic_energy"]) + abs(out["potential_energy"]))
    return (E(h) - E(-h)) / (2 * h), scale


@pytest.mark.parametrize("scene,overrides", CONSERVATIVE, ids=[s for s, _ in CONSERVATIVE])
def test_energy_conserved_without_dissipation(tmp_path, scene, overrides):
    if scene == "chain5":
        scene = _inline(tmp_path, chain_yaml(5, spring=2.0, damper=0.5, rest=0.1))
    num = numeric(scene, overrides)
    rng = np.random.default_rng(5)
    for _ in range(3):
        t, q, u = kr.random_state(num.model, rng)
        rate, scale = _energy_rate(num, t, q, u)
        assert abs(rate) < 1e-6 * scale, f"dE/dt = {rate}"


def _cart_energy_rates(overrides, seed):
    """(t, u, dE/dt, its scale) of the cart double pendulum with `overrides`, at 3 random states."""
    num = numeric("configs/cart_double_pendulum.yaml", overrides)
    rng = np.random.default_rng(seed)
    for _ in range(3):
        t, q, u = kr.random_state(num.model, rng)
        yield (t, u, *_energy_rate(num, t, q, u))


def test_energy_rate_equals_damper_power():
    """Cart with only rail friction: dE/dt = -c_cart * cart.u^2."""
    for _t, u, rate, scale in _cart_energy_rates({"F0": 0.0, "c_sh": 0.0, "c_wall": 0.0, "c_cart": 0.7}, 6):
        assert rate == pytest.approx(-0.7 * u[0] ** 2, abs=1e-6 * scale)


def test_energy_rate_equals_spring_damper_power():
    """Cart, only the wall spring-damper dissipates: L = x + 5, so dE/dt = -c_wall * cart.u^2."""
    for _t, u, rate, scale in _cart_energy_rates({"F0": 0.0, "c_sh": 0.0, "c_cart": 0.0, "c_wall": 0.3}, 7):
        assert rate == pytest.approx(-0.3 * u[0] ** 2, abs=1e-6 * scale)


def test_energy_rate_with_time_dependent_push():
    """Cart, only the push F0 sin(w t) along x: dE/dt = F0 sin(w t) * cart.u."""
    for t, u, rate, scale in _cart_energy_rates({"c_sh": 0.0, "c_cart": 0.0, "c_wall": 0.0}, 8):
        assert rate == pytest.approx(1.5 * math.sin(2.0 * t) * u[0], abs=1e-6 * scale)


def test_expression_parser():
    names = {"a": sympy.Integer(2), "elbow.q": sympy.Symbol("x")}
    assert kr.parse("a^3^2", names) == 2**9                 # right-associative
    assert kr.parse("-a^2", names) == -4                    # unary minus below ^
    assert kr.parse("2*elbow.q", names) == 2 * sympy.Symbol("x")
    assert kr.parse("1.5e-3", names) == pytest.approx(1.5e-3)
    assert kr.parse("atan2(1, 0)", names) == sympy.pi / 2
    assert kr.parse("min(a, 3) + max(a, 3) + abs(-a)", names) == 7
    with pytest.raises(kr.ExpressionError):
        kr.parse("b + 1", names)
