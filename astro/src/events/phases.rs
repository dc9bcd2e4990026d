//! Principal phases of the Moon.
//!
//! First guess: the mean phase of Meeus (*Astronomical Algorithms*, 2nd ed.,
//! ch. 49, eq. 49.1), which is within 0.6 day of the true phase. Refinement:
//! the instant when the apparent geocentric elongation in longitude
//! λ☾ − λ☉ (true ecliptic and equinox of date) equals 0°, 90°, 180° or 270°,
//! by Brent's method on the bracket mean ± 1.5 days (the elongation grows by
//! 10–15° per day, so the bracket always holds exactly one root and never
//! reaches the ±180° wrap).

use crate::ephemeris::{Body, Ephemeris, Epoch};
use crate::error::AstroError;
use crate::time::Instant;
use crate::units::*;

use super::{brent_root, check_interval, instant_tt};

/// A principal phase of the Moon.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
pub enum Phase {
    /// New Moon (elongation in longitude 0°).
    New,
    /// First quarter (90°).
    FirstQuarter,
    /// Full Moon (180°).
    Full,
    /// Last quarter (270°).
    LastQuarter,
}

impl Phase {
    /// `"new"`, `"first_quarter"`, `"full"` or `"last_quarter"` (spec/cli.md).
    pub const fn name(self) -> &'static str {
        match self {
            Phase::New => "new",
            Phase::FirstQuarter => "first_quarter",
            Phase::Full => "full",
            Phase::LastQuarter => "last_quarter",
        }
    }

    /// The quarter index 0–3 (new, first quarter, full, last quarter).
    pub const fn quarter(self) -> u8 {
        match self {
            Phase::New => 0,
            Phase::FirstQuarter => 1,
            Phase::Full => 2,
            Phase::LastQuarter => 3,
        }
    }

    fn from_quarter(q: i64) -> Phase {
        match q.rem_euclid(4) {
            0 => Phase::New,
            1 => Phase::FirstQuarter,
            2 => Phase::Full,
            _ => Phase::LastQuarter,
        }
    }
}

/// One principal phase and its instant.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PhaseEvent {
    /// Which phase.
    pub phase: Phase,
    /// When (TT and UT1).
    pub instant: Instant,
}

/// Mean synodic month, days (Meeus eq. 49.1).
pub const SYNODIC_MONTH: f64 = 29.530_588_861;

/// JDE of the mean new Moon of lunation 0 (2000 January 6), Meeus eq. 49.1.
const LUNATION_ZERO_JDE: JulianDay = 2_451_550.097_66;

/// The (fractional) mean lunation number at TT Julian day `jd`: the inverse
/// of [`mean_phase_jde`] without its tiny quadratic terms.
pub(crate) fn mean_lunation(jd: JulianDay) -> f64 {
    (jd - LUNATION_ZERO_JDE) / SYNODIC_MONTH
}

/// JDE (TT) of the mean phase with lunation number `k` (integer for new
/// Moon, +0.25 first quarter, +0.5 full, +0.75 last quarter; k = 0 is the
/// new Moon of 2000 January 6). Meeus eq. 49.1.
pub fn mean_phase_jde(k: f64) -> JulianDay {
    let t = k / 1236.85;
    LUNATION_ZERO_JDE
        + SYNODIC_MONTH * k
        + t * t * (0.000_154_37 + t * (-0.000_000_150 + t * 0.000_000_000_73))
}

/// The Moon's mean argument of latitude F at lunation `k`, radians
/// (Meeus eq. 49.6); |sin F| > 0.36 rules out an eclipse (Meeus ch. 54).
pub fn mean_argument_of_latitude(k: f64) -> Radians {
    let t = k / 1236.85;
    (160.710_8
        + 390.670_502_84 * k
        + t * t * (-0.001_611_8 + t * (-0.000_002_27 + t * 0.000_000_011)))
        * DEG
}

/// Apparent elongation in longitude λ☾ − λ☉ at TT Julian day `jd_tt`, radians in [−π, π).
pub fn elongation_in_longitude<E: Ephemeris>(
    eph: &E,
    jd_tt: JulianDay,
) -> Result<Radians, AstroError> {
    let epoch = Epoch::new(&instant_tt(jd_tt), eph.nutation_model());
    let m = eph.apparent(Body::Moon, &epoch)?;
    let s = eph.apparent(Body::Sun, &epoch)?;
    Ok(wrap_pi(m.ecl_lon - s.ecl_lon))
}

/// The true phase near lunation `k` (a multiple of 0.25), refined on the
/// apparent elongation in longitude to 1 ms.
pub fn phase_near<E: Ephemeris>(eph: &E, k: f64) -> Result<PhaseEvent, AstroError> {
    AstroError::check_range("lunation number", k, -1.0e6, 1.0e6)?;
    let q = libm::round(k * 4.0) as i64;
    let target = q.rem_euclid(4) as f64 * core::f64::consts::FRAC_PI_2;
    let jde = mean_phase_jde(q as f64 / 4.0);
    let f = |t: f64| -> Result<f64, AstroError> {
        Ok(wrap_pi(elongation_in_longitude(eph, t)? - target))
    };
    let (a, b) = (jde - 1.5, jde + 1.5);
    let fa = f(a)?;
    let fb = f(b)?;
    let t = brent_root(f, a, b, fa, fb, 1e-8)?;
    Ok(PhaseEvent {
        phase: Phase::from_quarter(q),
        instant: instant_tt(t),
    })
}

/// Iterator over the principal phases in `[from, to)`, chronological. Made
/// by [`phases`]; allocates nothing.
#[derive(Debug, Clone)]
pub struct Phases<E> {
    eph: E,
    q: i64,
    from: JulianDay,
    to: JulianDay,
    done: bool,
}

/// All principal Moon phases with `from ≤ t < to`. Errors: the interval is
/// reversed or longer than [`super::MAX_SEARCH_DAYS`].
pub fn phases<E: Ephemeris>(eph: E, from: &Instant, to: &Instant) -> Result<Phases<E>, AstroError> {
    let (a, b) = check_interval(from, to)?;
    let q = libm::floor(mean_lunation(a) * 4.0) as i64 - 4;
    Ok(Phases {
        eph,
        q,
        from: a,
        to: b,
        done: false,
    })
}

impl<E: Ephemeris> Iterator for Phases<E> {
    type Item = Result<PhaseEvent, AstroError>;

    fn next(&mut self) -> Option<Self::Item> {
        while !self.done {
            let k = self.q as f64 / 4.0;
            self.q += 1;
            if mean_phase_jde(k) > self.to + 2.0 {
                self.done = true;
                break;
            }
            if mean_phase_jde(k) < self.from - 2.0 {
                continue;
            }
            match phase_near(&self.eph, k) {
                Ok(ev) if ev.instant.jd_tt >= self.to => {
                    self.done = true;
                }
                Ok(ev) if ev.instant.jd_tt < self.from => {}
                other => return Some(other),
            }
        }
        None
    }
}

/// Walks the lunations around `[from, to)` one by one and yields what a
/// per-lunation search finds there (an eclipse, at most one per lunation)
/// whose time lies in the interval, chronologically; allocates nothing.
/// The engine of [`super::LunarEclipses`] and [`super::GlobalSolarEclipses`].
#[derive(Debug, Clone)]
pub(crate) struct LunationScan<E, T> {
    eph: E,
    k: i64,
    from: JulianDay,
    to: JulianDay,
    done: bool,
    /// The phase searched, in lunations after new Moon (0.5: full Moon).
    phase: f64,
    search: fn(&E, i64) -> Result<Option<T>, AstroError>,
    time: fn(&T) -> JulianDay,
}

impl<E: Ephemeris, T> LunationScan<E, T> {
    /// A scan of `[from, to)` (checked by [`check_interval`]).
    pub(crate) fn new(
        eph: E,
        from: &Instant,
        to: &Instant,
        phase: f64,
        search: fn(&E, i64) -> Result<Option<T>, AstroError>,
        time: fn(&T) -> JulianDay,
    ) -> Result<Self, AstroError> {
        let (a, b) = check_interval(from, to)?;
        Ok(LunationScan {
            eph,
            k: libm::floor(mean_lunation(a)) as i64 - 1,
            from: a,
            to: b,
            done: false,
            phase,
            search,
            time,
        })
    }

    /// The ephemeris the scan searches with.
    pub(crate) fn ephemeris(&self) -> &E {
        &self.eph
    }
}

impl<E: Ephemeris, T> Iterator for LunationScan<E, T> {
    type Item = Result<T, AstroError>;

    fn next(&mut self) -> Option<Self::Item> {
        while !self.done {
            let k = self.k;
            self.k += 1;
            let jde = mean_phase_jde(k as f64 + self.phase);
            if jde > self.to + 1.0 {
                self.done = true;
                break;
            }
            if jde < self.from - 1.0 {
                continue;
            }
            match (self.search)(&self.eph, k) {
                Ok(Some(e)) => {
                    let t = (self.time)(&e);
                    if t >= self.from && t < self.to {
                        return Some(Ok(e));
                    }
                }
                Ok(None) => {}
                Err(e) => return Some(Err(e)),
            }
        }
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Precision, Tiered};

    #[test]
    fn meeus_example_49a() {
        // Meeus example 49.a: new Moon of 1977 February, k = −283, JDE 2443192.65118.
        let ev = phase_near(&Tiered(Precision::Standard), -283.0).unwrap();
        assert_eq!(ev.phase, Phase::New);
        // True phase JDE 2443192.65118 (Meeus' periodic terms, to ~1 min).
        assert!((ev.instant.jd_tt - 2_443_192.651_18).abs() * 86_400.0 < 60.0);
    }
}
