"""Pictures of a mechanism: `draw` (one state of a scene) and `animate` (recorded poses).

Every position drawn comes from kanesens (`geometry.scene_geometry`, or a run file's /poses);
this module only places the points on a picture. Each artist carries a gid naming what it is
("body:rod1", "joint:elbow", "axis:elbow", "spring:s1", "constraint:loop", "force:push",
"ground"), so a test can read back what was drawn.

A scene is drawn in 2-D when it is planar at the drawn state: every point lies in one
coordinate plane, every revolute/cylindrical axis and planar-joint normal is perpendicular to it,
every prismatic axis in it, and no joint or constraint can leave it (spherical, universal, free,
rolling). Otherwise a 3-D projection.
"""
from __future__ import annotations

import numpy as np
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

_PLANAR_JOINTS = {"revolute", "prismatic", "planar", "weld", "cylindrical"}
BODY_COLOR, JOINT_COLOR, SPRING_COLOR, CONSTRAINT_COLOR = "#1f4e79", "#222222", "#2e8b57", "#c0392b"


def _points(geo):
    pts = [p for b in geo["bodies"].values() for p in [b["position"]] + b["ends"]]
    pts += [m["at"] for m in geo["points"]]
    for j in geo["joints"]:
        pts += [j["parent_point"], j["child_point"]]
    for s in geo["springs"]:
        pts += [s["a"], s["b"]]
    for c in geo["constraints"]:
        pts += [c[k] for k in ("a", "b", "center") if k in c]
        if c["type"] == "rolling":  # the rim
            pts += [c["center"] + c["radius"] * e for e in np.vstack([np.eye(3), -np.eye(3)])]
    pts += [f["at"] for f in geo["loads"]]
    return np.array(pts).reshape(-1, 3)


def planar_view(geo, tol=1e-9):
    """The index k of the world axis normal to the plane the scene moves in, or None."""
    if any(j["type"] not in _PLANAR_JOINTS for j in geo["joints"]):
        return None
    if any(c["type"] == "rolling" for c in geo["constraints"]):
        return None
    pts = _points(geo)
    scale = max(1.0, float(np.abs(pts).max())) if pts.size else 1.0
    for k in (2, 1, 0):
        if pts.size and np.ptp(pts[:, k]) > tol * scale:
            continue
        ok = True
        for j in geo["joints"]:
            for a in j["axes"]:
                along = abs(a[k])
                if j["type"] == "prismatic" and along > tol:
                    ok = False
                if j["type"] in ("revolute", "cylindrical", "planar") and abs(along - 1) > tol:
                    ok = False
        if ok:
            return k
    return None


def _zigzag(a, b, normal, width, turns=6):
    """A spring's zigzag from a to b, its teeth perpendicular to the line and to normal."""
    d = b - a
    length = np.linalg.norm(d)
    if length == 0:
        return np.array([a, b])
    e = d / length
    side = np.cross(e, normal)
    if np.linalg.norm(side) < 1e-9:
        side = np.cross(e, [1.0, 0, 0]) if abs(e[0]) < 0.9 else np.cross(e, [0, 1.0, 0])
    side /= np.linalg.norm(side)
    s = np.linspace(0.15, 0.85, 2 * turns + 1)
    off = np.r_[0, [(-1) ** i for i in range(1, 2 * turns)], 0] * min(width, 0.2 * length)
    mid = a + np.outer(s, d) + np.outer(off, side)
    return np.vstack([a, mid, b])


class _Canvas:
    """The same drawing calls for a 2-D plane (axes i, j) or a 3-D projection."""

    def __init__(self, ax, k):
        self.ax, self.k = ax, k
        self.ij = None if k is None else [i for i in range(3) if i != k]

    def _xy(self, pts):
        pts = np.atleast_2d(np.asarray(pts, float))
        return [pts[:, i] for i in (self.ij if self.ij else range(3))]

    def line(self, pts, gid, **kw):
        (h,) = self.ax.plot(*self._xy(pts), gid=gid, **kw)
        return h

    def arrow(self, p, v, gid, **kw):
        if self.ij:
            i, j = self.ij
            return self.ax.quiver([p[i]], [p[j]], [v[i]], [v[j]], angles="xy", scale_units="xy",
                                  scale=1, gid=gid, width=0.006, **kw)
        return self.ax.quiver([p[0]], [p[1]], [p[2]], [v[0]], [v[1]], [v[2]], gid=gid,
                              arrow_length_ratio=0.2, **kw)

    def text(self, p, s, **kw):
        return self.ax.text(*[p[i] for i in (self.ij if self.ij else range(3))], s, **kw)


def draw_on(ax, geo, k, scale, labels=True):
    """Draws geo on ax (a 2-D axes when k is the planar normal index, a 3-D one when k is None)."""
    cv = _Canvas(ax, k)
    normal = np.eye(3)[k] if k is not None else np.array([0, 0, 1.0])
    attach = {b: [] for b in geo["bodies"]}

    def on(body, p):
        if body in attach:
            attach[body].append(p)

    for j in geo["joints"]:
        on(j["child"], j["child_point"])
        on(j["parent"], j["parent_point"])
    for s in geo["springs"]:
        on(s["body_a"], s["a"])
        on(s["body_b"], s["b"])
    for c in geo["constraints"]:
        if "a" in c:
            on(c["body_a"], c["a"])
            on(c["body_b"], c["b"])
    for f in geo["loads"]:
        on(f["body"], f["at"])
    for m in geo["points"]:
        on(m["body"], m["at"])
    for name, b in geo["bodies"].items():
        attach[name] += b["ends"]
    # bodies: a stick from the mass center to every point attached to it
    for name, b in geo["bodies"].items():
        x = b["position"]
        for p in attach[name]:
            cv.line([x, p], f"body:{name}", color=BODY_COLOR, lw=4, solid_capstyle="round", zorder=2)
        cv.line([x], f"body:{name}", marker="o", ms=7, color=BODY_COLOR, mec="white", zorder=3)
        if labels:
            cv.text(x, f"  {name}", color=BODY_COLOR, fontsize=9, zorder=6)
    # ground points: where a joint, spring or constraint meets the world
    ground = [j["parent_point"] for j in geo["joints"] if j["parent"] == "ground"]
    ground += [s[e] for s in geo["springs"] for e, bn in (("a", "body_a"), ("b", "body_b"))
               if s[bn] == "ground"]
    ground += [c[e] for c in geo["constraints"] if "a" in c
               for e, bn in (("a", "body_a"), ("b", "body_b")) if c[bn] == "ground"]
    if ground:
        cv.line(ground, "ground", ls="none", marker="^", ms=12, color="#888888", zorder=1)
    # joints: both points (they coincide except along a prismatic axis), and the axes
    for j in geo["joints"]:
        gid = f"joint:{j['name']}"
        if np.linalg.norm(j["child_point"] - j["parent_point"]) > 1e-12:
            cv.line([j["parent_point"], j["child_point"]], gid, color=JOINT_COLOR, ls=":", lw=1)
        cv.line([j["child_point"]], gid, marker="o", ms=9, mfc="white", mec=JOINT_COLOR, mew=2,
                color=JOINT_COLOR, zorder=4)
        for a in j["axes"]:
            if k is not None and j["type"] != "prismatic":
                # an axis normal to the picture: a dot in the joint's circle
                cv.line([j["child_point"]], f"axis:{j['name']}", marker=".", ms=4, color=JOINT_COLOR,
                        zorder=5)
            else:
                cv.arrow(j["child_point"], 0.3 * scale * a, f"axis:{j['name']}", color="#d35400",
                         zorder=5)
        if labels:
            cv.text(j["child_point"], f"{j['name']}  ", color=JOINT_COLOR, fontsize=8, ha="right",
                    va="bottom", zorder=6)
    for s in geo["springs"]:
        cv.line(_zigzag(s["a"], s["b"], normal, 0.04 * scale), f"spring:{s['name']}", color=SPRING_COLOR, lw=1.5,
                zorder=3)
        if labels:
            cv.text(0.5 * (s["a"] + s["b"]), f" {s['name']}", color=SPRING_COLOR, fontsize=8)
    by_name = {j["name"]: j for j in geo["joints"]}
    for c in geo["constraints"]:
        gid = f"constraint:{c['name']}"
        where = None
        if c["type"] in ("coincident", "distance"):
            ls = "--" if c["type"] == "distance" else "-"
            cv.line([c["a"], c["b"]], gid, color=CONSTRAINT_COLOR, ls=ls, lw=1.5, marker="x", ms=9,
                    mew=2, zorder=5)
            where = c["a"]
        elif c["type"] == "rolling":
            n, ax_, r = c["normal"], c["axis"], c["radius"]
            u = np.cross(ax_, [1.0, 0, 0]) if abs(ax_[0]) < 0.9 else np.cross(ax_, [0, 1.0, 0])
            u /= np.linalg.norm(u)
            w = np.cross(ax_, u)
            th = np.linspace(0, 2 * np.pi, 73)
            cv.line(c["center"] + r * (np.outer(np.cos(th), u) + np.outer(np.sin(th), w)), gid,
                    color=CONSTRAINT_COLOR, lw=1.5, zorder=3)
            # the contact point: the rim point lowest along the normal
            down = -(n - np.dot(n, ax_) * ax_)
            down /= np.linalg.norm(down)
            contact = c["center"] + r * down
            cv.line([c["center"], contact], gid, color=CONSTRAINT_COLOR, ls=":", marker="x", ms=9,
                    mew=2, zorder=5)
            if k is None:  # the plane, a square around the contact
                t1 = np.cross(n, w if abs(np.dot(n, w)) < 0.9 else u)
                t1 /= np.linalg.norm(t1)
                t2 = np.cross(n, t1)
                h = 1.5 * r
                p0 = contact - np.dot(contact, n) * n + c["height"] * n
                sq = [p0 + h * (sa * t1 + sb * t2) for sa, sb in ((-1, -1), (1, -1), (1, 1), (-1, 1), (-1, -1))]
                cv.line(sq, "ground", color="#888888", lw=1)
            where = contact
        elif c["type"] == "coupler" and all(n in by_name for n in c["joints"]):
            a, b = (by_name[n]["child_point"] for n in c["joints"])
            cv.line([a, b], gid, color=CONSTRAINT_COLOR, ls="-.", lw=1, zorder=2)
            where = 0.5 * (a + b)
        if labels and where is not None:
            cv.text(where, f"  {c['name']}", color=CONSTRAINT_COLOR, fontsize=8, va="top", zorder=6)
    for m in geo["points"]:
        cv.line([m["at"]], f"point:{m['name']}", marker="D", ms=6, color="#e67e22", zorder=5)
        if labels:
            cv.text(m["at"], f"  {m['name']}", color="#e67e22", fontsize=8)
    for f in geo["loads"]:
        cv.line([f["at"]], f"force:{f['name']}", marker="*", ms=11, color="#8e44ad", zorder=5)
        if labels:
            cv.text(f["at"], f"  {f['name']}", color="#8e44ad", fontsize=8)


def extent(points):
    """Center and half-size of a cube around the points, with a margin."""
    lo, hi = points.min(axis=0), points.max(axis=0)
    half = 0.5 * float((hi - lo).max()) * 1.15
    return 0.5 * (lo + hi), max(half, 0.05 * float(np.abs(points).max()), 0.05)


def new_axes(k, title):
    if k is not None:
        fig, ax = plt.subplots(figsize=(6, 6))
    else:
        fig = plt.figure(figsize=(6.5, 6))
        ax = fig.add_subplot(projection="3d")
    ax.set_title(title, fontsize=10)
    return fig, ax


def frame_axes(ax, k, center, half):
    names = "xyz"
    if k is not None:
        i, j = [n for n in range(3) if n != k]
        ax.set_xlim(center[i] - half, center[i] + half)
        ax.set_ylim(center[j] - half, center[j] + half)
        ax.set_aspect("equal")
        ax.set_xlabel(f"{names[i]} [m]")
        ax.set_ylabel(f"{names[j]} [m]")
        ax.grid(True, lw=0.3, alpha=0.5)
    else:
        for n, setter in enumerate((ax.set_xlim, ax.set_ylim, ax.set_zlim)):
            setter(center[n] - half, center[n] + half)
        ax.set_box_aspect((1, 1, 1))
        ax.set_xlabel("x [m]")
        ax.set_ylabel("y [m]")
        ax.set_zlabel("z [m]")


def draw(geo, title=None):
    """The figure of one state of a scene (geometry.scene_geometry's result)."""
    k = planar_view(geo)
    fig, ax = new_axes(k, title or geo["scene"])
    center, half = extent(_points(geo))
    draw_on(ax, geo, k, half)
    frame_axes(ax, k, center, half)
    fig.tight_layout()
    return fig


# -- animation from recorded poses ---------------------------------------------------------------

def rotation(qwxyz):
    """The rotation matrix (world from body) of a unit quaternion, scalar first."""
    w, x, y, z = np.asarray(qwxyz, float) / np.linalg.norm(qwxyz)
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                     [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                     [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])


def moved(geo, poses, body_names):
    """geo with every body-fixed point carried to the poses (body, 7: x y z qw qx qy qz).

    A point fixed in body b at geo's state, p = x_b + R_b p_b, moves to x_b' + R_b' p_b;
    ground points stay. The poses are kanesens's own (record: poses)."""
    ref = {b: (v["position"], rotation(v["quaternion"])) for b, v in geo["bodies"].items()}
    now = {b: (np.asarray(poses[i][:3], float), rotation(poses[i][3:7]))
           for i, b in enumerate(body_names)}

    def carry(body, p):
        if body not in ref or body not in now:
            return p
        (x0, r0), (x1, r1) = ref[body], now[body]
        return x1 + r1 @ (r0.T @ (p - x0))

    def turn(body, v):
        if body not in ref or body not in now:
            return v
        return now[body][1] @ (ref[body][1].T @ v)

    out = {"scene": geo["scene"], "bodies": {}, "joints": [], "springs": [], "loads": [],
           "constraints": [], "points": [dict(m, at=carry(m["body"], m["at"])) for m in geo["points"]]}
    for b, v in geo["bodies"].items():
        i = body_names.index(b)
        out["bodies"][b] = {"position": np.asarray(poses[i][:3], float),
                            "quaternion": np.asarray(poses[i][3:7], float),
                            "ends": [carry(b, e) for e in v["ends"]]}
    for j in geo["joints"]:
        out["joints"].append(dict(j, parent_point=carry(j["parent"], j["parent_point"]),
                                  child_point=carry(j["child"], j["child_point"]),
                                  axes=[turn(j["parent"], a) for a in j["axes"]]))
    for s in geo["springs"]:
        out["springs"].append(dict(s, a=carry(s["body_a"], s["a"]), b=carry(s["body_b"], s["b"])))
    for f in geo["loads"]:
        out["loads"].append(dict(f, at=carry(f["body"], f["at"])))
    for c in geo["constraints"]:
        c = dict(c)
        if "a" in c:
            c["a"], c["b"] = carry(c["body_a"], c["a"]), carry(c["body_b"], c["b"])
        if c["type"] == "rolling":
            c["center"], c["axis"] = carry(c["body"], c["center"]), turn(c["body"], c["axis"])
        out["constraints"].append(c)
    return out


def animate(geo, times, poses, body_names, out, fps=20, max_frames=100, title=None, dpi=60):
    """Writes an animated GIF of the poses (time, body, 7); returns the frame indices drawn."""
    from matplotlib.animation import FuncAnimation, PillowWriter

    frames = np.unique(np.linspace(0, len(times) - 1, min(len(times), max_frames)).astype(int))
    states = [moved(geo, poses[f], body_names) for f in frames]
    k = planar_view(geo)
    allpts = np.vstack([_points(s) for s in states])
    center, half = extent(allpts)
    fig, ax = new_axes(k, title or geo["scene"])

    def frame(n):
        ax.clear()
        draw_on(ax, states[n], k, half, labels=False)
        frame_axes(ax, k, center, half)
        ax.set_title(f"{title or geo['scene']}   t = {times[frames[n]]:.2f} s", fontsize=10)
        return []

    anim = FuncAnimation(fig, frame, frames=len(frames), blit=False)
    anim.save(out, writer=PillowWriter(fps=fps), dpi=dpi)
    plt.close(fig)
    return frames, states
