#!/usr/bin/env python3
"""Print SOFA/ERFA (PyPI `pyerfa`) and Skyfield reference values used by the
tests of astro/src/frames/ (run by hand; the numbers are pasted into tests).

    pip install pyerfa skyfield skyfield-data
    python3 tools/gen_frames_refs.py
"""
import erfa
import numpy as np


def mat(name, m):
    print(name)
    for row in m:
        print("    [" + ", ".join(repr(float(x)) for x in row) + "],")


def main():
    mat("eraPmat76(2400000.5, 61000.0)", erfa.pmat76(2400000.5, 61000.0))
    rb, _, _ = erfa.bp00(2400000.5, 61000.0)
    mat("eraBp00 rb", rb)
    # Nutation matrix for given mean obliquity and nutation.
    eps = erfa.obl80(2400000.5, 61000.0)
    dpsi, deps = erfa.nut80(2400000.5, 61000.0)
    print("eraObl80, eraNut80 at MJD 61000:", repr(float(eps)), repr(float(dpsi)), repr(float(deps)))
    mat("eraNumat(eps, dpsi, deps)", erfa.numat(eps, dpsi, deps))
    # Nutation (full 106-term IAU 1980) at several dates, radians.
    print("(mjd_tt, dpsi, deps) from eraNut80:")
    for mjd in [15020.0, 33282.0, 44000.0, 51544.5, 55000.0, 60000.0, 69807.0]:
        dpsi, deps = erfa.nut80(2400000.5, mjd)
        print(f"    ({mjd}, {float(dpsi)!r}, {float(deps)!r}),")
    print("(jd_ut1, gmst) from eraGmst82:")
    for jd in [2415020.5, 2446895.5, 2451545.0, 2460000.25, 2488069.75]:
        print(f"    ({jd}, {float(erfa.gmst82(jd, 0.0))!r}),")
    earth_velocity()


def earth_velocity():
    """Barycentric velocity of the Earth from DE421 (AU/day, ICRS), via Skyfield."""
    import os
    import skyfield_data
    from skyfield.api import Loader

    load = Loader(os.path.join(os.path.dirname(skyfield_data.__file__), "data"))
    eph = load("de421.bsp")
    ts = load.timescale(builtin=False)
    earth = eph["earth"]
    print("(jd_tt, vx, vy, vz) barycentric Earth velocity, AU/d, ICRS, DE421:")
    for jd in [2415020.5, 2440000.5, 2446895.5, 2451545.0, 2455000.5, 2460000.5, 2469000.5]:
        t = ts.tt_jd(jd)
        v = earth.at(t).velocity.au_per_d
        print(f"    ({jd}, {float(v[0])!r}, {float(v[1])!r}, {float(v[2])!r}),")


if __name__ == "__main__":
    main()
