//! The peer crate `astro` (astro-rust, crates.io) reduced to apparent
//! places the way Meeus prescribes, so that its accuracy and cost can be
//! measured beside ours on the same instants.

use astro::planet::Planet as PeerPlanet;
use himmel_astro::units::ARCSEC;
use himmel_astro::Body;

/// Apparent geocentric (RA, Dec) in radians from astro-rust, true equator of
/// date: its series, its FK5 correction, Meeus' aberration, its nutation.
pub fn apparent_radec(body: Body, jd_tt: f64) -> (f64, f64) {
    let (dpsi, deps) = astro::nutation::nutation(jd_tt);
    // astro-rust 2.0's `mn_oblq_IAU` evaluates the IAU 1980 polynomial in
    // units of 10 000 years instead of centuries (it freezes the obliquity at
    // its J2000 value, ~47″ per century off); its Laskar form is right.
    let eps = astro::ecliptic::mn_oblq_laskar(jd_tt) + deps;
    let (lon, lat) = match body {
        Body::Moon => {
            let (p, _) = astro::lunar::geocent_ecl_pos(jd_tt);
            (p.long + dpsi, p.lat)
        }
        Body::Sun => {
            let (p, r) = astro::sun::geocent_ecl_pos(jd_tt);
            let (l, b) = astro::sun::ecl_coords_to_FK5(jd_tt, p.long, p.lat);
            (l - 20.4898 * ARCSEC / r + dpsi, b)
        }
        _ => {
            let planet = match body {
                Body::Mercury => PeerPlanet::Mercury,
                Body::Venus => PeerPlanet::Venus,
                Body::Mars => PeerPlanet::Mars,
                Body::Jupiter => PeerPlanet::Jupiter,
                _ => PeerPlanet::Saturn,
            };
            let (p, _) = astro::planet::geocent_apprnt_ecl_coords(&planet, jd_tt);
            let (l, b) = astro::planet::ecl_coords_to_FK5(jd_tt, p.long, p.lat);
            // Aberration with the Sun's longitude (Meeus eq. 23.2, no e-terms).
            let (s, _) = astro::sun::geocent_ecl_pos(jd_tt);
            let k = 20.49552 * ARCSEC;
            let dl = -k * (s.long - l).cos() / b.cos();
            let db = -k * b.sin() * (s.long - l).sin();
            (l + dl + dpsi, b + db)
        }
    };
    let ra = (lon.sin() * eps.cos() - lat.tan() * eps.sin()).atan2(lon.cos());
    let dec = (lat.sin() * eps.cos() + lat.cos() * eps.sin() * lon.sin()).asin();
    (ra.rem_euclid(std::f64::consts::TAU), dec)
}

/// The peer's raw theory call for `body` (what its users call per frame):
/// geocentric ecliptic coordinates of date, no nutation.
pub fn raw_position(body: Body, jd_tt: f64) -> (f64, f64, f64) {
    match body {
        Body::Moon => {
            let (p, d) = astro::lunar::geocent_ecl_pos(jd_tt);
            (p.long, p.lat, d)
        }
        Body::Sun => {
            let (p, d) = astro::sun::geocent_ecl_pos(jd_tt);
            (p.long, p.lat, d)
        }
        _ => {
            let planet = match body {
                Body::Mercury => PeerPlanet::Mercury,
                Body::Venus => PeerPlanet::Venus,
                Body::Mars => PeerPlanet::Mars,
                Body::Jupiter => PeerPlanet::Jupiter,
                _ => PeerPlanet::Saturn,
            };
            let (p, d) = astro::planet::geocent_apprnt_ecl_coords(&planet, jd_tt);
            (p.long, p.lat, d)
        }
    }
}
