//! Fixture loading and error statistics for Himmel's validation tests.
//!
//! The fixtures in `tests/fixtures/` are facts computed outside the project
//! (JPL DE421 through Skyfield, see `tools/gen_fixtures.py`); nothing here
//! runs the generator.

pub mod peer;

use std::path::PathBuf;

use himmel_astro::units::DEG;
use himmel_astro::{Body, Instant, Observer};
use serde::Deserialize;

/// One body's reference values (degrees, km).
#[derive(Debug, Clone, Deserialize)]
pub struct BodyRef {
    pub ra_deg: f64,
    pub dec_deg: f64,
    pub distance_km: f64,
    pub geometric_distance_km: f64,
    pub ecl_lon_deg: f64,
    pub ecl_lat_deg: f64,
    pub alt_deg: f64,
    pub az_deg: f64,
    pub topo_distance_km: f64,
    pub phase_angle_deg: Option<f64>,
    pub illuminated_fraction: Option<f64>,
    pub elongation_deg: Option<f64>,
    pub ae_libration_lon_deg: Option<f64>,
    pub ae_libration_lat_deg: Option<f64>,
    pub ae_magnitude: Option<f64>,
}

/// The reference bodies of one record.
#[derive(Debug, Clone, Deserialize)]
pub struct Bodies {
    pub sun: BodyRef,
    pub moon: BodyRef,
    pub mercury: BodyRef,
    pub venus: BodyRef,
    pub mars: BodyRef,
    pub jupiter: BodyRef,
    pub saturn: BodyRef,
}

impl Bodies {
    /// The reference of `body`.
    pub fn get(&self, body: Body) -> &BodyRef {
        match body {
            Body::Sun => &self.sun,
            Body::Moon => &self.moon,
            Body::Mercury => &self.mercury,
            Body::Venus => &self.venus,
            Body::Mars => &self.mars,
            Body::Jupiter => &self.jupiter,
            Body::Saturn => &self.saturn,
        }
    }
}

/// One instant and observer with every body's reference position.
#[derive(Debug, Clone, Deserialize)]
pub struct Record {
    pub jd_tt: f64,
    pub jd_ut1: f64,
    pub delta_t_s: f64,
    pub gast_hours: f64,
    pub lat: f64,
    pub lon: f64,
    pub elevation_m: f64,
    pub utc: Option<String>,
    pub label: Option<String>,
    pub bodies: Bodies,
}

impl Record {
    /// The reference instant (Skyfield's TT and UT1).
    pub fn instant(&self) -> Instant {
        Instant::from_tt_ut1(self.jd_tt, self.jd_ut1)
    }
    /// The reference observer.
    pub fn observer(&self) -> Observer {
        Observer::new(self.lat, self.lon, self.elevation_m).expect("fixture observer is valid")
    }
}

#[derive(Debug, Deserialize)]
struct FixtureFile {
    #[allow(dead_code)]
    source: String,
    records: Vec<Record>,
}

/// The fixtures folder.
pub fn fixtures_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("fixtures")
}

/// Loads `tests/fixtures/<name>`.
pub fn load(name: &str) -> Vec<Record> {
    let path = fixtures_dir().join(name);
    let text = std::fs::read_to_string(&path)
        .unwrap_or_else(|e| panic!("cannot read {}: {e}", path.display()));
    let f: FixtureFile = serde_json::from_str(&text)
        .unwrap_or_else(|e| panic!("bad fixture {}: {e}", path.display()));
    f.records
}

/// Great-circle angle between two directions given in degrees, arcseconds
/// (haversine-free vector form, accurate for tiny and large angles alike).
pub fn separation_arcsec(lon1_deg: f64, lat1_deg: f64, lon2_deg: f64, lat2_deg: f64) -> f64 {
    let v = |lon: f64, lat: f64| {
        let (lo, la) = (lon * DEG, lat * DEG);
        [la.cos() * lo.cos(), la.cos() * lo.sin(), la.sin()]
    };
    let (a, b) = (v(lon1_deg, lat1_deg), v(lon2_deg, lat2_deg));
    let cross = [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ];
    let s = (cross[0] * cross[0] + cross[1] * cross[1] + cross[2] * cross[2]).sqrt();
    let c = a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    s.atan2(c) / DEG * 3600.0
}

/// Median, 95th percentile and maximum of a sample.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Stats {
    pub median: f64,
    pub p95: f64,
    pub max: f64,
    pub n: usize,
}

impl Stats {
    /// Statistics of `values` (nearest-rank percentiles).
    pub fn of(values: &[f64]) -> Stats {
        assert!(!values.is_empty(), "no values");
        assert!(
            values.iter().all(|v| v.is_finite()),
            "non-finite error value"
        );
        let mut v = values.to_vec();
        v.sort_by(|a, b| a.partial_cmp(b).expect("finite"));
        let rank = |p: f64| v[(((p * v.len() as f64).ceil() as usize).max(1) - 1).min(v.len() - 1)];
        Stats {
            median: rank(0.5),
            p95: rank(0.95),
            max: v[v.len() - 1],
            n: v.len(),
        }
    }
}

impl std::fmt::Display for Stats {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "median {:.3}  p95 {:.3}  max {:.3}  (n = {})",
            self.median, self.p95, self.max, self.n
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn separation_is_symmetric_and_exact_for_known_angles() {
        assert!((separation_arcsec(0.0, 0.0, 1.0, 0.0) - 3600.0).abs() < 1e-9);
        assert!((separation_arcsec(10.0, 89.0, 190.0, 89.0) - 7200.0).abs() < 1e-6);
        assert!(separation_arcsec(359.9999, 0.0, -0.0001, 0.0) < 1e-6);
    }

    #[test]
    fn stats_use_nearest_rank() {
        let v: Vec<f64> = (1..=100).map(f64::from).collect();
        let s = Stats::of(&v);
        assert_eq!((s.median, s.p95, s.max), (50.0, 95.0, 100.0));
    }
}

/// Parses the fixtures' simple UTC strings `YYYY-MM-DDTHH:MM:SS[.fff]Z`.
pub fn parse_fixture_utc(s: &str) -> himmel_astro::UtcDateTime {
    let n = |a: usize, b: usize| s[a..b].parse::<u8>().expect("fixture utc field");
    let year: i32 = s[0..4].parse().expect("fixture year");
    let second: f64 = s[17..s.len() - 1].parse().expect("fixture second");
    himmel_astro::UtcDateTime::new(year, n(5, 7), n(8, 10), n(11, 13), n(14, 16), second)
        .expect("fixture utc is valid")
}

/// Errors of one tier for one body against a set of records: geocentric
/// apparent RA/Dec (great circle), topocentric alt/az (great circle on the
/// horizontal sphere), and geocentric distance (km).
#[derive(Debug, Clone)]
pub struct BodyErrors {
    pub geo_arcsec: Vec<f64>,
    pub ecl_arcsec: Vec<f64>,
    pub topo_arcsec: Vec<f64>,
    pub distance_km: Vec<f64>,
}

/// Compares `precision` with the references for `body` at every record.
pub fn body_errors(
    records: &[Record],
    body: Body,
    precision: himmel_astro::Precision,
    same_utc: bool,
) -> BodyErrors {
    let mut e = BodyErrors {
        geo_arcsec: Vec::new(),
        ecl_arcsec: Vec::new(),
        topo_arcsec: Vec::new(),
        distance_km: Vec::new(),
    };
    for r in records {
        let instant = if same_utc {
            let utc = parse_fixture_utc(r.utc.as_deref().expect("record has utc"));
            Instant::from_utc(&utc).expect("valid utc")
        } else {
            r.instant()
        };
        let sky = himmel_astro::Sky::new(precision, &instant);
        let geo = sky.apparent(body).expect("body available");
        let topo = r.observer().topocentric(&geo, sky.epoch());
        let want = r.bodies.get(body);
        e.geo_arcsec.push(separation_arcsec(
            geo.ra / DEG,
            geo.dec / DEG,
            want.ra_deg,
            want.dec_deg,
        ));
        e.ecl_arcsec.push(separation_arcsec(
            geo.ecl_lon / DEG,
            geo.ecl_lat / DEG,
            want.ecl_lon_deg,
            want.ecl_lat_deg,
        ));
        e.topo_arcsec.push(separation_arcsec(
            topo.az_deg(),
            topo.alt_deg(),
            want.az_deg,
            want.alt_deg,
        ));
        // Sun and Moon: geometric distance between centres at t; planets:
        // the light-time distance of Meeus ch. 33 (Skyfield's astrometric one).
        let want_d = match body {
            Body::Sun | Body::Moon => want.geometric_distance_km,
            _ => want.distance_km,
        };
        e.distance_km.push((geo.distance_km - want_d).abs());
    }
    e
}
