#!/usr/bin/env bash
# Regenerates the figures of docs/multi_sensor.md: the simulated interference study (three
# sensors around the paper's box, 1-3 active projectors, radii 2-10 px) through
# pcl_texlet_interference; copies the paper-like images (Fig. 11 grid at radii 2, 6, 10 and
# the Fig. 13 curves) and the inlier table into docs/images/multi_sensor/.
# Usage: scripts/make_multi_sensor_figures.sh [BUILD_DIR]   (default: build)
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-$root/build}
app=$build/apps/pcl_texlet_interference/pcl_texlet_interference
[[ -x $app ]] || { echo "make_multi_sensor_figures: build pcl_texlet_interference first ($app)" >&2; exit 2; }
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
"$app" --simulate --radii 2,4,6,8,10 --histogram-radii 2,6,10 --projectors 1,2,3 --seed 0 "$out/study"
dest=$root/docs/images/multi_sensor
mkdir -p "$dest"
cp "$out"/study/histogram_p*_r*.png "$out/study/inliers_vs_radius.png" "$out/study/inliers.json" "$dest/"
echo "figures written to $dest"
