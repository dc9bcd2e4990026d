#!/usr/bin/env python3
"""Reference sky events for himmel's event tests, from JPL DE421 via Skyfield.

Run by hand (never in CI); the output is committed as fact tables:

    pip install skyfield skyfield-data astronomy-engine numpy
    python3 tools/gen_events.py      # writes tests/fixtures/events_*.json

What is computed, and how (every definition matches spec/cli.md):

* events_phases.json — principal Moon phases 1990–2030,
  `skyfield.almanac.moon_phases` (apparent ecliptic longitude difference of
  date) with `find_discrete`.
* events_riseset.json — rise, set and upper transit of the Sun and the Moon
  for 2024 at sites from pole to pole. Horizons: Sun −0.8333°; Moon −0.5667°
  minus the topocentric semidiameter asin(1737.4 km / distance). Altitudes are
  Skyfield's topocentric apparent altitudes without refraction, sea-level
  observer on WGS84. Skyfield's own `find_risings` is not used: it is exactly
  the kind of search that fails in polar day/night. Instead the function
  altitude − horizon is sampled every minute and every sign change refined by
  bisection; transits are the − → + sign changes of the topocentric hour angle.
  Per UTC day the state is `normal` when a rise or set happens that day, else
  `always_up`/`always_down` from the sign at the day's noon.
* events_riseset_planets.json — the same for Venus, Mars and Jupiter
  (DE421 system barycentres; horizon −0.5667°, refraction only) at three sites.
* events_lunar.json — every lunar eclipse 1900–2050 from
  `skyfield.eclipselib.lunar_eclipses` (Explanatory Supplement 11.2.3, Danjon
  enlargement as 1.01 × the Moon's parallax), plus gamma (Moon centre distance
  from the shadow axis in Earth equatorial radii, positive north) and, for
  1990–2030, the contact times P1, U1–U4, P4 from the same geometry.
* events_solar_global.json — global solar eclipses 1900–2050 from Astronomy
  Engine's `SearchGlobalSolarEclipse` (a cross-check of type, peak and axis
  distance; Astronomy Engine has no hybrid type and reports those as total).
* events_solar_local.json — local circumstances at chosen sites, computed
  here from DE421 topocentric apparent positions (no refraction): contacts
  are the instants when the topocentric Sun–Moon separation equals the sum
  (C1, C4) or difference (C2, C3) of the topocentric semidiameters (Sun
  695 700 km, Moon 1737.4 km); maximum = minimum separation.

Sources: JPL DE421 (public domain) and IERS finals2000A.all, both from PyPI
`skyfield-data`; Skyfield (MIT); Astronomy Engine (MIT).
"""
import json
import math
import os

import numpy as np
import skyfield_data
from skyfield import almanac, eclipselib
from skyfield.api import Loader, wgs84
from skyfield.searchlib import find_discrete
import astronomy

HERE = os.path.dirname(os.path.abspath(__file__))
OUT = os.path.join(HERE, '..', 'tests', 'fixtures')
DATA = os.path.join(os.path.dirname(skyfield_data.__file__), 'data')

load = Loader(DATA)
ts = load.timescale(builtin=False)
eph = load('de421.bsp')
earth, sun, moon = eph['earth'], eph['sun'], eph['moon']
ERAD_KM = 6378.1366
MOON_R_KM = 1737.4
SUN_R_KM = 695700.0
DAY_MIN = 1440


def bisect(f, a, b, iters=40):
    """Vectorised bisection on TT Julian days; f(array) -> array."""
    a = np.array(a, dtype=float)
    b = np.array(b, dtype=float)
    fa = f(a)
    for _ in range(iters):
        m = 0.5 * (a + b)
        fm = f(m)
        left = np.sign(fm) == np.sign(fa)
        a = np.where(left, m, a)
        fa = np.where(left, fm, fa)
        b = np.where(left, b, m)
    return 0.5 * (a + b)


def crossings(f, jd0, jd1, step_days):
    """All sign changes of f on [jd0, jd1]: (jd_tt, direction +1 rising / -1 falling)."""
    out_t, out_d = [], []
    chunk = 31.0
    start = jd0
    while start < jd1:
        end = min(start + chunk, jd1)
        n = int(round((end - start) / step_days)) + 1
        grid = np.linspace(start, end, n)
        v = f(grid)
        s = np.sign(v)
        idx = np.nonzero(s[:-1] * s[1:] < 0)[0]
        if len(idx):
            roots = bisect(f, grid[idx], grid[idx + 1])
            out_t.extend(roots.tolist())
            out_d.extend(np.where(v[idx] < 0, 1, -1).tolist())
        start = end
    return out_t, out_d


# ---------------------------------------------------------------- phases
def gen_phases():
    t0 = ts.utc(1990, 1, 1)
    t1 = ts.utc(2031, 1, 1)
    t, y = find_discrete(t0, t1, almanac.moon_phases(eph))
    names = ['new', 'first_quarter', 'full', 'last_quarter']
    return [{'phase': names[int(p)], 'jd_tt': float(tt), 'utc': s}
            for p, tt, s in zip(y, t.tt, t.utc_iso(places=3))]


# ---------------------------------------------------------------- rise/set
SITES = [
    ('equator', 0.0, -78.5),
    ('cape_town', -33.92, 18.42),
    ('berlin', 52.52, 13.405),
    ('tromso', 69.65, 18.96),
    ('svalbard', 78.0, 15.6),
    ('ross_island', -78.0, 166.67),
    ('dateline', -17.7, -179.95),
    ('north_pole', 90.0, 0.0),
    ('south_pole', -90.0, 0.0),
]


def site_functions(observer, body, name):
    """f(jd) -> (altitude - horizon in degrees, hour angle in radians wrapped to [-pi, pi))."""
    def both(jd):
        t = ts.tt_jd(jd)
        app = observer.at(t).observe(body).apparent()
        alt, _, dist = app.altaz()
        if name == 'sun':
            h0 = -0.8333
        elif name == 'moon':
            h0 = -0.5667 - np.degrees(np.arcsin(MOON_R_KM / dist.km))
        else:
            h0 = -0.5667
        ha, _, _ = app.hadec()
        return alt.degrees - h0, (ha.radians + math.pi) % (2 * math.pi) - math.pi
    return both


def site_crossings(both, jd0, jd1, step_days):
    """Horizon crossings and upper transits on [jd0, jd1].

    One evaluation per sample serves both searches. Near-tangent passes
    (|f| at a local minimum below 0.02 degrees without a sign change) are
    re-sampled every second, so that a graze shorter than the step is kept.
    """
    f = lambda x: both(x)[0]
    g = lambda x: both(x)[1]
    rs, trans = [], []
    start = jd0
    while start < jd1:
        end = min(start + 31.0, jd1)
        n = int(round((end - start) / step_days)) + 1
        grid = np.linspace(start, end, n)
        v, ha = both(grid)
        s = np.sign(v)
        idx = np.nonzero(s[:-1] * s[1:] < 0)[0]
        if len(idx):
            roots = bisect(f, grid[idx], grid[idx + 1])
            rs.extend(zip(np.where(v[idx] < 0, 'rise', 'set').tolist(), roots.tolist()))
        av = np.abs(v)
        near = np.nonzero((av[1:-1] < 0.02) & (av[1:-1] <= av[:-2]) & (av[1:-1] <= av[2:])
                          & (s[:-2] == s[1:-1]) & (s[1:-1] == s[2:]))[0] + 1
        for i in near:
            fine = np.linspace(grid[i - 1], grid[i + 1], int(round(2 * step_days * 86400)) + 1)
            fv = f(fine)
            fs = np.sign(fv)
            fi = np.nonzero(fs[:-1] * fs[1:] < 0)[0]
            if len(fi):
                roots = bisect(f, fine[fi], fine[fi + 1])
                rs.extend(zip(np.where(fv[fi] < 0, 'rise', 'set').tolist(), roots.tolist()))
        idx = np.nonzero((ha[:-1] < 0) & (ha[1:] >= 0) & (ha[1:] - ha[:-1] < math.pi))[0]
        if len(idx):
            roots = bisect(g, grid[idx], grid[idx + 1])
            trans.extend(roots.tolist())
        start = end
    return rs + [('transit', t) for t in trans]


PLANET_SITES = [s for s in SITES if s[0] in ('equator', 'berlin', 'svalbard')]
PLANETS = (('venus', 'venus barycenter'), ('mars', 'mars barycenter'),
           ('jupiter', 'jupiter barycenter'))


def gen_riseset(sites=SITES, bodies=(('sun', 'sun'), ('moon', 'moon'))):
    year = 2024
    t0 = ts.utc(year, 1, 1)
    t1 = ts.utc(year + 1, 1, 1)
    out = []
    for site, lat, lon in sites:
        observer = earth + wgs84.latlon(lat, lon, elevation_m=0.0)
        for name, key in bodies:
            body = eph[key]
            both = site_functions(observer, body, name)
            events = site_crossings(both, t0.tt, t1.tt, 2.0 / DAY_MIN)
            events = sorted(set(events), key=lambda e: e[1])
            # Per-UTC-day states.
            states = []
            days = ts.utc(year, 1, range(1, 367))
            noon = ts.utc(year, 1, np.arange(1, 367), 12)
            fn = both(noon.tt)[0]
            ev_days = set()
            for kind, tt in events:
                if kind != 'transit':
                    ev_days.add(ts.tt_jd(tt).utc_strftime('%Y-%m-%d'))
            for d, v in zip(days.utc_strftime('%Y-%m-%d'), fn):
                if d in ev_days:
                    states.append('n')
                else:
                    states.append('u' if v > 0 else 'd')
            out.append({
                'site': site, 'lat': lat, 'lon': lon, 'body': name, 'year': year,
                'states': ''.join(states),
                'events': [[k, tt, ts.tt_jd(tt).utc_iso(places=3)] for k, tt in events],
            })
            print(site, name, len(events), 'events', flush=True)
    return out


# ---------------------------------------------------------------- lunar
def lunar_geometry(jd):
    """Skyfield eclipselib geometry at TT JDs: delta, rho_p, rho_u, s_m, moon vector, axis."""
    t = ts.tt_jd(jd)
    e = earth.at(t)
    s_app = e.observe(sun).apparent().position.km
    m_geo = (moon.at(t).position.km - e.position.km)
    ds = np.linalg.norm(s_app, axis=0)
    dm = np.linalg.norm(m_geo, axis=0)
    axis = -s_app / ds
    cosd = np.sum(axis * m_geo, axis=0) / dm
    perp = m_geo - np.sum(axis * m_geo, axis=0) * axis
    delta = np.arctan2(np.linalg.norm(perp, axis=0), cosd * dm)
    pi_m = ERAD_KM / dm
    pi_s = ERAD_KM / ds
    s_s = 696340.0 / ds
    pi_1 = 1.01 * pi_m
    s_m = np.arcsin(1737.1 / dm)
    return delta, pi_1 + pi_s + s_s, pi_1 + pi_s - s_s, s_m, perp, dm


def gen_lunar():
    t0 = ts.utc(1900, 1, 1)
    t1 = ts.utc(2051, 1, 1)
    t, code, det = eclipselib.lunar_eclipses(t0, t1, eph)
    names = ['penumbral', 'partial', 'total']
    out = []
    for i in range(len(t)):
        jd = t.tt[i]
        delta, rp, ru, sm, perp, dm = lunar_geometry(np.array([jd]))
        gamma = np.linalg.norm(perp[:, 0]) / ERAD_KM
        gamma *= 1.0 if perp[2, 0] >= 0 else -1.0
        rec = {
            'type': names[int(code[i])], 'jd_tt': float(jd), 'utc': t[i].utc_iso(places=3),
            'umbral_magnitude': float(det['umbral_magnitude'][i]),
            'penumbral_magnitude': float(det['penumbral_magnitude'][i]),
            'gamma': float(gamma),
        }
        if 1990 <= t[i].utc.year <= 2030:
            contacts = {}
            for label, which, sgn in (('p1', 1, -1), ('p4', 1, 1), ('u1', 2, -1),
                                      ('u4', 2, 1), ('u2', 3, -1), ('u3', 3, 1)):
                def g(x, which=which):
                    d, rp_, ru_, sm_, _, _ = lunar_geometry(x)
                    lim = {1: rp_ + sm_, 2: ru_ + sm_, 3: ru_ - sm_}[which]
                    return d - lim
                if g(np.array([jd]))[0] >= 0:
                    contacts[label] = None
                    continue
                far = jd + sgn * 0.4
                root = bisect(g, np.array([jd]), np.array([far]), iters=45)[0]
                contacts[label] = float(root)
            rec['contacts_jd_tt'] = contacts
        out.append(rec)
    return out


# ---------------------------------------------------------------- solar global
def gen_solar_global():
    out = []
    t = astronomy.Time.Make(1900, 1, 1, 0, 0, 0)
    end = astronomy.Time.Make(2051, 1, 1, 0, 0, 0)
    while True:
        g = astronomy.SearchGlobalSolarEclipse(t)
        if g.peak.ut > end.ut:
            break
        out.append({
            'kind': g.kind.name.lower(), 'jd_tt': g.peak.tt + 2451545.0,
            'utc': str(g.peak), 'distance_km': g.distance,
            'latitude': g.latitude if g.kind.name != 'Partial' else None,
            'longitude': g.longitude if g.kind.name != 'Partial' else None,
        })
        t = g.peak.AddDays(10.0)
    return out


# ---------------------------------------------------------------- solar local
LOCAL_CASES = [
    # (label, year, month, day, lat, lon)
    ('2024 total, Dallas', 2024, 4, 8, 32.7767, -96.797),
    ('2024 total, Mazatlan', 2024, 4, 8, 23.22, -106.42),
    ('2024 partial, New York', 2024, 4, 8, 40.71, -74.01),
    ('2017 total, Nashville', 2017, 8, 21, 36.16, -86.78),
    ('2017 total, Salem', 2017, 8, 21, 44.94, -123.03),
    ('2023 annular, Albuquerque', 2023, 10, 14, 35.08, -106.65),
    ('2021 annular at sunrise, New York (C1 below horizon)', 2021, 6, 10, 40.71, -74.01),
    ('2021 annular, Nunavut', 2021, 6, 10, 80.0, -80.0),
    ('2026 deep partial at sunset, Madrid', 2026, 8, 12, 40.42, -3.70),
    ('2027 total, Luxor', 2027, 8, 2, 25.69, 32.64),
    ('2015 total, Svalbard', 2015, 3, 20, 78.22, 15.65),
    ('2015 partial, Berlin', 2015, 3, 20, 52.52, 13.405),
    ('1999 total, Munich', 1999, 8, 11, 48.14, 11.58),
    ('2020 annular, Chiayi', 2020, 6, 21, 23.48, 120.45),
    ('2019 total at sunset, La Serena', 2019, 7, 2, -29.90, -71.25),
    ('2019 partial at sunset, Buenos Aires (C4 below horizon)', 2019, 7, 2, -34.60, -58.38),
    ('2030 annular, Hokkaido', 2030, 6, 1, 43.06, 141.35),
]


def overlap_fraction(s, rs, rm):
    """Fraction of the Sun's disk area covered by the Moon's (lens area)."""
    if s >= rs + rm:
        return 0.0
    if s <= abs(rs - rm):
        return min(1.0, (rm / rs) ** 2)
    a1 = rs * rs * math.acos((s * s + rs * rs - rm * rm) / (2 * s * rs))
    a2 = rm * rm * math.acos((s * s + rm * rm - rs * rs) / (2 * s * rm))
    a3 = 0.5 * math.sqrt((-s + rs + rm) * (s + rs - rm) * (s - rs + rm) * (s + rs + rm))
    return (a1 + a2 - a3) / (math.pi * rs * rs)


def local_geometry(observer, jd):
    t = ts.tt_jd(jd)
    o = observer.at(t)
    sa = o.observe(sun).apparent()
    ma = o.observe(moon).apparent()
    sep = sa.separation_from(ma).radians
    _, _, ds = sa.radec('date')
    _, _, dm = ma.radec('date')
    rs = np.arcsin(SUN_R_KM / ds.km)
    rm = np.arcsin(MOON_R_KM / dm.km)
    alt, _, _ = sa.altaz()
    return sep, rs, rm, alt.degrees


def gen_solar_local():
    out = []
    for label, y, mo, d, lat, lon in LOCAL_CASES:
        observer = earth + wgs84.latlon(lat, lon, elevation_m=0.0)
        day = ts.utc(y, mo, d, 12).tt
        f_outer = lambda x: (lambda g: g[0] - (g[1] + g[2]))(local_geometry(observer, x))
        f_inner = lambda x: (lambda g: g[0] - abs(g[1] - g[2]))(local_geometry(observer, x))
        grid = np.linspace(day - 0.75, day + 0.75, int(1.5 * DAY_MIN) + 1)
        sep, rs, rm, _ = local_geometry(observer, grid)
        i = int(np.argmin(sep))
        # Golden-section refine of the minimum separation.
        a, b = grid[max(i - 1, 0)], grid[min(i + 1, len(grid) - 1)]
        gr = (math.sqrt(5) - 1) / 2
        for _ in range(60):
            c = b - gr * (b - a)
            dd = a + gr * (b - a)
            if local_geometry(observer, np.array([c]))[0][0] < local_geometry(observer, np.array([dd]))[0][0]:
                b = dd
            else:
                a = c
        tmax = 0.5 * (a + b)
        s, rs_, rm_, alt_max = [float(v[0]) for v in local_geometry(observer, np.array([tmax]))]
        c1 = float(bisect(f_outer, np.array([tmax]), np.array([tmax - 0.3]), 45)[0])
        c4 = float(bisect(f_outer, np.array([tmax]), np.array([tmax + 0.3]), 45)[0])
        inner = s < abs(rs_ - rm_)
        c2 = float(bisect(f_inner, np.array([tmax]), np.array([tmax - 0.1]), 45)[0]) if inner else None
        c3 = float(bisect(f_inner, np.array([tmax]), np.array([tmax + 0.1]), 45)[0]) if inner else None
        kind = 'partial'
        if inner:
            kind = 'total' if rm_ > rs_ else 'annular'
        alt_c1 = float(local_geometry(observer, np.array([c1]))[3][0])
        alt_c4 = float(local_geometry(observer, np.array([c4]))[3][0])
        out.append({
            'label': label, 'lat': lat, 'lon': lon,
            'c1_jd_tt': c1, 'c2_jd_tt': c2, 'max_jd_tt': tmax, 'c3_jd_tt': c3, 'c4_jd_tt': c4,
            'max_utc': ts.tt_jd(tmax).utc_iso(places=3),
            'max_magnitude': (rs_ + rm_ - s) / (2 * rs_),
            'max_obscuration': overlap_fraction(s, rs_, rm_),
            'type_local': kind,
            'sun_alt_c1_deg': alt_c1, 'sun_alt_max_deg': alt_max, 'sun_alt_c4_deg': alt_c4,
        })
        print(label, kind, out[-1]['max_utc'], flush=True)
    return out


def dump(name, data, source):
    path = os.path.join(OUT, name)
    with open(path, 'w') as fh:
        json.dump({'source': source, 'data': data}, fh, separators=(',', ':'))
        fh.write('\n')
    print('wrote', path)


if __name__ == '__main__':
    import sys
    which = sys.argv[1:] or ['phases', 'lunar', 'solar_local', 'solar_global', 'riseset']
    src = 'JPL DE421 via Skyfield 1.55 (tools/gen_events.py)'
    if 'phases' in which:
        dump('events_phases.json', gen_phases(), src)
    if 'lunar' in which:
        dump('events_lunar.json', gen_lunar(), src)
    if 'solar_local' in which:
        dump('events_solar_local.json', gen_solar_local(), src)
    if 'solar_global' in which:
        dump('events_solar_global.json', gen_solar_global(),
             'Astronomy Engine SearchGlobalSolarEclipse (tools/gen_events.py)')
    if 'riseset' in which:
        dump('events_riseset.json', gen_riseset(), src)
    if 'riseset_planets' in which:
        dump('events_riseset_planets.json', gen_riseset(PLANET_SITES, PLANETS), src)
