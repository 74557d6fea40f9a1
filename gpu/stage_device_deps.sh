#!/usr/bin/env bash
# Copies the header-only and source dependencies of the GPU backend that a CUDA-only machine
# lacks (Random123, CLI11, GoogleTest's sources, all from this machine's Debian packages) into
# .device-deps/ (git-ignored), so they can travel with the working tree to the device machine.
set -euo pipefail
cd "$(dirname "$0")/.."
dest=.device-deps
rm -rf "$dest"
mkdir -p "$dest/include"
cp -r /usr/include/Random123 "$dest/include/"
cp -r /usr/include/CLI "$dest/include/"
cp -r /usr/src/googletest "$dest/googletest"
du -sh "$dest"
