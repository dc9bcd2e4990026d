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
* events_solar_local_spread.json (`python3 tools/gen_events.py
  solar_local_spread`) — the same local circumstances at sites placed on and
  near the limits of the central paths of 23 eclipses spread over 2001–2050
  (gen_solar_local_spread), plus Reykjavik 2026-08-12. The observer turns with
  himmel's own ΔT (read from astro/src/time/delta_t_data.rs and the same
  Espenak & Meeus extrapolation, himmel_delta_t_function), recorded per case
  as `delta_t_s`: beyond the IERS table Skyfield predicts ΔT differently
  (up to 17 s by 2050), which would move the contacts by seconds for reasons
  that have nothing to do with the ephemerides.

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


def local_geometry(observer, jd, tsx=None):
    t = (tsx or ts).tt_jd(jd)
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


def local_case(tsx, label, lat, lon, day):
    """Local circumstances at (lat, lon) of the eclipse nearest TT `day`
    (searched over day +- 0.75), with the timescale `tsx`."""
    observer = earth + wgs84.latlon(lat, lon, elevation_m=0.0)
    geo = lambda x: local_geometry(observer, x, tsx)
    f_outer = lambda x: (lambda g: g[0] - (g[1] + g[2]))(geo(x))
    f_inner = lambda x: (lambda g: g[0] - abs(g[1] - g[2]))(geo(x))
    grid = np.linspace(day - 0.75, day + 0.75, int(1.5 * DAY_MIN) + 1)
    sep, rs, rm, _ = geo(grid)
    i = int(np.argmin(sep))
    # Golden-section refine of the minimum separation.
    a, b = grid[max(i - 1, 0)], grid[min(i + 1, len(grid) - 1)]
    gr = (math.sqrt(5) - 1) / 2
    for _ in range(60):
        c = b - gr * (b - a)
        dd = a + gr * (b - a)
        if geo(np.array([c]))[0][0] < geo(np.array([dd]))[0][0]:
            b = dd
        else:
            a = c
    tmax = 0.5 * (a + b)
    s, rs_, rm_, alt_max = [float(v[0]) for v in geo(np.array([tmax]))]
    c1 = float(bisect(f_outer, np.array([tmax]), np.array([tmax - 0.3]), 45)[0])
    c4 = float(bisect(f_outer, np.array([tmax]), np.array([tmax + 0.3]), 45)[0])
    inner = s < abs(rs_ - rm_)
    c2 = float(bisect(f_inner, np.array([tmax]), np.array([tmax - 0.1]), 45)[0]) if inner else None
    c3 = float(bisect(f_inner, np.array([tmax]), np.array([tmax + 0.1]), 45)[0]) if inner else None
    kind = 'partial'
    if inner:
        kind = 'total' if rm_ > rs_ else 'annular'
    alt_c1 = float(geo(np.array([c1]))[3][0])
    alt_c4 = float(geo(np.array([c4]))[3][0])
    out = {
        'label': label, 'lat': lat, 'lon': lon,
        'c1_jd_tt': c1, 'c2_jd_tt': c2, 'max_jd_tt': tmax, 'c3_jd_tt': c3, 'c4_jd_tt': c4,
        'max_utc': tsx.tt_jd(tmax).utc_iso(places=3),
        'max_magnitude': (rs_ + rm_ - s) / (2 * rs_),
        'max_obscuration': overlap_fraction(s, rs_, rm_),
        'type_local': kind,
        'sun_alt_c1_deg': alt_c1, 'sun_alt_max_deg': alt_max, 'sun_alt_c4_deg': alt_c4,
        'delta_t_s': float(tsx.tt_jd(tmax).delta_t),
    }
    print(label, kind, out['max_utc'], flush=True)
    return out


def gen_solar_local():
    out = []
    for label, y, mo, d, lat, lon in LOCAL_CASES:
        case = local_case(ts, label, lat, lon, ts.utc(y, mo, d, 12).tt)
        del case['delta_t_s']
        out.append(case)
    return out


# ---------------------------------------------------------------- solar local, 2001-2050 spread
# Central eclipses spread over 2001-2050 (dates of greatest eclipse, UTC):
# total, annular and hybrid, low and high latitudes.
SPREAD_ECLIPSES = [
    (2001, 6, 21), (2003, 5, 31), (2005, 10, 3), (2006, 3, 29), (2009, 7, 22),
    (2012, 5, 20), (2013, 11, 3), (2016, 3, 9), (2020, 6, 21), (2023, 4, 20),
    (2026, 8, 12), (2027, 8, 2), (2030, 11, 25), (2033, 3, 30), (2034, 3, 20),
    (2035, 9, 2), (2038, 7, 2), (2041, 4, 30), (2042, 4, 20), (2045, 8, 12),
    (2046, 8, 2), (2048, 6, 11), (2050, 5, 20),
]
# Named sites near a path limit (label, year, month, day, lat, lon).
SPREAD_NAMED = [
    ('2026 total, Reykjavik (near the path limit)', 2026, 8, 12, 64.1466, -21.9426),
]
# Fractions of the distance from the central line to each path limit at
# which sites are placed (inside: short totality/annularity, the contacts most
# sensitive to the Moon's position; outside: a grazing partial eclipse).
SPREAD_FRACTIONS = (('central line', 0.0, 0), ('0.95 to the left limit', 0.95, -1),
                    ('0.95 to the right limit', 0.95, 1), ('1.05 beyond the right limit', 1.05, 1))

HIMMEL_DELTA_T_RS = os.path.join(HERE, '..', 'astro', 'src', 'time', 'delta_t_data.rs')


def himmel_delta_t_function():
    """ΔT(TT JD) exactly as himmel computes it from 1973 on (astro/src/time/delta_t.rs).

    Inside the IERS daily table the same values as Skyfield (the same
    finals2000A.all, read here from the compiled table in delta_t_data.rs);
    after its end Espenak & Meeus (2006) with the offset at the table end
    faded out over 100 years. Skyfield extrapolates differently (about 70 s
    flat until 2050, where himmel's model reaches 88 s): the prediction of
    ΔT is no part of what the fixture measures, so the reference observer
    turns with himmel's ΔT and the comparison isolates the ephemerides.
    """
    import re
    from gen_delta_t import tai_minus_utc
    text = open(HIMMEL_DELTA_T_RS).read()
    first_mjd = int(re.search(r'DAILY_FIRST_MJD: i32 = (\d+);', text).group(1))
    units = float(re.search(r'DAILY_UNITS_PER_SECOND: f64 = ([\d.]+);', text).group(1))
    body = text.split('pub(crate) static DAILY_DELTA_T')[1].split('= [', 1)[1].split('];', 1)[0]
    daily = np.array([int(v) for v in re.findall(r'-?\d+', body)], dtype=float) / units
    first_jd_utc = 2400000.5 + first_mjd
    last = len(daily) - 1
    last_jd_utc = first_jd_utc + last

    def tt_minus_utc(jd):
        return 32.184 + tai_minus_utc(jd - 2400000.5)

    last_jd_tt = last_jd_utc + tt_minus_utc(last_jd_utc) / 86400.0
    first_jd_tt = first_jd_utc + tt_minus_utc(first_jd_utc) / 86400.0

    def year_of(jd):
        return 2000.0 + (jd - 2451545.0) / 365.25

    def ms2004(y):
        u = (y - 1820.0) / 100.0
        return -20.0 + 32.0 * u * u

    pieces = {
        12: lambda y: 62.92 + 0.32217 * (y - 2000.0) + 0.005589 * (y - 2000.0) ** 2,
        13: lambda y: ms2004(y) - 0.5628 * (2150.0 - y),
        14: ms2004,
    }
    breaks = {12: 2050.0, 13: 2150.0}

    def espenak_meeus(y):
        if y < 2005.0:
            raise ValueError('only the pieces after 2005 are ported')
        i = 12 if y < 2050.0 else (13 if y < 2150.0 else 14)
        v = pieces[i](y)
        if i in breaks and breaks[i] - y < 25.0:
            b = breaks[i]
            v += (pieces[i + 1](b) - pieces[i](b)) * (1.0 - (b - y) / 25.0)
        return v

    offset = daily[last] - espenak_meeus(year_of(last_jd_tt))

    def one(jd_tt):
        if jd_tt < first_jd_tt:
            raise ValueError('before 1973: not ported')
        if jd_tt <= last_jd_tt:
            x = jd_tt - tt_minus_utc(jd_tt) / 86400.0 - first_jd_utc
            x = min(max(x, 0.0), float(last))
            i = min(int(math.floor(x)), last - 1)
            f = x - i
            return daily[i] + f * (daily[i + 1] - daily[i])
        y = year_of(jd_tt)
        fade = max(0.0, 1.0 - (y - year_of(last_jd_tt)) / 100.0)
        return espenak_meeus(y) + offset * fade

    def delta_t(tt):
        if np.ndim(tt) == 0:
            return one(float(tt))
        return np.array([one(float(v)) for v in np.ravel(tt)]).reshape(np.shape(tt))

    return delta_t


def axis_ground_point(tsx, jd):
    """Where the shadow axis (Sun -> Moon, apparent places) meets the WGS84
    ellipsoid at TT `jd`: (lat, lon) degrees, or None if it misses."""
    from skyfield.framelib import itrs
    t = tsx.tt_jd(jd)
    e = earth.at(t)
    m = e.observe(moon).apparent().frame_xyz(itrs).km
    s = e.observe(sun).apparent().frame_xyz(itrs).km
    d = (m - s) / np.linalg.norm(m - s)
    a, f = 6378.137, 1.0 / 298.257223563
    scale = np.array([1.0, 1.0, 1.0 / (1.0 - f)])
    ms, ds = m * scale, d * scale
    qa, qb, qc = ds @ ds, 2.0 * (ms @ ds), ms @ ms - a * a
    disc = qb * qb - 4.0 * qa * qc
    if disc < 0:
        return None
    lam = (-qb - math.sqrt(disc)) / (2.0 * qa)
    p = m + lam * d
    lon = math.degrees(math.atan2(p[1], p[0]))
    e2 = f * (2.0 - f)
    lat = math.degrees(math.atan2(p[2], (1.0 - e2) * math.hypot(p[0], p[1])))
    return lat, lon


def destination(lat, lon, bearing_deg, dist_km):
    """Great-circle destination on a 6371 km sphere (placing sites only)."""
    r = dist_km / 6371.0
    p1, l1, b = math.radians(lat), math.radians(lon), math.radians(bearing_deg)
    p2 = math.asin(math.sin(p1) * math.cos(r) + math.cos(p1) * math.sin(r) * math.cos(b))
    l2 = l1 + math.atan2(math.sin(b) * math.sin(r) * math.cos(p1),
                         math.cos(r) - math.sin(p1) * math.sin(p2))
    return math.degrees(p2), (math.degrees(l2) + 540.0) % 360.0 - 180.0


def bearing(lat1, lon1, lat2, lon2):
    p1, p2 = math.radians(lat1), math.radians(lat2)
    dl = math.radians(lon2 - lon1)
    x = math.sin(dl) * math.cos(p2)
    y = math.cos(p1) * math.sin(p2) - math.sin(p1) * math.cos(p2) * math.cos(dl)
    return math.degrees(math.atan2(x, y))


def golden_min(f, a, b, iters=40):
    gr = (math.sqrt(5) - 1) / 2
    for _ in range(iters):
        c = b - gr * (b - a)
        d = a + gr * (b - a)
        if f(c) < f(d):
            b = d
        else:
            a = c
    return 0.5 * (a + b)


def central_margin(tsx, lat, lon, t0):
    """min over time of separation - |r_sun - r_moon| (radians) near TT t0:
    negative inside the path of totality/annularity; and the Sun's altitude
    at that instant (degrees)."""
    observer = earth + wgs84.latlon(lat, lon, elevation_m=0.0)

    def g(x):
        sep, rs, rm, alt = local_geometry(observer, x, tsx)
        return sep - np.abs(rs - rm), alt

    grid = np.linspace(t0 - 0.1, t0 + 0.1, 577)
    v, _ = g(grid)
    i = int(np.argmin(v))
    a, b = grid[max(i - 1, 0)], grid[min(i + 1, len(grid) - 1)]
    tm = golden_min(lambda x: float(g(np.array([x]))[0][0]), a, b, 30)
    v, alt = g(np.array([tm]))
    return float(v[0]), float(alt[0])


def path_limit(tsx, lat, lon, brg, t0):
    """Distance (km) from (lat, lon) on the central line along `brg` to the
    path limit, or None (no limit found on the sunlit Earth within 2000 km)."""
    lo, hi = 0.0, 50.0
    while True:
        la, lo_ = destination(lat, lon, brg, hi)
        m, alt = central_margin(tsx, la, lo_, t0)
        if alt < 0.0:
            return None
        if m > 0.0:
            break
        lo, hi = hi, hi * 2.0
        if hi > 2000.0:
            return None
    while hi - lo > 0.05:
        mid = 0.5 * (lo + hi)
        la, lo_ = destination(lat, lon, brg, mid)
        if central_margin(tsx, la, lo_, t0)[0] > 0.0:
            hi = mid
        else:
            lo = mid
    return 0.5 * (lo + hi)


def gen_solar_local_spread():
    """Sites on and near the limits of the central paths of eclipses spread
    over 2001-2050 (SPREAD_ECLIPSES): the central line at greatest eclipse
    (Astronomy Engine's peak time; the point where the apparent shadow axis
    meets the WGS84 ellipsoid), sites 0.95 of the way to either path limit
    (measured perpendicular to the path), one 1.05 of the way beyond a limit
    (grazing partial), and SPREAD_NAMED. Local circumstances as in
    gen_solar_local, with himmel's ΔT (himmel_delta_t_function). Sites whose
    Sun is below 1 degree at maximum are left out. The type in the labels is
    Astronomy Engine's (it calls the hybrids of 2013, 2023 and 2050 total)."""
    tsx = load.timescale(builtin=False)
    tsx.delta_t_function = himmel_delta_t_function()
    out = []
    for y, mo, d in SPREAD_ECLIPSES:
        g = astronomy.SearchGlobalSolarEclipse(astronomy.Time.Make(y, mo, d, 0, 0, 0).AddDays(-5.0))
        tp = g.peak.tt + 2451545.0
        kind = g.kind.name.lower()
        p0 = axis_ground_point(tsx, tp)
        pa, pb = axis_ground_point(tsx, tp - 2.0 / 1440), axis_ground_point(tsx, tp + 2.0 / 1440)
        if p0 is None or pa is None or pb is None:
            raise ValueError(f'{y}-{mo}-{d}: the axis misses the Earth at greatest eclipse')
        track = bearing(pa[0], pa[1], pb[0], pb[1])
        limits = {s: path_limit(tsx, p0[0], p0[1], track + 90.0 * s, tp) for s in (-1, 1)}
        print(f'{y}-{mo:02}-{d:02} {kind}: central ({p0[0]:.3f}, {p0[1]:.3f}), track {track:.1f}°, '
              f'limits {limits}', flush=True)
        for name, frac, side in SPREAD_FRACTIONS:
            if side == 0:
                lat, lon = p0
            else:
                w = limits[side]
                if w is None:
                    continue
                lat, lon = destination(p0[0], p0[1], track + 90.0 * side, frac * w)
            label = f'{y}-{mo:02}-{d:02} {kind}, {name} ({lat:.4f}, {lon:.4f})'
            case = local_case(tsx, label, round(lat, 4), round(lon, 4), tp)
            if case['sun_alt_max_deg'] < 1.0:
                print('  left out (Sun low):', label, flush=True)
                continue
            out.append(case)
    for label, y, mo, d, lat, lon in SPREAD_NAMED:
        out.append(local_case(tsx, label, lat, lon, tsx.utc(y, mo, d, 12).tt))
    return out


def dump(name, data, source):
    path = os.path.join(OUT, name)
    with open(path, 'w') as fh:
        json.dump({'source': source, 'data': data}, fh, separators=(',', ':'))
        fh.write('\n')
    print('wrote', path)


if __name__ == '__main__':
    import sys
    which = sys.argv[1:] or ['phases', 'lunar', 'solar_local', 'solar_local_spread',
                            'solar_global', 'riseset']
    src = 'JPL DE421 via Skyfield 1.55 (tools/gen_events.py)'
    if 'phases' in which:
        dump('events_phases.json', gen_phases(), src)
    if 'lunar' in which:
        dump('events_lunar.json', gen_lunar(), src)
    if 'solar_local' in which:
        dump('events_solar_local.json', gen_solar_local(), src)
    if 'solar_local_spread' in which:
        dump('events_solar_local_spread.json', gen_solar_local_spread(),
             'JPL DE421 via Skyfield 1.55 with himmel\'s Delta T (tools/gen_events.py solar_local_spread)')
    if 'solar_global' in which:
        dump('events_solar_global.json', gen_solar_global(),
             'Astronomy Engine SearchGlobalSolarEclipse (tools/gen_events.py)')
    if 'riseset' in which:
        dump('events_riseset.json', gen_riseset(), src)
    if 'riseset_planets' in which:
        dump('events_riseset_planets.json', gen_riseset(PLANET_SITES, PLANETS), src)
