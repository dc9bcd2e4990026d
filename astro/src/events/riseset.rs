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
//! Search: the horizon crossings are the roots of
//! g(t) = sin(altitude(t)) − sin(horizon(t)) (sin is monotonic on
//! [−90°, 90°], so these are exactly the roots of altitude − horizon). g is
//! scanned over the day with the method of [`super::scan_crossings`] at a
//! two-hour step, using the curvature bound |g''| ≤ 42 per day²: with
//! sin h = sin φ sin δ + cos φ cos δ cos H, the Earth's rotation
//! (ω = 6.300 rad/day) gives |d²/dt²| ≤ ω² cos φ cos δ ≤ 39.7/day² everywhere,
//! the Moon's diurnal parallax (≤ 0.0167 rad) adds ≤ 0.7/day², its motion in
//! declination (and the cross term with the hour angle) less than 0.3/day²,
//! the change of the Moon's semidiameter nothing noticeable. With the
//! two-hour step the margin is 42·(1/12)²/8 = 0.036 (about 2°): a segment
//! whose samples both lie further from the horizon cannot hide a pair of
//! crossings; nearer ones are halved down to 1 s (a graze shallower than
//! 42·(1 s)²/8 ≈ 7·10⁻¹⁰, i.e. 4·10⁻⁸ degrees, is not an event).
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

use super::{brent_root, instant_tt, scan_segment, ScanParams};

/// Standard horizon of the Sun's centre, degrees (refraction + semidiameter).
pub const SUN_HORIZON_DEG: Degrees = -0.8333;
/// Standard refraction at the horizon, degrees (used for the Moon and planets).
pub const REFRACTION_HORIZON_DEG: Degrees = -0.5667;
/// Bound on |d²(sin altitude − sin horizon)/dt²|, per day² (module docs).
pub const MAX_SINE_ALTITUDE_CURVATURE: f64 = 42.0;
/// Scan step of the horizon search, days (two hours).
pub const SCAN_STEP_DAYS: f64 = 2.0 / 24.0;
/// Grid points of a search over at most two days.
const MAX_GRID: usize = 26;

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

/// sin(altitude) − sin(horizon) and the wrapped hour angle (module docs).
fn sample<E: Ephemeris>(
    eph: &E,
    body: Body,
    observer: &Observer,
    horizon: &Horizon,
    jd_tt: JulianDay,
) -> Result<(f64, Radians), AstroError> {
    let epoch = Epoch::new(&instant_tt(jd_tt), eph.nutation_model());
    let geo = eph.apparent(body, &epoch)?;
    let topo = observer.topocentric(&geo, &epoch);
    let h0 = horizon.altitude_deg(topo.distance_km) * DEG;
    Ok((
        libm::sin(topo.alt) - libm::sin(h0),
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
        max_curvature: MAX_SINE_ALTITUDE_CURVATURE,
        min_span: 1.0 / SECONDS_PER_DAY,
        tol: 1e-2 / SECONDS_PER_DAY,
    };
    // One evaluation per grid point serves both searches: f for the horizon
    // scan, the hour angle for transits.
    let n = (libm::ceil((t1 - t0) / SCAN_STEP_DAYS).max(1.0) as usize).min(MAX_GRID - 1);
    let h = (t1 - t0) / n as f64;
    let mut grid = [(0.0, 0.0, 0.0); MAX_GRID];
    for (i, g) in grid.iter_mut().enumerate().take(n + 1) {
        let t = if i == n { t1 } else { t0 + h * i as f64 };
        let (f, ha) = sample(eph, body, observer, horizon, t)?;
        *g = (t, f, ha);
    }
    let mut f =
        |t: f64| -> Result<f64, AstroError> { Ok(sample(eph, body, observer, horizon, t)?.0) };
    let mut crossings = 0usize;
    for w in grid[..=n].windows(2) {
        let ((a, fa, _), (b, fb, _)) = (w[0], w[1]);
        scan_segment(
            &mut f,
            a,
            b,
            fa,
            fb,
            &params,
            &mut |c| {
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
            },
            0,
        )?;
    }
    // Transits: the hour angle grows by ~30° per step; refine the − → +
    // sign changes (the +π → −π wrap is a + → − change).
    let ha = |t: f64| -> Result<f64, AstroError> { Ok(sample(eph, body, observer, horizon, t)?.1) };
    for w in grid[..=n].windows(2) {
        let ((a, _, ha_a), (b, _, ha_b)) = (w[0], w[1]);
        if ha_a < 0.0 && ha_b >= 0.0 && ha_b - ha_a < core::f64::consts::PI {
            let t = brent_root(ha, a, b, ha_a, ha_b, params.tol)?;
            if t < t1 {
                out.push(Event {
                    kind: EventKind::Transit,
                    instant: instant_tt(t),
                });
            }
        }
    }
    let first_value = grid[0].1;
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
