#!/usr/bin/env python3
"""The Milky Way brightness map of himmel-skymodel (never run in CI).

Input: Stellarium 0.22.2 (Debian `stellarium-data`) `textures/milkyway.png`,
2048×1024 RGBA, the all-sky panorama by Axel Mellinger (Mellinger 2009, PASP
121, 1180), processed by Stellarium (stars removed, background subtracted).
Licence: "Modify and redistribute this image if proper credit to the original
image is given" (Stellarium's copyright file, §4.6).

Frame (determined by `check_frame` below against M42, the LMC, the SMC, M31,
the Pleiades and η Car, all found within 0.3°): plate carrée in ICRS/J2000
equatorial coordinates, right ascension α = 90° − 360°·u (mod 360°, u = x/W:
α = 270° at the centre, increasing to the LEFT as seen from inside the
sphere), declination δ = 90° − 180°·v (v = y/H).

Output: skymodel/data/milkyway.bin, "HMMW", u16 version 1, u16 width,
u16 height, u16 reserved, f32 scale, then width×height×3 u8 sRGB-encoded
samples (box-filtered in linear light). `scale` turns the linearised sample
luminance Y (0..1) into cd/m²: the mean of scale·Y over |b| < 5° equals the
integrated starlight of the galactic equator above the galactic-pole level,
both without the catalogue stars that the renderer draws as points
((BAND_S10 − catalogue |b| < 5°) − (POLE_S10 − catalogue |b| > 60°), in S10
converted to cd/m²; the catalogue's flux densities are computed here from
catalog/data/stars.bin, every star with V ≤ 6.5).

Usage: python3 tools/gen_milkyway.py /path/to/milkyway.png
"""
import math
import os
import struct
import sys

import numpy as np
from PIL import Image

HERE = os.path.dirname(os.path.abspath(__file__))
OUT = os.path.join(HERE, "..", "skymodel", "data", "milkyway.bin")
W, H = 512, 256

# Integrated starlight in V averaged over galactic longitude (Roach & Megill
# 1961, as tabulated by Leinert et al. 1998, A&AS 127, 1, §8): about 250 S10
# on the galactic equator and about 25 S10 at the galactic poles.
BAND_S10 = 250.0
POLE_S10 = 25.0
# One S10 (one V = 10 star per square degree): 2.54e-6 lx · 1e-4 / (π/180)² sr.
S10_CD_M2 = 2.54e-6 * 1e-4 / (math.pi / 180.0) ** 2

# ICRS → galactic rotation (Hipparcos catalogue, vol. 1, §1.5.3).
ICRS_TO_GAL = np.array([
    [-0.0548755604, -0.8734370902, -0.4838350155],
    [0.4941094279, -0.4448296300, 0.7469822445],
    [-0.8676661490, -0.1980763734, 0.4559837762],
])


def srgb_to_linear(c):
    c = c / 255.0
    return np.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4)


def linear_to_srgb(x):
    x = np.clip(x, 0.0, 1.0)
    return np.where(x <= 0.0031308, 12.92 * x, 1.055 * x ** (1 / 2.4) - 0.055) * 255.0


def radec_of_pixels(w, h):
    u = (np.arange(w) + 0.5) / w
    v = (np.arange(h) + 0.5) / h
    U, V = np.meshgrid(u, v)
    ra = np.radians((90.0 - 360.0 * U) % 360.0)
    dec = np.radians(90.0 - 180.0 * V)
    return ra, dec


def catalogue_s10():
    """Mean surface brightness (S10) of the embedded catalogue's stars
    (V ≤ 6.5) at |b| < 5° and at |b| > 60°."""
    b = open(os.path.join(HERE, "..", "catalog", "data", "stars.bin"), "rb").read()
    assert b[:4] == b"HMSC"
    _, _, n, _, _, _ = struct.unpack_from("<HHIIId", b, 4)
    off = 4 + struct.calcsize("<HHIIId")
    lat, flux = [], []
    for i in range(n):
        r = b[off + 32 * i: off + 32 * (i + 1)]
        _, _, _, ra, dec = struct.unpack_from("<IHHIi", r, 0)
        ra, dec = ra * 2 * math.pi / 2 ** 32, dec * math.pi / 2 ** 32
        v = struct.unpack_from("<h", r, 28)[0] * 0.001
        x = np.array([math.cos(dec) * math.cos(ra), math.cos(dec) * math.sin(ra), math.sin(dec)])
        lat.append(math.degrees(math.asin((ICRS_TO_GAL @ x)[2])))
        flux.append(10 ** (-0.4 * (v - 10.0)))
    lat, flux = np.abs(np.array(lat)), np.array(flux)

    def density(lo, hi):
        area = 2 * 2 * math.pi * (math.sin(math.radians(hi)) - math.sin(math.radians(lo)))
        return flux[(lat >= lo) & (lat < hi)].sum() / (area * (180 / math.pi) ** 2)

    return density(0, 5), density(60, 90.001)


def check_frame(lin):
    """Centroids of compact features against their catalogue places."""
    y = lin.mean(axis=2)
    h, w = y.shape
    feats = {"M42": (83.82, -5.39, 8), "LMC": (80.89, -69.76, 40),
             "SMC": (13.19, -72.83, 25), "M31": (10.68, 41.27, 15),
             "Pleiades": (56.75, 24.12, 10), "eta Car": (161.26, -59.68, 10)}
    for name, (ra, de, r) in feats.items():
        x0 = int(((90.0 - ra) / 360.0) % 1.0 * w)
        y0 = int((90.0 - de) / 180.0 * h)
        ys = np.arange(max(0, y0 - r), min(h, y0 + r))
        xs = np.arange(x0 - r, x0 + r)
        sub = y[np.ix_(ys, xs % w)]
        s = np.clip(sub - np.median(sub), 0, None) ** 2
        cy = (s.sum(1) @ (ys + 0.5)) / s.sum()
        cx = (s.sum(0) @ (xs + 0.5)) / s.sum()
        ra_f = (90.0 - cx / w * 360.0) % 360.0
        de_f = 90.0 - cy / h * 180.0
        d_ra = ((ra_f - ra + 180) % 360 - 180) * math.cos(math.radians(de))
        print(f"{name:9s} offset {d_ra:+.2f}° RA·cosδ, {de_f - de:+.2f}° Dec")
        assert abs(d_ra) < 0.4 and abs(de_f - de) < 0.4, name


def main():
    src = sys.argv[1] if len(sys.argv) > 1 else "/work/wt/assets/milkyway.png"
    img = np.asarray(Image.open(src).convert("RGB")).astype(np.float64)
    lin = srgb_to_linear(img)
    check_frame(lin)
    fy, fx = img.shape[0] // H, img.shape[1] // W
    small = lin.reshape(H, fy, W, fx, 3).mean(axis=(1, 3))
    Y = small @ np.array([0.2126, 0.7152, 0.0722])
    ra, dec = radec_of_pixels(W, H)
    x = np.stack([np.cos(dec) * np.cos(ra), np.cos(dec) * np.sin(ra), np.sin(dec)], -1)
    b = np.degrees(np.arcsin(np.clip((x @ ICRS_TO_GAL.T)[..., 2], -1, 1)))
    band = np.abs(b) < 5.0
    wgt = np.cos(dec)
    mean_band = (Y * wgt)[band].sum() / wgt[band].sum()
    cat_band, cat_pole = catalogue_s10()
    floor = POLE_S10 - cat_pole
    target = (BAND_S10 - cat_band) - floor
    print(f"catalogue stars: {cat_band:.1f} S10 at |b|<5°, {cat_pole:.1f} S10 at |b|>60°;"
          f" diffuse floor {floor:.1f} S10, map band mean {target:.1f} S10")
    scale = target * S10_CD_M2 / mean_band
    print(f"mean linear Y on |b|<5°: {mean_band:.5f}; scale {scale:.4e} cd/m² per unit")
    enc = np.round(linear_to_srgb(small)).astype(np.uint8)
    with open(OUT, "wb") as f:
        f.write(b"HMMW")
        f.write(struct.pack("<HHHHf", 1, W, H, 0, scale))
        f.write(enc.tobytes())
    print(f"wrote {OUT} ({os.path.getsize(OUT)} bytes)")


if __name__ == "__main__":
    main()
