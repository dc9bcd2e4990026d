#!/usr/bin/env python3
"""Reference apparent places of bright stars (never run in CI).

Skyfield 1.55 `Star` objects built from the very catalogue values embedded in
himmel-catalog (catalog/data/stars.bin, decoded here: ICRS position at
J1991.25, proper motion, parallax; radial velocity 0), observed from DE421's
Earth plus a WGS84 observer, `.apparent()` (light deflection by the Sun,
Jupiter, Saturn; aberration with the observer's barycentric velocity including
the Earth's rotation), true equator and equinox of date (IAU 2006/2000A) and
unrefracted topocentric alt/az. Time: TT is given to both; UT1 is recorded
from Skyfield's time scale (finals2000A.all) so that the comparison tests the
astrometry and not the ΔT models.

Usage: python3 tools/gen_star_fixtures.py   -> tests/fixtures/stars_skyfield.json
"""
import json
import math
import os
import random
import struct

import erfa
import skyfield_data
from skyfield.api import Loader, Star, wgs84

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.join(HERE, "..")
DATA = os.path.join(os.path.dirname(skyfield_data.__file__), "data")
load = Loader(DATA)
ts = load.timescale(builtin=False)
eph = load("de421.bsp")
earth = eph["earth"]


def read_catalog():
    b = open(os.path.join(ROOT, "catalog", "data", "stars.bin"), "rb").read()
    assert b[:4] == b"HMSC"
    ver, rec, n, nnames, slen, epoch = struct.unpack_from("<HHIIId", b, 4)
    off = 4 + struct.calcsize("<HHIIId")
    stars = []
    for i in range(n):
        hip, hr, ni, ra, dec, pmra, pmdec, plx, v, bv = struct.unpack_from("<IHHIiiiihh", b, off + i * rec)
        stars.append(dict(hip=hip, name_index=ni, ra=ra / 2**32 * 2 * math.pi,
                          dec=dec / 2**32 * math.pi, pmra=pmra / 100, pmdec=pmdec / 100,
                          plx=plx / 100, v=v / 1000))
    p = off + n * rec
    names = []
    for i in range(nnames):
        ent = []
        for _ in range(4):
            ln = b[p]
            ent.append(b[p + 1:p + 1 + ln].decode("utf-8"))
            p += 1 + ln
        names.append(ent)
    for s in stars:
        s["name"] = names[s["name_index"]][0] if s["name_index"] != 0xFFFF else ""
    return stars, epoch


def main():
    stars, epoch = read_catalog()
    bright = [s for s in stars if s["name"]][:30]
    rng = random.Random(4)
    observers = [(-89.9, 33.0, 0.0), (51.4769, -0.0005, 46.0), (-33.9249, 18.4241, 10.0),
                 (19.8207, -155.468, 4205.0), (64.1, -179.9, 0.0)]
    cases = []
    for _ in range(24):
        year = rng.uniform(1950.0, 2050.0)
        jd_tt = 2451545.0 + (year - 2000.0) * 365.25
        t = ts.tt_jd(jd_tt)
        for (lat, lon, h) in observers:
            topos = earth + wgs84.latlon(lat, lon, elevation_m=h)
            obs = topos.at(t)
            for s in bright:
                star = Star(ra_hours=math.degrees(s["ra"]) / 15.0, dec_degrees=math.degrees(s["dec"]),
                            ra_mas_per_year=s["pmra"], dec_mas_per_year=s["pmdec"],
                            parallax_mas=s["plx"], radial_km_per_s=0.0, epoch=epoch)
                app = obs.observe(star).apparent()
                alt, az, _ = app.altaz()
                cases.append(dict(hip=s["hip"], jd_tt=jd_tt, jd_ut1=float(t.ut1),
                                  lat=lat, lon=lon, elevation_m=h,
                                  alt_deg=alt.degrees, az_deg=az.degrees))
        # Geocentric apparent places, true equator and equinox of date.
        g = earth.at(t)
        for s in bright:
            star = Star(ra_hours=math.degrees(s["ra"]) / 15.0, dec_degrees=math.degrees(s["dec"]),
                        ra_mas_per_year=s["pmra"], dec_mas_per_year=s["pmdec"],
                        parallax_mas=s["plx"], radial_km_per_s=0.0, epoch=epoch)
            ra, dec, _ = g.observe(star).apparent().radec(epoch="date")
            cases.append(dict(hip=s["hip"], jd_tt=jd_tt, jd_ut1=float(t.ut1), geocentric=True,
                              ra_deg=ra._degrees, dec_deg=dec.degrees))
    # ±100 years from the catalogue epoch (outside DE421): SOFA/ERFA
    # (IAU 2006/2000A, its own Earth ephemeris epv00). Catalogue propagated
    # to J2000 with eraPmsafe, then eraAtci13 (ICRS -> CIRS: space motion,
    # parallax, light deflection, aberration, bias-precession-nutation) and
    # RA(true equinox) = RA(CIRS) - equation of the origins.
    for year in [1891.25, 1895.0, 1925.6, 2060.3, 2075.0, 2091.25]:
        jd_tt = 2451545.0 + (year - 2000.0) * 365.25
        for s in bright:
            pmr = s["pmra"] / 1000.0 / 3600.0 * math.pi / 180.0 / math.cos(s["dec"])
            pmd = s["pmdec"] / 1000.0 / 3600.0 * math.pi / 180.0
            r2, d2, pr2, pd2, px2, rv2 = erfa.pmsafe(s["ra"], s["dec"], pmr, pmd, s["plx"] / 1000.0, 0.0,
                                                      epoch, 0.0, 2451545.0, 0.0)
            ri, di, eo = erfa.atci13(r2, d2, pr2, pd2, px2, rv2, jd_tt, 0.0)
            cases.append(dict(hip=s["hip"], jd_tt=jd_tt, jd_ut1=jd_tt, geocentric=True, erfa=True,
                              ra_deg=math.degrees(erfa.anp(ri - eo)), dec_deg=math.degrees(di)))
    out = dict(
        source="tools/gen_star_fixtures.py: Skyfield 1.55 Star + DE421 Earth, catalogue values of "
               "catalog/data/stars.bin, radial velocity 0, unrefracted; 'erfa' cases: pyerfa pmsafe+atci13",
        stars=[dict(hip=s["hip"], name=s["name"], vmag=s["v"]) for s in bright],
        cases=cases)
    path = os.path.join(ROOT, "tests", "fixtures", "stars_skyfield.json")
    with open(path, "w") as f:
        json.dump(out, f, indent=0)
    print(len(cases), "cases ->", path)
    print([s["name"] for s in bright])


if __name__ == "__main__":
    main()
