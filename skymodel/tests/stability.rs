//! Numerical-stability campaign (issue 19, design principle 5): properties
//! that must hold for every input, checked with `proptest` over random
//! instants from −4000 to +8000, observers anywhere (the poles and ±180°
//! longitude drawn on purpose), elevations from −400 m to 20 km, every body
//! and accuracy tier.
//!
//! `HIMMEL_STABILITY_CASES` sets the number of cases of each property
//! (default 250: 2 000 cases in all, the CI smoke run). The full campaign:
//!
//! ```sh
//! HIMMEL_STABILITY_CASES=100000 cargo test -p himmel-skymodel --test stability
//! ```
//!
//! Its command, counts and time are recorded in `docs/hardening.md`.

use std::sync::OnceLock;

use himmel_astro::events::phases::phases;
use himmel_astro::events::solar_eclipse::{solar_eclipses, sun_visible_fraction};
use himmel_astro::events::{MAX_SEARCH_JD, MIN_SEARCH_JD};
use himmel_astro::frames::refraction_true_to_apparent;
use himmel_astro::time::calendar_date;
use himmel_astro::units::DEG;
use himmel_astro::{Body, Instant, Observer, Precision, Sky, Tiered, UtcDateTime};
use himmel_skymodel::camera::Exposure;
use himmel_skymodel::projection::Projection;
use himmel_skymodel::scene::{Effect, Scene};
use himmel_skymodel::state::SkyState;
use proptest::prelude::*;
use proptest::test_runner::Config;

/// Cases per property: `HIMMEL_STABILITY_CASES`, default 250.
fn config() -> Config {
    let cases = std::env::var("HIMMEL_STABILITY_CASES")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(250);
    Config {
        cases,
        // Failures are reported with their inputs; no files in the tree.
        failure_persistence: None,
        ..Config::default()
    }
}

/// Latitude: uniform, or exactly a pole or the equator.
fn latitude() -> impl Strategy<Value = f64> {
    prop_oneof![
        8 => -90.0..=90.0f64,
        1 => prop::sample::select(vec![-90.0, 90.0, 0.0, -89.999_999, 89.999_999]),
    ]
}

/// East longitude: uniform, or exactly ±180° or 0°.
fn longitude() -> impl Strategy<Value = f64> {
    prop_oneof![
        8 => -180.0..=180.0f64,
        1 => prop::sample::select(vec![-180.0, 180.0, 0.0, 359.999, -359.999]),
    ]
}

/// Elevation above the ellipsoid, m.
fn elevation() -> impl Strategy<Value = f64> {
    prop_oneof![3 => -400.0..20_000.0f64, 1 => Just(0.0)]
}

/// A TT Julian day within the searchable years −4000 … +8000.
fn jd_tt() -> impl Strategy<Value = f64> {
    MIN_SEARCH_JD..MAX_SEARCH_JD
}

fn precision() -> impl Strategy<Value = Precision> {
    prop::sample::select(vec![Precision::Low, Precision::Standard, Precision::High])
}

/// Civil UTC at (about) TT Julian day `jd`, whole milliseconds, for a scene.
fn utc_near(jd: f64) -> UtcDateTime {
    let (y, m, d) = calendar_date(jd);
    let day = d.floor();
    let ms = ((d - day) * 86_400_000.0).floor().min(86_399_999.0);
    let s = ms / 1000.0;
    UtcDateTime::new(
        y,
        m,
        day as u8,
        (s / 3600.0) as u8,
        ((s % 3600.0) / 60.0) as u8,
        s % 60.0,
    )
    .unwrap()
}

/// Whether a `Debug` rendering holds a NaN or an infinity anywhere.
fn has_non_finite(debug: &str) -> bool {
    debug
        .split(|c: char| !(c.is_ascii_alphanumeric() || c == '.'))
        .any(|tok| tok == "NaN" || tok == "inf")
}

fn unit(v: [f64; 3]) -> bool {
    ((v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt() - 1.0).abs() < 1e-9
}

fn scene_at(lat: f64, lon: f64, elevation: f64, precision: Precision) -> Scene {
    let mut s = Scene::default();
    s.observer.lat_deg = lat;
    s.observer.lon_deg = lon;
    s.observer.elevation_m = elevation;
    s.precision = precision.name().into();
    s
}

/// Solar eclipses 1900–2100 (greatest eclipse, TT), found once.
fn eclipses() -> &'static [f64] {
    static LIST: OnceLock<Vec<f64>> = OnceLock::new();
    LIST.get_or_init(|| {
        let from = Instant::from_tt(2_415_020.5);
        let to = Instant::from_tt(2_488_069.5);
        solar_eclipses(Tiered(Precision::Standard), &from, &to)
            .unwrap()
            .map(|e| e.unwrap().greatest.jd_tt)
            .collect()
    })
}

proptest! {
    #![proptest_config(config())]

    /// Every number of the sky state is finite; the Sun and Moon directions
    /// are unit vectors; fractions lie in [0, 1], angles in their ranges.
    #[test]
    fn sky_state_is_finite_everywhere(
        lat in latitude(), lon in longitude(), elev in elevation(), jd in jd_tt(),
        precision in precision(),
    ) {
        let scene = scene_at(lat, lon, elev, precision);
        let st = SkyState::at_utc(&scene, utc_near(jd)).unwrap();
        let debug = format!("{:?} {:?} {:?} {:?}", st.sun, st.moon, st.night.planets, st.night.star_frame);
        prop_assert!(!has_non_finite(&debug), "{debug}");
        prop_assert!(st.jd_tt.is_finite() && st.observer_altitude_km.is_finite());
        prop_assert!(unit(st.sun.enu) && unit(st.moon.enu) && unit(st.celestial_pole));
        prop_assert!((0.0..=1.0).contains(&st.sun.visible_fraction));
        prop_assert!((0.0..=1.0).contains(&st.moon.illuminated_fraction));
        for alt in [st.sun.alt_deg, st.sun.alt_refracted_deg, st.moon.alt_deg, st.moon.alt_refracted_deg] {
            prop_assert!((-90.0..=90.0).contains(&alt), "{alt}");
        }
        for az in [st.sun.az_deg, st.moon.az_deg] {
            prop_assert!((0.0..360.0).contains(&az), "{az}");
        }
        prop_assert!(st.sun.illuminance_lux > 120_000.0 && st.sun.illuminance_lux < 146_000.0);
    }

    /// Apparent geocentric places are continuous in time: between t and
    /// t + 1 min no body moves more than its greatest apparent motion
    /// (Moon 16.5°/day; Mercury, the fastest planet, 2.2°/day; the Sun
    /// 1.02°/day; with a 1.5× margin), and the distance changes by less
    /// than its greatest rate (Moon 0.1 km/s, planets 75 km/s).
    #[test]
    fn positions_are_continuous_in_time(
        jd in jd_tt(), body in prop::sample::select(Body::ALL.to_vec()),
        precision in precision(),
    ) {
        let minute = 1.0 / 1440.0;
        let a = Sky::new(precision, &Instant::from_tt(jd)).apparent(body).unwrap();
        let b = Sky::new(precision, &Instant::from_tt(jd + minute)).apparent(body).unwrap();
        let sep = (a.dec.sin() * b.dec.sin() + a.dec.cos() * b.dec.cos() * (a.ra - b.ra).cos())
            .clamp(-1.0, 1.0)
            .acos()
            / DEG;
        let (deg_per_day, km_s) = match body {
            Body::Moon => (16.5, 0.1),
            Body::Sun => (1.02, 0.6),
            _ => (2.2, 75.0),
        };
        prop_assert!(sep < 1.5 * deg_per_day * minute, "{body:?} moved {sep}° in a minute at JD {jd}");
        prop_assert!((a.distance_km - b.distance_km).abs() < 1.5 * km_s * 60.0);
        prop_assert!(a.ra.is_finite() && a.dec.is_finite() && a.ecl_lon.is_finite() && a.ecl_lat.is_finite());
    }

    /// The apparent altitude h + R(h) grows with the true altitude h
    /// everywhere from nadir to zenith (the fade below −1° included), in any
    /// weather in the accepted ranges, and R is finite and ≥ 0.
    #[test]
    fn refraction_keeps_altitudes_in_order(
        h1 in -90.0..=90.0f64, dh in 0.0..=10.0f64,
        pressure in 0.0..1100.0f64, temperature in -90.0..60.0f64,
    ) {
        let h2 = (h1 + dh).min(90.0);
        let r1 = refraction_true_to_apparent(h1 * DEG, pressure, temperature);
        let r2 = refraction_true_to_apparent(h2 * DEG, pressure, temperature);
        prop_assert!(r1.is_finite() && r1 >= 0.0 && r2.is_finite() && r2 >= 0.0);
        prop_assert!(h1 * DEG + r1 <= h2 * DEG + r2 + 1e-12, "h {h1} → {h2}: R {r1} → {r2}");
        let f = himmel_skymodel::refraction::refraction_of_apparent((h1 * DEG) as f32);
        prop_assert!(f.is_finite() && f >= 0.0);
    }

    /// The visible fraction of the Sun's disk lies in [0, 1] everywhere,
    /// within ±4 h of each solar eclipse of 1900–2100 and at any instant.
    #[test]
    fn visible_fraction_of_the_sun_is_a_fraction(
        lat in latitude(), lon in longitude(), elev in elevation(),
        pick in any::<prop::sample::Index>(), hours in -4.0..4.0f64, jd in jd_tt(),
        precision in precision(),
    ) {
        let obs = Observer::new(lat, lon, elev).unwrap();
        let near = eclipses()[pick.index(eclipses().len())] + hours / 24.0;
        for t in [near, jd] {
            let f = sun_visible_fraction(&Tiered(precision), &obs, &Instant::from_tt(t)).unwrap();
            prop_assert!((0.0..=1.0).contains(&f), "{f} at JD {t}, {lat} {lon}");
        }
    }

    /// The Moon's physical ephemeris is finite at any instant and within a
    /// minute of every new and full Moon (phase angle 180° and 0°).
    #[test]
    fn moon_physical_ephemeris_is_finite_at_every_phase(
        jd in MIN_SEARCH_JD..MAX_SEARCH_JD - 10.0, minutes in -1.0..1.0f64, precision in precision(),
    ) {
        // Principal phases are 6.5–8.2 days apart.
        let next = phases(Tiered(precision), &Instant::from_tt(jd), &Instant::from_tt(jd + 9.0))
            .unwrap()
            .next()
            .unwrap()
            .unwrap();
        for t in [jd, next.instant.jd_tt + minutes / 1440.0] {
            let m = Sky::new(precision, &Instant::from_tt(t)).moon_physical().unwrap();
            let debug = format!("{m:?}");
            prop_assert!(!has_non_finite(&debug), "{debug}");
            prop_assert!((0.0..=1.0).contains(&m.illuminated_fraction));
            prop_assert!((0.0..=std::f64::consts::PI).contains(&m.phase_angle));
        }
    }

    /// A phase search over [a, b) finds exactly the events of [a, m) and
    /// [m, b) together: none lost, none found twice, at the same instants.
    #[test]
    fn phase_search_agrees_over_sub_intervals(
        a in MIN_SEARCH_JD..MAX_SEARCH_JD - 200.0, len in 0.0..200.0f64, cut in 0.0..1.0f64,
    ) {
        let eph = Tiered(Precision::Low);
        let b = a + len;
        let m = a + cut * len;
        let list = |x: f64, y: f64| -> Vec<f64> {
            phases(eph, &Instant::from_tt(x), &Instant::from_tt(y))
                .unwrap()
                .map(|e| e.unwrap().instant.jd_tt)
                .collect()
        };
        let whole = list(a, b);
        let mut parts = list(a, m);
        parts.extend(list(m, b));
        prop_assert_eq!(whole.len(), parts.len(), "[{}, {}) cut at {}", a, b, m);
        for (w, p) in whole.iter().zip(&parts) {
            prop_assert!((w - p).abs() < 1e-9, "{w} vs {p}");
        }
    }

    /// A valid scene survives JSON: `Scene::from_json(to_json(s)) == s`,
    /// every f64 to the bit.
    #[test]
    fn scene_json_round_trip(
        lat in latitude(), lon in longitude(), elev in elevation(), jd in jd_tt(),
        precision in precision(),
        projection in prop::sample::select(vec![Projection::Fisheye, Projection::Equirect, Projection::Perspective, Projection::Cubemap]),
        width in 1u32..=2048, height in 1u32..=2048,
        yaw in -720.0..=720.0f64, pitch in -90.0..=90.0f64, fov in 0.001..179.999f64,
        effects in prop::sample::subsequence(Effect::ALL.to_vec(), 0..=7),
        ev in prop::option::of(-30.0..=40.0f64),
        sun_scale in 0.01..=100.0f64, moon_scale in 0.01..=100.0f64,
        night_vision in any::<bool>(), dither in any::<bool>(),
    ) {
        let mut s = scene_at(lat, lon, elev, precision);
        let t = utc_near(jd);
        s.time.utc = format!(
            "{}{:04}-{:02}-{:02}T{:02}:{:02}:{:06.3}Z",
            if t.year < 0 { "-" } else { "" },
            t.year.abs(), t.month, t.day, t.hour, t.minute, t.second
        );
        s.camera.projection = projection;
        s.camera.width = width;
        s.camera.height = height;
        s.camera.yaw_deg = yaw;
        s.camera.pitch_deg = pitch;
        s.camera.fov_deg = fov;
        s.effects = effects;
        s.exposure = match ev { Some(v) => Exposure::Ev100(v), None => Exposure::Auto };
        s.sun_scale = sun_scale;
        s.moon_scale = moon_scale;
        s.night_vision = night_vision;
        s.dither = dither;
        prop_assert!(s.validate().is_ok(), "{:?}", s.validate());
        let json = serde_json::to_string(&s).unwrap();
        let back = Scene::from_json(&json).map_err(|e| TestCaseError::fail(format!("{e}: {json}")))?;
        prop_assert_eq!(&back, &s);
        // The time it names is the instant the sky state is computed for.
        prop_assert!(SkyState::at(&back).is_ok(), "{}", s.time.utc);
    }
}
