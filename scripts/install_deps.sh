#!/usr/bin/env bash
# Installs the Debian 12 packages pcl_texlet builds, tests and runs with.
# Usage: sudo scripts/install_deps.sh   (idempotent; safe to re-run)
set -euo pipefail
export DEBIAN_FRONTEND=noninteractive
SUDO=""
if [[ $(id -u) -ne 0 ]]; then SUDO="sudo"; fi

packages=(
  build-essential cmake pkg-config git
  libpcl-dev pcl-tools libeigen3-dev libopenni2-dev libvtk9-dev
  libceres-dev libyaml-cpp-dev nlohmann-json3-dev libcli11-dev librandom123-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  libpng-dev libtiff-dev
  gnuplot-nox
  python3-numpy python3-pil   # test/generators/independent_walls.py: recordings made apart from the simulator
  xvfb xauth libgl1-mesa-dri
  clang   # the libFuzzer targets (PCL_TEXLET_FUZZ, docs/fuzzing.md): clang-14 with libclang_rt.fuzzer
)

# Skip apt entirely when everything is already there (fast re-runs in CI).
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "install_deps: installing ${#missing[@]} package(s): ${missing[*]}"
  $SUDO apt-get update -q
  $SUDO apt-get install -y -q --no-install-recommends "${missing[@]}"
else
  echo "install_deps: all ${#packages[@]} packages already installed"
fi
