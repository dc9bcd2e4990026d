#!/usr/bin/env python3
"""Reference positions for himmel's validation tests, from JPL DE421 via Skyfield.

Run by hand (never in CI); the output is committed as a fact table:

    pip install skyfield skyfield-data astronomy-engine
    python3 tools/gen_fixtures.py            # writes tests/fixtures/de421_*.json

Sources: JPL DE421 ephemeris (public domain) and IERS finals2000A.all (UT1-UTC,
leap seconds), both as shipped by the PyPI package `skyfield-data`; Skyfield's
reduction (IAU 2000A nutation, IAU 2006 precession, light time, aberration,
gravitational deflection). Moon librations and planet magnitudes from
Astronomy Engine (PyPI `astronomy-engine`).
"""
import json
import math
import os
import random

import numpy as np
import skyfield_data
from skyfield.api import Loader, wgs84
from skyfield.framelib import ecliptic_frame
from skyfield import almanac  # noqa: F401  (keeps skyfield's optional imports honest)
import astronomy

HERE = os.path.dirname(os.path.abspath(__file__))
OUT = os.path.join(HERE, '..', 'tests', 'fixtures')
DATA = os.path.join(os.path.dirname(skyfield_data.__file__), 'data')

load = Loader(DATA)
ts = load.timescale(builtin=False)  # uses finals2000A.all from skyfield-data
eph = load('de421.bsp')
earth = eph['earth']
BODIES = {
    'sun': eph['sun'],
    'moon': eph['moon'],
    'mercury': eph['mercury barycenter'],
    'venus': eph['venus barycenter'],
    'mars': eph['mars barycenter'],
    'jupiter': eph['jupiter barycenter'],
    'saturn': eph['saturn barycenter'],
}
AE_BODY = {
    'mercury': astronomy.Body.Mercury, 'venus': astronomy.Body.Venus,
    'mars': astronomy.Body.Mars, 'jupiter': astronomy.Body.Jupiter,
    'saturn': astronomy.Body.Saturn,
}
KM_PER_AU = 149597870.700


def ae_time(t):
    # Astronomy Engine counts UT days since J2000 (and derives TT itself).
    return astronomy.Time(t.ut1 - 2451545.0)


def body_record(t, observer, name, target):
    astrometric = earth.at(t).observe(target)
    app = astrometric.apparent()
    ra, dec, dist = app.radec(epoch='date')
    lat, lon, _ = app.frame_latlon(ecliptic_frame)
    topo = (earth + observer).at(t).observe(target).apparent()
    alt, az, tdist = topo.altaz()
    rec = {
        'ra_deg': ra._degrees, 'dec_deg': dec.degrees, 'distance_km': dist.km,
        # Geometric distance between centres at t (no light time).
        'geometric_distance_km': (target - earth).at(t).distance().km,
        'ecl_lon_deg': lon.degrees, 'ecl_lat_deg': lat.degrees,
        'alt_deg': alt.degrees, 'az_deg': az.degrees, 'topo_distance_km': tdist.km,
    }
    if name == 'moon':
        sun_app = earth.at(t).observe(BODIES['sun']).apparent()
        rec['phase_angle_deg'] = app.phase_angle(BODIES['sun']).degrees
        rec['illuminated_fraction'] = float(app.fraction_illuminated(BODIES['sun']))
        rec['elongation_deg'] = app.separation_from(sun_app).degrees
        lib = astronomy.Libration(ae_time(t))
        rec['ae_libration_lon_deg'] = lib.elon
        rec['ae_libration_lat_deg'] = lib.elat
    if name in AE_BODY:
        ill = astronomy.Illumination(AE_BODY[name], ae_time(t))
        rec['ae_magnitude'] = ill.mag
        rec['phase_angle_deg'] = app.phase_angle(BODIES['sun']).degrees
    return rec


def instant_record(t, lat, lon, elev, extra=None):
    obs = wgs84.latlon(lat, lon, elevation_m=elev)
    rec = {
        'jd_tt': float(t.tt), 'jd_ut1': float(t.ut1), 'delta_t_s': float(t.delta_t),
        'gast_hours': float(t.gast),
        'lat': lat, 'lon': lon, 'elevation_m': elev,
        'bodies': {n: body_record(t, obs, n, b) for n, b in BODIES.items()},
    }
    if extra:
        rec.update(extra)
    return rec


def random_observer(rng):
    lat = math.degrees(math.asin(rng.uniform(-1.0, 1.0)))
    lon = rng.uniform(-180.0, 180.0)
    elev = rng.choice([0.0, 0.0, rng.uniform(0.0, 4000.0)])
    return round(lat, 6), round(lon, 6), round(elev, 1)


def main():
    rng = random.Random(20261122)
    os.makedirs(OUT, exist_ok=True)

    # 1. Random TT instants across 1900-2050 with random observers.
    jd0 = ts.utc(1900, 1, 1).tt
    jd1 = ts.utc(2050, 1, 1).tt
    same_tt = []
    for _ in range(600):
        t = ts.tt_jd(rng.uniform(jd0, jd1))
        same_tt.append(instant_record(t, *random_observer(rng)))

    # 2. Civil UTC instants in the observed-UT1 era (1973-2025).
    same_utc = []
    for _ in range(200):
        y = rng.randint(1973, 2024)
        t0 = ts.utc(y, 1, 1)
        t = ts.tt_jd(t0.tt + rng.uniform(0.0, 365.0))
        utc = t.utc_strftime('%Y-%m-%dT%H:%M:%S')
        # Re-create from the rounded civil string so the UTC is exact.
        yy, mo, dd = int(utc[0:4]), int(utc[5:7]), int(utc[8:10])
        hh, mi, ss = int(utc[11:13]), int(utc[14:16]), int(utc[17:19])
        t = ts.utc(yy, mo, dd, hh, mi, ss)
        lat, lon, elev = random_observer(rng)
        same_utc.append(instant_record(t, lat, lon, elev, {'utc': utc + 'Z'}))

    # 3. Hard cases.
    hard = []

    def add(label, t, lat, lon, elev=0.0, utc=None):
        extra = {'label': label}
        if utc:
            extra['utc'] = utc
        hard.append(instant_record(t, lat, lon, elev, extra))

    j2000 = ts.tt_jd(2451545.0)
    for lat, lon in [(90.0, 0.0), (-90.0, 0.0), (0.0, 180.0), (0.0, -180.0), (89.9999, 45.0),
                     (-89.9, 120.0), (45.0, 180.0), (-45.0, -180.0)]:
        add(f'J2000 observer {lat},{lon}', j2000, lat, lon)
    add('1900-01-01', ts.utc(1900, 1, 1), 51.48, 0.0, 0.0, '1900-01-01T00:00:00Z')
    add('2050-01-01', ts.utc(2050, 1, 1), -33.9, 18.4, 0.0, '2050-01-01T00:00:00Z')
    add('1899-12-31 TT', ts.tt_jd(2415020.0), 0.0, 0.0)
    for label, args, utc in [
            ('before leap second', (2016, 12, 31, 23, 59, 59.5), '2016-12-31T23:59:59.500Z'),
            ('inside leap second', (2016, 12, 31, 23, 59, 60.5), '2016-12-31T23:59:60.500Z'),
            ('after leap second', (2017, 1, 1, 0, 0, 0.5), '2017-01-01T00:00:00.500Z')]:
        add(label, ts.utc(*args), 52.52, 13.40, 34.0, utc)
    # Moon at the zenith and the nadir: put the observer under the Moon.
    for k in range(4):
        t = ts.tt_jd(2451545.0 + 1000.0 * k + 0.37)
        ra, dec, _ = earth.at(t).observe(BODIES['moon']).apparent().radec(epoch='date')
        lon = ((ra.hours - t.gast) * 15.0 + 180.0) % 360.0 - 180.0
        # Geodetic latitude slightly differs from the declination; refine.
        lat = dec.degrees
        for _ in range(5):
            obs = wgs84.latlon(lat, lon)
            alt, az, _ = (earth + obs).at(t).observe(BODIES['moon']).apparent().altaz()
            lat += (90.0 - alt.degrees) * math.cos(math.radians(az.degrees))
            lon += (90.0 - alt.degrees) * math.sin(math.radians(az.degrees)) / max(0.1, math.cos(math.radians(lat)))
            lat = max(-90.0, min(90.0, lat))
        add(f'Moon at zenith {k}', t, lat, lon)
        add(f'Moon at nadir {k}', t, -lat, (lon + 360.0) % 360.0 - 180.0)

    for name, data in [('de421_same_tt.json', same_tt), ('de421_same_utc.json', same_utc),
                       ('de421_hard_cases.json', hard)]:
        with open(os.path.join(OUT, name), 'w') as f:
            json.dump({'source': 'JPL DE421 via Skyfield %s (tools/gen_fixtures.py)' % __import__('skyfield').__version__,
                       'records': data}, f, indent=None, separators=(',', ':'))
            f.write('\n')
        print(name, len(data))


if __name__ == '__main__':
    main()
