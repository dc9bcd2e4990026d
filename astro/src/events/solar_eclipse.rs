//! Solar eclipses: global circumstances (Besselian-style geometry), local
//! circumstances for an observer, and the visible fraction of the Sun's disk.
//!
//! **Global geometry** (Explanatory Supplement to the Astronomical Almanac,
//! 1992, §8.3; Meeus *Elements of Solar Eclipses*). Lengths in equatorial
//! Earth radii a = 6378.137 km. From the apparent geocentric Sun S and Moon
//! M, the shadow axis runs along ĝ = (S − M)/|S − M|. The fundamental plane
//! passes through the Earth's centre perpendicular to ĝ, with x̂ toward
//! east (ẑ × ĝ normalised) and ŷ = ĝ × x̂ toward north. The Moon projects to
//! (x, y) at height z = M·ĝ. With k = 1737.4/a and R☉ = 695 700 km/a:
//! sin f₁ = (R☉ + k)/g, sin f₂ = (R☉ − k)/g; the penumbral and umbral
//! radii on the fundamental plane are l₁ = (z + k/sin f₁) tan f₁ and
//! l₂ = (z − k/sin f₂) tan f₂ (l₂ < 0: the umbra reaches the plane, a total
//! eclipse). The Earth's flattening (WGS84) is handled by the usual scaling
//! y₁ = y/ρ₁, ρ₁ = √(1 − e² cos² d), d the declination of ĝ, which turns the
//! Earth's outline on the plane into the unit circle; m = √(x² + y₁²).
//!
//! Greatest eclipse is the instant when the axis passes closest to the
//! Earth's centre; `gamma` = ±√(x² + y²) then, positive north. Type: the
//! axis meets the Earth (m < 1) — total if the umbral radius at the surface
//! point L₂ = l₂ − ζ tan f₂ (ζ = √(1 − m²)) is negative, annular otherwise,
//! hybrid if total at greatest but annular (l₂ > 0) where the central line
//! begins or ends (m = 1); the axis misses but the umbra/antumbra touches
//! (m < 1 + |l₂|): total or annular by the sign of l₂ (non-central); else
//! partial while m < 1 + l₁. Magnitude at greatest eclipse (NASA's
//! convention): central (L₁ − L₂)/(L₁ + L₂) with L₁ = l₁ − ζ tan f₁;
//! otherwise (l₁ − (m − 1))/(l₁ + l₂). The Moon's radius is the IAU mean
//! 1737.4 km (k = 0.272 40) throughout; NASA's canon uses the smaller
//! k = 0.272 281 for umbral phases, so an eclipse within about 0.0005 of
//! magnitude 1 (e.g. 1948 May 9) may be typed hybrid/total here and annular
//! there.
//!
//! **Local circumstances** come straight from topocentric apparent places of
//! the Sun and the Moon (no refraction): with separation s and topocentric
//! semidiameters r☉ (695 700 km) and r☾ (1737.4 km), C1/C4 are the instants
//! s = r☉ + r☾, C2/C3 s = |r☉ − r☾|, maximum the minimum of s; magnitude
//! (r☉ + r☾ − s)/(2r☉); obscuration the covered fraction of the Sun's disk
//! area (lens area of two circles). Contact instants are geometric: they are
//! reported even when the Sun is below the horizon at that moment. An
//! eclipse is *visible* (and returned by the local search) when the Sun's
//! centre is above the standard −0.8333° horizon at some moment between C1
//! and C4.
//!
//! **Which Moon.** Contacts are only as good as the Moon's place: with the
//! standard tier's Meeus ch. 47 series (a few arcseconds) they are off by
//! 10 s in the open and up to 40 s near a path limit, where the limbs graze
//! and a site may even change its local type; with the DE421 Moon of
//! [`Precision::High`] they are within 0.5 s of DE421.
//! [`local_solar_eclipses_preferring_de421`] uses the high tier for every
//! eclipse the DE421 Moon covers ([`de421_covers_eclipse`]) and a given
//! fallback elsewhere, at about the standard tier's cost; it is what
//! `himmel eclipses --kind solar --local` runs unless `--precision` is given.

use glam::DVec3;

use crate::ephemeris::{Apparent, Body, Ephemeris, Epoch, Precision, Tiered};
use crate::error::AstroError;
use crate::frames::NutationModel;
use crate::moon::DE421_SPAN;
use crate::observe::Observer;
use crate::time::Instant;
use crate::units::*;

use super::phases::{mean_argument_of_latitude, mean_phase_jde, LunationScan};
use super::riseset::{events_between, DayState, Horizon};
use super::{brent_min, brent_root, check_interval, instant_tt};

/// WGS84 first eccentricity squared.
const E2: f64 = WGS84_F * (2.0 - WGS84_F);

/// Besselian-style elements of one instant (lengths in equatorial Earth radii).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BesselianGeometry {
    /// x of the shadow axis on the fundamental plane (east).
    pub x: f64,
    /// y of the shadow axis on the fundamental plane (north).
    pub y: f64,
    /// Declination of the axis direction ĝ (toward the Sun), radians.
    pub d: Radians,
    /// Penumbral radius on the fundamental plane.
    pub l1: f64,
    /// Umbral radius on the fundamental plane (negative: total).
    pub l2: f64,
    /// tan f₁ (penumbral cone half-angle).
    pub tan_f1: f64,
    /// tan f₂ (umbral cone half-angle).
    pub tan_f2: f64,
}

impl BesselianGeometry {
    /// Elements from apparent geocentric vectors of the Sun and Moon, km,
    /// equatorial frame of date.
    pub fn from_vectors(sun: DVec3, moon: DVec3) -> BesselianGeometry {
        let s = sun / WGS84_A_KM;
        let m = moon / WGS84_A_KM;
        let gv = s - m;
        let g = gv.length();
        let gh = gv / g;
        let xh = DVec3::Z.cross(gh);
        let xh = if xh.length_squared() > 1e-24 {
            xh.normalize()
        } else {
            DVec3::X
        };
        let yh = gh.cross(xh);
        let (x, y, z) = (m.dot(xh), m.dot(yh), m.dot(gh));
        let k = MOON_RADIUS_KM / WGS84_A_KM;
        let rs = SUN_RADIUS_KM / WGS84_A_KM;
        let sf1 = (rs + k) / g;
        let sf2 = (rs - k) / g;
        let tan_f1 = sf1 / libm::sqrt(1.0 - sf1 * sf1);
        let tan_f2 = sf2 / libm::sqrt(1.0 - sf2 * sf2);
        let l1 = (z + k / sf1) * tan_f1;
        let l2 = (z - k / sf2) * tan_f2;
        BesselianGeometry {
            x,
            y,
            d: safe_asin(gh.z),
            l1,
            l2,
            tan_f1,
            tan_f2,
        }
    }

    /// Distance of the axis from the Earth's centre on the fundamental plane.
    pub fn axis_distance(&self) -> f64 {
        libm::hypot(self.x, self.y)
    }

    /// The same with the Earth's flattening scaled out (1 = the Earth's limb).
    pub fn scaled_axis_distance(&self) -> f64 {
        let cd = libm::cos(self.d);
        let rho1 = libm::sqrt(1.0 - E2 * cd * cd);
        libm::hypot(self.x, self.y / rho1)
    }
}

/// Besselian-style geometry at `instant`.
pub fn besselian_geometry<E: Ephemeris>(
    eph: &E,
    instant: &Instant,
) -> Result<BesselianGeometry, AstroError> {
    let epoch = Epoch::new(instant, eph.nutation_model());
    let s = eph.apparent(Body::Sun, &epoch)?.vector_km();
    let m = eph.apparent(Body::Moon, &epoch)?.vector_km();
    Ok(BesselianGeometry::from_vectors(s, m))
}

fn bessel_tt<E: Ephemeris>(eph: &E, t: JulianDay) -> Result<BesselianGeometry, AstroError> {
    besselian_geometry(eph, &instant_tt(t))
}

/// Type of a solar eclipse (global).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum SolarEclipseKind {
    /// Only the penumbra touches the Earth.
    Partial,
    /// The antumbra touches the Earth.
    Annular,
    /// The umbra touches the Earth.
    Total,
    /// Total along part of the central line, annular at its ends.
    Hybrid,
}

impl SolarEclipseKind {
    /// `"partial"`, `"annular"`, `"total"` or `"hybrid"` (spec/cli.md).
    pub const fn name(self) -> &'static str {
        match self {
            SolarEclipseKind::Partial => "partial",
            SolarEclipseKind::Annular => "annular",
            SolarEclipseKind::Total => "total",
            SolarEclipseKind::Hybrid => "hybrid",
        }
    }
}

/// Global circumstances of a solar eclipse.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GlobalSolarEclipse {
    /// Type.
    pub kind: SolarEclipseKind,
    /// Greatest eclipse: the axis closest to the Earth's centre.
    pub greatest: Instant,
    /// Gamma, equatorial Earth radii, positive when the axis passes north.
    pub gamma: f64,
    /// Magnitude at greatest eclipse (module docs).
    pub magnitude: f64,
    /// Whether the shadow axis meets the Earth.
    pub central: bool,
}

/// The solar eclipse of the new Moon with lunation number `k`, if any.
pub fn solar_eclipse_of_lunation<E: Ephemeris>(
    eph: &E,
    k: i64,
) -> Result<Option<GlobalSolarEclipse>, AstroError> {
    let kk = k as f64;
    if libm::sin(mean_argument_of_latitude(kk)).abs() > 0.40 {
        return Ok(None);
    }
    let jde = mean_phase_jde(kk);
    let (tg, _) = brent_min(
        |t| Ok(bessel_tt(eph, t)?.axis_distance()),
        jde - 0.8,
        jde + 0.8,
        1e-7,
    )?;
    let b = bessel_tt(eph, tg)?;
    let m = b.scaled_axis_distance();
    if m >= 1.0 + b.l1 {
        return Ok(None);
    }
    let gamma = b.axis_distance() * if b.y >= 0.0 { 1.0 } else { -1.0 };
    let (kind, magnitude, central) = if m < 1.0 {
        let zeta = libm::sqrt(1.0 - m * m);
        let big_l1 = b.l1 - zeta * b.tan_f1;
        let big_l2 = b.l2 - zeta * b.tan_f2;
        let mag = (big_l1 - big_l2) / (big_l1 + big_l2);
        let kind = if big_l2 < 0.0 {
            // Hybrid when the central line starts or ends annular.
            let edge = |before: bool| -> Result<f64, AstroError> {
                let f = |t: f64| Ok(bessel_tt(eph, t)?.scaled_axis_distance() - 1.0);
                let far = if before { tg - 0.3 } else { tg + 0.3 };
                let (f0, ff) = (f(tg)?, f(far)?);
                if ff <= 0.0 {
                    return Ok(bessel_tt(eph, far)?.l2);
                }
                let t = brent_root(f, tg, far, f0, ff, 1e-7)?;
                Ok(bessel_tt(eph, t)?.l2)
            };
            if edge(true)? > 0.0 || edge(false)? > 0.0 {
                SolarEclipseKind::Hybrid
            } else {
                SolarEclipseKind::Total
            }
        } else {
            SolarEclipseKind::Annular
        };
        (kind, mag, true)
    } else {
        let mag = (b.l1 - (m - 1.0)) / (b.l1 + b.l2);
        let kind = if m < 1.0 + b.l2.abs() {
            if b.l2 < 0.0 {
                SolarEclipseKind::Total
            } else {
                SolarEclipseKind::Annular
            }
        } else {
            SolarEclipseKind::Partial
        };
        (kind, mag, false)
    };
    Ok(Some(GlobalSolarEclipse {
        kind,
        greatest: instant_tt(tg),
        gamma,
        magnitude,
        central,
    }))
}

/// Iterator over the solar eclipses with greatest eclipse in `[from, to)`
/// (made by [`solar_eclipses`]; no allocation).
#[derive(Debug, Clone)]
pub struct GlobalSolarEclipses<E>(LunationScan<E, GlobalSolarEclipse>);

/// All solar eclipses with greatest eclipse in `[from, to)`. Search: every
/// new Moon of Meeus' mean lunation (eq. 49.1) with |sin F| ≤ 0.40; the axis
/// distance is minimised over the mean new Moon ± 0.8 day.
pub fn solar_eclipses<E: Ephemeris>(
    eph: E,
    from: &Instant,
    to: &Instant,
) -> Result<GlobalSolarEclipses<E>, AstroError> {
    LunationScan::new(eph, from, to, 0.0, solar_eclipse_of_lunation, |e| {
        e.greatest.jd_tt
    })
    .map(GlobalSolarEclipses)
}

impl<E: Ephemeris> Iterator for GlobalSolarEclipses<E> {
    type Item = Result<GlobalSolarEclipse, AstroError>;

    fn next(&mut self) -> Option<Self::Item> {
        self.0.next()
    }
}

/// Topocentric disks of the Sun and the Moon at one instant, radians.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LocalDisks {
    /// Separation of the centres.
    pub separation: Radians,
    /// The Sun's topocentric semidiameter.
    pub sun_semidiameter: Radians,
    /// The Moon's topocentric semidiameter.
    pub moon_semidiameter: Radians,
    /// The Sun's topocentric altitude (unrefracted).
    pub sun_alt: Radians,
}

impl LocalDisks {
    /// Eclipse magnitude: fraction of the Sun's diameter covered,
    /// (r☉ + r☾ − s)/(2r☉) (≤ 0 when the disks are apart).
    pub fn magnitude(&self) -> f64 {
        (self.sun_semidiameter + self.moon_semidiameter - self.separation)
            / (2.0 * self.sun_semidiameter)
    }

    /// Obscuration: fraction of the Sun's disk area covered by the Moon.
    pub fn obscuration(&self) -> f64 {
        disk_overlap_fraction(
            self.separation,
            self.sun_semidiameter,
            self.moon_semidiameter,
        )
    }
}

/// Fraction of the area of a disk of radius `rs` covered by a disk of
/// radius `rm` whose centre is `s` away (the lens area of two circles,
/// e.g. Weisstein, *Circle–Circle Intersection*), in [0, 1].
pub fn disk_overlap_fraction(s: f64, rs: f64, rm: f64) -> f64 {
    if rs.is_nan() || rs <= 0.0 || s >= rs + rm {
        return 0.0;
    }
    if s <= (rs - rm).abs() {
        return ((rm * rm) / (rs * rs)).min(1.0);
    }
    let a1 = rs * rs * safe_acos((s * s + rs * rs - rm * rm) / (2.0 * s * rs));
    let a2 = rm * rm * safe_acos((s * s + rm * rm - rs * rs) / (2.0 * s * rm));
    let q = (-s + rs + rm) * (s + rs - rm) * (s - rs + rm) * (s + rs + rm);
    let a3 = 0.5 * libm::sqrt(q.max(0.0));
    ((a1 + a2 - a3) / (core::f64::consts::PI * rs * rs)).clamp(0.0, 1.0)
}

/// The topocentric disks of the Sun and Moon for `observer` at `instant`.
pub fn local_disks<E: Ephemeris>(
    eph: &E,
    observer: &Observer,
    instant: &Instant,
) -> Result<LocalDisks, AstroError> {
    let epoch = Epoch::new(instant, eph.nutation_model());
    let s = observer.topocentric(&eph.apparent(Body::Sun, &epoch)?, &epoch);
    let m = observer.topocentric(&eph.apparent(Body::Moon, &epoch)?, &epoch);
    Ok(LocalDisks {
        separation: s.separation_deg(&m) * DEG,
        sun_semidiameter: s.semidiameter_deg(SUN_RADIUS_KM) * DEG,
        moon_semidiameter: m.semidiameter_deg(MOON_RADIUS_KM) * DEG,
        sun_alt: s.alt,
    })
}

/// Fraction of the Sun's disk visible (not covered by the Moon) for
/// `observer` at `instant`, in [0, 1]: 1 − obscuration. The horizon is not
/// considered (the renderer handles it).
pub fn sun_visible_fraction<E: Ephemeris>(
    eph: &E,
    observer: &Observer,
    instant: &Instant,
) -> Result<f64, AstroError> {
    Ok(1.0 - local_disks(eph, observer, instant)?.obscuration())
}

/// Type of a solar eclipse at one place.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum LocalSolarKind {
    /// The Moon covers part of the Sun.
    Partial,
    /// The Moon passes inside the Sun's disk.
    Annular,
    /// The Moon covers the Sun completely.
    Total,
}

impl LocalSolarKind {
    /// `"partial"`, `"annular"` or `"total"` (spec/cli.md).
    pub const fn name(self) -> &'static str {
        match self {
            LocalSolarKind::Partial => "partial",
            LocalSolarKind::Annular => "annular",
            LocalSolarKind::Total => "total",
        }
    }
}

/// Local circumstances of a solar eclipse.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LocalSolarEclipse {
    /// Local type.
    pub kind: LocalSolarKind,
    /// First contact (geometric; may be below the horizon).
    pub c1: Instant,
    /// Second contact (start of totality/annularity).
    pub c2: Option<Instant>,
    /// Maximum eclipse (minimum separation).
    pub max: Instant,
    /// Third contact.
    pub c3: Option<Instant>,
    /// Fourth contact.
    pub c4: Instant,
    /// Magnitude at maximum.
    pub max_magnitude: f64,
    /// Obscuration at maximum.
    pub max_obscuration: f64,
    /// The Sun's unrefracted altitude at C1, maximum and C4, radians.
    pub sun_alt_c1: Radians,
    /// See [`LocalSolarEclipse::sun_alt_c1`].
    pub sun_alt_max: Radians,
    /// See [`LocalSolarEclipse::sun_alt_c1`].
    pub sun_alt_c4: Radians,
    /// Whether the Sun is above the standard horizon (−0.8333°) at some
    /// moment between C1 and C4.
    pub visible: bool,
}

/// Local circumstances for `observer` of the solar eclipse whose greatest
/// global eclipse is at TT Julian day `greatest` (e.g. from
/// [`solar_eclipses`]); `None` if the Moon's disk never touches the Sun's
/// from there. The window searched is greatest ± 0.25 day (the penumbra
/// crosses the Earth in at most 6.5 hours); the separation is sampled
/// every 10 minutes and its minimum refined by Brent's method, contacts by
/// Brent's root finder on each side of the maximum (the separation is
/// unimodal in the window: the Moon gains ≥ 0.25°/h on the Sun even against
/// the diurnal parallax).
pub fn local_circumstances<E: Ephemeris>(
    eph: &E,
    observer: &Observer,
    greatest: JulianDay,
) -> Result<Option<LocalSolarEclipse>, AstroError> {
    let disks = |t: f64| local_disks(eph, observer, &instant_tt(t));
    let outer = |t: f64| -> Result<f64, AstroError> {
        let d = disks(t)?;
        Ok(d.separation - (d.sun_semidiameter + d.moon_semidiameter))
    };
    let inner = |t: f64| -> Result<f64, AstroError> {
        let d = disks(t)?;
        Ok(d.separation - (d.sun_semidiameter - d.moon_semidiameter).abs())
    };
    const N: usize = 72;
    let (w0, w1) = (greatest - 0.25, greatest + 0.25);
    let h = (w1 - w0) / N as f64;
    let mut best = (0usize, f64::INFINITY);
    for i in 0..=N {
        let v = outer(w0 + h * i as f64)?;
        if v < best.1 {
            best = (i, v);
        }
    }
    let lo = w0 + h * best.0.saturating_sub(1) as f64;
    let hi = (w0 + h * (best.0 + 1) as f64).min(w1);
    let (tmax, _) = brent_min(|t| Ok(disks(t)?.separation), lo, hi, 1e-8)?;
    let dmax = disks(tmax)?;
    let fmax = dmax.separation - (dmax.sun_semidiameter + dmax.moon_semidiameter);
    if fmax >= 0.0 {
        return Ok(None);
    }
    let tol = 1e-3 / SECONDS_PER_DAY;
    let root_side =
        |f: &dyn Fn(f64) -> Result<f64, AstroError>, end: f64| -> Result<Option<f64>, AstroError> {
            let f0 = f(tmax)?;
            let fe = f(end)?;
            if f0 >= 0.0 || fe <= 0.0 {
                return Ok(None);
            }
            Ok(Some(brent_root(f, tmax, end, f0, fe, tol)?))
        };
    let c1 = root_side(&outer, w0)?.unwrap_or(w0);
    let c4 = root_side(&outer, w1)?.unwrap_or(w1);
    let (c2, c3) = (root_side(&inner, c1)?, root_side(&inner, c4)?);
    let kind = match (c2, c3) {
        (Some(_), _) | (_, Some(_)) => {
            if dmax.moon_semidiameter > dmax.sun_semidiameter {
                LocalSolarKind::Total
            } else {
                LocalSolarKind::Annular
            }
        }
        _ => LocalSolarKind::Partial,
    };
    let sun_alt_c1 = disks(c1)?.sun_alt;
    let sun_alt_c4 = disks(c4)?.sun_alt;
    let horizon = Horizon::standard(Body::Sun);
    let visible = if sun_alt_c1 / DEG > horizon.altitude_deg(1.0e8)
        || sun_alt_c4 / DEG > horizon.altitude_deg(1.0e8)
        || dmax.sun_alt / DEG > horizon.altitude_deg(1.0e8)
    {
        true
    } else {
        let ev = events_between(eph, Body::Sun, observer, &horizon, c1, c4)?;
        ev.state != DayState::AlwaysDown
    };
    Ok(Some(LocalSolarEclipse {
        kind,
        c1: instant_tt(c1),
        c2: c2.map(instant_tt),
        max: instant_tt(tmax),
        c3: c3.map(instant_tt),
        c4: instant_tt(c4),
        max_magnitude: dmax.magnitude(),
        max_obscuration: dmax.obscuration(),
        sun_alt_c1,
        sun_alt_max: dmax.sun_alt,
        sun_alt_c4,
        visible,
    }))
}

/// Iterator over the solar eclipses visible from an observer (module docs)
/// whose local maximum lies in `[from, to)` (made by
/// [`local_solar_eclipses`] or [`local_solar_eclipses_preferring_de421`];
/// no allocation).
#[derive(Debug, Clone)]
pub struct LocalSolarEclipses<E> {
    global: GlobalSolarEclipses<E>,
    observer: Observer,
    from: JulianDay,
    to: JulianDay,
    /// Local circumstances with `Tiered(Precision::High)` wherever
    /// [`de421_covers_eclipse`].
    prefer_de421: bool,
}

/// Days on either side of greatest eclipse that the DE421 Moon must cover
/// for [`local_solar_eclipses_preferring_de421`] to use it: the local
/// search window of [`local_circumstances`] (± 0.25 day) with room to spare
/// (the light time, the visibility check between C1 and C4), so that one
/// eclipse never mixes two Moons.
pub const DE421_ECLIPSE_MARGIN_DAYS: f64 = 0.5;

/// The high tier for the local circumstances of one eclipse at close to the
/// standard tier's cost: the DE421 Moon of [`Precision::High`], and the Sun
/// of the standard tier (truncated VSOP87D, 17× cheaper than the full series)
/// plus the difference full − truncated taken once, at greatest eclipse. The
/// terms the truncation drops change slowly, so within ± 0.5 day of
/// greatest eclipse the sum stays within 0.03″ and 20 km of the full series
/// (unit test `high_sun_offset_holds_over_an_eclipse_window`: 0.021″, 14 km;
/// a few hundredths of a second of contact time), where the truncated
/// series alone is off by up to 0.8″ (2.8 s of contact time near a path
/// limit).
#[derive(Debug, Clone, Copy, PartialEq)]
struct HighForEclipse {
    /// Full − truncated VSOP87D apparent ecliptic longitude, latitude
    /// (radians) and distance (km) of the Sun at greatest eclipse.
    sun_offset: (Radians, Radians, Km),
}

impl HighForEclipse {
    fn new(greatest: JulianDay) -> Result<HighForEclipse, AstroError> {
        let epoch = Epoch::new(&instant_tt(greatest), Precision::High.nutation_model());
        let full = Tiered(Precision::High).apparent(Body::Sun, &epoch)?;
        let truncated = Tiered(Precision::Standard).apparent(Body::Sun, &epoch)?;
        Ok(HighForEclipse {
            sun_offset: (
                wrap_pi(full.ecl_lon - truncated.ecl_lon),
                full.ecl_lat - truncated.ecl_lat,
                full.distance_km - truncated.distance_km,
            ),
        })
    }
}

impl Ephemeris for HighForEclipse {
    fn nutation_model(&self) -> NutationModel {
        // Standard and high share IAU 1980, so the offset is of date too.
        Precision::High.nutation_model()
    }

    fn apparent(&self, body: Body, epoch: &Epoch) -> Result<Apparent, AstroError> {
        if body != Body::Sun {
            return Tiered(Precision::High).apparent(body, epoch);
        }
        let s = Tiered(Precision::Standard).apparent(Body::Sun, epoch)?;
        let (dlon, dlat, dkm) = self.sun_offset;
        Ok(Apparent::from_ecliptic(
            s.ecl_lon + dlon,
            s.ecl_lat + dlat,
            s.distance_km + dkm,
            epoch,
        ))
    }
}

/// Whether the embedded DE421 Moon ([`DE421_SPAN`], 1899-07-29 …
/// 2053-10-09) covers the whole local-circumstances window of the eclipse
/// whose greatest global eclipse is at TT Julian day `greatest`
/// (± [`DE421_ECLIPSE_MARGIN_DAYS`]).
pub fn de421_covers_eclipse(greatest: JulianDay) -> bool {
    let (first, last) = DE421_SPAN;
    greatest - DE421_ECLIPSE_MARGIN_DAYS >= first && greatest + DE421_ECLIPSE_MARGIN_DAYS <= last
}

/// All solar eclipses visible from `observer` with the local maximum in
/// `[from, to)`.
pub fn local_solar_eclipses<E: Ephemeris>(
    eph: E,
    observer: &Observer,
    from: &Instant,
    to: &Instant,
) -> Result<LocalSolarEclipses<E>, AstroError> {
    local_search(eph, observer, from, to, false)
}

/// All solar eclipses visible from `observer` with the local maximum in
/// `[from, to)`, each with the best Moon available: the local circumstances
/// of an eclipse that the DE421 Moon covers ([`de421_covers_eclipse`]:
/// greatest eclipse between 1899-07-30 and 2053-10-08) come from the high
/// tier (DE421 Moon, full VSOP87D Sun), those of any other eclipse from
/// `fallback`. The choice is made per eclipse, never within one. `fallback`
/// also runs the global scan that finds the eclipses and centres each local
/// search window (its greatest-eclipse instant is only a starting point).
///
/// The high tier's Sun is evaluated as the truncated series plus the
/// full − truncated difference at greatest eclipse (within 0.03″ of the full
/// series over the eclipse): the results equal those of
/// [`local_solar_eclipses`] with `Tiered(Precision::High)` to a few
/// hundredths of a second, at about 1.3× the cost of the standard tier
/// instead of about 14× (criterion, README).
///
/// This is what `himmel eclipses --kind solar --local` runs when no
/// `--precision` is given, with `fallback = Tiered(Precision::Standard)`:
/// contacts within 2 s of DE421 for 2001–2050 (0.48 s at worst over 92
/// sites on and near the limits of 23 central paths, test
/// `local_solar_default_within_2_s_of_de421_2001_2050` in `tests/`; the
/// standard tier: 40 s, and a different local type at 10 of them).
pub fn local_solar_eclipses_preferring_de421<E: Ephemeris>(
    fallback: E,
    observer: &Observer,
    from: &Instant,
    to: &Instant,
) -> Result<LocalSolarEclipses<E>, AstroError> {
    local_search(fallback, observer, from, to, true)
}

fn local_search<E: Ephemeris>(
    eph: E,
    observer: &Observer,
    from: &Instant,
    to: &Instant,
    prefer_de421: bool,
) -> Result<LocalSolarEclipses<E>, AstroError> {
    let (a, b) = check_interval(from, to)?;
    let global = solar_eclipses(eph, &instant_tt(a - 0.3), &instant_tt(b + 0.3))?;
    Ok(LocalSolarEclipses {
        global,
        observer: *observer,
        from: a,
        to: b,
        prefer_de421,
    })
}

impl<E: Ephemeris> Iterator for LocalSolarEclipses<E> {
    type Item = Result<LocalSolarEclipse, AstroError>;

    fn next(&mut self) -> Option<Self::Item> {
        loop {
            let g = match self.global.next()? {
                Ok(g) => g,
                Err(e) => return Some(Err(e)),
            };
            let greatest = g.greatest.jd_tt;
            let local = if self.prefer_de421 && de421_covers_eclipse(greatest) {
                HighForEclipse::new(greatest)
                    .and_then(|eph| local_circumstances(&eph, &self.observer, greatest))
            } else {
                local_circumstances(self.global.0.ephemeris(), &self.observer, greatest)
            };
            match local {
                Ok(Some(l)) if l.visible && l.max.jd_tt >= self.from && l.max.jd_tt < self.to => {
                    return Some(Ok(l))
                }
                Ok(_) => {}
                Err(e) => return Some(Err(e)),
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn high_sun_offset_holds_over_an_eclipse_window() {
        // The Sun of HighForEclipse against the full VSOP87D Sun, ± 0.5 day
        // around 400 instants over the DE421 span (every 141 days, 1900–2053).
        let (mut worst, mut worst_km): (f64, f64) = (0.0, 0.0);
        for k in 0..400 {
            let t0 = 2_415_100.0 + 141.0 * k as f64;
            let eph = HighForEclipse::new(t0).unwrap();
            for dt in [-0.5, -0.25, 0.0, 0.25, 0.5] {
                let epoch = Epoch::new(&instant_tt(t0 + dt), eph.nutation_model());
                let a = eph.apparent(Body::Sun, &epoch).unwrap();
                let b = Tiered(Precision::High).apparent(Body::Sun, &epoch).unwrap();
                let sep = a
                    .vector_km()
                    .normalize()
                    .angle_between(b.vector_km().normalize());
                worst = worst.max(sep / ARCSEC);
                worst_km = worst_km.max((a.distance_km - b.distance_km).abs());
                let m = eph.apparent(Body::Moon, &epoch).unwrap();
                assert_eq!(
                    m,
                    Tiered(Precision::High)
                        .apparent(Body::Moon, &epoch)
                        .unwrap()
                );
            }
        }
        // Measured: 0.021″ and 14 km (20 km of 1 AU: 0.0001″ of semidiameter).
        assert!(worst < 0.03, "{worst}\"");
        assert!(worst_km < 20.0, "{worst_km} km");
    }

    #[test]
    fn overlap_fraction_limits_and_equal_disks() {
        assert_eq!(disk_overlap_fraction(2.1, 1.0, 1.0), 0.0);
        assert_eq!(disk_overlap_fraction(0.0, 1.0, 1.1), 1.0);
        assert!((disk_overlap_fraction(0.0, 1.0, 0.5) - 0.25).abs() < 1e-15);
        // Two unit circles one radius apart: lens area 2π/3 − √3/2.
        let lens =
            (2.0 * core::f64::consts::PI / 3.0 - libm::sqrt(3.0) / 2.0) / core::f64::consts::PI;
        assert!((disk_overlap_fraction(1.0, 1.0, 1.0) - lens).abs() < 1e-12);
        // Continuous at both contacts.
        assert!(disk_overlap_fraction(2.0 - 1e-9, 1.0, 1.0) < 1e-9);
        assert!((disk_overlap_fraction(0.5 + 1e-12, 1.0, 0.5) - 0.25).abs() < 1e-6);
    }

    #[test]
    fn besselian_geometry_of_an_aligned_configuration() {
        // Sun 1 AU along +x, Moon 360 000 km (near perigee) along +x on the
        // axis: the axis passes through the Earth's centre and the umbra
        // reaches it (at the mean distance, 384 400 km, it would not).
        let sun = DVec3::new(KM_PER_AU, 0.0, 0.0);
        let moon = DVec3::new(360_000.0, 0.0, 0.0);
        let b = BesselianGeometry::from_vectors(sun, moon);
        assert!(b.axis_distance() < 1e-12);
        assert!(b.l2 < 0.0 && b.l1 > 0.5, "{b:?}");
        let far = BesselianGeometry::from_vectors(sun, DVec3::new(384_400.0, 0.0, 0.0));
        assert!(far.l2 > 0.0);
        // Umbral cone: the vertex lies (R☉ − k)/... behind the Moon; at the
        // Earth's centre the umbral radius is k − z·tan f₂ below zero.
        let k = MOON_RADIUS_KM / WGS84_A_KM;
        let z = 360_000.0 / WGS84_A_KM;
        assert!((b.l2 - (z * b.tan_f2 - k * libm::sqrt(1.0 + b.tan_f2 * b.tan_f2))).abs() < 1e-12);
    }
}
