#!/usr/bin/env bash
# Runs pcl_texlet_bench (timing against PCL's normal estimators, accuracy on simulated scenes,
# the paper's Table 1 and Fig. 8, scaling) and draws its plots with gnuplot.
#
#   bash scripts/make_benchmark_figures.sh [extra pcl_texlet_bench options]
#   PLOTS_ONLY=1 bash scripts/make_benchmark_figures.sh   # redraw from the last run's data
#
# Writes docs/benchmarks.json (every figure), docs/benchmarks.txt (the tables as printed),
# the plotted data in docs/images/benchmarks/data/ and
# docs/images/benchmarks/{timing,fig8,scaling_texlets,scaling_radius}.png. BUILD selects the
# build folder (default build/); the app must be built (scripts/build.sh). Takes about 15
# minutes on 2 busy cores.
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD=${BUILD:-build}
APP="$BUILD/apps/pcl_texlet_bench/pcl_texlet_bench"
command -v gnuplot > /dev/null || { echo "make_benchmark_figures.sh: gnuplot is not installed" >&2; exit 2; }

IMAGES=docs/images/benchmarks
DATA=$IMAGES/data
mkdir -p "$DATA"

if [ -z "${PLOTS_ONLY:-}" ]; then
  [ -x "$APP" ] || { echo "make_benchmark_figures.sh: $APP is not built (run scripts/build.sh)" >&2; exit 2; }
  RUN=$(mktemp -d)
  trap 'rm -rf "$RUN"' EXIT
  # Everything in one run, so every ratio is measured under the same conditions.
  "$APP" --table1 --fig8 --scaling --json "$RUN/benchmarks.json" --data-dir "$RUN" "$@" | tee "$RUN/benchmarks.txt"
  cp "$RUN"/*.dat "$DATA/"
  # Renamed into place: no half-written result if the run failed.
  cp "$RUN/benchmarks.json" docs/.benchmarks.json.tmp && mv docs/.benchmarks.json.tmp docs/benchmarks.json
  cp "$RUN/benchmarks.txt" docs/.benchmarks.txt.tmp && mv docs/.benchmarks.txt.tmp docs/benchmarks.txt
fi

CPU=$(sed -n 's/.*"cpu": "\(.*\)",*$/\1/p' docs/benchmarks.json | head -1)
CORES=$(sed -n 's/.*"hardware_threads": \([0-9]*\).*/\1/p' docs/benchmarks.json | head -1)
THREADS=$(sed -n 's/.*"threads_used": \([0-9]*\).*/\1/p' docs/benchmarks.json | head -1)
MACHINE="$CPU, $CORES cores, $THREADS threads"
# Both scaling plots draw the same columns of their scaling_*.dat (median CPU ms per method).
SCALING_CURVES='using 2:6 with linespoints lw 2 title "texlets, no uncertainty", \
     "" using 2:12 with linespoints lw 2 title "texlets, analytic", \
     "" using 2:24 with linespoints lw 2 title "NormalEstimationOMP, same disc", \
     "" using 2:18 axes x1y2 with linespoints lw 2 dt 2 title "texlets, Monte Carlo 50 (right axis)"'

gnuplot <<EOF
set terminal pngcairo size 1100,620 enhanced font "DejaVu Sans,11"
set grid ytics
set key top left

# --- median time per method with its interquartile range ---------------------------------
set output "$IMAGES/timing.png"
set title "Time per 640x480 frame at the same hexagonal centres (${MACHINE})"
set ylabel "ms per frame (median; error bar: interquartile range)"
set logscale y
set style fill solid 0.5 border -1
set xtics rotate by -35 left noenhanced
set xrange [-0.6:12.6]
set rmargin 20
set bmargin 11
set key top left
plot "$DATA/timing.dat" using (\$1-0.18):3:4:5:(0.36):xtic(2) with boxerrorbars lc rgb "#4472c4" title "wall clock", \
     "" using (\$1+0.18):9:10:11:(0.36) with boxerrorbars lc rgb "#ed7d31" title "CPU time, all threads"
unset logscale y
set xtics norotate enhanced
set autoscale x
set rmargin
set bmargin

# --- the paper's Fig. 8 ------------------------------------------------------------------
set output "$IMAGES/fig8.png"
set multiplot layout 1,2 title "Normal angle error against added depth noise (plane 1 m away, tilted 30 deg, radius 6 px)"
set xlabel "depth noise SD, mm"
set title "(a) mean"
set ylabel "mean angle error, deg"
plot "$DATA/fig8.dat" using 1:2 with linespoints lw 2 title "normal averaging (Eq. 5)", \
     "" using 1:4 with linespoints lw 2 title "PCA (closed form)", \
     "" using 1:6 with linespoints lw 2 dt 2 title "SVD (reference)"
set title "(b) variance"
set ylabel "variance of the angle error, deg^2"
plot "$DATA/fig8.dat" using 1:3 with linespoints lw 2 title "normal averaging (Eq. 5)", \
     "" using 1:5 with linespoints lw 2 title "PCA (closed form)", \
     "" using 1:7 with linespoints lw 2 dt 2 title "SVD (reference)"
unset multiplot

# --- scaling -----------------------------------------------------------------------------
set ytics nomirror
set y2tics
set ylabel "CPU ms per frame, all threads (none, analytic, NormalEstimationOMP)"
set y2label "CPU ms per frame, all threads (Monte Carlo, 50 samples)"
set output "$IMAGES/scaling_texlets.png"
set title "CPU time against the number of texlets (spacing 2-12 px, radius 6 px; ${MACHINE})"
set xlabel "texlet centres per 640x480 frame"
plot "$DATA/scaling_spacing.dat" ${SCALING_CURVES}
set output "$IMAGES/scaling_radius.png"
set title "CPU time against the neighbourhood size (radius 2-10 px, spacing 6 px; ${MACHINE})"
set xlabel "pixels in the neighbourhood disc"
plot "$DATA/scaling_radius.dat" ${SCALING_CURVES}
EOF

echo "make_benchmark_figures.sh: docs/benchmarks.json, docs/benchmarks.txt, $DATA/*.dat and $IMAGES/*.png written" >&2
