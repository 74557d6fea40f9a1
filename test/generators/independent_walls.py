#!/usr/bin/env python3
"""Wall recordings of a structured-light sensor, made independently of pcl_texlet's simulator.

The model lab's proofs must not rest on data made by the same code whose functional forms the
lab assumes. This generator shares nothing with src/simulation: its own geometry, its own
random numbers (numpy's PCG64), and effects in other physically plausible forms (a drift that
scales depth, a disparity distortion in Herrera's form, stripes of random widths whose offsets
wander, an incidence law in powers of 1/cos, ...), with the base noise added in depth or in
disparity. It writes the recording folder format every pcl_texlet app reads (camera.yaml,
depth/*.png in whole millimetres, rgb/*.png where the wall is printed, meta.yaml) and, for the
tests only, truth.yaml with what was hidden (the lab never reads it).

  independent_walls.py OUT [--width W --height H --frames N --distance M --tilt-x DEG
      --tilt-y DEG --seed S --sensor-seed S --noise-in depth|disparity --projectors P]
      [--effect NAME[:key=value,...]]...

Effects (NAME and keys; defaults in EFFECTS below): see docs/model_lab.md, "The independent
generator".
"""
import argparse
import math
import os
import sys

import numpy as np
from PIL import Image

# The paper's Eq. 4 (the published base model: SD in mm of depth, r in px from the image
# centre, d in mm), not the simulator's code.
PAPER = (2.344, -1.202e-2, -2.734e-3, 1.818e-5, 6.516e-6, 1.233e-6)

EFFECTS = {
    # vocabulary effects, in forms of this generator's own
    'axial_quadratic': {'sigma_px': 0.03},
    'radial': {'gain': 1.5, 'power': 4.0},
    'disparity_quantization': {'step_px': 0.125, 'lattice_scale': 1.0, 'where': 'after'},
    'incidence_angle': {'power': 1.3, 'max_deg': 78.0},
    'vertical_stripes': {'offset_px': 0.12, 'mean_width_px': 0.0, 'change': 0.35, 'rho': 0.6},
    'depth_distortion': {'space': 'disparity', 'amplitude_px': 0.25, 'alpha1': 0.012},
    'interference': {'gain': 1.2, 'hole_rate': 0.02},
    'temporal_drift': {'form': 'scale', 'amplitude': 0.004, 'tau_frames': 6.0},
    # effects outside the vocabulary
    'row_bands': {'offset_px': 0.12, 'mean_height_px': 0.0},
    'intensity': {'gain': 2.0, 'dark': 0.07, 'bias_px': 0.0},
    'correlated': {'window_px': 9},
    'temporal_ar1': {'rho': 0.8},
}


def parse_effect(text):
    name, _, rest = text.partition(':')
    if name not in EFFECTS:
        raise SystemExit('independent_walls.py: unknown effect %r (known: %s)' % (name, ', '.join(EFFECTS)))
    params = dict(EFFECTS[name])
    for item in filter(None, rest.split(',')):
        key, _, value = item.partition('=')
        if key not in params:
            raise SystemExit('independent_walls.py: effect %s has no parameter %r' % (name, key))
        params[key] = type(params[key])(value) if not isinstance(params[key], str) else value
    return name, params


def rotation(tilt_x_deg, tilt_y_deg):
    ax, ay = math.radians(tilt_x_deg), math.radians(tilt_y_deg)
    rx = np.array([[1, 0, 0], [0, math.cos(ax), -math.sin(ax)], [0, math.sin(ax), math.cos(ax)]])
    ry = np.array([[math.cos(ay), 0, math.sin(ay)], [0, 1, 0], [-math.sin(ay), 0, math.cos(ay)]])
    return ry @ rx


def wall(args):
    """Depth (m) along the optical axis and cos(incidence) of the plane at every pixel."""
    u, v = np.meshgrid(np.arange(args.width, dtype=float), np.arange(args.height, dtype=float))
    rays = np.stack([(u - args.cx) / args.fx, (v - args.cy) / args.fy, np.ones_like(u)], axis=-1)
    normal = rotation(args.tilt_x, args.tilt_y) @ np.array([0.0, 0.0, -1.0])
    point = np.array([0.0, 0.0, args.distance])
    z = (normal @ point) / (rays @ normal)
    cos_inc = np.abs(rays @ normal) / np.linalg.norm(rays, axis=-1)
    return u, v, z, cos_inc


def bands(rng, length, mean_width):
    """Band index of each of `length` columns (or rows): widths drawn from an exponential law."""
    out = np.empty(length, dtype=int)
    pos, band = 0, 0
    while pos < length:
        w = max(2, int(rng.exponential(mean_width)))
        out[pos:pos + w] = band
        pos, band = pos + w, band + 1
    return out


def box_filter(noise, w):
    """Mean over a w x w window (wrapping at the borders), scaled back to unit variance."""
    c = np.cumsum(np.cumsum(np.pad(noise, ((w, 0), (w, 0)), mode='wrap'), axis=0), axis=1)
    s = c[w:, w:] - c[:-w, w:] - c[w:, :-w] + c[:-w, :-w]
    return s / w  # the sum of w^2 unit normals has SD w


def printed_albedo(rng, u, v, width):
    """A printed wall: soft blobs and bars of grey from 0.05 to 1 (reflectivity)."""
    a = np.full(u.shape, 0.65)
    for _ in range(14):
        cu, cv, s = rng.uniform(0, u.max()), rng.uniform(0, v.max()), rng.uniform(0.04, 0.14) * width
        a -= rng.uniform(0.3, 0.6) * np.exp(-((u - cu) ** 2 + (v - cv) ** 2) / (2 * s * s))
    a += 0.3 * (np.sin(2 * math.pi * u / (0.37 * width)) > 0.6)
    return np.clip(a, 0.05, 1.0)


def main():
    p = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    p.add_argument('out')
    p.add_argument('--width', type=int, default=320)
    p.add_argument('--height', type=int, default=240)
    p.add_argument('--frames', type=int, default=20)
    p.add_argument('--distance', type=float, default=1.5, help='metres along the optical axis')
    p.add_argument('--tilt-x', type=float, default=0.0)
    p.add_argument('--tilt-y', type=float, default=0.0)
    p.add_argument('--seed', type=int, default=1)
    p.add_argument('--sensor-seed', type=int, default=-1,
                   help="the sensor's own draws (the distortion map); default: --seed")
    p.add_argument('--noise-in', choices=['depth', 'disparity'], default='depth')
    p.add_argument('--projectors', type=int, default=1)
    p.add_argument('--fx', type=float, default=0.0, help='default 571.3 x width / 640')
    p.add_argument('--baseline', type=float, default=0.0752)
    p.add_argument('--effect', action='append', default=[])
    args = p.parse_args()
    if args.width < 16 or args.height < 16 or args.frames < 1 or not 0.3 < args.distance < 8:
        raise SystemExit('independent_walls.py: bad size, frame count or distance')
    if os.path.exists(args.out):
        raise SystemExit('independent_walls.py: %s exists' % args.out)
    effects = dict(parse_effect(e) for e in args.effect)
    args.fx = args.fx or 571.3 * args.width / 640
    args.fy = args.fx * 1.003
    args.cx, args.cy = args.width / 2 + 2.7 * args.width / 640, args.height / 2 - 1.9 * args.width / 640
    rng = np.random.default_rng(args.seed)
    fb = args.fx * args.baseline  # px m

    u, v, z0, cos_inc = wall(args)
    r = np.hypot(u - args.width / 2, v - args.height / 2)  # the paper's r: from the image centre
    d_mm = 1000 * z0
    sd = PAPER[0] + PAPER[1] * r + PAPER[2] * d_mm + PAPER[3] * r * r + PAPER[4] * r * d_mm + PAPER[5] * d_mm * d_mm
    sd = np.maximum(sd, 0.3)  # mm; the paper's fit is for 0.7 to 1.75 m
    j = 1000 * z0 * z0 / fb  # mm of depth per px of disparity
    valid = np.ones(z0.shape, dtype=bool)
    static_bias = np.zeros(z0.shape)  # mm
    static_disparity_px = np.zeros(z0.shape)  # added to the disparity, px
    albedo = None

    if 'axial_quadratic' in effects:
        sd = np.hypot(sd, effects['axial_quadratic']['sigma_px'] * j)
    if 'radial' in effects:
        e = effects['radial']
        corner = math.hypot(args.width / 2, args.height / 2)
        sd = sd * (1 + e['gain'] * (r / corner) ** e['power'])
    if 'incidence_angle' in effects:
        e = effects['incidence_angle']
        sd = sd * np.power(1 / np.maximum(cos_inc, 0.05), e['power'])
        valid &= cos_inc > math.cos(math.radians(e['max_deg']))
    if 'interference' in effects:
        sd = sd * math.sqrt(1 + effects['interference']['gain'] * (args.projectors - 1))
    if 'intensity' in effects:
        e = effects['intensity']
        albedo = printed_albedo(rng, u, v, args.width)
        sd = sd * (1 + e['gain'] * (1 - albedo) ** 2)
        valid &= albedo > e['dark']
        # A dim dot's centroid is found off its place: a disparity offset growing with the darkness.
        static_disparity_px += e['bias_px'] * (1 - albedo) ** 1.5
    if 'depth_distortion' in effects:
        e = effects['depth_distortion']
        x, y = (u - args.cx) / args.width, (v - args.cy) / args.width
        if e['space'] == 'disparity':
            # Herrera et al. 2012: a per-pixel map D(u, v) times exp(alpha0 - alpha1 d), d the
            # raw disparity; here D is a bowl plus a few smooth bumps, alpha1 per px of disparity.
            field = 0.6 * (x * x + y * y) / 0.3125
            # The map belongs to the sensor: the same in every recording made with one --sensor-seed.
            sensor = np.random.default_rng(args.sensor_seed if args.sensor_seed >= 0 else args.seed)
            for _ in range(5):
                cx, cy, s = sensor.uniform(-0.5, 0.5), sensor.uniform(-0.4, 0.4), sensor.uniform(0.12, 0.3)
                field += sensor.choice([-1, 1]) * 0.5 * np.exp(-((x - cx) ** 2 + (y - cy) ** 2) / (2 * s * s))
            d = fb / z0
            d_ref = fb / 1.5
            # Applied to the disparity itself (below), as the toolbox corrects it: in depth, -j delta
            # is only its first order, off by j delta^2 / d (tens of mm where delta is a good part
            # of a pixel and d is small).
            static_disparity_px += e['amplitude_px'] * field * np.exp(-e['alpha1'] * (d - d_ref) * 640 / args.width)
        else:
            rho2 = x * x + y * y
            static_bias += d_mm * (0.004 * rho2 - 0.006 * rho2 * rho2) * e['amplitude_px'] / 0.25

    step = effects.get('disparity_quantization', {}).get('step_px', 0.125)
    lattice = 1000 * fb / step * effects.get('disparity_quantization', {}).get('lattice_scale', 1.0)  # z_k = C / k, mm
    stripes = effects.get('vertical_stripes')
    rowb = effects.get('row_bands')
    if stripes:
        stripes['mean_width_px'] = stripes['mean_width_px'] or args.width / 7
        col_band = bands(rng, args.width, stripes['mean_width_px'])
        band_offset = rng.normal(0, stripes['offset_px'], col_band.max() + 1)
    ar1 = None
    os.makedirs(os.path.join(args.out, 'depth'))
    if albedo is not None:
        os.makedirs(os.path.join(args.out, 'rgb'))
    for t in range(args.frames):
        offset_mm = np.zeros(z0.shape)
        scale = 1.0
        if 'temporal_drift' in effects:
            e = effects['temporal_drift']
            warm = math.exp(-t / e['tau_frames'])
            if e['form'] == 'scale':  # the focal length or baseline changes: depth scales
                scale = 1 + e['amplitude'] * warm
            else:  # the pattern shifts: a disparity offset
                offset_mm += -j * e['amplitude'] * warm
        if stripes:
            if t > 0 and rng.uniform() < stripes['change']:
                col_band = bands(rng, args.width, stripes['mean_width_px'])
                band_offset = rng.normal(0, stripes['offset_px'], col_band.max() + 1)
            else:  # the band offsets wander
                band_offset = stripes['rho'] * band_offset + math.sqrt(1 - stripes['rho'] ** 2) * rng.normal(
                    0, stripes['offset_px'], band_offset.size)
            offset_mm += -j * band_offset[col_band][None, :]
        if rowb:
            row_band = bands(rng, args.height, rowb['mean_height_px'] or args.height / 8)
            offset_mm += -j * rng.normal(0, rowb['offset_px'], row_band.max() + 1)[row_band][:, None]
        white = rng.standard_normal(z0.shape)
        if 'correlated' in effects:
            white = box_filter(white, effects['correlated']['window_px'])
        if 'temporal_ar1' in effects:
            rho = effects['temporal_ar1']['rho']
            ar1 = white if ar1 is None else rho * ar1 + math.sqrt(1 - rho * rho) * white
            white = ar1
        truth_mm = d_mm * scale + static_bias + offset_mm
        truth_mm = 1000 * fb / (1000 * fb / truth_mm + static_disparity_px)
        where = effects.get('disparity_quantization', {}).get('where')
        if where == 'before':
            truth_mm = lattice / np.maximum(1, np.round(lattice / truth_mm))
        elif where == 'both':  # camera.yaml's lattice before the noise, the sensor's own after it
            camera_lattice = 1000 * fb / step
            truth_mm = camera_lattice / np.maximum(1, np.round(camera_lattice / truth_mm))
        if args.noise_in == 'depth':
            z_mm = truth_mm + sd * white
        else:
            fb_mm = 1000 * fb
            z_mm = fb_mm / (fb_mm / truth_mm + sd / j * white)
        if where in ('after', 'both'):
            z_mm = lattice / np.maximum(1, np.round(lattice / z_mm))
        ok = valid.copy()
        if 'interference' in effects and args.projectors > 1:
            holes = rng.uniform(size=z0.shape) < effects['interference']['hole_rate'] * (args.projectors - 1)
            ok &= ~holes
        depth = np.where(ok & (z_mm > 400) & (z_mm < 8000), np.round(z_mm), 0).astype(np.uint16)
        Image.fromarray(depth, mode='I;16').save(os.path.join(args.out, 'depth', '%06d.png' % t))
        if albedo is not None:
            grey = (255 * albedo).astype(np.uint8)
            Image.fromarray(np.stack([grey] * 3, axis=-1), mode='RGB').save(os.path.join(args.out, 'rgb', '%06d.png' % t))

    K = [args.fx, 0, args.cx, 0, args.fy, args.cy, 0, 0, 1]
    with open(os.path.join(args.out, 'camera.yaml'), 'w') as f:
        f.write('image_width: %d\nimage_height: %d\n' % (args.width, args.height))
        f.write('camera_matrix:\n  rows: 3\n  cols: 3\n  data: [%s]\n' % ', '.join(repr(float(k)) for k in K))
        f.write('distortion_model: plumb_bob\ndistortion_coefficients:\n  rows: 1\n  cols: 5\n  data: [0, 0, 0, 0, 0]\n')
        f.write('baseline_m: %r\ndisparity_subpixel: 0.125\n' % args.baseline)
    with open(os.path.join(args.out, 'meta.yaml'), 'w') as f:
        f.write('generator: independent_walls.py\nscene: plane\nprojectors: %d\n' % args.projectors)
    with open(os.path.join(args.out, 'truth.yaml'), 'w') as f:
        f.write('# what independent_walls.py hid in this recording (for tests; the lab never reads it)\n')
        f.write('seed: %d\nnoise_in: %s\nlattice_constant_mm: %r\n' % (args.seed, args.noise_in, lattice))
        f.write('effects:\n' + ''.join('  %s: {%s}\n' % (n, ', '.join('%s: %s' % kv for kv in e.items()))
                                         for n, e in effects.items()) if effects else 'effects: {}\n')


if __name__ == '__main__':
    main()
