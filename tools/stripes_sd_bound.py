#!/usr/bin/env python3
"""How far can any noise model bring the per-pixel temporal SD error (the lab's sd_rmse_mm) down
on the proof's vertical-stripes recordings? A Monte-Carlo bound, no dependencies.

The recordings of test/test_lab.cpp (FindsVerticalStripes): 320 x 240 (f = 290 px, baseline
0.075 m), walls at 0.8 .. 3 m, 30 frames, the paper's base noise (Eq. 4, in depth, rounded to
whole mm), and vertical stripes with their defaults: 6 bands at random columns, each with a
disparity offset drawn from N(0, 0.125^2 px), a new layout every `period` frames. A pixel's
measured SD over the 30 frames then holds the sample variance of only 30 / period draws of its
column's offset, which no model can know. The best any model can predict for a pixel, in the RMS
sense, is the expected measured SD given its covariates, E[s | b, J] (b: base SD, J = z^2 / f b);
this script estimates that by simulation and reports the sd_rmse it leaves, as a share of the
paper model's (which predicts b alone). The lab's criterion is a share of 0.5 or less.

  python3 tools/stripes_sd_bound.py [period ...]      (default: 10 2)
"""
import math
import random
import sys

P = dict(p00=2.344, p10=-0.01202, p01=-0.002734, p20=1.818e-05, p11=6.516e-06, p02=1.233e-06)
FB = 290 * 0.075  # f b, px m
W, H, FRAMES, BANDS, OFFSET_PX = 320, 240, 30, 6, 0.125


def base_sd(r, z):
    return P["p00"] + P["p10"] * r + P["p01"] * z + P["p20"] * r * r + P["p11"] * r * z + P["p02"] * z * z


def sample_sd(x):
    m = sum(x) / len(x)
    return math.sqrt(sum((v - m) ** 2 for v in x) / (len(x) - 1))


def column_offsets(period, rng):
    """Per column, the disparity offset in each frame (a band's, redrawn every period frames)."""
    cols = [[0.0] * FRAMES for _ in range(W)]
    for epoch in range(0, FRAMES, period):
        bounds = [rng.randrange(1, W) for _ in range(BANDS - 1)]
        offsets = [rng.gauss(0.0, OFFSET_PX) for _ in range(BANDS)]
        for u in range(W):
            band = sum(1 for b in bounds if b <= u)
            for t in range(epoch, min(FRAMES, epoch + period)):
                cols[u][t] = offsets[band]
    return cols


def measured_sd(b, J, offs, rng):
    return sample_sd([round(J * offs[t] + rng.gauss(0.0, b)) for t in range(FRAMES)])


def bound(period, seed=1, pixels_per_column=2, draws=300):
    rng = random.Random(seed)
    se_paper = se_lab = se_best = 0.0
    for z in (800.0, 1350.0, 1900.0, 2450.0, 3000.0):
        J = z * z / (1000.0 * FB)
        cols = column_offsets(period, rng)
        for u in range(0, W, 4):
            for _ in range(pixels_per_column):
                v = rng.randrange(H)
                b = base_sd(math.hypot(u - W / 2, v - H / 2), z)
                s = measured_sd(b, J, cols[u], rng)
                # E[s | b, J]: the same pixel under fresh stripe layouts and noise.
                best = sum(measured_sd(b, J, column_offsets_one(period, rng), rng) for _ in range(draws)) / draws
                lab = math.sqrt(b * b + 1.0 / 12.0 + (OFFSET_PX * J) ** 2)  # the variance, as the lab predicts it
                se_paper += (s - b) ** 2
                se_lab += (s - lab) ** 2
                se_best += (s - best) ** 2
    return math.sqrt(se_lab / se_paper), math.sqrt(se_best / se_paper)


def column_offsets_one(period, rng):
    """One column's offsets per frame: a fresh N(0, OFFSET_PX^2) draw every period frames."""
    out = []
    for epoch in range(0, FRAMES, period):
        o = rng.gauss(0.0, OFFSET_PX)
        out += [o] * min(period, FRAMES - epoch)
    return out


if __name__ == "__main__":
    for period in [int(a) for a in sys.argv[1:]] or [10, 2]:
        lab, best = bound(period)
        print(f"period {period:2d} frames: sd_rmse / paper's: the lab's prediction (full variance) {lab:.3f}, "
              f"the best possible, E[s | covariates] {best:.3f}")
