//! Position providers behind one trait.
//!
//! An [`Ephemeris`] turns a body and an [`Epoch`] into the body's apparent
//! geocentric place ([`Apparent`]). Three kinds exist:
//!
//! * [`Tiered`] — the computed ephemeris at a [`Precision`] tier;
//! * [`Cached`] — wraps another provider and reuses its results while the
//!   instant stays within a caller-chosen tolerance (for per-frame rendering,
//!   where the Moon moves 0.5″ per second and a frame lasts 16 ms);
//! * [`Manual`] — positions supplied by the caller (art-directed skies).
//!
//! The reduction from theory to apparent place follows Meeus (Astronomical
//! Algorithms, 2nd ed.): ch. 25 (Sun), ch. 33 (planets: light time, FK5
//! correction, aberration, nutation), ch. 47 (Moon). The high-tier Moon comes
//! from a Chebyshev fit to JPL DE421 and is reduced by vector algebra: light
//! time, frame bias, IAU 1976 precession, IAU 1980 nutation.

use core::cell::Cell;

use glam::DVec3;

use crate::error::AstroError;
use crate::frames::{self, Nutation, NutationModel};
use crate::moon;
use crate::planets::{self, Planet, Series};
use crate::time::Instant;
use crate::units::*;

/// A solar-system body that the ephemerides know.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "lowercase"))]
pub enum Body {
    /// The Sun.
    Sun,
    /// The Moon.
    Moon,
    /// Mercury.
    Mercury,
    /// Venus.
    Venus,
    /// Mars.
    Mars,
    /// Jupiter.
    Jupiter,
    /// Saturn.
    Saturn,
}

impl Body {
    /// Every body, in the order of the command-line contract.
    pub const ALL: [Body; 7] = [
        Body::Sun,
        Body::Moon,
        Body::Mercury,
        Body::Venus,
        Body::Mars,
        Body::Jupiter,
        Body::Saturn,
    ];

    /// Lower-case English name (`"sun"`, `"moon"`, `"mars"`, …).
    pub const fn name(self) -> &'static str {
        match self {
            Body::Sun => "sun",
            Body::Moon => "moon",
            Body::Mercury => "mercury",
            Body::Venus => "venus",
            Body::Mars => "mars",
            Body::Jupiter => "jupiter",
            Body::Saturn => "saturn",
        }
    }

    /// Parses a lower-case name as written by [`Body::name`] (ASCII case is ignored).
    pub fn from_name(name: &str) -> Option<Body> {
        Body::ALL
            .into_iter()
            .find(|b| b.name().eq_ignore_ascii_case(name))
    }

    /// The planet of the VSOP87 theory, or `None` for the Sun and the Moon.
    pub const fn planet(self) -> Option<Planet> {
        match self {
            Body::Mercury => Some(Planet::Mercury),
            Body::Venus => Some(Planet::Venus),
            Body::Mars => Some(Planet::Mars),
            Body::Jupiter => Some(Planet::Jupiter),
            Body::Saturn => Some(Planet::Saturn),
            Body::Sun | Body::Moon => None,
        }
    }
}

/// Accuracy tier. Errors and costs of each tier against JPL DE421 are
/// measured and published in the README (`cargo run -p himmel-tests --release
/// --bin accuracy-table`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "lowercase"))]
pub enum Precision {
    /// Meeus ch. 25 low-accuracy Sun (0.01°), a short lunar series, mean
    /// Keplerian planets, the short nutation series.
    Low,
    /// VSOP87D truncated, Meeus ch. 47 Moon with all its terms, IAU 1980 nutation.
    #[default]
    Standard,
    /// Full VSOP87D, the Moon from a Chebyshev fit to DE421 (1900–2050; the
    /// standard series outside that span), IAU 1980 nutation.
    High,
}

impl Precision {
    /// Every tier, cheapest first.
    pub const ALL: [Precision; 3] = [Precision::Low, Precision::Standard, Precision::High];

    /// `"low"`, `"standard"` or `"high"`.
    pub const fn name(self) -> &'static str {
        match self {
            Precision::Low => "low",
            Precision::Standard => "standard",
            Precision::High => "high",
        }
    }

    /// Parses a name as written by [`Precision::name`].
    pub fn from_name(name: &str) -> Option<Precision> {
        Precision::ALL
            .into_iter()
            .find(|p| p.name().eq_ignore_ascii_case(name))
    }

    /// The nutation series consistent with this tier.
    pub const fn nutation_model(self) -> NutationModel {
        match self {
            Precision::Low => NutationModel::Short,
            Precision::Standard | Precision::High => NutationModel::Iau1980,
        }
    }
}

/// Everything about an instant that every body's reduction shares: the
/// instant itself, nutation and obliquity. Compute it once per instant and
/// reuse it for all bodies and observers; sidereal time, which only
/// topocentric places need, comes from [`Epoch::gast`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Epoch {
    /// The instant (TT and UT1).
    pub instant: Instant,
    /// Julian centuries of TT since J2000.0.
    pub t: JulianCenturies,
    /// Nutation in longitude and obliquity (IAU 1980 or the short series).
    pub nutation: Nutation,
    /// Which nutation series produced [`Epoch::nutation`].
    pub nutation_model: NutationModel,
    /// Mean obliquity of the ecliptic of date (Meeus eq. 22.2).
    pub mean_obliquity: Radians,
    /// True obliquity ε = ε₀ + Δε.
    pub true_obliquity: Radians,
    /// sin ε of the true obliquity (shared by every ecliptic ↔ equatorial
    /// conversion at this instant).
    pub sin_obliquity: f64,
    /// cos ε of the true obliquity.
    pub cos_obliquity: f64,
    /// The low tier's lunar arguments, shared with its short nutation
    /// series (present when `nutation_model` is [`NutationModel::Short`]).
    low: Option<moon::LowArguments>,
}

impl Epoch {
    /// Prepares the reduction quantities of `instant` with the given nutation series.
    pub fn new(instant: &Instant, nutation_model: NutationModel) -> Epoch {
        let t = instant.centuries_tt();
        let (nutation, low) = match nutation_model {
            NutationModel::Short => {
                // One set of phasors serves the short nutation series and
                // the low-tier Moon.
                let args = moon::LowArguments::at(t);
                let [om, two_sun, two_moon] = args.nutation_arguments();
                let n = frames::nutation_short_from(om, two_sun, two_moon);
                (n, Some(args))
            }
            model => (frames::nutation(t, model), None),
        };
        let mean_obliquity = frames::mean_obliquity(t);
        let true_obliquity = mean_obliquity + nutation.deps;
        let (sin_obliquity, cos_obliquity) = sincos_obliquity(true_obliquity);
        Epoch {
            instant: *instant,
            t,
            nutation,
            nutation_model,
            mean_obliquity,
            true_obliquity,
            sin_obliquity,
            cos_obliquity,
            low,
        }
    }

    /// Greenwich apparent sidereal time, radians in [0, 2π): GMST (IAU 1982,
    /// Meeus eq. 12.4) plus the equation of the equinoxes Δψ cos ε, as in
    /// [`crate::time::gast`]. About 15 ns; evaluated on demand because
    /// geocentric places do not need it.
    pub fn gast(&self) -> Radians {
        wrap_tau(crate::time::gmst(self.instant.jd_ut1) + self.nutation.dpsi * self.cos_obliquity)
    }

    /// Rotation from ICRF (GCRS axes) to the true equator and equinox of date:
    /// frame bias, IAU 1976 precession, IAU 1980 nutation.
    pub fn icrf_to_true_of_date(&self) -> glam::DMat3 {
        frames::nutation_matrix(self.mean_obliquity, &self.nutation)
            * frames::precession_matrix(self.t)
            * frames::frame_bias_matrix()
    }
}

/// An apparent geocentric place: true equator and equinox of date, including
/// light time, annual aberration, precession and nutation.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Apparent {
    /// Right ascension, radians in [0, 2π).
    pub ra: Radians,
    /// Declination, radians in [−π/2, π/2].
    pub dec: Radians,
    /// Distance from the Earth's centre (light-time corrected), km.
    pub distance_km: Km,
    /// Apparent ecliptic longitude (true ecliptic and equinox of date), radians in [0, 2π).
    pub ecl_lon: Radians,
    /// Apparent ecliptic latitude, radians.
    pub ecl_lat: Radians,
}

impl Apparent {
    /// Builds an apparent place from ecliptic coordinates of date (Meeus
    /// eq. 13.3–13.4 on vectors, with the epoch's sin ε and cos ε).
    pub fn from_ecliptic(lon: Radians, lat: Radians, distance_km: Km, epoch: &Epoch) -> Apparent {
        let lon = wrap_tau(lon);
        let (sl, cl) = crate::fastmath::sincos(lon);
        let (sb, cb) = crate::fastmath::sincos(lat);
        let (se, ce) = (epoch.sin_obliquity, epoch.cos_obliquity);
        let x = cb * cl;
        let y = cb * sl * ce - sb * se;
        let z = cb * sl * se + sb * ce;
        let (ra, dec) = xyz_to_angles(x, y, z);
        Apparent {
            ra,
            dec,
            distance_km,
            ecl_lon: lon,
            ecl_lat: lat,
        }
    }

    /// Builds an apparent place from equatorial coordinates of date (Meeus
    /// eq. 13.1–13.2 on vectors, with the epoch's sin ε and cos ε).
    pub fn from_equatorial(ra: Radians, dec: Radians, distance_km: Km, epoch: &Epoch) -> Apparent {
        let ra = wrap_tau(ra);
        let (sa, ca) = crate::fastmath::sincos(ra);
        let (sd, cd) = crate::fastmath::sincos(dec);
        let (se, ce) = (epoch.sin_obliquity, epoch.cos_obliquity);
        let x = cd * ca;
        let y = cd * sa * ce + sd * se;
        let z = -cd * sa * se + sd * ce;
        let (ecl_lon, ecl_lat) = xyz_to_angles(x, y, z);
        Apparent {
            ra,
            dec,
            distance_km,
            ecl_lon,
            ecl_lat,
        }
    }

    /// Geocentric position vector, km, true equator and equinox of date.
    pub fn vector_km(&self) -> DVec3 {
        frames::spherical_to_vector(self.ra, self.dec, self.distance_km)
    }
}

/// (sin ε, cos ε) by a Taylor expansion about ε₀(J2000) = 84 381.448″:
/// the obliquity stays within 2e-3 rad of it for ±8 centuries, where the
/// cubic is good to 1e-12; farther out the full sine.
#[inline]
fn sincos_obliquity(eps: Radians) -> (f64, f64) {
    // sin and cos of 84 381.448″.
    const S0: f64 = 0.397_777_155_931_913_7;
    const C0: f64 = 0.917_482_062_069_181_8;
    let d = eps - 84_381.448 * ARCSEC;
    if d.abs() > 2e-3 {
        return crate::fastmath::sincos(eps);
    }
    let d2 = d * d;
    let (a, b) = (1.0 - 0.5 * d2, d - d * d2 * (1.0 / 6.0));
    (S0 * a + C0 * b, C0 * a - S0 * b)
}

/// (longitude in [0, 2π), latitude) of a unit vector, both from `atan2`
/// (finite and accurate at the poles; longitude 0 there). NaN components
/// give NaN angles.
#[inline]
fn xyz_to_angles(x: f64, y: f64, z: f64) -> (Radians, Radians) {
    // The callers build (x, y, z) from sines and cosines: a unit vector, or
    // NaN, which passes through.
    let rho = libm::sqrt(x * x + y * y);
    let mut lon = if rho == 0.0 {
        0.0
    } else {
        crate::fastmath::atan2_unit(y, x)
    };
    if lon < 0.0 {
        lon += TAU;
        // −1e-17 rounds up to exactly 2π.
        if lon >= TAU {
            lon = 0.0;
        }
    }
    (lon, crate::fastmath::latitude_unit(z, rho))
}

/// A source of apparent geocentric places.
pub trait Ephemeris {
    /// The nutation series the provider is consistent with; an [`Epoch`]
    /// built for it should use this model.
    fn nutation_model(&self) -> NutationModel {
        NutationModel::Iau1980
    }

    /// Apparent geocentric place of `body` at `epoch`.
    fn apparent(&self, body: Body, epoch: &Epoch) -> Result<Apparent, AstroError>;
}

impl<E: Ephemeris + ?Sized> Ephemeris for &E {
    fn nutation_model(&self) -> NutationModel {
        (**self).nutation_model()
    }
    fn apparent(&self, body: Body, epoch: &Epoch) -> Result<Apparent, AstroError> {
        (**self).apparent(body, epoch)
    }
}

/// The computed ephemeris at one [`Precision`] tier.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Tiered(pub Precision);

impl Ephemeris for Tiered {
    fn nutation_model(&self) -> NutationModel {
        self.0.nutation_model()
    }

    fn apparent(&self, body: Body, epoch: &Epoch) -> Result<Apparent, AstroError> {
        Ok(match (body, self.0) {
            (Body::Sun, Precision::Low) => sun_low(epoch),
            (Body::Sun, Precision::Standard) => sun_vsop87(epoch, Series::Truncated),
            (Body::Sun, Precision::High) => sun_vsop87(epoch, Series::Full),
            (Body::Moon, Precision::Low) => moon_low(epoch),
            (Body::Moon, Precision::Standard) => moon_series(epoch, moon::meeus47(epoch.t)),
            (Body::Moon, Precision::High) => {
                moon_de421(epoch).unwrap_or_else(|| moon_series(epoch, moon::meeus47(epoch.t)))
            }
            (_, tier) => {
                let planet = body
                    .planet()
                    .ok_or(AstroError::BodyUnavailable { body: body.name() })?;
                planet_apparent(epoch, planet, tier)
            }
        })
    }
}

/// Sun, low tier: Meeus ch. 25 low accuracy (apparent longitude, β = 0).
fn sun_low(epoch: &Epoch) -> Apparent {
    let (lon, r) = planets::sun_low(epoch.instant.jd_tt);
    Apparent::from_ecliptic(lon, 0.0, r * KM_PER_AU, epoch)
}

/// Sun from VSOP87D (Meeus ch. 25, "higher accuracy"): geometric λ = L + 180°,
/// β = −B, FK5 correction (eq. 32.3), annual aberration (eq. 23.2, which for
/// the Sun reduces to the classic −20.4898″/R), nutation in longitude.
fn sun_vsop87(epoch: &Epoch, series: Series) -> Apparent {
    let (l, b, r) = planets::heliocentric(Planet::Earth, epoch.instant.jd_tt, series);
    let sun_lon = wrap_tau(l + core::f64::consts::PI);
    let (dl, db) = planets::fk5_correction(sun_lon, -b, epoch.t);
    let (lon, lat) = (sun_lon + dl, -b + db);
    let (al, ab) = annual_aberration(lon, lat, sun_lon, epoch.t);
    Apparent::from_ecliptic(
        lon + al + epoch.nutation.dpsi,
        lat + ab,
        r * KM_PER_AU,
        epoch,
    )
}

/// Annual aberration in ecliptic coordinates, Meeus eq. 23.2 (with the
/// e-terms): Δλ, Δβ to add, radians. `sun_lon` is the Sun's true geometric
/// longitude. Heliocentric Keplerian motion of the Earth: the neglected
/// barycentric and lunar terms amount to about 0.01″.
fn annual_aberration(
    lon: Radians,
    lat: Radians,
    sun_lon: Radians,
    t: JulianCenturies,
) -> (Radians, Radians) {
    const KAPPA: Radians = 20.495_52 * ARCSEC;
    let e = 0.016_708_634 - 0.000_042_037 * t - 0.000_000_126_7 * t * t;
    let perihelion = (102.937_35 + 1.719_46 * t + 0.000_46 * t * t) * DEG;
    let cos_lat = libm::cos(lat);
    // cos β vanishes only at the ecliptic poles, where longitude is undefined
    // anyway; keep the quotient finite.
    let cos_lat = if cos_lat.abs() < 1e-12 {
        1e-12
    } else {
        cos_lat
    };
    let dlon =
        (-KAPPA * libm::cos(sun_lon - lon) + e * KAPPA * libm::cos(perihelion - lon)) / cos_lat;
    let dlat =
        -KAPPA * libm::sin(lat) * (libm::sin(sun_lon - lon) - e * libm::sin(perihelion - lon));
    (dlon, dlat)
}

/// Planets, Meeus ch. 33: heliocentric positions of the planet (at t − τ) and
/// the Earth (at t), light time iterated to convergence, FK5 correction,
/// annual aberration, nutation in longitude. Light deflection by the Sun
/// (< 0.1″ more than 10° from the Sun) is neglected.
fn planet_apparent(epoch: &Epoch, planet: Planet, tier: Precision) -> Apparent {
    let jd = epoch.instant.jd_tt;
    let helio = |p: Planet, jd: JulianDay| match tier {
        Precision::Low => planets::heliocentric_low_vector(p, jd),
        Precision::Standard => {
            let (l, b, r) = planets::heliocentric(p, jd, Series::Truncated);
            frames::spherical_to_vector(l, b, r)
        }
        Precision::High => {
            let (l, b, r) = planets::heliocentric(p, jd, Series::Full);
            frames::spherical_to_vector(l, b, r)
        }
    };
    let earth = helio(Planet::Earth, jd);
    // Light time from the geometric distance at t, then the planet at
    // t − τ. The distance changes by at most ~40 km/s × τ meanwhile, so τ is
    // good to ~0.1 s and a further iteration would move no planet by even
    // 0.001″.
    let tau = (helio(planet, jd) - earth).length() * LIGHT_DAYS_PER_AU;
    let geo = helio(planet, jd - tau) - earth;
    let (lon, lat, delta) = frames::vector_to_spherical(geo);
    // The Sun's geometric longitude, opposite the Earth's heliocentric one.
    let sun_lon = wrap_tau(libm::atan2(earth.y, earth.x) + core::f64::consts::PI);
    let (lon, lat) = if tier == Precision::Low {
        (lon, lat)
    } else {
        let (dl, db) = planets::fk5_correction(lon, lat, epoch.t);
        (lon + dl, lat + db)
    };
    let (al, ab) = annual_aberration(lon, lat, sun_lon, epoch.t);
    Apparent::from_ecliptic(
        lon + al + epoch.nutation.dpsi,
        lat + ab,
        delta * KM_PER_AU,
        epoch,
    )
}

/// Moon from an ELP series (Meeus ch. 47): the series already includes the
/// constant light-time term; the apparent longitude adds nutation. Aberration
/// does not enter: for a body this close, the Earth's displacement during the
/// light time cancels the annual aberration to within micro-arcseconds.
fn moon_series(epoch: &Epoch, (lon, lat, dist): (Radians, Radians, Km)) -> Apparent {
    Apparent::from_ecliptic(lon + epoch.nutation.dpsi, lat, dist, epoch)
}

/// Moon, low tier: [`moon::low`] plus nutation in longitude, converted to
/// RA/Dec as in [`Apparent::from_ecliptic`]. sin λ and cos λ come from
/// e^{iL′} (held by the epoch) times e^{i(Σl + Δψ)} (|Σl| < 9.2°, a short
/// series), sin β and cos β from the small-angle series (|β| < 5.4°).
fn moon_low(epoch: &Epoch) -> Apparent {
    let own;
    let args = match &epoch.low {
        Some(shared) => shared,
        None => {
            own = moon::LowArguments::at(epoch.t);
            &own
        }
    };
    let (sigma_l, lat, dist) = moon::low_terms(args);
    let dl = sigma_l + epoch.nutation.dpsi;
    let mut lon = args.l_prime_angle + dl;
    if lon < 0.0 {
        lon += TAU;
    } else if lon >= TAU {
        lon -= TAU;
    }
    let (sd, cd) = crate::fastmath::sincos_small(dl);
    let (sp, cp) = (args.l_prime.sin, args.l_prime.cos);
    let (sl, cl) = (sp * cd + cp * sd, cp * cd - sp * sd);
    let (sb, cb) = crate::fastmath::sincos_small(lat);
    let (se, ce) = (epoch.sin_obliquity, epoch.cos_obliquity);
    let (ra, dec) = xyz_to_angles(cb * cl, cb * sl * ce - sb * se, cb * sl * se + sb * ce);
    Apparent {
        ra,
        dec,
        distance_km: dist,
        ecl_lon: lon,
        ecl_lat: lat,
    }
}

/// Moon from the DE421 fit: geometric position at t − τ (the light-time and
/// annual-aberration effects of the Earth's motion cancel, see
/// [`moon_series`]), then ICRF → true equator and equinox of date.
fn moon_de421(epoch: &Epoch) -> Option<Apparent> {
    let jd = epoch.instant.jd_tt;
    let mut r = moon::de421(jd)?;
    for _ in 0..2 {
        let tau = r.length() / SPEED_OF_LIGHT_KM_S / SECONDS_PER_DAY;
        r = moon::de421(jd - tau)?;
    }
    let tod = epoch.icrf_to_true_of_date() * r;
    let (ra, dec, dist) = frames::vector_to_spherical(tod);
    Some(Apparent::from_equatorial(ra, dec, dist, epoch))
}

/// Reuses the results of another provider while the instant stays within a
/// tolerance: a renderer asking for the Moon 60 times a second can keep one
/// result for, say, a second (0.5″ of lunar motion).
///
/// The cache holds one result per body; it is not `Sync` (use one per thread).
#[derive(Debug)]
pub struct Cached<E> {
    inner: E,
    tolerance_days: f64,
    slots: [Cell<Option<(JulianDay, Apparent)>>; 7],
}

impl<E: Ephemeris> Cached<E> {
    /// Wraps `inner`; results are reused while |ΔTT| ≤ `tolerance`.
    pub fn new(inner: E, tolerance: Seconds) -> Result<Self, AstroError> {
        let tolerance = AstroError::check_range("cache tolerance (s)", tolerance, 0.0, 1e9)?;
        Ok(Cached {
            inner,
            tolerance_days: tolerance / SECONDS_PER_DAY,
            slots: Default::default(),
        })
    }

    /// The wrapped provider.
    pub fn inner(&self) -> &E {
        &self.inner
    }

    /// Forgets every cached result.
    pub fn clear(&self) {
        for s in &self.slots {
            s.set(None);
        }
    }
}

fn slot_index(body: Body) -> usize {
    Body::ALL.iter().position(|b| *b == body).unwrap_or(0)
}

impl<E: Ephemeris> Ephemeris for Cached<E> {
    fn nutation_model(&self) -> NutationModel {
        self.inner.nutation_model()
    }

    fn apparent(&self, body: Body, epoch: &Epoch) -> Result<Apparent, AstroError> {
        let slot = &self.slots[slot_index(body)];
        let jd = epoch.instant.jd_tt;
        if let Some((at, place)) = slot.get() {
            if (jd - at).abs() <= self.tolerance_days {
                return Ok(place);
            }
        }
        let place = self.inner.apparent(body, epoch)?;
        slot.set(Some((jd, place)));
        Ok(place)
    }
}

/// Caller-supplied positions for art-directed skies: each body keeps the
/// apparent right ascension, declination and distance it was given, whatever
/// the instant. Bodies without a position report
/// [`AstroError::BodyUnavailable`].
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Manual {
    places: [Option<(Radians, Radians, Km)>; 7],
}

impl Manual {
    /// An empty provider.
    pub fn new() -> Self {
        Self::default()
    }

    /// Sets `body` to the apparent place (degrees, km). Declination must be
    /// within ±90° and the distance positive.
    pub fn set(
        &mut self,
        body: Body,
        ra_deg: Degrees,
        dec_deg: Degrees,
        distance_km: Km,
    ) -> Result<&mut Self, AstroError> {
        let ra = AstroError::check_range("right ascension", ra_deg, -360.0, 360.0)?;
        let dec = AstroError::check_range("declination", dec_deg, -90.0, 90.0)?;
        let d = AstroError::check_range("distance", distance_km, 1e-3, 1e20)?;
        self.places[slot_index(body)] = Some((wrap_tau(ra * DEG), dec * DEG, d));
        Ok(self)
    }

    /// Builder form of [`Manual::set`].
    pub fn with(
        mut self,
        body: Body,
        ra_deg: Degrees,
        dec_deg: Degrees,
        distance_km: Km,
    ) -> Result<Self, AstroError> {
        self.set(body, ra_deg, dec_deg, distance_km)?;
        Ok(self)
    }
}

impl Ephemeris for Manual {
    fn apparent(&self, body: Body, epoch: &Epoch) -> Result<Apparent, AstroError> {
        let (ra, dec, d) = self.places[slot_index(body)]
            .ok_or(AstroError::BodyUnavailable { body: body.name() })?;
        Ok(Apparent::from_equatorial(ra, dec, d, epoch))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn obliquity_sine_and_cosine() {
        let mut t = -30.0;
        while t < 30.0 {
            let eps = frames::mean_obliquity(t);
            let (s, c) = sincos_obliquity(eps);
            assert!((s - libm::sin(eps)).abs() < 1e-12 && (c - libm::cos(eps)).abs() < 1e-12);
            t += 0.0137;
        }
    }

    #[test]
    fn low_epoch_nutation_matches_the_short_series() {
        // The epoch derives the short series from the lunar phasors; the
        // stand-alone series uses Meeus ch. 22's own mean longitudes.
        let mut jd = J2000 - 2.0 * DAYS_PER_CENTURY;
        while jd < J2000 + 2.0 * DAYS_PER_CENTURY {
            let e = Epoch::new(&Instant::from_tt(jd), NutationModel::Short);
            let n = frames::nutation(e.t, NutationModel::Short);
            assert!((e.nutation.dpsi - n.dpsi).abs() < 0.01 * ARCSEC, "{jd}");
            assert!((e.nutation.deps - n.deps).abs() < 0.01 * ARCSEC, "{jd}");
            jd += 37.3;
        }
    }

    #[test]
    fn low_moon_is_the_same_with_either_epoch() {
        // Without the shared arguments (an IAU 1980 epoch) the low tier
        // evaluates them itself; only the nutation differs (≤ 0.6″).
        for k in 0..500 {
            let t = Instant::from_tt(J2000 - 20_000.0 + f64::from(k) * 80.1);
            let low = Tiered(Precision::Low);
            let short = Epoch::new(&t, NutationModel::Short);
            let a = low.apparent(Body::Moon, &short).unwrap();
            let b = low
                .apparent(Body::Moon, &Epoch::new(&t, NutationModel::Iau1980))
                .unwrap();
            assert!(
                wrap_pi(a.ra - b.ra).abs() * libm::cos(a.dec) < 1.0 * ARCSEC,
                "{k}"
            );
            assert!((a.dec - b.dec).abs() < 1.0 * ARCSEC, "{k}");
            // And the vector form agrees with the series' own λ, β.
            let (lon, lat, dist) = moon::low(t.centuries_tt());
            let c = Apparent::from_ecliptic(lon + short.nutation.dpsi, lat, dist, &short);
            assert!(
                wrap_pi(a.ra - c.ra).abs() < 1e-6 && (a.dec - c.dec).abs() < 1e-6,
                "{k}"
            );
        }
    }
}
