"""Where everything of a scene is, computed by kanesens itself.

kanesens_post does no kinematics of its own: `scene_geometry` writes a study whose `outputs:` are
the world position of every drawn point (body mass centers, both sides of every joint, the ends
of springs and constraints, force points), every body's orientation, and the scene's constant
vectors (joint axes, points on the ground) as expressions; runs `kanesens simulate` on it; and
reads the values at the first output time. The state is the scene's initial state (with --set
applied), made consistent with the constraints exactly as `simulate` and `run` do.
"""
from __future__ import annotations

import json
import os
import shutil
import subprocess
import tempfile
from pathlib import Path

import numpy as np
import yaml


class GeometryError(Exception):
    """A scene kanesens refuses, or no kanesens executable."""


def find_kanesens(explicit=None):
    """The kanesens executable: explicit, $KANESENS, PATH, or build/kanesens of this checkout."""
    for candidate in (explicit, os.environ.get("KANESENS"), shutil.which("kanesens"),
                      Path(__file__).resolve().parents[2] / "build" / "kanesens"):
        if candidate and Path(candidate).is_file() and os.access(candidate, os.X_OK):
            return str(candidate)
    raise GeometryError("no kanesens executable: pass --kanesens PATH or set KANESENS")


def _text(v):
    return str(v) if not isinstance(v, bool) else str(int(v))


def _vec(v, default=(0, 0, 0)):
    v = default if v is None else v
    return [_text(x) for x in v]


def _plus(a, b):
    return [f"({x})+({y})" for x, y in zip(a, b)]


# the keys of the constant vector each joint type is drawn with
_AXIS_KEY = {"revolute": "axis", "prismatic": "axis", "cylindrical": "axis", "planar": "axis"}


class _Plan:
    """Output names for the points of a scene: world positions and constants."""

    def __init__(self):
        self.outputs = {}
        self.n = 0

    def point(self, body, p):
        """World position of point p (body frame, or world for ground): an output name, or a
        constant-vector key."""
        name = f"ksdraw_{self.n}"
        self.n += 1
        if body == "ground":
            for c, x in zip("xyz", p):
                self.outputs[f"{name}_{c}"] = {"expression": x}
            return ("const", name)
        self.outputs[name] = {"type": "position", "body": body, "point": p}
        return ("pos", name)

    def scalar(self, x):
        name = f"ksdraw_{self.n}"
        self.n += 1
        self.outputs[name] = {"expression": _text(x)}
        return ("scalar", name)

    def orientation(self, body):
        name = f"ksdraw_{self.n}"
        self.n += 1
        self.outputs[name] = {"type": "orientation", "body": body}
        return ("quat", name)

    @staticmethod
    def value(ref, outputs):
        kind, name = ref
        first = lambda v: v[0] if isinstance(v, list) else v  # noqa: E731 - series or number
        if kind == "pos":
            return np.array([first(outputs[f"{name}.{c}"]) for c in "xyz"], float)
        if kind == "const":
            return np.array([first(outputs[f"{name}_{c}"]) for c in "xyz"], float)
        if kind == "quat":
            return np.array([first(outputs[f"{name}.{c}"]) for c in ("qw", "qx", "qy", "qz")], float)
        return float(first(outputs[name]))


def _joint_sets(q):
    """--q JOINT=V[,V..] to --set initial conditions (naming.md: J.q0, J.q0[i])."""
    sets = []
    for item in q or []:
        joint, sep, values = item.partition("=")
        vals = [v.strip() for v in values.split(",") if v.strip()]
        if not sep or not joint or not vals:
            raise GeometryError(f"--q {item}: expected JOINT=VALUE or JOINT=V1,V2,...")
        if len(vals) == 1:
            sets.append(f"{joint}.q0={vals[0]}")
        else:
            sets += [f"{joint}.q0[{i}]={v}" for i, v in enumerate(vals)]
    return sets


def _load(path):
    try:
        doc = yaml.safe_load(path.read_text(encoding="utf-8"))
        return doc["scene"]
    except (OSError, yaml.YAMLError, KeyError, TypeError) as err:
        raise GeometryError(f"{path}: not a scene or study file ({err})") from None


def scene_geometry(scene_path, q=None, sets=(), kanesens=None, study_outputs=None):
    """Positions (world, m) of everything `draw` shows, as a dict of plain numpy arrays.

    scene_path is a scene file, or a study file: then its scene, and the points of its
    position, velocity and acceleration outputs (or those of study_outputs, a study's `outputs:`
    map) are drawn."""
    exe = find_kanesens(kanesens)
    scene_path = Path(scene_path).resolve()
    scene = _load(scene_path)
    marks = []
    if isinstance(scene, str):  # a study: its scene file is relative to the study
        study_outputs = yaml.safe_load(scene_path.read_text(encoding="utf-8")).get("outputs")
        scene_path = (scene_path.parent / scene).resolve()
        scene = _load(scene_path)
    if not isinstance(study_outputs, dict):
        study_outputs = {}
    if not isinstance(scene, dict):
        raise GeometryError(f"{scene_path}: not a scene file")
    plan = _Plan()
    for name, spec in study_outputs.items():
        if isinstance(spec, dict) and spec.get("type") in ("position", "velocity", "acceleration"):
            marks.append((name, spec["body"], plan.point(spec["body"], _vec(spec.get("point")))))
    bodies = [b["name"] for b in scene.get("bodies") or []]
    refs = {"bodies": {b: (plan.point(b, ["0", "0", "0"]), plan.orientation(b)) for b in bodies}}
    ends = {}  # a rod or cylinder shape: the two ends of its axis
    for b in scene.get("bodies") or []:
        shape = b.get("inertia") if isinstance(b.get("inertia"), dict) else {}
        if shape.get("shape") in ("rod", "cylinder") and shape.get("axis") in ("x", "y", "z"):
            k = "xyz".index(shape["axis"])
            tip = [f"({_text(shape['length'])})/2" if i == k else "0" for i in range(3)]
            ends[b["name"]] = [plan.point(b["name"], tip),
                               plan.point(b["name"], [f"-{t}" if t != "0" else t for t in tip])]
    joints = []
    for j in scene.get("joints") or []:
        parent, child = j["parent"], j["child"]
        pp, cp = _vec(j.get("parent_point")), _vec(j.get("child_point"))
        entry = {"name": j["name"], "type": j["type"], "parent": parent, "child": child,
                 "parent_point": plan.point(parent, pp), "child_point": plan.point(child, cp)}
        axes = []
        if j["type"] in _AXIS_KEY and j.get("axis") is not None:
            axes = [_vec(j["axis"])]
        elif j["type"] == "universal" and j.get("axes") is not None:
            axes = [_vec(a) for a in j["axes"]]
        if parent == "ground":  # the axis tips: constant world vectors
            entry["axes"] = [plan.point("ground", a) for a in axes]
            entry["axes_from"] = None
        else:  # the axis is fixed in the parent: the parent's point pp + a, minus pp
            entry["axes"] = [plan.point(parent, _plus(pp, a)) for a in axes]
            entry["axes_from"] = entry["parent_point"]
        joints.append(entry)
    springs, loads = [], []
    for f in scene.get("forces") or []:
        if f.get("type") == "spring_damper":
            springs.append({"name": f.get("name", "spring_damper"),
                            "body_a": f["body_a"], "body_b": f["body_b"],
                            "a": plan.point(f["body_a"], _vec(f.get("point_a"))),
                            "b": plan.point(f["body_b"], _vec(f.get("point_b")))})
        elif f.get("type") in ("force", "torque"):
            loads.append({"name": f.get("name", f["type"]), "type": f["type"], "body": f["body"],
                          "at": plan.point(f["body"], _vec(f.get("point")))})
    constraints = []
    for c in scene.get("constraints") or []:
        kind = c.get("type")
        entry = {"name": c.get("name", kind), "type": kind}
        if kind in ("coincident", "distance"):
            entry["body_a"], entry["body_b"] = c["body_a"], c["body_b"]
            entry["a"] = plan.point(c["body_a"], _vec(c.get("point_a")))
            entry["b"] = plan.point(c["body_b"], _vec(c.get("point_b")))
        elif kind == "rolling":
            entry["body"] = c["body"]
            entry["center"] = plan.point(c["body"], ["0", "0", "0"])
            entry["axis_tip"] = plan.point(c["body"], _vec(c.get("axis")))
            entry["radius"] = plan.scalar(c["radius"])
            entry["normal"] = plan.point("ground", _vec(c.get("normal"), (0, 0, 1)))
            entry["height"] = plan.scalar(c.get("height", 0))
        elif kind == "coupler":
            entry["joints"] = [c["joint_a"], c["joint_b"]]
        constraints.append(entry)

    study = {"kanesens": 1, "scene": str(scene_path), "time": {"end": 1e-6, "outputs": 2},
             "record": ["states"], "outputs": plan.outputs}
    with tempfile.TemporaryDirectory(prefix="kanesens-draw-") as tmp:
        path = Path(tmp) / "draw_study.yaml"
        path.write_text(yaml.safe_dump(study, sort_keys=False), encoding="utf-8")
        cmd = [exe, "simulate", str(path), "--sens", "none"]
        for s in list(sets) + _joint_sets(q):
            cmd += ["--set", s]
        proc = subprocess.run(cmd, capture_output=True, text=True, check=False)
    # exit 4: the integration failed after the initial state, whose outputs are still printed
    if proc.returncode not in (0, 4):
        msg = proc.stderr.strip().splitlines()
        raise GeometryError(msg[-1] if msg else f"kanesens simulate exited {proc.returncode}")
    result = json.loads(proc.stdout)
    out = result["outputs"]
    val = lambda ref: _Plan.value(ref, out)  # noqa: E731

    geo = {"scene": scene.get("name", scene_path.stem), "gravity": np.array(
        [float(x) for x in scene.get("gravity", [0, 0, 0])]) if all(
        isinstance(x, (int, float)) for x in scene.get("gravity", [0, 0, 0])) else None,
        "state_names": result["state_names"], "state": np.array(result["states"][0], float),
        "bodies": {}, "joints": [], "springs": [], "loads": [], "constraints": []}
    for b, (pos, quat) in refs["bodies"].items():
        geo["bodies"][b] = {"position": val(pos), "quaternion": val(quat),
                            "ends": [val(e) for e in ends.get(b, [])]}
    geo["points"] = [{"name": n, "body": b, "at": val(ref)} for n, b, ref in marks]
    for j in joints:
        g = {k: j[k] for k in ("name", "type", "parent", "child")}
        g["parent_point"], g["child_point"] = val(j["parent_point"]), val(j["child_point"])
        base = np.zeros(3) if j["axes_from"] is None else val(j["axes_from"])
        axes = []
        for ref in j["axes"]:
            a = val(ref) - base
            axes.append(a / np.linalg.norm(a) if np.linalg.norm(a) > 0 else a)
        g["axes"] = axes
        geo["joints"].append(g)
    for s in springs:
        geo["springs"].append({"name": s["name"], "body_a": s["body_a"], "body_b": s["body_b"],
                               "a": val(s["a"]), "b": val(s["b"])})
    for f in loads:
        geo["loads"].append({"name": f["name"], "type": f["type"], "body": f["body"],
                             "at": val(f["at"])})
    for c in constraints:
        g = {k: v for k, v in c.items() if k in ("name", "type", "body", "body_a", "body_b")}
        if c["type"] in ("coincident", "distance"):
            g["a"], g["b"] = val(c["a"]), val(c["b"])
        elif c["type"] == "rolling":
            center = val(c["center"])
            axis = val(c["axis_tip"]) - center
            normal = val(c["normal"])
            g.update(center=center, axis=axis / np.linalg.norm(axis), radius=val(c["radius"]),
                     normal=normal / np.linalg.norm(normal), height=val(c["height"]))
        elif c["type"] == "coupler":
            g["joints"] = c["joints"]
        geo["constraints"].append(g)
    return geo
