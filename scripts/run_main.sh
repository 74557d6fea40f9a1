#!/usr/bin/env bash
# The main job: installs, builds, and extracts texlets (50-sample Monte Carlo uncertainty)
# from the bundled real Kinect frames, printing a summary. Texlet PCD files go to out/kinect/.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install_deps.sh
bash scripts/build.sh
build/apps/pcl_texlet_extract/pcl_texlet_extract data/kinect/grabber_sequence/pcd out/kinect "$@"
