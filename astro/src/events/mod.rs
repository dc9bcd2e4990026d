//! Sky events: Moon phases, rise/set/transit, lunar and solar eclipses.
//!
//! Everything here is built on one small search toolkit that works on
//! continuous functions of time (TT Julian days):
//!
//! * [`scan_crossings`] — finds every sign change of `f` on an interval. It
//!   samples at a fixed `step` and uses a bound `M` on |f''| to prove that a
//!   pair of same-signed samples cannot hide a pair of roots: between samples
//!   `a`, `b` the function stays above the chord minus `M·(b−a)²/8` (the
//!   interpolation-error bound of linear interpolation, e.g. Burden & Faires,
//!   *Numerical Analysis*, Thm. 3.3). Where that margin does not clear zero
//!   the interval is halved until it does, or until it is shorter than
//!   `min_span` (a tangency shallower than `M·min_span²/8` is not an event).
//!   So the documented step cannot skip an event, however close two roots are
//!   (a body grazing the horizon), down to `min_span`.
//! * [`brent_root`] — Brent's method (Brent 1973, *Algorithms for
//!   Minimization without Derivatives*, ch. 4) on a sign-changing bracket.
//! * [`brent_min`] — Brent's parabolic/golden-section minimiser (ibid. ch. 5)
//!   on a unimodal bracket.
//!
//! Nothing allocates: scans report through a callback, the searches are
//! iterators or return fixed-capacity results.
//!
//! The instant of a TT Julian day is [`Instant::from_tt`] (UT1 from the ΔT
//! model, which inside the IERS table is the table itself), so event times
//! convert back to UTC with [`Instant::to_utc`].

pub mod lunar_eclipse;
pub mod phases;
pub mod riseset;
pub mod solar_eclipse;

use crate::error::AstroError;
use crate::time::Instant;
use crate::units::{JulianDay, SECONDS_PER_DAY};

pub use lunar_eclipse::{LunarEclipse, LunarEclipseKind, LunarEclipses, ShadowGeometry};
pub use phases::{Phase, PhaseEvent, Phases};
pub use riseset::{DayEvents, DayState, Event, EventKind, Horizon};
pub use solar_eclipse::{
    GlobalSolarEclipse, GlobalSolarEclipses, LocalSolarEclipse, LocalSolarEclipses, LocalSolarKind,
    SolarEclipseKind,
};

/// Longest search interval accepted by the interval searches (phases,
/// eclipses): 1000 Julian years, in days. Longer requests are an
/// [`AstroError::OutOfRange`] so that a typo cannot start a search that runs
/// for minutes.
pub const MAX_SEARCH_DAYS: f64 = 1000.0 * 365.25;

/// The instant at TT Julian day `jd_tt` (UT1 from ΔT).
#[inline]
pub fn instant_tt(jd_tt: JulianDay) -> Instant {
    Instant::from_tt(jd_tt)
}

/// Earliest instant the interval searches accept, TT Julian day (−4000 January 1, Julian calendar).
/// Meeus' mean-lunation polynomial (eq. 49.1), which seeds every search, and
/// the lunar series behind the standard tier are fitted to a few millennia
/// around J2000; far outside them the first guesses stop being within a day.
pub const MIN_SEARCH_JD: JulianDay = 260_423.5;
/// Latest instant the interval searches accept, TT Julian day (8000 January 1).
pub const MAX_SEARCH_JD: JulianDay = 4_642_999.5;

/// Checks a search interval `[from, to]` (TT Julian days): finite, ordered,
/// within years −4000 … +8000 ([`MIN_SEARCH_JD`], [`MAX_SEARCH_JD`]) and at
/// most [`MAX_SEARCH_DAYS`] long.
pub fn check_interval(from: &Instant, to: &Instant) -> Result<(JulianDay, JulianDay), AstroError> {
    let (a, b) = (from.jd_tt, to.jd_tt);
    AstroError::check_range(
        "search start (TT Julian day)",
        a,
        MIN_SEARCH_JD,
        MAX_SEARCH_JD,
    )?;
    AstroError::check_range("search end (TT Julian day)", b, a, MAX_SEARCH_JD)?;
    AstroError::check_range("search length (days)", b - a, 0.0, MAX_SEARCH_DAYS)?;
    Ok((a, b))
}

/// A sign change found by [`scan_crossings`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Crossing {
    /// The root, TT Julian day.
    pub jd_tt: JulianDay,
    /// `true` when `f` goes from negative to positive.
    pub rising: bool,
}

/// Root of `f` in `[a, b]` by Brent's method (Brent 1973, ch. 4), given
/// `fa = f(a)` and `fb = f(b)` of opposite signs (or one of them zero).
/// Converges to `tol` (same unit as the argument, e.g. days). Errors of `f`
/// propagate.
pub fn brent_root<F>(
    mut f: F,
    mut a: f64,
    mut b: f64,
    mut fa: f64,
    mut fb: f64,
    tol: f64,
) -> Result<f64, AstroError>
where
    F: FnMut(f64) -> Result<f64, AstroError>,
{
    if fa == 0.0 {
        return Ok(a);
    }
    if fb == 0.0 {
        return Ok(b);
    }
    let mut c = a;
    let mut fc = fa;
    let mut d = b - a;
    let mut e = d;
    for _ in 0..100 {
        if (fb > 0.0) == (fc > 0.0) {
            c = a;
            fc = fa;
            d = b - a;
            e = d;
        }
        if fc.abs() < fb.abs() {
            a = b;
            b = c;
            c = a;
            fa = fb;
            fb = fc;
            fc = fa;
        }
        let tol1 = 2.0 * f64::EPSILON * b.abs() + 0.5 * tol;
        let xm = 0.5 * (c - b);
        if xm.abs() <= tol1 || fb == 0.0 {
            return Ok(b);
        }
        if e.abs() >= tol1 && fa.abs() > fb.abs() {
            let s = fb / fa;
            let (mut p, mut q);
            if a == c {
                p = 2.0 * xm * s;
                q = 1.0 - s;
            } else {
                let qq = fa / fc;
                let r = fb / fc;
                p = s * (2.0 * xm * qq * (qq - r) - (b - a) * (r - 1.0));
                q = (qq - 1.0) * (r - 1.0) * (s - 1.0);
            }
            if p > 0.0 {
                q = -q;
            }
            p = p.abs();
            let min1 = 3.0 * xm * q - (tol1 * q).abs();
            let min2 = (e * q).abs();
            if 2.0 * p < min1.min(min2) {
                e = d;
                d = p / q;
            } else {
                d = xm;
                e = d;
            }
        } else {
            d = xm;
            e = d;
        }
        a = b;
        fa = fb;
        b += if d.abs() > tol1 { d } else { tol1.copysign(xm) };
        fb = f(b)?;
    }
    Ok(b)
}

/// Minimum of `f` on `[a, b]` by Brent's method (golden section with
/// parabolic steps; Brent 1973, ch. 5). `f` should be unimodal on the
/// bracket; the result is then its minimum to `tol`. Returns `(x, f(x))`.
pub fn brent_min<F>(mut f: F, a: f64, b: f64, tol: f64) -> Result<(f64, f64), AstroError>
where
    F: FnMut(f64) -> Result<f64, AstroError>,
{
    const CGOLD: f64 = 0.381_966_011_250_105_1;
    let (mut a, mut b) = if a < b { (a, b) } else { (b, a) };
    let mut x = a + CGOLD * (b - a);
    let (mut w, mut v) = (x, x);
    let mut fx = f(x)?;
    let (mut fw, mut fv) = (fx, fx);
    let mut d: f64 = 0.0;
    let mut e: f64 = 0.0;
    for _ in 0..200 {
        let xm = 0.5 * (a + b);
        let tol1 = tol + 1e-12 * x.abs();
        let tol2 = 2.0 * tol1;
        if (x - xm).abs() <= tol2 - 0.5 * (b - a) {
            break;
        }
        let mut golden = true;
        if e.abs() > tol1 {
            let r = (x - w) * (fx - fv);
            let mut q = (x - v) * (fx - fw);
            let mut p = (x - v) * q - (x - w) * r;
            q = 2.0 * (q - r);
            if q > 0.0 {
                p = -p;
            }
            q = q.abs();
            let etemp = e;
            e = d;
            if p.abs() < (0.5 * q * etemp).abs() && p > q * (a - x) && p < q * (b - x) {
                d = p / q;
                let u = x + d;
                if u - a < tol2 || b - u < tol2 {
                    d = tol1.copysign(xm - x);
                }
                golden = false;
            }
        }
        if golden {
            e = if x >= xm { a - x } else { b - x };
            d = CGOLD * e;
        }
        let u = if d.abs() >= tol1 {
            x + d
        } else {
            x + tol1.copysign(d)
        };
        let fu = f(u)?;
        if fu <= fx {
            if u >= x {
                a = x;
            } else {
                b = x;
            }
            v = w;
            fv = fw;
            w = x;
            fw = fx;
            x = u;
            fx = fu;
        } else {
            if u < x {
                a = u;
            } else {
                b = u;
            }
            if fu <= fw || w == x {
                v = w;
                fv = fw;
                w = u;
                fw = fu;
            } else if fu <= fv || v == x || v == w {
                v = u;
                fv = fu;
            }
        }
    }
    Ok((x, fx))
}

/// Parameters of [`scan_crossings`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ScanParams {
    /// Sampling step, days.
    pub step: f64,
    /// Upper bound of |f''| over the interval, units of f per day².
    pub max_curvature: f64,
    /// Shortest interval that is still subdivided, days.
    pub min_span: f64,
    /// Root tolerance, days.
    pub tol: f64,
}

/// Every sign change of the continuous function `f` on `[t0, t1]`, in
/// chronological order, reported through `emit` (see the module
/// documentation for why `params.step` cannot skip a pair of roots).
///
/// Cost: one evaluation per step, plus a few halvings where `f` comes within
/// `M·step²/8` of zero, plus about ten evaluations per root.
pub fn scan_crossings<F, G>(
    mut f: F,
    t0: f64,
    t1: f64,
    params: &ScanParams,
    mut emit: G,
) -> Result<(), AstroError>
where
    F: FnMut(f64) -> Result<f64, AstroError>,
    G: FnMut(Crossing),
{
    let bad = |x: f64| x.is_nan() || x <= 0.0;
    if bad(t1 - t0) || bad(params.step) {
        return Ok(());
    }
    let n = libm::ceil((t1 - t0) / params.step).max(1.0) as u64;
    let h = (t1 - t0) / n as f64;
    let mut a = t0;
    let mut fa = f(a)?;
    for i in 1..=n {
        let b = if i == n { t1 } else { t0 + h * i as f64 };
        let fb = f(b)?;
        scan_segment(&mut f, a, b, fa, fb, params, &mut emit, 0)?;
        a = b;
        fa = fb;
    }
    Ok(())
}

/// One step of [`scan_crossings`]: the sign changes of `f` on `[a, b]` given
/// `fa = f(a)` and `fb = f(b)` (for callers that sample the grid themselves,
/// e.g. to share evaluations between several searches). `depth` is 0.
#[allow(clippy::too_many_arguments)]
pub fn scan_segment<F, G>(
    f: &mut F,
    a: f64,
    b: f64,
    fa: f64,
    fb: f64,
    params: &ScanParams,
    emit: &mut G,
    depth: u32,
) -> Result<(), AstroError>
where
    F: FnMut(f64) -> Result<f64, AstroError>,
    G: FnMut(Crossing),
{
    // A root at exactly a sample is attributed to the segment it starts.
    let pa = fa >= 0.0;
    let pb = fb >= 0.0;
    if pa != pb {
        let t = brent_root(&mut *f, a, b, fa, fb, params.tol)?;
        emit(Crossing {
            jd_tt: t,
            rising: !pa,
        });
        return Ok(());
    }
    let span = b - a;
    let margin = params.max_curvature * span * span / 8.0;
    if fa.abs().min(fb.abs()) > margin || span <= params.min_span || depth > 40 {
        return Ok(());
    }
    let m = 0.5 * (a + b);
    let fm = f(m)?;
    scan_segment(f, a, m, fa, fm, params, emit, depth + 1)?;
    scan_segment(f, m, b, fm, fb, params, emit, depth + 1)
}

/// Seconds between two TT Julian days.
#[inline]
pub fn seconds_between(a: JulianDay, b: JulianDay) -> f64 {
    (b - a) * SECONDS_PER_DAY
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn brent_finds_roots_and_minima() {
        let r = brent_root(
            |x| Ok(libm::cos(x) - x),
            0.0,
            1.0,
            1.0,
            libm::cos(1.0) - 1.0,
            1e-14,
        )
        .unwrap();
        assert!((r - 0.739_085_133_215_160_6).abs() < 1e-12);
        let (x, fx) = brent_min(|x| Ok((x - 0.3) * (x - 0.3) + 2.0), -1.0, 2.0, 1e-10).unwrap();
        assert!((x - 0.3).abs() < 1e-8 && (fx - 2.0).abs() < 1e-12);
    }

    #[test]
    fn scan_finds_two_close_roots_between_samples() {
        // Roots at 0.5 ± 1e-4 (a "grazing" pair far inside one step); |f''| = 2.
        let f = |x: f64| Ok((x - 0.5) * (x - 0.5) - 1e-8);
        let params = ScanParams {
            step: 0.3,
            max_curvature: 2.0,
            min_span: 1e-9,
            tol: 1e-12,
        };
        let mut found = [0.0; 4];
        let mut n = 0;
        scan_crossings(f, 0.0, 1.0, &params, |c| {
            found[n] = c.jd_tt;
            n += 1;
        })
        .unwrap();
        assert_eq!(n, 2);
        assert!((found[0] - (0.5 - 1e-4)).abs() < 1e-9);
        assert!((found[1] - (0.5 + 1e-4)).abs() < 1e-9);
        // A function that stays above zero reports nothing.
        let mut count = 0;
        scan_crossings(
            |x: f64| Ok((x - 0.5) * (x - 0.5) + 1e-8),
            0.0,
            1.0,
            &params,
            |_| count += 1,
        )
        .unwrap();
        assert_eq!(count, 0);
    }
}
