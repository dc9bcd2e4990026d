#!/usr/bin/env python3
"""What order-n SH occlusion (S3HO) can do for an idealised courtyard under
a given sky (issue 16; the README's S3HO section quotes its output).

Run by hand, never in CI. The sky: Himmel's equirect EXR of the instant and
its --stats (as tools/world_reference.py makes them in its --work folder),
the Sun and Moon disks removed as that tool removes them. The courtyard: a
floor point at (0, 0, z) between four walls of height `--wall-h` at
±`--half` m (the atrium's outer walls), its exact visibility V(ω). For each
point it prints, as fractions of the open floor's sky irradiance:

* truth: ∫ L V cos dω / ∫ L cos dω;
* S3HO of order n (the wgpu lighting pass's form): E_open − Σ L_lm
  (T_open,lm − T_lm), with L_lm the radiance's and T_lm = ∫ V cos Y_lm dω
  the transfer's real SH coefficients up to order n;
* scalar AO: ∫ V cos dω / π.

    /tmp/venv/bin/python tools/s3ho_ideal.py \\
        --env /tmp/himmel-world-ref/2024-12-21T11_45_00Z_56.5_10.0_0_env_disks.exr \\
        --stats /tmp/himmel-world-ref/2024-12-21T11_45_00Z_56.5_10.0_0_env_disks_stats.json
"""

import argparse
import json
import math
import os
import sys

import numpy as np
from scipy.special import sph_harm_y

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import world_reference as wr  # noqa: E402


def real_sh(d, order):
    """Real orthonormal SH up to `order` at unit directions d (..., 3), the
    polar axis +y (up); rows (order + 1)²."""
    theta = np.arccos(np.clip(d[..., 1], -1.0, 1.0))
    phi = np.arctan2(d[..., 0], d[..., 2])
    out = []
    for l in range(order + 1):
        for m in range(-l, l + 1):
            y = sph_harm_y(l, abs(m), theta, phi)
            if m < 0:
                out.append(math.sqrt(2.0) * (-1) ** m * y.imag)
            elif m == 0:
                out.append(y.real)
            else:
                out.append(math.sqrt(2.0) * (-1) ** m * y.real)
    return np.array(out)


def wall_elevation(d, z, half, wall_h):
    """Elevation (rad) of the walls' top seen from (0, 0, z) along the
    horizontal part of each direction."""
    hx, hz = d[..., 0], d[..., 2]
    n = np.hypot(hx, hz) + 1e-12
    ux, uz = hx / n, hz / n
    big = 1e9
    tx = np.where(np.abs(ux) > 1e-9, half / np.maximum(np.abs(ux), 1e-9), big)
    tz = np.where(uz > 1e-9, (half - z) / np.maximum(uz, 1e-9),
                  np.where(uz < -1e-9, (half + z) / np.maximum(-uz, 1e-9), big))
    return np.arctan2(wall_h, np.minimum(tx, tz))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--env", required=True)
    ap.add_argument("--stats", required=True)
    ap.add_argument("--half", type=float, default=13.0)
    ap.add_argument("--wall-h", type=float, default=8.0)
    ap.add_argument("--z", type=float, nargs="+", default=[-8.0, 0.0, 7.0, 9.5])
    ap.add_argument("--orders", type=int, nargs="+", default=[2, 3, 6])
    args = ap.parse_args()
    wr.setup_mitsuba("scalar_rgb")
    env, _ = wr.remove_disks(wr.read_exr_rgb(args.env), json.load(open(args.stats)))
    h, w = env.shape[:2]
    d, domega, _ = wr.equirect_dirs(h, w)
    lum = wr.luminance(env)
    cos = np.clip(d[..., 1], 0.0, None)
    alt = np.arcsin(np.clip(d[..., 1], -1.0, 1.0))
    e_open = (lum * cos * domega).sum()
    vis = {z: alt > wall_elevation(d, z, args.half, args.wall_h) for z in args.z}
    print(f"open floor: {e_open:.1f} lux (sky without the disks)")
    print("z (m): " + ", ".join(f"{z:g}" for z in args.z))
    print("truth: " + ", ".join(
        f"{(lum * v * cos * domega).sum() / e_open:.3f}" for v in vis.values()))
    print("scalar AO: " + ", ".join(
        f"{(v * cos * domega).sum() / math.pi:.3f}" for v in vis.values()))
    for order in args.orders:
        b = real_sh(d, order)
        l_lm = (b * lum * domega).sum(axis=(1, 2))
        t_open = (b * cos * domega).sum(axis=(1, 2))
        row = []
        for v in vis.values():
            t = (b * v * cos * domega).sum(axis=(1, 2))
            row.append((e_open - (l_lm * (t_open - t)).sum()) / e_open)
        print(f"S3HO order {order}: " + ", ".join(f"{r:.3f}" for r in row))


if __name__ == "__main__":
    main()
