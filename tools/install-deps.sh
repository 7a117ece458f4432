#!/usr/bin/env bash
# Installs kanesens's build, test and run dependencies from Debian 12's archive.
# Idempotent: installs only the packages that are missing, says what it does.
# Works as root (CI) or with sudo. Set KANESENS_PEERS=1 to also install the peer engines
# (MuJoCo, Simbody) used by the optional comparison benchmarks.
set -euo pipefail

packages=(
  build-essential cmake ninja-build pkg-config git
  libeigen3-dev libopenmpi-dev openmpi-bin libhdf5-openmpi-dev hdf5-tools
  libsundials-dev libyaml-cpp-dev libcli11-dev libfmt-dev libboost-dev
  libgtest-dev libbenchmark-dev
  python3 python3-numpy python3-h5py python3-xarray python3-h5netcdf python3-matplotlib
  python3-scipy python3-sympy python3-pytest python3-yaml python3-pil python3-openturns
  python3-venv python3-setuptools python3-wheel
)
if [[ "${KANESENS_PEERS:-0}" == 1 ]]; then
  packages+=(libmujoco-dev libsimbody-dev)
fi

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [[ ${#missing[@]} -eq 0 ]]; then
  echo "install-deps: all ${#packages[@]} Debian packages already installed; nothing to do."
  exit 0
fi

sudo_cmd=()
if [[ $(id -u) -ne 0 ]]; then
  if command -v sudo >/dev/null; then sudo_cmd=(sudo); else
    echo "install-deps: need root (or sudo) to install: ${missing[*]}" >&2; exit 1
  fi
fi

echo "install-deps: installing ${#missing[@]} missing package(s): ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
"${sudo_cmd[@]}" apt-get update -qq
"${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
echo "install-deps: done."
