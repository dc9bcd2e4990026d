#!/usr/bin/env python3
"""Converts Stellarium's lunar texture (Debian stellarium-data 0.22.2,
textures/moon.png, 1024x512 RGB, public domain: USGS Astrogeology + Celestia
Clementine maps) into the raw 8-bit grey map the Moon pass embeds:
skymodel/data/moon_albedo_1024x512.u8 (row-major, north row first, selenographic
longitude -180 at the left edge, 0 at the centre, east positive to the right;
the value is the grey Y = 0.2126 R + 0.7152 G + 0.0722 B of the stored
channel values; the Moon pass takes it as proportional to albedo). Never run in CI.

usage: tools/moon_albedo.py /path/to/moon.png skymodel/data/moon_albedo_1024x512.u8
"""
import sys
import numpy as np
from PIL import Image

src, dst = sys.argv[1], sys.argv[2]
a = np.asarray(Image.open(src).convert("RGB").resize((1024, 512), Image.LANCZOS), dtype=np.float64) / 255.0
y = 0.2126 * a[..., 0] + 0.7152 * a[..., 1] + 0.0722 * a[..., 2]
np.clip(np.round(y * 255.0), 0, 255).astype(np.uint8).tofile(dst)
