#!/usr/bin/env python3
"""Wall recordings noised by a published Kinect simulator (Handa et al.'s simkinect), for
measuring the lab and the texlets' covariances on noise that neither pcl_texlet nor its
independent generator made (docs/texlet_covariances.md, section 8).

The simulator is not part of this project: give the folder of a checkout of it (its
add_noise.py; it needs python3-opencv and python3-scipy). Its functions add_gaussian_shifts
(each pixel read from a place shifted by N(0, 1/2 px)) and filterDisp (the 9 x 9 matcher over
its dot pattern) are called as they are; around them this script does what the simulator's
own script does: disparity = f b / z with its f = 480 px and b = 0.075 m, rounded to 1/8 px
before the matcher, and after it the depth in centimetres on the lattice 35130 / k with
N(0, 1/6) added to k. The clean wall is independent_walls.py's (same geometry, same camera
conventions); the output is the recording folder every pcl_texlet app reads, depth in whole
millimetres.

  published_simulator_walls.py SIMKINECT_DIR OUT [--frames N --distance M --tilt-x DEG
      --tilt-y DEG --seed S]
"""
import argparse
import os
import sys
from types import SimpleNamespace

import numpy as np
from PIL import Image

sys.dont_write_bytecode = True  # no __pycache__ in the source tree
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from independent_walls import wall  # noqa: E402

# The simulator's constants (its script's main): focal length (px) and baseline (m) of its
# disparity, and its depth lattice in centimetres.
FOCAL_PX = 480.0
BASELINE_M = 0.075
LATTICE_CM = 35130.0
INVALID = 99999999.9


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument('simkinect', help='folder of a checkout of the published simulator (add_noise.py)')
    p.add_argument('out')
    p.add_argument('--frames', type=int, default=20)
    p.add_argument('--distance', type=float, default=1.5, help='metres along the optical axis')
    p.add_argument('--tilt-x', type=float, default=0.0)
    p.add_argument('--tilt-y', type=float, default=0.0)
    p.add_argument('--seed', type=int, default=1)
    args = p.parse_args()
    if args.frames < 1 or not 0.5 < args.distance < 4.5:
        raise SystemExit('published_simulator_walls.py: bad frame count or distance')
    if os.path.exists(args.out):
        raise SystemExit('published_simulator_walls.py: %s exists' % args.out)
    source = os.path.join(args.simkinect, 'add_noise.py')
    pattern_file = os.path.join(args.simkinect, 'data', 'kinect-pattern_3x3.png')
    if not os.path.isfile(source) or not os.path.isfile(pattern_file):
        raise SystemExit('published_simulator_walls.py: %s has no add_noise.py and data/kinect-pattern_3x3.png'
                         % args.simkinect)
    sys.path.insert(0, os.path.abspath(args.simkinect))
    import cv2
    import add_noise

    # The simulator's image: 640 x 480 with its focal length; the principal point at the centre.
    geometry = SimpleNamespace(width=640, height=480, fx=FOCAL_PX, fy=FOCAL_PX, cx=320.0, cy=240.0,
                               distance=args.distance, tilt_x=args.tilt_x, tilt_y=args.tilt_y)
    _, _, z0, _ = wall(geometry)  # metres
    pattern = cv2.imread(pattern_file, 0)
    np.random.seed(args.seed)  # the simulator draws from numpy's global generator
    os.makedirs(os.path.join(args.out, 'depth'))
    for t in range(args.frames):
        shifted = add_noise.add_gaussian_shifts(z0.astype(np.float32))
        disparity = np.round(FOCAL_PX * BASELINE_M / (shifted + 1e-10) * 8.0) / 8.0
        matched = add_noise.filterDisp(disparity, pattern, INVALID)
        valid = matched != INVALID
        depth_cm = np.where(valid, 100.0 * FOCAL_PX * BASELINE_M / np.where(valid, matched, 1.0), 0.0)
        k = np.where(valid, LATTICE_CM / np.maximum(np.round(depth_cm), 1.0), 1.0)
        noisy_cm = LATTICE_CM / np.maximum(np.round(k + np.random.normal(size=k.shape) / 6.0 + 0.5), 1.0)
        depth_mm = np.where(valid & (noisy_cm > 40) & (noisy_cm < 800), np.round(10.0 * noisy_cm), 0)
        Image.fromarray(depth_mm.astype(np.uint16), mode='I;16').save(
            os.path.join(args.out, 'depth', '%06d.png' % t))
        print('%s: frame %d of %d' % (args.out, t + 1, args.frames), file=sys.stderr, flush=True)

    K = [FOCAL_PX, 0, 320.0, 0, FOCAL_PX, 240.0, 0, 0, 1]
    with open(os.path.join(args.out, 'camera.yaml'), 'w') as f:
        f.write('image_width: 640\nimage_height: 480\n')
        f.write('camera_matrix:\n  rows: 3\n  cols: 3\n  data: [%s]\n' % ', '.join(repr(float(x)) for x in K))
        f.write('distortion_model: plumb_bob\ndistortion_coefficients:\n  rows: 1\n  cols: 5\n  data: [0, 0, 0, 0, 0]\n')
        f.write('baseline_m: %r\ndisparity_subpixel: 0.125\n' % BASELINE_M)
    with open(os.path.join(args.out, 'meta.yaml'), 'w') as f:
        f.write('generator: published_simulator_walls.py (simkinect)\nscene: plane\nprojectors: 1\n')


if __name__ == '__main__':
    main()
