//! Apparent places of the 30 brightest named stars of the embedded catalogue
//! against Skyfield 1.55 `Star` objects built from the same catalogue values
//! with DE421's Earth (1950–2050, observers from −89.9° to +64°), and against
//! SOFA/ERFA at ±100 years from the catalogue epoch
//! (`tools/gen_star_fixtures.py`). Also the fast path against the exact path.
//! Measured figures are printed: `cargo test -p himmel-tests --test stars -- --nocapture`.

use himmel_astro::frames::{equatorial_to_vector, NutationModel};
use himmel_astro::stars::{FastStar, FrameRotation, StarReduction};
use himmel_astro::units::{ARCSEC, DEG};
use himmel_astro::{Epoch, Instant, Observer};
use himmel_catalog::Catalog;
use himmel_tests::{fixtures_dir, Stats};
use serde::Deserialize;

#[derive(Deserialize)]
struct Case {
    hip: u32,
    jd_tt: f64,
    jd_ut1: f64,
    #[serde(default)]
    lat: f64,
    #[serde(default)]
    lon: f64,
    #[serde(default)]
    elevation_m: f64,
    alt_deg: Option<f64>,
    az_deg: Option<f64>,
    ra_deg: Option<f64>,
    dec_deg: Option<f64>,
    #[serde(default)]
    erfa: bool,
}

#[derive(Deserialize)]
struct Fixture {
    cases: Vec<Case>,
}

fn fixture() -> Fixture {
    let text = std::fs::read_to_string(fixtures_dir().join("stars_skyfield.json")).unwrap();
    serde_json::from_str(&text).unwrap()
}

fn angle(a: glam::DVec3, b: glam::DVec3) -> f64 {
    a.cross(b).length().atan2(a.dot(b))
}

#[test]
fn topocentric_alt_az_within_one_arcsecond_of_skyfield() {
    let cat = Catalog::embedded().unwrap();
    let mut alt_err = Vec::new();
    let mut az_err = Vec::new();
    let mut polar = 0;
    for c in fixture().cases.iter().filter(|c| c.alt_deg.is_some()) {
        let star = cat.by_hip(c.hip).unwrap();
        let epoch = Epoch::new(
            &Instant::from_tt_ut1(c.jd_tt, c.jd_ut1),
            NutationModel::Iau1980,
        );
        let obs = Observer::new(c.lat, c.lon, c.elevation_m).unwrap();
        let t = StarReduction::new(&epoch).topocentric(&star.astrometry, &obs);
        let (alt, az) = (c.alt_deg.unwrap(), c.az_deg.unwrap());
        alt_err.push((t.alt_deg() - alt).abs() * 3600.0);
        // Azimuth error as an angle on the sky (×cos alt).
        let daz = (t.az_deg() - az + 540.0).rem_euclid(360.0) - 180.0;
        az_err.push(daz.abs() * 3600.0 * (alt * DEG).cos());
        if c.lat < -89.0 {
            polar += 1;
        }
    }
    let (sa, sz) = (Stats::of(&alt_err), Stats::of(&az_err));
    println!("alt error (arcsec): {sa}\naz·cos(alt) error (arcsec): {sz}");
    assert!(alt_err.len() >= 3000 && polar >= 600);
    assert!(sa.max <= 1.0 && sz.max <= 1.0, "{sa} / {sz}");
}

#[test]
fn geocentric_apparent_places_within_one_arcsecond_over_two_centuries() {
    let cat = Catalog::embedded().unwrap();
    let (mut near, mut far) = (Vec::new(), Vec::new());
    for c in fixture().cases.iter().filter(|c| c.ra_deg.is_some()) {
        let star = cat.by_hip(c.hip).unwrap();
        let epoch = Epoch::new(
            &Instant::from_tt_ut1(c.jd_tt, c.jd_ut1),
            NutationModel::Iau1980,
        );
        let app = StarReduction::new(&epoch).apparent(&star.astrometry);
        let want = equatorial_to_vector(c.ra_deg.unwrap() * DEG, c.dec_deg.unwrap() * DEG);
        let e = angle(app.vector, want) / ARCSEC;
        if c.erfa {
            far.push(e);
        } else {
            near.push(e);
        }
    }
    let (sn, sf) = (Stats::of(&near), Stats::of(&far));
    println!("1950–2050 vs Skyfield (arcsec): {sn}\n±100 yr vs ERFA (arcsec): {sf}");
    assert!(
        !far.is_empty() && sn.max <= 1.0 && sf.max <= 1.0,
        "{sn} / {sf}"
    );
}

/// The fast path (cached unit vectors with proper-motion rates, one matrix
/// and one aberration vector per frame) against the exact path, for every
/// catalogue star, over ±100 years of the refresh epoch.
#[test]
fn fast_path_within_two_arcseconds_for_fifty_years() {
    let cat = Catalog::embedded().unwrap();
    let refresh = 2_451_545.0;
    let fast: Vec<FastStar> = cat
        .stars()
        .iter()
        .map(|s| FastStar::new(&s.astrometry, refresh))
        .collect();
    let obs = Observer::new(52.5, 13.4, 40.0).unwrap();
    let mut rows = Vec::new();
    for years in [
        -100.0, -75.0, -50.0, -25.0, -5.0, 0.0, 5.0, 25.0, 50.0, 75.0, 100.0,
    ] {
        let epoch = Epoch::new(
            &Instant::from_tt(refresh + years * 365.25 + 0.37),
            NutationModel::Iau1980,
        );
        let red = StarReduction::new(&epoch);
        let frame = FrameRotation::new(&epoch, &obs, refresh);
        let mut worst: f64 = 0.0;
        for (s, f) in cat.stars().iter().zip(&fast) {
            let exact = red.topocentric(&s.astrometry, &obs).enu();
            worst = worst.max(angle(exact, frame.enu(f)) / ARCSEC);
        }
        println!("fast vs exact at {years:+} yr: max {worst:.3}″");
        rows.push((years, worst));
    }
    for (years, worst) in rows {
        if f64::abs(years) <= 50.0 {
            assert!(worst <= 2.0, "{years}: {worst}″");
        }
        assert!(worst.is_finite());
    }
}
