#!/usr/bin/env bash
# Installs the Debian 12 packages volts needs, only those that are missing.
# Run as root (or with sudo available). Safe to run repeatedly.
set -euo pipefail

PKGS=(
  build-essential cmake pkg-config
  libcgal-dev libgmp-dev libmpfr-dev libboost-dev
  libeigen3-dev
  libopenmesh-dev
  libtet1.5-dev
  libnlopt-cxx-dev
  libvtk9-dev
  libyaml-cpp-dev
  nlohmann-json3-dev
  libsimdjson-dev
  libgtest-dev libgmock-dev
  python3
  gmsh  # the tests run `gmsh bezier.msh -check` (tests/extract/exports_check.h)
)
if [[ "${VOLTS_WITH_GMSH:-0}" == 1 ]]; then PKGS+=(libgmsh-dev); fi  # bench/bench_tet_route only

missing=()
for p in "${PKGS[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done
if ((${#missing[@]} == 0)); then
  echo "[install-deps] all ${#PKGS[@]} packages present"
  exit 0
fi
echo "[install-deps] installing: ${missing[*]}"
SUDO=""
if [[ $(id -u) -ne 0 ]]; then SUDO="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
