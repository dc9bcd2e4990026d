#!/usr/bin/env python3
"""Reference fixtures for himmel-astro's Moon (run by hand, never in CI).

1. astro/data/moon_check.json — 2000 random TT instants 1900..2050 with the
   apparent geocentric Moon from Skyfield + JPL DE421 (de421.bsp of PyPI
   skyfield-data): ecliptic longitude/latitude of the true ecliptic and
   equinox of date, geometric distance between the centres, and Skyfield's IAU 2000A nutation in longitude
   Δψ at the same instant, so that a test can compare Meeus ch. 47
   (mean equinox of date) as λ + Δψ, β.
   Skyfield's apparent place includes light time and annual aberration; for
   the geocentric Moon their sum reduces to Meeus' constant −0.70″ light-time
   term, so the comparison is like with like.

2. astro/data/moon_libration_check.json — 20 instants with the apparent
   places of Moon and Sun from Skyfield (inputs of `moon::physical`) and, as
   reference values, Astronomy Engine's (PyPI astronomy-engine)
   `Libration(time)` (elon, elat; Meeus ch. 53 optical + physical librations)
   and `Illumination(Body.Moon, time)` (phase angle, illuminated fraction).
"""
import importlib.metadata
import json
import math
import os

import astronomy
import numpy as np
from skyfield.api import load
from skyfield.framelib import ecliptic_frame
from skyfield.nutationlib import iau2000a_radians, mean_obliquity
import skyfield_data

HERE = os.path.dirname(os.path.abspath(__file__))
DATA = os.path.join(HERE, "..", "astro", "data")
JD_1900 = 2415020.5  # 1900-01-01 0h
JD_2050 = 2469807.5  # 2050-01-01 0h
ASEC = 180.0 / math.pi * 3600.0

ts = load.timescale(builtin=True)
eph = load(os.path.join(os.path.dirname(skyfield_data.__file__), "data", "de421.bsp"))
earth, moon, sun = eph["earth"], eph["moon"], eph["sun"]


def write_fixture(path, header, rows):
    """JSON object with one row of numbers per line (diff-friendly)."""
    with open(path, "w") as fh:
        fh.write("{\n")
        for key, value in header.items():
            fh.write(f"{json.dumps(key)}: {json.dumps(value)},\n")
        fh.write('"rows": [\n')
        fh.write(",\n".join(json.dumps(r) for r in rows))
        fh.write("\n]}\n")
    json.load(open(path))


def apparent(body, t):
    app = earth.at(t).observe(body).apparent()
    lat, lon, dist = app.frame_latlon(ecliptic_frame)
    ra, dec, _ = app.radec(epoch="date")
    return lon.radians, lat.radians, ra.radians, dec.radians, dist.km


def meeus_fixture():
    rng = np.random.default_rng(47)
    jd = np.sort(rng.uniform(JD_1900, JD_2050, 2000))
    t = ts.tt_jd(jd)
    lon, lat, _, _, _ = apparent(moon, t)
    # Geometric distance between the centres at t. The astrometric/apparent
    # vector's length is not it: it spans the Earth's barycentric motion
    # during the light time (~38 km).
    dist = (moon - earth).at(t).distance().km
    dpsi, _ = iau2000a_radians(t)
    rows = [[round(float(jd[i]), 6), float(np.degrees(lon[i])), float(np.degrees(lat[i])),
             float(dist[i]), float(dpsi[i] * ASEC)] for i in range(len(jd))]
    write_fixture(os.path.join(DATA, "moon_check.json"), {
        "source": "Skyfield + JPL DE421: earth.at(t).observe(moon).apparent().frame_latlon(ecliptic_frame); "
                  "dpsi = skyfield.nutationlib.iau2000a_radians(t)",
        "generator": "tools/gen_moon_check.py",
        "columns": ["jd_tt", "lon_true_of_date_deg", "lat_deg", "geometric_distance_km", "dpsi_arcsec"],
    }, rows)


def libration_fixture():
    rng = np.random.default_rng(53)
    jd = np.sort(rng.uniform(JD_1900, JD_2050, 18)).tolist()
    # Meeus Examples 48.a/53.a (1992 April 12 0h TD) and one J2000 instant.
    jd += [2448724.5, 2451545.0]
    rows = []
    for j in jd:
        t = ts.tt_jd(j)
        m = list(apparent(moon, t))
        m[4] = (moon - earth).at(t).distance().km
        s = apparent(sun, t)
        dpsi, deps = iau2000a_radians(t)
        eps = mean_obliquity(t.tdb) / ASEC + deps
        at = astronomy.Time.FromTerrestrialTime(j - 2451545.0)
        lib = astronomy.Libration(at)
        ill = astronomy.Illumination(astronomy.Body.Moon, at)
        rows.append([j, *(float(v) for v in m), *(float(v) for v in s), float(dpsi), float(eps),
                     (j - 2451545.0) / 36525.0, lib.elon, lib.elat, ill.phase_angle, ill.phase_fraction])
    write_fixture(os.path.join(DATA, "moon_libration_check.json"), {
        "source": "inputs: Skyfield + JPL DE421 apparent places of date (IAU 2000A nutation); "
                  "reference: astronomy-engine Libration(time).elon/.elat and Illumination(Body.Moon, time)",
        "astronomy_engine_version": importlib.metadata.version("astronomy-engine"),
        "generator": "tools/gen_moon_check.py",
        "columns": ["jd_tt", "moon_lon", "moon_lat", "moon_ra", "moon_dec", "moon_distance_km",
                    "sun_lon", "sun_lat", "sun_ra", "sun_dec", "sun_distance_km", "dpsi", "true_obliquity",
                    "t_centuries", "ae_elon_deg", "ae_elat_deg", "ae_phase_angle_deg", "ae_phase_fraction"],
        "units": "angles in radians unless the name says deg",
    }, rows)


if __name__ == "__main__":
    meeus_fixture()
    libration_fixture()
    print("wrote moon_check.json and moon_libration_check.json")
