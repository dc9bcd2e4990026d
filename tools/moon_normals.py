#!/usr/bin/env python3
"""Converts Stellarium's lunar normal map (Debian stellarium-data 0.22.2,
textures/moon_normals.png, 1024x512 RGB tangent-space normals; same
public-domain sources as textures/moon.png) into the 512x256 two-channel map
the Moon pass embeds: skymodel/data/moon_normals_512x256.u8 (row-major, north
row first, longitude -180 at the left edge; per texel two bytes, the normal's
east and north components as round(127.5 * (c + 1)), clamped to 0..255).

The source stores x = east and y = SOUTH (image-down): on the inner walls of
Copernicus, Tycho and Theophilus the east wall has x < 0 (it faces west, to
the centre) and the north wall y > 0; this script flips y to north. Never run
in CI.

usage: tools/moon_normals.py /path/to/moon_normals.png skymodel/data/moon_normals_512x256.u8
"""
import sys
import numpy as np
from PIL import Image

src, dst = sys.argv[1], sys.argv[2]
a = np.asarray(Image.open(src).convert("RGB"), dtype=np.float64) / 255.0 * 2.0 - 1.0
# 2x2 box downsampling of the vectors, then renormalise.
a = a.reshape(256, 2, 512, 2, 3).mean(axis=(1, 3))
a /= np.linalg.norm(a, axis=2, keepdims=True)
east, north = a[..., 0], -a[..., 1]
out = np.stack([east, north], axis=-1)
np.clip(np.round(127.5 * (out + 1.0)), 0, 255).astype(np.uint8).tofile(dst)
