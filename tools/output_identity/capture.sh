#!/usr/bin/env bash
# capture.sh BUILD OUTDIR: the outputs a refactoring must leave as they were (texlets of the bundled
# frames for every fit and uncertainty, simulator recordings for every effect, a lab session and
# the texlets of the model it fits), written into OUTDIR from the apps of the build BUILD. Compare
# two captures with compare.py. Run from anywhere; OUTDIR must not exist yet.
set -eu
[ $# -eq 2 ] || { echo "usage: capture.sh BUILD OUTDIR" >&2; exit 2; }
B=$1; O=$2
[ ! -e "$O" ] || { echo "capture.sh: $O already exists" >&2; exit 2; }
mkdir -p "$O"
D=$(cd "$(dirname "$0")/../.." && pwd)/data/kinect/grabber_sequence/pcd
EX=$B/apps/pcl_texlet_extract/pcl_texlet_extract
SIM=$B/apps/pcl_texlet_sim/pcl_texlet_sim
LAB=$B/apps/pcl_texlet_lab/pcl_texlet_lab
for fit in pca svd averaging; do for unc in montecarlo analytic none; do
  $EX -q --ascii -f $fit -u $unc $D $O/tex_${fit}_${unc} > /dev/null
done; done
$EX -q --ascii -s 4 -r 8 -t 5 $D $O/tex_thr > /dev/null
# a noise model with terms
for e in none axial_quadratic radial disparity_quantization incidence_angle vertical_stripes depth_distortion interference temporal_drift lateral_noise intrinsics; do
  args=(); [ $e != none ] && args=(--effect $e)
  $SIM -q --width 160 --height 120 --frames 4 --seed 11 --tilt-y 30 --projectors 2 "${args[@]}" $O/sim_$e
done
$SIM -q --scene box --width 160 --height 120 --frames 3 --seed 5 --projectors 3 --effect interference --effect lateral_noise $O/sim_box
$SIM -q --width 160 --height 120 --frames 3 --seed 5 --effect radial --effect incidence_angle --effect axial_quadratic --effect depth_distortion --effect temporal_drift --effect vertical_stripes --effect disparity_quantization $O/sim_many
# lab on small walls
for k in 0 1 2; do
  d=(0.9 1.6 2.4); t=(0 30 55)
  $SIM -q --width 160 --height 120 --frames 12 --distance ${d[k]} --tilt-y ${t[k]} --seed $((70+k)) --effect incidence_angle --effect temporal_drift $O/wall_$k
done
$LAB --auto 2 --report $O/lab $O/wall_0 $O/wall_1 $O/wall_2 > $O/lab_stdout.txt 2>&1 || echo "lab rc $?"
$EX -q --ascii --noise-model $O/lab/model.yaml $O/wall_1 $O/tex_labmodel > /dev/null
