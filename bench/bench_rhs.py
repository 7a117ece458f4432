#!/usr/bin/python3
"""Right-hand-side speed of kanesens against MuJoCo's mj_forward on planar and spatial N-link
chains (docs/benchmarks.md).

    /usr/bin/python3 bench/bench_rhs.py [OUT_DIR] [--ns "1 2 4 8 16 32"] [--rounds 3] [--repeat 31]
        [--build build-bench] [--spatial-axes z,x]
    env (defaults of the options): NS ROUNDS REPEAT KANESENS_BUILD_DIR KANESENS_JOBS
    quick smoke test (seconds, not for the docs): bench/bench_rhs.py /tmp/rhs --ns 1,2 --rounds 1 --repeat 3

Builds kanesens and the MuJoCo peer (-DKANESENS_PEERS=ON; needs libmujoco-dev:
KANESENS_PEERS=1 tools/install-deps.sh) into the build directory, then, in one run, alternates
for every N and every round: `kanesens bench rhs` on the chain, the MuJoCo bench on the same
chain and state, `kanesens bench rhs` on the chain with its last axis tilted 1e-3 rad out of
the plane (which forces the general 3-D evaluation), then both engines on the spatial chain
(joint axes cycling through --spatial-axes, default z, x: neighbouring axes perpendicular, so
kanesens evaluates it with the general 3-D code). Each program reports a median over batches;
the tables show the median of those over the rounds. Check: kanesens eom's u̇ at MuJoCo's state
against MuJoCo's qacc, on both chains.

Writes --json (default bench/results/bench_rhs.json: every round of every program, the command
line) and, in OUT_DIR (default out/bench), the scenes/ and raw/ files; bench/make_tables.py makes
docs/benchmarks.md's tables from the JSON.
"""
from __future__ import annotations

import argparse
import json
from pathlib import Path

import common as c

WHO = "bench_rhs"


def agreement(kanesens, scene, mj) -> dict:
    """kanesens eom's u̇ at MuJoCo's state against MuJoCo's qacc."""
    ks = c.run_json([kanesens, "eom", scene, "--q=" + c.fmt_list(mj["qpos"]), "--u=" + c.fmt_list(mj["qvel"])])
    scale = max(1.0, max(abs(x) for x in mj["qacc"]))
    return {"max_abs_diff_udot_qacc": max(abs(a - b) for a, b in zip(ks["udot"], mj["qacc"])), "scale": scale}


def report(out: Path, json_out: Path, rounds: int, repeat: int, ns, spatial_axes: str, load_start) -> None:
    load = lambda f: c.load_json(out / "raw" / f"{f}.json")
    med = c.median
    rows, raw = [], {}
    for n in ns:
        k = [load(f"kanesens_{n}_{r}") for r in range(1, rounds + 1)]
        m = [load(f"mujoco_{n}_{r}") for r in range(1, rounds + 1)]
        t = [load(f"tilted_{n}_{r}") for r in range(1, rounds + 1)]
        ks = [load(f"kanesens_spatial_{n}_{r}") for r in range(1, rounds + 1)]
        ms = [load(f"mujoco_spatial_{n}_{r}") for r in range(1, rounds + 1)]
        rows.append({"n": n,
                     "kanesens_rhs_ns": med([x["rhs"]["median_ns"] for x in k]),
                     "kanesens_mf_ns": med([x["mass_matrix_and_forcing"]["median_ns"] for x in k]),
                     "kanesens_jacobian_ns": med([x["jacobian_dual"]["median_ns"] for x in k]),
                     "kanesens_3d_rhs_ns": med([x["rhs"]["median_ns"] for x in t]),
                     "kanesens_3d_mf_ns": med([x["mass_matrix_and_forcing"]["median_ns"] for x in t]),
                     "mujoco_forward_ns": med([x["mj_forward"]["median_ns"] for x in m]),
                     "kanesens_spatial_rhs_ns": med([x["rhs"]["median_ns"] for x in ks]),
                     "kanesens_spatial_mf_ns": med([x["mass_matrix_and_forcing"]["median_ns"] for x in ks]),
                     "mujoco_spatial_forward_ns": med([x["mj_forward"]["median_ns"] for x in ms]),
                     "kanesens_path": k[0].get("path", "?"), "tilted_path": t[0].get("path", "?"),
                     "spatial_path": ks[0].get("path", "?"),
                     "agreement": load(f"agree_{n}"), "agreement_spatial": load(f"agree_spatial_{n}")})
        raw[n] = {"kanesens": k, "mujoco": m, "kanesens_tilted": t, "kanesens_spatial": ks, "mujoco_spatial": ms}
    with open(json_out, "w") as f:
        json.dump({**c.provenance(load_start), "rounds": rounds, "repeat": repeat, "spatial_axes": spatial_axes,
                   "rows": rows, "raw": raw}, f, indent=1)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("out", nargs="?", default=str(c.ROOT / "out" / "bench"), help="output directory")
    ap.add_argument("--ns", default=c.env_default("NS", "1 2 4 8 16 32"), help="chain sizes N")
    ap.add_argument("--rounds", type=int, default=int(c.env_default("ROUNDS", 3)))
    ap.add_argument("--repeat", type=int, default=int(c.env_default("REPEAT", 31)), help="batches per program")
    ap.add_argument("--build", default=c.env_default("KANESENS_BUILD_DIR", str(c.ROOT / "build-bench")))
    ap.add_argument("--spatial-axes", default="z,x",
                    help="joint axes of the spatial chain, cycled (letters x, y, z)")
    ap.add_argument("--json", default=str(c.ROOT / "bench" / "results" / "bench_rhs.json"),
                    help="where the results go (all rounds, the command line)")
    a = ap.parse_args(argv)
    out, ns = Path(a.out), [int(x) for x in c.words(a.ns)]
    (out / "scenes").mkdir(parents=True, exist_ok=True)
    (out / "raw").mkdir(parents=True, exist_ok=True)

    c.cmake_build(a.build, ["kanesens", "mujoco_chain_bench"], configure="always",
                  options=["-DCMAKE_BUILD_TYPE=Release", "-DKANESENS_PEERS=ON", "-DKANESENS_BUILD_TESTS=OFF"])
    kanesens, mujoco = c.kanesens_exe(a.build), c.peer_exe(a.build, "mujoco_chain_bench")

    for n in ns:
        (out / "scenes" / f"chain{n}.yaml").write_text(c.chain_scene_yaml(n))
        (out / "scenes" / f"chain{n}_tilted.yaml").write_text(c.chain_scene_yaml(n, 1e-3))
        (out / "scenes" / f"chain{n}_spatial.yaml").write_text(c.chain_scene_yaml(n, axes=a.spatial_axes))
    load_start = c.loadavg()

    for r in range(1, a.rounds + 1):
        for n in ns:
            c.log(WHO, f"round {r}/{a.rounds}, N = {n}")
            rhs = lambda scene: c.run_json([kanesens, "bench", "rhs", scene, "--repeat", a.repeat, "--json"])
            c.write_json(out / "raw" / f"kanesens_{n}_{r}.json", rhs(out / "scenes" / f"chain{n}.yaml"))
            c.write_json(out / "raw" / f"mujoco_{n}_{r}.json", c.run_json([mujoco, n, "--repeat", a.repeat]))
            c.write_json(out / "raw" / f"tilted_{n}_{r}.json", rhs(out / "scenes" / f"chain{n}_tilted.yaml"))
            c.write_json(out / "raw" / f"kanesens_spatial_{n}_{r}.json", rhs(out / "scenes" / f"chain{n}_spatial.yaml"))
            c.write_json(out / "raw" / f"mujoco_spatial_{n}_{r}.json",
                         c.run_json([mujoco, n, "--repeat", a.repeat, "--axes", a.spatial_axes]))

    # Same equations? kanesens's u̇ at MuJoCo's state against MuJoCo's qacc.
    for n in ns:
        mj = c.load_json(out / "raw" / f"mujoco_{n}_1.json")
        c.write_json(out / "raw" / f"agree_{n}.json", agreement(kanesens, out / "scenes" / f"chain{n}.yaml", mj))
        mj = c.load_json(out / "raw" / f"mujoco_spatial_{n}_1.json")
        c.write_json(out / "raw" / f"agree_spatial_{n}.json",
                     agreement(kanesens, out / "scenes" / f"chain{n}_spatial.yaml", mj))

    report(out, Path(a.json), a.rounds, a.repeat, ns, a.spatial_axes, load_start)
    c.log(WHO, f"wrote {a.json}; tables: bench/make_tables.py")


if __name__ == "__main__":
    main()
