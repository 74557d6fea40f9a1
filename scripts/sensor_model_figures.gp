# Draws the figures of docs/sensor_model.md from the data files of pcl_texlet_sensor_figures.
# Usage: gnuplot -e "data='DATA_DIR'; out='PNG_DIR'" scripts/sensor_model_figures.gp
# (scripts/make_sensor_model_figures.sh does all of it.)

if (!exists("data") || !exists("out")) {
  print "set data='folder of the .dat files' and out='folder for the PNGs' with -e"
  exit status 2
}
d(f) = data."/".f
o(f) = out."/".f

# Settings every figure starts from (after `reset`, which keeps variables but not styles).
common = "set datafile missing 'NaN'; set grid lc rgb '#dddddd'; set key box opaque samplen 2; \
set style line 1 lc rgb '#1f77b4' lw 2 pt 7 ps 0.7; set style line 2 lc rgb '#d62728' lw 2 pt 5 ps 0.7; \
set style line 3 lc rgb '#2ca02c' lw 2 pt 9 ps 0.8; set style line 4 lc rgb '#9467bd' lw 2 pt 11 ps 0.8; \
set style line 11 lc rgb '#1f77b4' lw 1.5 dt 2; set style line 12 lc rgb '#d62728' lw 1.5 dt 2; \
set style line 13 lc rgb '#2ca02c' lw 1.5 dt 2; set style line 14 lc rgb '#9467bd' lw 1.5 dt 2"
sequential = "set palette defined (0 '#000004', 1 '#3b0f70', 2 '#8c2981', 3 '#de4968', 4 '#fe9f6d', 5 '#fcfdbf')"
diverging = "set palette defined (0 '#2166ac', 1 '#67a9cf', 2 '#f7f7f7', 3 '#ef8a62', 4 '#b2182b')"
image_axes = "set size ratio -1; set autoscale xfix; set autoscale yfix; set yrange [*:*] reverse; \
set xlabel 'image column u (px)'; set ylabel 'image row v (px)'; unset grid; unset key"
plot_axes = "set size noratio; set autoscale; set yrange [*:*] noreverse; set grid; set key"
wide = "set terminal pngcairo size 960,440 font 'Sans,10'"
single = "set terminal pngcairo size 800,500 font 'Sans,10'"
tall = "set terminal pngcairo size 800,720 font 'Sans,10'"

# --- base noise ------------------------------------------------------------------------------
reset; eval common; eval wide
set output o('base_noise.png')
set multiplot layout 1,2 title "Base noise: the paper's polynomial f(r,d); per-pixel SD over 30 frames of a frontal wall"
eval image_axes; eval sequential
set title 'temporal SD per pixel, wall at 1.5 m'
set cblabel 'SD (mm)'
plot d('base_noise_map.dat') using 1:2:3 with image notitle
eval plot_axes
set yrange [0:*]
set xlabel 'distance from the principal point r (px)'
set ylabel 'depth SD (mm)'
set title 'SD vs radius: simulated (points), sqrt(f(r,d)^2 + 1/12) (dashed)'
set key top left
plot d('base_noise_radius.dat') using 1:2 with points ls 1 title 'wall at 0.8 m', '' using 1:3 with lines ls 11 notitle, \
     '' using 1:4 with points ls 2 title 'wall at 1.2 m', '' using 1:5 with lines ls 12 notitle, \
     '' using 1:6 with points ls 3 title 'wall at 1.6 m', '' using 1:7 with lines ls 13 notitle
unset multiplot

# --- projector shadows -----------------------------------------------------------------------
reset; eval common; eval wide
set output o('projector_shadows.png')
set multiplot layout 1,2 title "Projector shadows: a panel at 1.5 m in front of a wall; the projector is 7.5 cm right of the camera"
set title 'central row, frame 0, wall at 1.8 m (0 = no reading)'
set xlabel 'image column u (px)'
set ylabel 'reported depth (mm)'
set yrange [-50:2000]
set key center left
plot d('projector_shadows_row_off.dat') using 1:2 with linespoints ls 1 title 'shadows off (--no-shadows)', \
     d('projector_shadows_row_on.dat') using 1:2 with linespoints ls 2 title 'shadows on (default)'
set autoscale
set yrange [0:*]
set title 'shadow width left of the panel edge'
set xlabel 'distance of the wall behind (m)'
set ylabel 'width (px, mean over rows and frames)'
set key top left
plot d('projector_shadows.dat') using 1:2 with points ls 2 title 'simulated', \
     '' using 1:3 with linespoints ls 12 title 'f b (1/z_{front} - 1/z_{back})'
unset multiplot

# --- axial_quadratic -------------------------------------------------------------------------
reset; eval common; eval single
set output o('axial_quadratic.png')
set title "axial\\_quadratic: a constant disparity SD gives a depth SD growing with z^2 (frontal wall, central pixels, 30 frames)"
set xlabel 'distance to the wall z (m)'
set ylabel 'depth SD (mm)'
set key top left
set yrange [0:*]
plot d('axial_quadratic.dat') using 1:2 with points ls 1 title 'base noise, simulated', \
     '' using 1:4 with lines ls 11 title 'base: sqrt(f(0,d)^2 + 1/12)', \
     '' using 1:3 with points ls 2 title 'base + axial\_quadratic (sigma\_px 0.02), simulated', \
     '' using 1:5 with lines ls 12 title 'sqrt(f^2 + (sigma\_px z^2/(f b))^2 + 1/12)'

# --- radial ----------------------------------------------------------------------------------
reset; eval common; eval single
set output o('radial.png')
set title "radial: SD x (1 + gain (r/r_{ref})^2), gain 0.5, r_{ref} 400 px (frontal wall at 1.5 m, 30 frames)"
set xlabel 'distance from the principal point r (px)'
set ylabel 'depth SD (mm)'
set key top left
set yrange [0:*]
plot d('radial.dat') using 1:2 with points ls 1 title 'base noise, simulated', \
     '' using 1:4 with lines ls 11 title 'base model', \
     '' using 1:3 with points ls 2 title 'base + radial, simulated', \
     '' using 1:5 with lines ls 12 title 'base + radial model'

# --- disparity_quantization ------------------------------------------------------------------
reset; eval common; eval wide
set output o('disparity_quantization.png')
set multiplot layout 1,2 title "disparity\\_quantization: disparity in 1/8 px steps, depth on the lattice 1000 f b / (k/8)"
set title 'reported depths, frontal wall at 1.5 m (all pixels, 30 frames)'
set xlabel 'reported depth (mm)'
set ylabel 'fraction of readings'
set logscale y
set yrange [1e-6:1.5]
set format y '10^{%T}'
set style fill solid 0.6 noborder
set boxwidth 0.9
set key top left
plot d('disparity_quantization_hist.dat') using 1:($2 > 0 ? $2 : NaN) with boxes lc rgb '#1f77b4' title 'base noise', \
     '' using 1:($3 > 0 ? $3 : NaN) with boxes lc rgb '#d62728' title 'base + quantisation', \
     d('disparity_quantization_lattice.dat') using 2:(1e-6):(0):(1.5) with vectors nohead lc rgb '#888888' dt 3 title 'lattice depths'
unset logscale y
set format y '%g'
set autoscale
set style fill empty
set title 'mean error along a wall tilted 5 degrees (central row, 30 frames)'
set xlabel 'true depth (mm)'
set ylabel 'mean reported - true depth (mm)'
set xrange [1460:1540]
set yrange [-5:5]
set key bottom center horizontal
plot d('disparity_quantization_staircase.dat') using 1:3 with lines ls 2 title 'base + quantisation', \
     '' using 1:2 with lines ls 1 title 'base noise', \
     '' using 1:4 with lines ls 13 title '+- half a step, z^2 (1/8) / (2 f b)', '' using 1:(-$4) with lines ls 13 notitle
unset multiplot

# --- incidence_angle -------------------------------------------------------------------------
reset; eval common; eval wide
set output o('incidence_angle.png')
set multiplot layout 1,2 title "incidence\\_angle: SD x (1 + gain (1/cos(theta) - 1)), gain 0.5; no reading beyond 80 degrees (wall at 1.5 m)"
set title 'depth SD of the central pixels, 30 frames'
set xlabel 'wall tilt = incidence angle at the image centre (degrees)'
set ylabel 'depth SD (mm)'
set key top left
set yrange [0:*]
set xrange [0:90]
plot d('incidence_angle.dat') using 1:2 with points ls 1 title 'base noise', '' using 1:4 with lines ls 11 notitle, \
     '' using 1:3 with points ls 2 title 'base + incidence\_angle', '' using 1:5 with lines ls 12 title 'models (dashed)'
set title 'readings of the central pixels'
set ylabel 'fraction of pixel-frames with a reading'
set yrange [0:1.05]
set key bottom left
plot d('incidence_angle.dat') using 1:6 with linespoints ls 1 title 'base noise', \
     '' using 1:7 with linespoints ls 2 title 'base + incidence\_angle'
unset multiplot

# --- vertical_stripes ------------------------------------------------------------------------
reset; eval common; eval tall
set output o('vertical_stripes.png')
set multiplot layout 2,1 title "vertical\\_stripes: 6 column bands, offset SD 1/8 px, a new layout every 10 frames (frontal wall at 1.5 m)"
eval image_axes; eval diverging
set title 'reported - true depth, frame 0 (4x4 pixel means)'
set cblabel 'mm'
set cbrange [-15:15]
plot d('vertical_stripes_map.dat') using 1:2:3 with image notitle
eval plot_axes
set title 'column means of reported - true depth'
set xlabel 'image column u (px)'
set ylabel 'column mean (mm)'
set key outside right top
plot d('vertical_stripes_profile.dat') using 1:2 with lines ls 1 title 'base, frame 0', \
     '' using 1:3 with lines ls 2 title 'stripes, frame 0', \
     '' using 1:4 with lines ls 3 title 'stripes, frame 10'
unset multiplot

# --- depth_distortion ------------------------------------------------------------------------
reset; eval common; eval wide
set output o('depth_distortion.png')
set multiplot layout 1,2 title "depth\\_distortion: a static disparity bias map (bowl 0.1 px at the corner + ripple 0.05 px RMS)"
eval image_axes; eval diverging
set title 'mean reported - true depth, wall at 1.5 m, 30 frames'
set cblabel 'mm'
set cbrange [-12:12]
plot d('depth_distortion_map.dat') using 1:2:3 with image notitle
eval plot_axes
set title 'central rows: simulated (points) and -z^2 delta/(f b) (lines)'
set xlabel 'image column u (px)'
set ylabel 'mean bias (mm)'
set key bottom center
plot d('depth_distortion_row.dat') using 1:2 every 8 with points ls 1 title 'wall at 1.0 m', '' using 1:3 with lines ls 11 notitle, \
     '' using 1:4 every 8 with points ls 2 title 'wall at 1.5 m', '' using 1:5 with lines ls 12 notitle, \
     '' using 1:6 every 8 with points ls 3 title 'wall at 2.0 m', '' using 1:7 with lines ls 13 notitle
unset multiplot

# --- interference ----------------------------------------------------------------------------
reset; eval common; eval wide
set output o('interference.png')
set multiplot layout 1,2 title "interference: other projectors on the same wall (1.5 m; sensors 0.3 m apart)"
eval image_axes
set palette defined (0 '#f0f0f0', 1 '#d62728')
unset colorbox
set title 'holes in frame 0 with 3 active projectors (red)'
plot d('interference_holes_map.dat') using 1:2:3 with image notitle
eval plot_axes
set colorbox
set title 'simulated (points) and sqrt(1 + L), 1 - exp(-0.1 L) (dashed)'
set xlabel 'active projectors'
set xrange [0.8:3.2]
set xtics 1
set ylabel 'depth SD of the central pixels (mm)'
set y2label 'fraction of pixel-frames without a reading'
set yrange [0:*]
set y2range [0:0.25]
set y2tics
set ytics nomirror
set key top left
plot d('interference.dat') using 1:2 with linespoints ls 1 title 'SD, interference off', \
     '' using 1:3 with points ls 2 title 'SD, interference on', '' using 1:4 with lines ls 12 notitle, \
     '' using 1:6 axes x1y2 with points ls 3 title 'holes, interference on', '' using 1:7 axes x1y2 with lines ls 13 notitle, \
     '' using 1:5 axes x1y2 with linespoints ls 4 title 'holes, interference off'
unset multiplot

# --- temporal_drift --------------------------------------------------------------------------
reset; eval common; eval single
set output o('temporal_drift.png')
set title "temporal\\_drift: disparity offset 0.2 px exp(-frame/10) (frontal wall at 1.5 m)"
set xlabel 'frame'
set ylabel 'frame mean of reported - true depth (mm)'
set key bottom right
plot d('temporal_drift.dat') using 1:2 with points ls 1 title 'base noise', \
     '' using 1:3 with points ls 2 title 'base + temporal\_drift', \
     '' using 1:4 with lines ls 12 title '1000 (f b / (f b/z + 0.2 exp(-k/10)) - z)'

# --- lateral_noise ---------------------------------------------------------------------------
reset; eval common; eval wide
set output o('lateral_noise.png')
set multiplot layout 1,2 title "lateral\\_noise: edge jitter of 0.8 px (a panel at 1.5 m over the left half, a wall at 1.8 m)"
eval image_axes; eval sequential
set title 'frame 0 around the step, with lateral noise'
set cblabel 'reported depth (mm)'
plot d('lateral_noise_crop.dat') using 1:2:3 with image notitle
eval plot_axes
set title 'pixels reporting the panel, by column (all rows, 30 frames)'
set xlabel 'column - first column of the wall (px)'
set ylabel 'fraction reporting the panel'
set yrange [-0.05:1.05]
set key bottom left
plot d('lateral_noise.dat') using 1:2 with linespoints ls 1 title 'base noise', \
     '' using 1:3 with points ls 2 title 'base + lateral\_noise', \
     '' using 1:4 with lines ls 12 title 'Phi((-0.5 - offset) / 0.8)'
unset multiplot

# --- intrinsics ------------------------------------------------------------------------------
reset; eval common; eval wide
set output o('intrinsics.png')
set multiplot layout 1,2 title "intrinsics: camera.yaml says fx = fy = 1.088 x the rendering camera's (OpenNI's IR field of view on registered depth)"
set title 'lateral error, frontal wall at 1.5 m, central row'
set xlabel 'image column u (px)'
set ylabel 'x from camera.yaml - true x (mm)'
set key top right
plot d('intrinsics_row.dat') using 1:4 every 8 with points ls 2 title 'back-projected (PinholeModel)', \
     '' using 1:5 with lines ls 12 title 'x (1/1.088 - 1)'
set title 'fitted tilt of a wall turned about the image y axis'
set xlabel 'true tilt (degrees)'
set ylabel 'fitted - true tilt (degrees)'
set yrange [-0.8:3]
set key at graph 0.98, graph 0.5 right top
plot d('intrinsics_tilt.dat') using 1:($3 - $1) with points ls 2 title 'camera.yaml intrinsics', \
     '' using 1:($4 - $1) with lines ls 12 title 'atan(1.088 tan(tilt)) - tilt', \
     '' using 1:($2 - $1) with points ls 1 title 'true intrinsics'
unset multiplot
