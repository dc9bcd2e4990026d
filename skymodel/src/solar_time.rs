//! Local apparent solar time: addressing an instant by the fraction of the
//! day (`time.day_fraction`, `--day-fraction F`).
//!
//! Apparent solar time is the hour angle of the true (apparent) Sun plus
//! 12 h: it reads 12:00 exactly when the Sun crosses the observer's meridian
//! (upper transit). It differs from local mean time (UT1 + λ/15°) by the
//! equation of time E, |E| < 17 min (Meeus, *Astronomical Algorithms* 2nd
//! ed., ch. 28: E = apparent − mean solar time). Rather than a series for E,
//! the instant is solved from the definition, with the astronomy core's own
//! places:
//!
//! ```text
//!   H(t) = LAST(t) − α☉(t)            local apparent sidereal time minus the
//!                                     Sun's apparent geocentric right ascension
//!   LAT(t) = (H(t) + π) / 2π  (mod 1)  apparent solar time as a fraction of a day
//!   find t on the local date with LAT(t) = F
//! ```
//!
//! The geocentric place is used, as for the civil definition of apparent
//! time; the topocentric Sun's hour angle differs by its parallax
//! (≤ 8.8″, ≤ 0.6 s of time).
//!
//! *The local date* is the calendar date of local mean time (UT1 + λ/15°)
//! at the scene's instant, so that `--day-fraction 0.5` is the solar noon
//! of the day the observer is living, at any longitude. Newton's iteration
//! converges fast because apparent solar time runs at one day per day to
//! within the rate of E (≤ 30 s per day, 3.5·10⁻⁴): each round shrinks the
//! error by that factor, and four rounds reach microseconds.

use himmel_astro::{Body, Instant, Observer, Precision, Sky, UtcDateTime};

use crate::scene_error::SceneError;

const SECONDS_PER_DAY: f64 = 86_400.0;
const TAU: f64 = core::f64::consts::TAU;

/// `x` wrapped into [−0.5, 0.5).
fn wrap_half(x: f64) -> f64 {
    x - (x + 0.5).floor()
}

/// The instant `days` after `base`, both time scales shifted alike (UT1
/// runs at the rate of TT to 10⁻⁸ over these spans).
pub fn instant_after(base: &Instant, days: f64) -> Instant {
    Instant::from_tt_ut1(base.jd_tt + days, base.jd_ut1 + days)
}

/// Local apparent solar time at `instant` for `observer`, as a fraction of
/// a day in [0, 1) (0.5 = the Sun on the meridian).
pub fn apparent_solar_time(
    instant: &Instant,
    observer: &Observer,
    precision: Precision,
) -> Result<f64, SceneError> {
    let sky = Sky::new(precision, instant);
    let sun = sky.apparent(Body::Sun).map_err(|e| SceneError {
        field: "time.utc".into(),
        message: e.to_string(),
    })?;
    let hour_angle = observer.local_sidereal_time(sky.epoch()) - sun.ra;
    let f = (hour_angle + core::f64::consts::PI) / TAU;
    Ok(f - f.floor())
}

/// The instant whose local apparent solar time is `fraction` of a day
/// (0 ≤ F < 1; 0.25 = apparent solar 06:00) on the local date of `utc` at
/// `observer`'s longitude (see the module documentation). Errors name
/// `time.day_fraction` when F is outside [0, 1), `time.utc` when the
/// instant is outside the astronomy core's range.
pub fn day_fraction_instant(
    utc: &UtcDateTime,
    observer: &Observer,
    precision: Precision,
    fraction: f64,
) -> Result<UtcDateTime, SceneError> {
    if !(fraction.is_finite() && (0.0..1.0).contains(&fraction)) {
        return Err(SceneError {
            field: "time.day_fraction".into(),
            message: format!("{fraction} is outside [0, 1) (0.25 = apparent solar 06:00)"),
        });
    }
    let base = Instant::from_utc(utc).map_err(|e| SceneError {
        field: "time.utc".into(),
        message: e.to_string(),
    })?;
    // Local mean midnight (UT1) of the local date, in days from `base`.
    let lmt = base.jd_ut1 + observer.lon_deg() / 360.0;
    let midnight = ((lmt - 0.5).floor() + 0.5) - lmt;
    // Local mean time F as the first guess, then Newton on LAT(t) − F.
    let mut days = midnight + fraction;
    for _ in 0..6 {
        let lat = apparent_solar_time(&instant_after(&base, days), observer, precision)?;
        let err = wrap_half(fraction - lat);
        days += err;
        if err.abs() * SECONDS_PER_DAY < 1e-6 {
            break;
        }
    }
    Ok(instant_after(&base, days).to_utc())
}

#[cfg(test)]
mod tests {
    use super::*;
    use himmel_astro::events::riseset::{rise_set_transit, EventKind};
    use himmel_astro::Tiered;

    fn utc(s: &str) -> UtcDateTime {
        himmel_astro::time::parse_rfc3339(s).unwrap()
    }

    fn seconds_between(a: &UtcDateTime, b: &UtcDateTime) -> f64 {
        let (a, b) = (Instant::from_utc(a).unwrap(), Instant::from_utc(b).unwrap());
        (b.jd_tt - a.jd_tt) * SECONDS_PER_DAY
    }

    /// F = 0.5 is the Sun's upper transit found independently by the
    /// events module (its own root search on the topocentric hour angle):
    /// equal within 1 s of time at several longitudes and seasons, including
    /// the extremes of the equation of time (Feb 11: −14.2 min, Nov 3:
    /// +16.4 min, Meeus ch. 28).
    #[test]
    fn half_day_is_the_transit_of_the_events_module() {
        for (date, lat, lon) in [
            ("2024-02-11T12:00:00Z", 48.14, 11.58),
            ("2024-11-03T12:00:00Z", -33.9, 151.2),
            ("2024-06-21T12:00:00Z", 32.78, -96.8),
            ("2024-03-20T12:00:00Z", 0.0, 0.0),
        ] {
            let obs = Observer::new(lat, lon, 0.0).unwrap();
            let noon = day_fraction_instant(&utc(date), &obs, Precision::Standard, 0.5).unwrap();
            let ev = rise_set_transit(
                &Tiered(Precision::Standard),
                Body::Sun,
                &obs,
                noon.year,
                noon.month,
                noon.day,
            )
            .unwrap();
            let transit = ev
                .events()
                .iter()
                .find(|e| e.kind == EventKind::Transit)
                .expect("a transit that day")
                .instant
                .to_utc();
            let dt = seconds_between(&noon, &transit);
            assert!(dt.abs() < 1.0, "{date} {lon}: {dt} s");
        }
    }

    /// The equation of time E = apparent − mean solar time at Greenwich on
    /// 1992 October 13.0 TD: Meeus example 28.b gives E = +13m42.7s
    /// (3.427351°, from the VSOP87 Sun).
    #[test]
    fn equation_of_time_matches_meeus_example_28b() {
        let obs = Observer::new(0.0, 0.0, 0.0).unwrap();
        let t = Instant::from_tt(2_448_908.5);
        let apparent = apparent_solar_time(&t, &obs, Precision::High).unwrap();
        let mean = t.jd_ut1 + 0.5 - (t.jd_ut1 + 0.5).floor();
        let e = wrap_half(apparent - mean) * SECONDS_PER_DAY;
        let meeus = 3.427351 / 360.0 * SECONDS_PER_DAY;
        assert!((e - meeus).abs() < 0.5, "E = {e} s, Meeus {meeus} s");
    }

    #[test]
    fn quarter_is_six_hours_before_noon_and_the_date_is_local() {
        // Far west of Greenwich early in the UTC day: the local date is
        // the date of local mean time, the day before the UTC date.
        let obs = Observer::new(20.0, -150.0, 0.0).unwrap();
        // 2024-05-01T06:00Z is 20:00 LMT of April 30 at 150° W.
        let t = utc("2024-05-01T06:00:00Z");
        let q = day_fraction_instant(&t, &obs, Precision::Standard, 0.25).unwrap();
        let n = day_fraction_instant(&t, &obs, Precision::Standard, 0.5).unwrap();
        // Apparent 06:00 is six apparent-solar hours before noon: 6 h of
        // mean time to within the change of E in 6 h (< 8 s).
        let dt = seconds_between(&q, &n);
        assert!((dt - 21_600.0).abs() < 8.0, "{dt}");
        // Noon of April 30 at 150° W is near 22:00 UTC that day.
        assert_eq!((n.month, n.day, n.hour), (4, 30, 21));
        let lat = apparent_solar_time(&Instant::from_utc(&q).unwrap(), &obs, Precision::Standard)
            .unwrap();
        assert!((lat - 0.25).abs() * SECONDS_PER_DAY < 1e-3, "{lat}");
    }

    #[test]
    fn fraction_outside_the_day_is_refused() {
        let obs = Observer::new(0.0, 0.0, 0.0).unwrap();
        let t = utc("2024-05-01T06:00:00Z");
        for f in [1.0, -0.1, f64::NAN] {
            let e = day_fraction_instant(&t, &obs, Precision::Low, f).unwrap_err();
            assert_eq!(e.field, "time.day_fraction");
        }
    }
}
