#!/usr/bin/env python3
"""Fit Chebyshev polynomials to the geocentric Moon of JPL DE421 and write
astro/data/moon_de421.bin (plus a small check fixture) for himmel-astro's
high-accuracy Moon tier.

Source: JPL Development Ephemeris DE421 (Folkner, Williams & Boggs 2008,
IPN Progress Report 42-178), as distributed in `de421.bsp` by the PyPI
package `skyfield-data`. JPL ephemerides are produced by NASA/JPL and are in
the public domain. DE421 spans 1899-07-29 .. 2053-10-09 (TDB).

The geocentric Moon is the SPK segment Earth-Moon barycentre -> Moon (3 -> 301)
minus Earth-Moon barycentre -> Earth (3 -> 399), in km, ICRF axes, argument TDB.

File layout (all little-endian):
  offset  0: 8 bytes  magic b"MOONCHEB"
  offset  8: f64      start of the first interval, Julian day TDB
  offset 16: f64      interval length, days
  offset 24: u32      number of coefficients per component (degree + 1)
  offset 28: u32      number of intervals
  offset 32: f32 coefficients, interval-major, then component (x, y, z),
             then Chebyshev order 0..n-1, km.

Each interval is fitted by interpolation at the n Chebyshev-Gauss nodes
(near-minimax); coefficients are rounded to f32 (relative precision 6e-8,
~0.02 km on the 400 000 km leading terms). The script reports the largest
error it measured at 64 equally spaced points per interval, i.e. mostly
between the fit nodes, with the f32-rounded coefficients.

Run by hand (never in CI):  python3 tools/gen_moon_de421.py
"""
import json
import os
import struct

import numpy as np
import skyfield_data
from jplephem.spk import SPK

INTERVAL_DAYS = 32.0
NCOEF = 30
HERE = os.path.dirname(os.path.abspath(__file__))
OUT_BIN = os.path.join(HERE, "..", "astro", "data", "moon_de421.bin")
OUT_CHECK = os.path.join(HERE, "..", "astro", "data", "moon_de421_check.json")

kernel = SPK.open(os.path.join(os.path.dirname(skyfield_data.__file__), "data", "de421.bsp"))
emb_moon, emb_earth = kernel[3, 301], kernel[3, 399]


def geocentric_moon(jd_tdb):
    """Geocentric Moon, km, ICRF axes, shape (3, len(jd_tdb))."""
    return emb_moon.compute(jd_tdb) - emb_earth.compute(jd_tdb)


def write_fixture(path, header, rows):
    """JSON object with one row of numbers per line (diff-friendly)."""
    with open(path, "w") as fh:
        fh.write("{\n")
        for key, value in header.items():
            fh.write(f"{json.dumps(key)}: {json.dumps(value)},\n")
        fh.write('"rows": [\n')
        fh.write(",\n".join(json.dumps(r) for r in rows))
        fh.write("\n]}\n")
    json.load(open(path))  # must stay valid JSON


def main():
    start, end = emb_moon.start_jd, emb_moon.end_jd
    count = int((end - start) // INTERVAL_DAYS)
    n = NCOEF
    k = np.arange(n)
    nodes = np.cos(np.pi * (k + 0.5) / n)
    t0 = start + INTERVAL_DAYS * np.arange(count)
    jd = t0[:, None] + (nodes[None, :] + 1.0) * INTERVAL_DAYS / 2.0
    f = geocentric_moon(jd.ravel()).reshape(3, count, n)
    basis = np.cos(np.outer(np.arange(n), np.pi * (k + 0.5) / n))
    c = 2.0 / n * np.einsum("cik,jk->cij", f, basis)
    c[:, :, 0] *= 0.5
    c32 = c.astype(np.float32)

    # Error with the stored (f32) coefficients, 64 points per interval.
    m = 64
    xt = np.linspace(-1.0, 1.0, m)
    jdt = t0[:, None] + (xt[None, :] + 1.0) * INTERVAL_DAYS / 2.0
    truth = geocentric_moon(jdt.ravel()).reshape(3, count, m)
    fit = np.einsum("cij,mj->cim", c32.astype(np.float64), np.polynomial.chebyshev.chebvander(xt, n - 1))
    err_km = np.sqrt(((fit - truth) ** 2).sum(axis=0))
    dist_km = np.sqrt((truth**2).sum(axis=0))
    err_arcsec = err_km / dist_km * 206264.806

    with open(OUT_BIN, "wb") as fh:
        fh.write(b"MOONCHEB")
        fh.write(struct.pack("<ddII", start, INTERVAL_DAYS, n, count))
        fh.write(np.ascontiguousarray(c32.transpose(1, 0, 2)).astype("<f4").tobytes())
    size = os.path.getsize(OUT_BIN)
    covered_end = start + count * INTERVAL_DAYS
    print(f"span JD {start} .. {covered_end} ({count} intervals of {INTERVAL_DAYS} d, {n} coefficients)")
    print(f"wrote {OUT_BIN}: {size} bytes")
    print(f"max fit error {err_km.max():.4f} km = {err_arcsec.max():.5f} arcsec; "
          f"p99 {np.percentile(err_km, 99):.4f} km; median {np.median(err_km):.4f} km")

    # Check fixture: 50 instants spread over the span, off the nodes.
    rng = np.random.default_rng(421)
    jd_check = np.sort(rng.uniform(start, covered_end, 50))
    jd_check[0], jd_check[-1] = start + 0.123, covered_end - 0.377
    pos = geocentric_moon(jd_check)
    rows = [[float(j), *(float(v) for v in pos[:, i])] for i, j in enumerate(jd_check)]
    write_fixture(OUT_CHECK, {
        "source": "JPL DE421 (de421.bsp from PyPI skyfield-data) via jplephem: segment 3->301 minus 3->399",
        "generator": "tools/gen_moon_de421.py",
        "columns": ["jd_tdb", "x_km", "y_km", "z_km"],
    }, rows)
    print(f"wrote {OUT_CHECK}: {len(rows)} rows")


if __name__ == "__main__":
    main()
