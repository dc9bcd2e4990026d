//! Rise, set and upper transit of the Sun, the Moon and the planets for an
//! observer and a UTC calendar day, polar day and night included.
//!
//! Horizons (spec/cli.md): the Sun rises or sets when the geometric
//! (unrefracted) topocentric altitude of its centre is −0.8333° (34′ of
//! refraction plus 16′ semidiameter); the Moon at −0.5667° (refraction)
//! minus its topocentric semidiameter asin(1737.4 km / distance), parallax
//! included; planets at −0.5667°. The horizon is the sea-level one: the
//! observer's elevation moves the observer but adds no dip.
//!
//! Search: the function f(t) = altitude(t) − horizon(t) is scanned over the
//! day with [`super::scan_crossings`] at a one-hour step, using the
//! curvature bound |f''| ≤ 2400°/day²: the Earth's rotation gives
//! |d²h/dt²| ≤ ω² cos φ cos δ with ω = 360.99°/day (6.30 rad/day, so
//! ω² = 2274°/day²), topocentric parallax adds at most 1°·ω² = 40°/day², the
//! Moon's motion in declination less than 2°/day². The bound holds wherever
//! the altitude is away from the zenith (where it has a cusp); an hour-long
//! interval containing a zenith passage has both ends far above the horizon
//! and cannot hold a root. Near-tangent passes are subdivided down to 1 s
//! (a graze shallower than 2400·(1 s)²/8 ≈ 4·10⁻⁸ degrees is not an event).
//! Upper transit: the instant when the topocentric hour angle crosses 0
//! from negative to positive (whatever the altitude).
//!
//! Day state: `Normal` when a rise or a set happens in the day, otherwise
//! `AlwaysUp` / `AlwaysDown` from the sign of f (which then cannot change
//! within the day).

use crate::ephemeris::{Body, Ephemeris, Epoch};
use crate::error::AstroError;
use crate::observe::Observer;
use crate::time::{Instant, UtcDateTime};
use crate::units::*;

use super::{brent_root, instant_tt, scan_crossings, ScanParams};

/// Standard horizon of the Sun's centre, degrees (refraction + semidiameter).
pub const SUN_HORIZON_DEG: Degrees = -0.8333;
/// Standard refraction at the horizon, degrees (used for the Moon and planets).
pub const REFRACTION_HORIZON_DEG: Degrees = -0.5667;
/// Bound on |d²(altitude − horizon)/dt²|, degrees per day² (module docs).
pub const MAX_ALTITUDE_CURVATURE: f64 = 2400.0;
/// Scan step of the horizon search, days (one hour).
pub const SCAN_STEP_DAYS: f64 = 1.0 / 24.0;

/// The altitude that counts as "on the horizon" for a body.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Horizon {
    /// A fixed geometric altitude of the body's centre, degrees.
    Fixed(Degrees),
    /// −0.5667° minus the topocentric semidiameter of a sphere of this radius (km).
    RefractionMinusSemidiameter(Km),
}

impl Horizon {
    /// The spec/cli.md horizon of `body`.
    pub fn standard(body: Body) -> Horizon {
        match body {
            Body::Sun => Horizon::Fixed(SUN_HORIZON_DEG),
            Body::Moon => Horizon::RefractionMinusSemidiameter(MOON_RADIUS_KM),
            _ => Horizon::Fixed(REFRACTION_HORIZON_DEG),
        }
    }

    /// The horizon altitude for a body at topocentric distance `distance_km`, degrees.
    pub fn altitude_deg(&self, distance_km: Km) -> Degrees {
        match *self {
            Horizon::Fixed(h) => h,
            Horizon::RefractionMinusSemidiameter(r) => {
                REFRACTION_HORIZON_DEG - safe_asin(r / distance_km.max(r)) / DEG
            }
        }
    }
}

/// What happens.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum EventKind {
    /// The body's centre rises through the horizon.
    Rise,
    /// The body's centre sets through the horizon.
    Set,
    /// Upper meridian transit (topocentric hour angle 0).
    Transit,
}

impl EventKind {
    /// `"rise"`, `"set"` or `"transit"` (spec/cli.md).
    pub const fn name(self) -> &'static str {
        match self {
            EventKind::Rise => "rise",
            EventKind::Set => "set",
            EventKind::Transit => "transit",
        }
    }
}

/// One rise, set or transit.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Event {
    /// What.
    pub kind: EventKind,
    /// When.
    pub instant: Instant,
}

/// Whether the body crosses the horizon that day.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum DayState {
    /// At least one rise or set.
    Normal,
    /// Above the horizon all day.
    AlwaysUp,
    /// Below the horizon all day.
    AlwaysDown,
}

impl DayState {
    /// `"normal"`, `"always_up"` or `"always_down"` (spec/cli.md).
    pub const fn name(self) -> &'static str {
        match self {
            DayState::Normal => "normal",
            DayState::AlwaysUp => "always_up",
            DayState::AlwaysDown => "always_down",
        }
    }
}

/// Most events kept for one day. A body crosses the horizon at most a few
/// times a day (altitude is monotonic between culminations up to the slow
/// change of declination), so this is never reached in practice; if it
/// were, [`DayEvents::truncated`] says so.
pub const MAX_DAY_EVENTS: usize = 12;

/// The events of one UTC day, chronological (fixed capacity, no allocation).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DayEvents {
    /// The day's state.
    pub state: DayState,
    events: [Event; MAX_DAY_EVENTS],
    len: usize,
    /// `true` if more than [`MAX_DAY_EVENTS`] events were found (the rest dropped).
    pub truncated: bool,
}

impl DayEvents {
    /// The events, in chronological order.
    pub fn events(&self) -> &[Event] {
        &self.events[..self.len]
    }

    fn push(&mut self, e: Event) {
        if self.len < MAX_DAY_EVENTS {
            self.events[self.len] = e;
            self.len += 1;
        } else {
            self.truncated = true;
        }
    }

    fn sort(&mut self) {
        // Insertion sort: a handful of items.
        let ev = &mut self.events[..self.len];
        for i in 1..ev.len() {
            let mut j = i;
            while j > 0 && ev[j - 1].instant.jd_tt > ev[j].instant.jd_tt {
                ev.swap(j - 1, j);
                j -= 1;
            }
        }
    }
}

/// Altitude minus horizon, degrees, and the topocentric hour angle wrapped
/// to [−π, π), at TT Julian day `jd_tt`.
pub fn altitude_above_horizon<E: Ephemeris>(
    eph: &E,
    body: Body,
    observer: &Observer,
    horizon: &Horizon,
    jd_tt: JulianDay,
) -> Result<(Degrees, Radians), AstroError> {
    let epoch = Epoch::new(&instant_tt(jd_tt), eph.nutation_model());
    let geo = eph.apparent(body, &epoch)?;
    let topo = observer.topocentric(&geo, &epoch);
    Ok((
        topo.alt / DEG - horizon.altitude_deg(topo.distance_km),
        wrap_pi(topo.hour_angle),
    ))
}

/// TT Julian days of 0h UTC of `(year, month, day)` and of the next day.
pub fn utc_day_bounds(year: i32, month: u8, day: u8) -> Result<(JulianDay, JulianDay), AstroError> {
    let start = Instant::from_utc(&UtcDateTime::new(year, month, day, 0, 0, 0.0)?)?;
    let days = crate::time::days_in_month(year, month);
    let (ny, nm, nd) = if day < days {
        (year, month, day + 1)
    } else if month < 12 {
        (year, month + 1, 1)
    } else {
        (
            year.checked_add(1).ok_or(AstroError::InvalidDate {
                what: "year",
                reason: "year out of range",
            })?,
            1,
            1,
        )
    };
    // 1582 October 4 is followed by October 15.
    let next = if year == 1582 && month == 10 && day == 4 {
        UtcDateTime::new(1582, 10, 15, 0, 0, 0.0)?
    } else {
        UtcDateTime::new(ny, nm, nd, 0, 0, 0.0)?
    };
    let end = Instant::from_utc(&next)?;
    Ok((start.jd_tt, end.jd_tt))
}

/// Rise, set and upper transit of `body` for `observer` during the UTC day
/// `year-month-day`, with the horizon of [`Horizon::standard`].
pub fn rise_set_transit<E: Ephemeris>(
    eph: &E,
    body: Body,
    observer: &Observer,
    year: i32,
    month: u8,
    day: u8,
) -> Result<DayEvents, AstroError> {
    let (t0, t1) = utc_day_bounds(year, month, day)?;
    events_between(eph, body, observer, &Horizon::standard(body), t0, t1)
}

/// Rise, set and upper transit of `body` with `t0 ≤ t < t1` (TT Julian days,
/// at most two days apart) for any horizon definition.
pub fn events_between<E: Ephemeris>(
    eph: &E,
    body: Body,
    observer: &Observer,
    horizon: &Horizon,
    t0: JulianDay,
    t1: JulianDay,
) -> Result<DayEvents, AstroError> {
    AstroError::check_range("search span (days)", t1 - t0, 0.0, 2.0)?;
    let dummy = Event {
        kind: EventKind::Transit,
        instant: instant_tt(t0),
    };
    let mut out = DayEvents {
        state: DayState::Normal,
        events: [dummy; MAX_DAY_EVENTS],
        len: 0,
        truncated: false,
    };
    let params = ScanParams {
        step: SCAN_STEP_DAYS,
        max_curvature: MAX_ALTITUDE_CURVATURE,
        min_span: 1.0 / SECONDS_PER_DAY,
        tol: 1e-3 / SECONDS_PER_DAY,
    };
    // Hour-angle samples for the transit search, kept from the same
    // evaluations as the horizon scan on the regular grid.
    let mut crossings = 0usize;
    let mut first_value = 0.0;
    let mut first = true;
    let f = |t: f64| -> Result<f64, AstroError> {
        let (h, _) = altitude_above_horizon(eph, body, observer, horizon, t)?;
        if first {
            first_value = h;
            first = false;
        }
        Ok(h)
    };
    scan_crossings(f, t0, t1, &params, |c| {
        if c.jd_tt < t1 {
            crossings += 1;
            out.push(Event {
                kind: if c.rising {
                    EventKind::Rise
                } else {
                    EventKind::Set
                },
                instant: instant_tt(c.jd_tt),
            });
        }
    })?;
    // Transits: the hour angle grows by ~15°/h; sample hourly and refine the
    // − → + sign changes (the +π → −π wrap is a + → − change).
    let n = libm::ceil((t1 - t0) / SCAN_STEP_DAYS).max(1.0) as usize;
    let h = (t1 - t0) / n as f64;
    let ha = |t: f64| -> Result<f64, AstroError> {
        Ok(altitude_above_horizon(eph, body, observer, horizon, t)?.1)
    };
    let mut a = t0;
    let mut fa = ha(a)?;
    for i in 1..=n {
        let b = if i == n { t1 } else { t0 + h * i as f64 };
        let fb = ha(b)?;
        if fa < 0.0 && fb >= 0.0 && fb - fa < core::f64::consts::PI {
            let t = brent_root(ha, a, b, fa, fb, params.tol)?;
            if t < t1 {
                out.push(Event {
                    kind: EventKind::Transit,
                    instant: instant_tt(t),
                });
            }
        }
        a = b;
        fa = fb;
    }
    out.sort();
    out.state = if crossings > 0 {
        DayState::Normal
    } else if first_value >= 0.0 {
        DayState::AlwaysUp
    } else {
        DayState::AlwaysDown
    };
    Ok(out)
}
