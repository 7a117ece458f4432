#!/usr/bin/env bash
# Sets up and runs every test: installs missing Debian packages, builds (warnings as errors),
# then runs ctest, which covers the labels unit, regression, mpi and python (pytest under
# Debian's /usr/bin/python3, which sees python3-h5py etc.). Pass ctest arguments through, e.g.
#   tools/test.sh -L unit
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
bash "$root/tools/install-deps.sh"
bash "$root/tools/build.sh" -DKANESENS_WERROR=ON
build=${KANESENS_BUILD_DIR:-$root/build}
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
cd "$build"
ctest --output-on-failure -j "${KANESENS_JOBS:-$(nproc)}" "$@"
