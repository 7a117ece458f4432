"""Independent reference for kanesens: a scene YAML turned into Kane's equations by SymPy.

This module re-implements the scene semantics of docs/reference/scene.md with
``sympy.physics.mechanics`` (ReferenceFrame, Point, RigidBody, KanesMethod). It shares no
code with the C++ engine; the two are compared number for number by
tests/python/test_eom_vs_sympy.py through the JSON fixtures written by generate_fixtures.py.

Conventions implemented (docs/reference/scene.md is the contract):

* ``ground`` is the Newtonian frame N with origin O. Every body frame has its origin at the
  body's mass center G; ``inertia`` is the central tensor in the body frame (entries as
  ``sympy.physics.mechanics.inertia``: xx, yy, zz, xy, yz, xz; or a shape).
* A joint connects ``parent_point`` (parent frame, from the parent's mass center) with
  ``child_point`` (child frame, from the child's mass center). At q = 0 the child frame is
  parallel to the parent frame and the two points coincide. ``axis``/``axes`` are given in
  the parent frame and normalised.
* revolute     R = rot(axis, q), u = q'
* prismatic    child point = parent point + q axis, u = q'
* cylindrical  R = rot(axis, q1), child point = parent point + q2 axis, u = q'
* universal    R = rot(a1, q1) rot(a2, q2) (a2 in the parent frame at q = 0, carried by the
               first rotation), u = q'
* planar       child point = parent point + q1 e1 + q2 e2 (parent components), R = rot(n, q3),
               with e1 = unit(x - (x.n) n) (y if n is parallel to x), e2 = n x e1; u = q'
* spherical    q = (w, x, y, z) unit quaternion, scalar first, rotating child-frame vectors into
               the parent frame; u = angular velocity of the child relative to the parent in
               child components; q' = 1/2 q (x) (0, u)
* free         q = (x, y, z) = position of child point relative to parent point in parent
               components, then the quaternion as spherical; u = (x', y', z') then omega as
               spherical.
* weld         child rigidly attached, R = I, child point at the parent point.

Loads: gravity m g at every mass center; joint spring/damper: generalized force
-k (q - rest) - c u added to that joint's speed; spring_damper between two points: force on a
is (k (L - rest) + c L') e_ab, b gets the opposite; applied forces at a body point and torques,
components in ``world`` or ``body`` frame.

Outputs follow SymPy's KanesMethod: M u' = forcing (``mass_matrix`` / ``forcing``, not the
``_full`` versions), with q' eliminated through the kinematic differential equations.
Kinetic energy = sum 1/2 m v.v + 1/2 w.I.w; potential energy = sum -m g.r_G + joint springs
1/2 k (q - rest)^2 + spring_dampers 1/2 k (L - rest)^2.

Usage::

    model = build_model("configs/double_pendulum.yaml")
    num = NumericModel(model)           # lambdified
    out = num.evaluate(t, q, u)         # dict: mass_matrix, forcing, kinetic_energy, ...

Run with Debian's /usr/bin/python3 (it has sympy, numpy and yaml).
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import sympy as sp
import yaml
from sympy.parsing.sympy_parser import parse_expr, auto_number, factorial_notation
from sympy.physics.mechanics import (KanesMethod, Point, ReferenceFrame, RigidBody,
                                     dynamicsymbols, inertia, msubs)
from sympy.physics.vector import Vector

T = dynamicsymbols._t

# ----------------------------------------------------------------------------------------------
# Expressions
# ----------------------------------------------------------------------------------------------

_FUNCTIONS = {
    "sin": sp.sin, "cos": sp.cos, "tan": sp.tan, "asin": sp.asin, "acos": sp.acos,
    "atan": sp.atan, "atan2": sp.atan2, "exp": sp.exp, "log": sp.log, "sqrt": sp.sqrt,
    "abs": sp.Abs, "min": sp.Min, "max": sp.Max, "pi": sp.pi,
}
_DOTTED = re.compile(r"\b([A-Za-z_]\w*)\.([A-Za-z_]\w*)")


def _mangle(name: str) -> str:
    """State name ``elbow.q`` -> Python identifier ``elbow__DOT__q``."""
    return name.replace(".", "__DOT__")


class ExpressionError(ValueError):
    pass


def parse(value, names: dict, where: str = "") -> sp.Expr:
    """Parse a scene number/expression into a SymPy expression.

    ``names`` maps identifiers (parameter names, ``t``, state names such as ``elbow.q``) to
    SymPy objects. ``^`` is power (right-associative, as Python's ``**``); unary minus binds
    weaker than ``^`` (``-a^2`` = -(a^2)), as in Python. Unknown identifiers are errors.
    """
    if isinstance(value, bool):
        raise ExpressionError(f"{where}: boolean is not a number")
    if isinstance(value, (int, float)):
        return sp.nsimplify(value) if isinstance(value, int) else sp.Float(value, 30)
    if not isinstance(value, str):
        raise ExpressionError(f"{where}: expected a number or expression, got {value!r}")
    text = _DOTTED.sub(lambda m: _mangle(m.group(0)), value.replace("^", "**"))
    local = dict(_FUNCTIONS)
    local.update({_mangle(k): v for k, v in names.items()})
    tokens = re.findall(r"(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?|[A-Za-z_]\w*", text)
    ident = {tok for tok in tokens if not (tok[0].isdigit() or tok[0] == ".")}
    unknown = sorted(i for i in ident if i not in local)
    if unknown:
        raise ExpressionError(f"{where}: unknown name(s) {unknown} in {value!r}")
    try:
        expr = parse_expr(text, local_dict=local, global_dict={"Integer": sp.Integer,
                          "Float": sp.Float, "Rational": sp.Rational, "Symbol": sp.Symbol},
                          transformations=(auto_number, factorial_notation))
    except Exception as exc:  # noqa: BLE001 - re-raised with context
        raise ExpressionError(f"{where}: cannot parse {value!r}: {exc}") from exc
    return sp.sympify(expr)


# ----------------------------------------------------------------------------------------------
# Small geometry helpers
# ----------------------------------------------------------------------------------------------

def rot(axis, angle) -> sp.Matrix:
    """Rodrigues rotation matrix for a unit ``axis`` (3-vector) and ``angle``."""
    a = sp.Matrix(axis)
    K = sp.Matrix([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])
    return sp.eye(3) + sp.sin(angle) * K + (1 - sp.cos(angle)) * K * K


def quat_to_dcm(w, x, y, z) -> sp.Matrix:
    """Child->parent rotation matrix of a unit quaternion (w, x, y, z), scalar first."""
    return sp.Matrix([
        [1 - 2 * (y**2 + z**2), 2 * (x * y - w * z), 2 * (x * z + w * y)],
        [2 * (x * y + w * z), 1 - 2 * (x**2 + z**2), 2 * (y * z - w * x)],
        [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x**2 + y**2)],
    ])


def quat_rate(qv, w) -> list:
    """q' = 1/2 q (x) (0, w) for q = (qw, qx, qy, qz) and body angular velocity w."""
    qw, qx, qy, qz = qv
    wx, wy, wz = w
    return [
        sp.Rational(1, 2) * (-qx * wx - qy * wy - qz * wz),
        sp.Rational(1, 2) * (qw * wx + qy * wz - qz * wy),
        sp.Rational(1, 2) * (qw * wy + qz * wx - qx * wz),
        sp.Rational(1, 2) * (qw * wz + qx * wy - qy * wx),
    ]


def _unit(vec) -> sp.Matrix:
    v = sp.Matrix(vec)
    n = sp.sqrt(sum(c**2 for c in v))
    if n == 0:
        raise ValueError("zero axis")
    return sp.Matrix([sp.nsimplify(c / n) if c.is_Rational else c / n for c in v])


def _vec(frame: ReferenceFrame, comps) -> Vector:
    return comps[0] * frame.x + comps[1] * frame.y + comps[2] * frame.z


def planar_directions(n) -> tuple[sp.Matrix, sp.Matrix]:
    """In-plane unit directions (e1, e2) of a planar joint with unit normal n."""
    n = sp.Matrix(n)
    ex = sp.Matrix([1, 0, 0])
    e = ex - n.dot(ex) * n
    if sp.sqrt(e.dot(e)).evalf() < 1e-12:
        e = sp.Matrix([0, 1, 0]) - n.dot(sp.Matrix([0, 1, 0])) * n
    e1 = e / sp.sqrt(e.dot(e))
    e2 = n.cross(e1)
    return e1, e2


# ----------------------------------------------------------------------------------------------
# The model
# ----------------------------------------------------------------------------------------------

JOINT_NAMES = {
    "revolute": (["q"], ["u"]),
    "prismatic": (["q"], ["u"]),
    "cylindrical": (["q1", "q2"], ["u1", "u2"]),
    "universal": (["q1", "q2"], ["u1", "u2"]),
    "planar": (["q1", "q2", "q3"], ["u1", "u2", "u3"]),
    "spherical": (["qw", "qx", "qy", "qz"], ["wx", "wy", "wz"]),
    "free": (["x", "y", "z", "qw", "qx", "qy", "qz"], ["vx", "vy", "vz", "wx", "wy", "wz"]),
    "weld": ([], []),
}


@dataclass
class Model:
    """Everything SymPy needs for Kane's method, built from one scene."""
    name: str
    path: str
    coordinate_names: list
    speed_names: list
    q: list
    u: list
    kdes: list                     # q' - N(q) u  (one per coordinate)
    qdot_map: dict                 # q' -> N(q) u
    N: ReferenceFrame
    bodies: list                   # RigidBody, declaration order
    loads: list                    # (Point|Frame, Vector)
    joint_forces: list             # extra generalized forces, one per speed (expressions)
    kinetic_energy: sp.Expr = 0
    potential_energy: sp.Expr = 0
    gravity: sp.Matrix = field(default_factory=lambda: sp.zeros(3, 1))
    mass_matrix: sp.Matrix | None = None
    forcing: sp.Matrix | None = None


def _shape_inertia(spec: dict, m, pnames: dict, where: str):
    shape = spec["shape"]
    P = lambda key: parse(spec[key], pnames, f"{where}.{key}")  # noqa: E731
    if shape == "point":
        return (0, 0, 0)
    if shape == "sphere":
        r = P("radius")
        return (sp.Rational(2, 5) * m * r**2,) * 3
    if shape == "box":
        a, b, c = (parse(v, pnames, f"{where}.size") for v in spec["size"])
        return (m * (b**2 + c**2) / 12, m * (a**2 + c**2) / 12, m * (a**2 + b**2) / 12)
    if shape in ("rod", "cylinder"):
        axis = spec.get("axis")
        if axis not in ("x", "y", "z"):
            raise ValueError(f"{where}.axis: expected x, y or z, got {axis!r}")
        if shape == "rod":
            along, across = 0, m * P("length")**2 / 12
        else:
            r, h = P("radius"), P("length")
            along, across = m * r**2 / 2, m * (3 * r**2 + h**2) / 12
        d = [across, across, across]
        d["xyz".index(axis)] = along
        return tuple(d)
    raise ValueError(f"{where}.shape: unknown shape {shape!r}")


def build_model(path: str | Path, overrides: dict | None = None) -> Model:
    """Parse a scene YAML file and build frames, points, bodies, loads and kinematics.

    ``overrides`` replaces parameter values (name -> number), like ``kanesens --set``.
    """
    path = Path(path)
    doc = yaml.safe_load(path.read_text())
    if doc.get("kanesens") != 1:
        raise ValueError(f"{path}: expected 'kanesens: 1'")
    sc = doc["scene"]

    # Parameters, in order; each may use the earlier ones. Values are exact/30-digit numbers.
    pvals: dict = {}
    for name, val in (sc.get("parameters") or {}).items():
        if overrides and name in overrides:
            val = overrides[name]
        pvals[name] = parse(val, pvals, f"parameters.{name}").evalf(30)
    for name in overrides or {}:
        if name not in pvals:
            raise ValueError(f"override of unknown parameter {name!r}")

    gravity = sp.Matrix([parse(g, pvals, "gravity") for g in sc.get("gravity", [0, 0, 0])])

    N = ReferenceFrame("N")
    O = Point("O")
    O.set_vel(N, 0)

    # Bodies: frame + mass center (placed later by the joints).
    bodies: dict = {}
    body_order = []
    for b in sc["bodies"]:
        bname = b["name"]
        where = f"bodies.{bname}"
        m = parse(b["mass"], pvals, f"{where}.mass")
        frame = ReferenceFrame(f"F_{bname}")
        G = Point(f"G_{bname}")
        ispec = b.get("inertia", {}) or {}
        if "shape" in ispec:
            ixx, iyy, izz = _shape_inertia(ispec, m, pvals, f"{where}.inertia")
            ixy = iyz = ixz = 0
        else:
            get = lambda k: parse(ispec.get(k, 0), pvals, f"{where}.inertia.{k}")  # noqa: E731
            ixx, iyy, izz, ixy, iyz, ixz = (get(k) for k in ("xx", "yy", "zz", "xy", "yz", "xz"))
        I = inertia(frame, ixx, iyy, izz, ixy, iyz, ixz)
        bodies[bname] = {"frame": frame, "G": G, "mass": m, "inertia": I, "placed": False}
        body_order.append(bname)

    def frame_of(name):
        return N if name == "ground" else bodies[name]["frame"]

    def point_of(name):
        return O if name == "ground" else bodies[name]["G"]

    # Joints: coordinates, speeds, kinematics.
    qs, us, qnames, unames, kdes = [], [], [], [], []
    state_syms: dict = {}
    joint_specs = []
    for j in sc.get("joints", []):
        jname, jtype = j["name"], j["type"]
        if jtype not in JOINT_NAMES:
            raise ValueError(f"joint {jname}: unknown type {jtype}")
        qn, un = JOINT_NAMES[jtype]
        jq = [dynamicsymbols(f"{jname}__{n}") for n in qn]
        ju = [dynamicsymbols(f"{jname}__{n}") for n in un]
        for n, s in zip(qn, jq):
            state_syms[f"{jname}.{n}"] = s
        for n, s in zip(un, ju):
            state_syms[f"{jname}.{n}"] = s
        qs += jq
        us += ju
        qnames += [f"{jname}.{n}" for n in qn]
        unames += [f"{jname}.{n}" for n in un]
        joint_specs.append((j, jq, ju))

    qdot_map = {}
    for j, jq, ju in joint_specs:
        jname, jtype = j["name"], j["type"]
        where = f"joints.{jname}"
        P, C = frame_of(j["parent"]), frame_of(j["child"])
        if j["child"] == "ground":
            raise ValueError(f"{where}: ground cannot be a child")
        child = bodies[j["child"]]
        if child["placed"]:
            raise ValueError(f"{where}: body {j['child']} already has a parent joint")
        pp = [parse(v, pvals, f"{where}.parent_point") for v in j.get("parent_point", [0, 0, 0])]
        cp = [parse(v, pvals, f"{where}.child_point") for v in j.get("child_point", [0, 0, 0])]
        Pp = point_of(j["parent"]).locatenew(f"Pp_{jname}", _vec(P, pp))
        translation = Vector(0)

        def axis_of(key="axis"):
            return _unit([parse(v, pvals, f"{where}.{key}") for v in j[key]])

        if jtype == "revolute":
            a = axis_of()
            C.orient_axis(P, _vec(P, a), jq[0])
            C.set_ang_vel(P, ju[0] * _vec(P, a))
        elif jtype == "prismatic":
            a = axis_of()
            C.orient_axis(P, P.z, 0)
            C.set_ang_vel(P, 0)
            translation = jq[0] * _vec(P, a)
        elif jtype == "cylindrical":
            a = axis_of()
            C.orient_axis(P, _vec(P, a), jq[0])
            C.set_ang_vel(P, ju[0] * _vec(P, a))
            translation = jq[1] * _vec(P, a)
        elif jtype == "universal":
            a1 = _unit([parse(v, pvals, f"{where}.axes[0]") for v in j["axes"][0]])
            a2 = _unit([parse(v, pvals, f"{where}.axes[1]") for v in j["axes"][1]])
            A = ReferenceFrame(f"A_{jname}")
            A.orient_axis(P, _vec(P, a1), jq[0])
            A.set_ang_vel(P, ju[0] * _vec(P, a1))
            C.orient_axis(A, _vec(A, a2), jq[1])       # a2 carried by the first rotation
            C.set_ang_vel(A, ju[1] * _vec(A, a2))
        elif jtype == "planar":
            n = axis_of()
            e1, e2 = planar_directions(n)
            C.orient_axis(P, _vec(P, n), jq[2])
            C.set_ang_vel(P, ju[2] * _vec(P, n))
            translation = jq[0] * _vec(P, e1) + jq[1] * _vec(P, e2)
        elif jtype in ("spherical", "free"):
            quat = jq[-4:]
            w = ju[-3:]
            C.orient_quaternion(P, tuple(quat))      # checked against quat_to_dcm in tests
            C.set_ang_vel(P, _vec(C, w))
            for qi, rate in zip(quat, quat_rate(quat, w)):
                qdot_map[qi.diff(T)] = rate
            if jtype == "free":
                translation = _vec(P, jq[:3])
                for qi, ui in zip(jq[:3], ju[:3]):
                    qdot_map[qi.diff(T)] = ui
        elif jtype == "weld":
            C.orient_axis(P, P.z, 0)
            C.set_ang_vel(P, 0)
        if jtype not in ("spherical", "free"):
            for qi, ui in zip(jq, ju):
                qdot_map[qi.diff(T)] = ui
        Cp = Pp.locatenew(f"Cp_{jname}", translation)
        child["G"].set_pos(Cp, -_vec(C, cp))
        child["placed"] = True
    for bname in body_order:
        if not bodies[bname]["placed"]:
            raise ValueError(f"body {bname} is not the child of any joint")
    kdes = [qi.diff(T) - qdot_map[qi.diff(T)] for qi in qs]

    def velocity(point: Point) -> Vector:
        """Velocity in N of a point, in terms of q, u (q' eliminated)."""
        v = point.pos_from(O).dt(N)
        return msubs(v, qdot_map)

    rigid = []
    ke = sp.Integer(0)
    pe = sp.Integer(0)
    loads = []
    for bname in body_order:
        b = bodies[bname]
        G, F = b["G"], b["frame"]
        vG = velocity(G)
        G.set_vel(N, vG)
        w = F.ang_vel_in(N)
        rigid.append(RigidBody(bname, G, F, b["mass"], (b["inertia"], G)))
        ke += sp.Rational(1, 2) * b["mass"] * (vG & vG) + sp.Rational(1, 2) * (w & (b["inertia"] & w))
        if any(g != 0 for g in gravity):
            loads.append((G, b["mass"] * _vec(N, gravity)))
            rG = G.pos_from(O).to_matrix(N)
            pe += -b["mass"] * gravity.dot(rG)

    # Names usable in force expressions: parameters, t, every state name.
    fnames = dict(pvals)
    fnames["t"] = T
    fnames.update(state_syms)

    # Joint springs and dampers: generalized forces on that joint's speed.
    joint_forces = [sp.Integer(0)] * len(us)
    for j, jq, ju in joint_specs:
        where = f"joints.{j['name']}"
        if ("spring" in j or "damper" in j) and len(jq) != 1:
            raise ValueError(f"{where}: spring/damper only on 1-DOF joints")
        k = us.index(ju[0]) if ju else None
        if "spring" in j:
            ks = parse(j["spring"]["k"], fnames, f"{where}.spring.k")
            rest = parse(j["spring"].get("rest", 0), fnames, f"{where}.spring.rest")
            joint_forces[k] += -ks * (jq[0] - rest)
            pe += ks * (jq[0] - rest) ** 2 / 2
        if "damper" in j:
            c = parse(j["damper"]["c"], fnames, f"{where}.damper.c")
            joint_forces[k] += -c * ju[0]

    def body_point(bname, comps, label):
        """A point fixed in body ``bname`` (or ground) at ``comps`` (body frame, from G)."""
        frame, base = frame_of(bname), point_of(bname)
        Pt = base.locatenew(label, _vec(frame, comps))
        Pt.set_vel(N, velocity(Pt) if bname != "ground" else Vector(0))
        return Pt

    for i, f in enumerate(sc.get("forces") or []):
        ftype = f["type"]
        where = f"forces.{f.get('name', i)}"
        if ftype == "spring_damper":
            pa = [parse(v, pvals, f"{where}.point_a") for v in f.get("point_a", [0, 0, 0])]
            pb = [parse(v, pvals, f"{where}.point_b") for v in f.get("point_b", [0, 0, 0])]
            Pa = body_point(f["body_a"], pa, f"SDa{i}")
            Pb = body_point(f["body_b"], pb, f"SDb{i}")
            r_ab = Pb.pos_from(Pa).to_matrix(N)
            v_ab = (Pb.vel(N) - Pa.vel(N)).to_matrix(N)
            L = sp.sqrt(r_ab.dot(r_ab))
            Ldot = r_ab.dot(v_ab) / L
            k = parse(f.get("k", 0), fnames, f"{where}.k")
            c = parse(f.get("c", 0), fnames, f"{where}.c")
            rest = parse(f.get("rest", 0), fnames, f"{where}.rest")
            tension = k * (L - rest) + c * Ldot
            Fa = _vec(N, tension * r_ab / L)
            loads.append((Pa, Fa))
            loads.append((Pb, -Fa))
            pe += k * (L - rest) ** 2 / 2
        elif ftype in ("force", "torque"):
            comps = [parse(v, fnames, f"{where}.vector") for v in f["vector"]]
            fr = f.get("frame", "world")
            if fr not in ("world", "body"):
                raise ValueError(f"{where}.frame: expected world or body")
            vec = _vec(N if fr == "world" else frame_of(f["body"]), comps)
            if ftype == "force":
                pt = [parse(v, pvals, f"{where}.point") for v in f.get("point", [0, 0, 0])]
                loads.append((body_point(f["body"], pt, f"AF{i}"), vec))
            else:
                loads.append((frame_of(f["body"]), vec))
        else:
            raise ValueError(f"{where}: unknown force type {ftype}")

    if sc.get("constraints"):
        raise NotImplementedError("constraints are not part of the SymPy reference yet")

    return Model(name=sc["name"], path=str(path), coordinate_names=qnames, speed_names=unames,
                 q=qs, u=us, kdes=kdes, qdot_map=qdot_map, N=N, bodies=rigid, loads=loads,
                 joint_forces=joint_forces, kinetic_energy=msubs(ke, qdot_map),
                 potential_energy=pe, gravity=gravity)


def kane_equations(model: Model) -> Model:
    """Run KanesMethod; fill model.mass_matrix (nu x nu) and model.forcing (nu)."""
    km = KanesMethod(model.N, q_ind=model.q, u_ind=model.u, kd_eqs=model.kdes)
    # Loads on frames/points whose velocity is identically zero (ground) contribute nothing;
    # KanesMethod handles them, but skipping them keeps the expressions smaller.
    km.kanes_equations(model.bodies, model.loads)
    M = km.mass_matrix
    f = km.forcing + sp.Matrix(model.joint_forces)
    qdots = set(model.qdot_map)
    for expr in list(M) + list(f):
        left = expr.atoms(sp.Derivative) & qdots
        if left:
            raise RuntimeError(f"q' left in the equations: {left}")
    model.mass_matrix, model.forcing = M, f
    return model


class NumericModel:
    """Lambdified M(q), f(t, q, u), kinetic and potential energy of a Model."""

    def __init__(self, model: Model):
        if model.mass_matrix is None:
            kane_equations(model)
        self.model = model
        qs, us = sp.symbols(f"qq0:{len(model.q)}"), sp.symbols(f"uu0:{len(model.u)}")
        ts = sp.Symbol("tt")
        sub = dict(zip(model.q, qs))
        sub.update(dict(zip(model.u, us)))
        sub[T] = ts

        def prep(e):
            return msubs(e, sub) if not isinstance(e, (int, float)) else sp.sympify(e)

        exprs = [prep(model.mass_matrix), prep(model.forcing),
                 prep(model.kinetic_energy), prep(model.potential_energy)]
        self._f = sp.lambdify([ts, list(qs), list(us)], exprs, modules="numpy", cse=True)
        qdot = [prep(model.qdot_map[qi.diff(T)]) for qi in model.q]
        self._qdot = sp.lambdify([list(qs), list(us)], qdot, modules="numpy")

    def qdot(self, q, u) -> np.ndarray:
        """q' = N(q) u (nq) from the kinematic differential equations."""
        return np.array(self._qdot([float(x) for x in q], [float(x) for x in u]), dtype=float)

    def evaluate(self, t: float, q, u) -> dict:
        M, f, ke, pe = self._f(float(t), [float(x) for x in q], [float(x) for x in u])
        nu = len(self.model.u)
        M = np.array(M, dtype=float).reshape(nu, nu)
        f = np.array(f, dtype=float).reshape(nu)
        return {"mass_matrix": M, "forcing": f,
                "kinetic_energy": float(ke), "potential_energy": float(pe)}


def random_state(model: Model, rng: np.random.Generator) -> tuple[float, list, list]:
    """A random (t, q, u): angles/positions in [-pi, pi], unit quaternions, u in [-2, 2]."""
    q = []
    names = model.coordinate_names
    i = 0
    while i < len(names):
        if names[i].endswith(".qw"):
            v = rng.normal(size=4)
            v /= np.linalg.norm(v)
            q += list(v)
            i += 4
        else:
            q.append(rng.uniform(-math.pi, math.pi))
            i += 1
    u = list(rng.uniform(-2.0, 2.0, size=len(model.u)))
    t = float(rng.uniform(0.0, 10.0))
    return t, [float(x) for x in q], [float(x) for x in u]
