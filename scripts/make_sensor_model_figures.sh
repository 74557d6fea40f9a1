#!/usr/bin/env bash
# Regenerates the figures of docs/sensor_model.md: builds pcl_texlet_sensor_figures, runs it
# (640x480, 30 frames, seed 0: every simulated recording is the same on every machine), and
# draws the PNGs with gnuplot into docs/images/sensor_model/. About two minutes on two cores.
#
#   bash scripts/make_sensor_model_figures.sh [BUILD_DIR]     (default: build)
#
# The data files are kept in BUILD_DIR/sensor_model_figures/ for a look with gnuplot.
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
if [ ! -f "$build/CMakeCache.txt" ]; then
  cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release
fi
cmake --build "$build" -j "$(nproc 2>/dev/null || echo 2)" --target pcl_texlet_sensor_figures
app="$build/apps/pcl_texlet_sensor_figures/pcl_texlet_sensor_figures"
data="$build/sensor_model_figures"
images=docs/images/sensor_model
rm -rf "$data"
"$app" "$data" --width 640 --height 480 --frames 30 --seed 0
mkdir -p "$images"
gnuplot -e "data='$data'; out='$images'" scripts/sensor_model_figures.gp
echo "figures in $images:"
ls -l "$images"
echo "key numbers: $data/summary.txt"
