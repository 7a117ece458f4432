#!/usr/bin/env bash
# Sets up and runs the main job on the bundled example: installs missing Debian packages, builds
# kanesens, installs the post-processing package (python/) into a venv, runs the flagship
# uncertainty study (configs/double_pendulum_uq.yaml: a Saltelli design over the double
# pendulum's m2, L1 and initial angle, with forward sensitivities) as an `mpirun -np 2` ensemble
# into out/double_pendulum_uq.h5, then summarises it, computes Sobol' indices, writes plots
# (out/*.png), a picture of the mechanism (out/double_pendulum.png) and an animation of one
# sample's recorded poses (out/double_pendulum.gif) with `kanesens-post`.
#   env: KANESENS_RANKS=2 KANESENS_OUT=out KANESENS_VENV=.venv KANESENS_BUILD_DIR=build
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
ranks=${KANESENS_RANKS:-2}
out=${KANESENS_OUT:-$root/out}
venv=${KANESENS_VENV:-$root/.venv}
build=${KANESENS_BUILD_DIR:-$root/build}
bash "$root/tools/install-deps.sh"
bash "$root/tools/build.sh"
# The package into a venv that sees Debian's numpy, h5py, xarray... (no PyPI: no build
# isolation, no dependency resolution; see python/README.md).
[[ -x $venv/bin/pip ]] || /usr/bin/python3 -m venv --system-site-packages "$venv"
"$venv/bin/pip" install --quiet --disable-pip-version-check --no-build-isolation --no-deps --no-index "$root/python"
post="$venv/bin/kanesens-post"
mkdir -p "$out"
export KANESENS="$build/kanesens"   # draw and animate ask kanesens where everything is
echo "== kanesens-post draw (the scene at its initial state, with the study's tip point)"
"$post" draw "$root/configs/double_pendulum_uq.yaml" -o "$out/double_pendulum.png"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
h5="$out/double_pendulum_uq.h5"
echo "== mpirun -np $ranks kanesens run configs/double_pendulum_uq.yaml -o $h5"
mpirun -np "$ranks" --oversubscribe "$build/kanesens" run "$root/configs/double_pendulum_uq.yaml" \
  -o "$h5" --overwrite
echo "== kanesens-post summary"
"$post" summary "$h5"
echo "== kanesens-post sobol (elbow angle at t = 2 s)"
"$post" sobol "$h5" --output elbow.q --at 2
"$post" plot "$h5" --states shoulder.q,elbow.q --outputs energy --out "$out/double_pendulum_uq_states.png"
"$post" plot "$h5" --kind sensitivities --states elbow.q --out "$out/double_pendulum_uq_sensitivities.png"
echo "== kanesens-post animate (sample 0's recorded poses)"
"$post" animate "$h5" --sample 0 -o "$out/double_pendulum.gif"
echo "== done: $h5, $out/*.png and $out/double_pendulum.gif"
