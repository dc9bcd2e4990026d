#!/usr/bin/env python3
"""Reference values for the tests of astro/src/planets (run by hand, never in CI).

1. Heliocentric geometric positions from JPL DE421 (Skyfield + skyfield_data's
   de421.bsp), expressed in the frame of VSOP87D: ecliptic and mean equinox of
   date. Skyfield's `mean_equator_and_equinox_of_date` frame (frame bias and IAU
   2006 precession) is rotated about x by the IAU 2006 mean obliquity of date.
   Printed as (L°, B°, R AU) per planet and date; TT is used as TDB.
2. Apparent visual magnitudes from Astronomy Engine (`astronomy.Illumination`),
   with the inputs r, Δ, phase angle and Saturn's ring tilt that Astronomy Engine
   itself reports, for a loose comparison with the Astronomical Almanac formulas.

    python3 tools/check_vsop87.py
"""

import math
import os

import numpy as np
import skyfield_data
import astronomy
from skyfield.api import load_file, load
from skyfield import framelib
from skyfield.nutationlib import mean_obliquity

ts = load.timescale(builtin=True)
eph = load_file(os.path.join(os.path.dirname(skyfield_data.__file__), "data", "de421.bsp"))

BODIES = {
    "Mercury": "mercury",
    "Venus": "venus",
    "Earth": "earth",
    "Mars": "mars barycenter",
    "Jupiter": "jupiter barycenter",
    "Saturn": "saturn barycenter",
}

DATES_TT = [2415020.5, 2433282.5, 2448908.5, 2448976.5, 2451545.0, 2460000.5, 2469807.5]


def helio_ecliptic_of_date(name, jd_tt):
    t = ts.tt_jd(jd_tt)
    sun = eph["sun"].at(t)
    body = eph[BODIES[name]].at(t)
    p = body.position.au - sun.position.au
    r_eq = framelib.mean_equator_and_equinox_of_date.rotation_at(t)
    x, y, z = r_eq @ p
    eps = mean_obliquity(t.tdb) / 3600.0 * math.pi / 180.0
    ye = math.cos(eps) * y + math.sin(eps) * z
    ze = -math.sin(eps) * y + math.cos(eps) * z
    r = math.sqrt(x * x + ye * ye + ze * ze)
    lon = math.degrees(math.atan2(ye, x)) % 360.0
    lat = math.degrees(math.asin(ze / r))
    return lon, lat, r


def main():
    print("// DE421 heliocentric, ecliptic & mean equinox of date: (planet, jd_tt, L deg, B deg, R au)")
    for name in BODIES:
        for jd in DATES_TT:
            lon, lat, r = helio_ecliptic_of_date(name, jd)
            print(f"    (Planet::{name}, {jd:.1f}, {lon:.7f}, {lat:.7f}, {r:.9f}),")

    print("// Astronomy Engine magnitudes: (planet, jd_tt, r au, delta au, phase deg, ring tilt deg, mag)")
    ae = {
        "Mercury": astronomy.Body.Mercury,
        "Venus": astronomy.Body.Venus,
        "Mars": astronomy.Body.Mars,
        "Jupiter": astronomy.Body.Jupiter,
        "Saturn": astronomy.Body.Saturn,
    }
    for name, body in ae.items():
        for jd in [2448976.5, 2451545.0, 2455000.5, 2458000.5, 2460000.5, 2461000.5]:
            t = astronomy.Time(jd - 2451545.0)  # ut; TT−UT is irrelevant here
            ill = astronomy.Illumination(body, t)
            tilt = ill.ring_tilt if ill.ring_tilt is not None else 0.0
            print(
                f"    (Planet::{name}, {jd:.1f}, {ill.helio_dist:.6f}, {ill.geo_dist:.6f}, "
                f"{ill.phase_angle:.4f}, {tilt:.4f}, {ill.mag:.3f}),"
            )


if __name__ == "__main__":
    main()
