//! Apparent places of catalogue stars: space motion to the date, parallax,
//! gravitational light deflection by the Sun, annual (and diurnal)
//! aberration, frame bias, precession and nutation — then the observer's
//! horizon.
//!
//! The exact path follows the rigorous vector method of Kaplan et al. (1989,
//! *AJ* 97, 1197; the NOVAS / Skyfield `Star` model) and the Explanatory
//! Supplement (1992) §3.2: the star moves on a straight line at constant
//! velocity in the barycentric frame, the observer sees it from the Earth's
//! barycentric position, light is bent by the Sun and aberrated by the
//! observer's velocity, and the direction is rotated from the ICRS to the true
//! equator and equinox of date (IAU 1976 precession, IAU 1980 nutation).
//!
//! The fast path ([`FastStar`], [`FrameRotation`]) is what a renderer needs
//! for thousands of stars per frame: one rotation matrix per frame (ICRS →
//! horizon, full precession and nutation), one aberration vector per frame,
//! and per star a unit vector plus its proper-motion rate, re-based when the
//! date leaves a tolerance around the refresh epoch. It omits parallax and
//! light deflection; its error against the exact path is measured in the tests.
//!
//! ```
//! use himmel_astro::stars::{Astrometry, StarReduction};
//! use himmel_astro::{Epoch, Instant, Observer};
//! use himmel_astro::frames::NutationModel;
//! // Sirius, Hipparcos new reduction (epoch J1991.25)
//! let sirius = Astrometry::new(1.7678185359, -0.2916993748, -546.01, -1223.07, 379.21, 0.0,
//!     Astrometry::J1991_25)?;
//! let epoch = Epoch::new(&Instant::from_tt(2_460_000.5), NutationModel::Iau1980);
//! let red = StarReduction::new(&epoch);
//! let app = red.apparent(&sirius);
//! assert!((app.ra_deg() - 101.4).abs() < 0.3 && (app.dec_deg() + 16.74).abs() < 0.1);
//! let here = Observer::new(48.1, 11.6, 520.0)?;
//! let topo = red.topocentric(&sirius, &here);
//! assert!(topo.alt_deg().is_finite());
//! # Ok::<(), himmel_astro::AstroError>(())
//! ```

use glam::{DMat3, DVec3};

use crate::ephemeris::Epoch;
use crate::error::AstroError;
use crate::frames;
use crate::observe::Observer;
use crate::planets::{self, Planet, Series};
use crate::units::*;

/// Milliarcseconds → radians.
const MAS: f64 = ARCSEC / 1000.0;
/// Days per Julian year.
const DAYS_PER_YEAR: f64 = 365.25;
/// Speed of light, AU/day.
const C_AU_PER_DAY: f64 = 1.0 / LIGHT_DAYS_PER_AU;
/// Heliocentric gravitational constant over c², AU (GM☉/c² = 1476.6 m).
const SUN_GM_OVER_C2_AU: f64 = 1.476_625_04 / KM_PER_AU;
/// Smallest parallax used for the distance: a star with zero or negative
/// parallax is put at 1 Gpc (as NOVAS and Skyfield do).
const MIN_PARALLAX_MAS: f64 = 1.0e-6;

/// Catalogue astrometry of one star: ICRS position at the catalogue epoch,
/// proper motion, parallax and radial velocity.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Astrometry {
    /// Right ascension (ICRS) at [`Astrometry::epoch`], radians in [0, 2π).
    pub ra: Radians,
    /// Declination (ICRS) at the epoch, radians.
    pub dec: Radians,
    /// Proper motion in right ascension times cos δ (μα*), mas/yr.
    pub pm_ra_mas_yr: f64,
    /// Proper motion in declination, mas/yr.
    pub pm_dec_mas_yr: f64,
    /// Annual parallax, mas (≤ 0 means "unknown", treated as 1 Gpc).
    pub parallax_mas: f64,
    /// Radial velocity, km/s, positive receding (0 when unknown).
    pub radial_velocity_km_s: f64,
    /// Catalogue epoch of the position, Julian day (TT).
    pub epoch: JulianDay,
}

impl Astrometry {
    /// The Hipparcos epoch J1991.25 (TT), JD 2448349.0625.
    pub const J1991_25: JulianDay = 2_448_349.062_5;

    /// Validated astrometry: `ra` in [0, 2π] and `dec` in [−π/2, π/2]
    /// radians (ICRS, at `epoch` JD TT), proper motions in mas/yr (|μ| ≤
    /// 20 000), parallax in mas (< 1 000 000), radial velocity in km/s
    /// (|v| < 100 000). Every value must be finite.
    pub fn new(
        ra: Radians,
        dec: Radians,
        pm_ra_mas_yr: f64,
        pm_dec_mas_yr: f64,
        parallax_mas: f64,
        radial_velocity_km_s: f64,
        epoch: JulianDay,
    ) -> Result<Self, AstroError> {
        AstroError::check_range("right ascension", ra, 0.0, TAU)?;
        AstroError::check_range("declination", dec, -TAU / 4.0, TAU / 4.0)?;
        AstroError::check_range("proper motion in RA", pm_ra_mas_yr, -2e4, 2e4)?;
        AstroError::check_range("proper motion in Dec", pm_dec_mas_yr, -2e4, 2e4)?;
        AstroError::check_range("parallax", parallax_mas, -1e6, 1e6)?;
        AstroError::check_range("radial velocity", radial_velocity_km_s, -1e5, 1e5)?;
        AstroError::check_range("epoch", epoch, 0.0, 1e7)?;
        Ok(Astrometry {
            ra,
            dec,
            pm_ra_mas_yr,
            pm_dec_mas_yr,
            parallax_mas,
            radial_velocity_km_s,
            epoch,
        })
    }

    /// Barycentric position (AU) and velocity (AU/day) of the star in the
    /// ICRS at the catalogue epoch.
    ///
    /// Kaplan et al. (1989) eqs. 1–3 (NOVAS `starvectors`): distance
    /// 1/sin ϖ; proper motion and radial velocity turned into a space
    /// velocity, with the Doppler factor k = 1/(1 − v_r/c) for the changing
    /// light time.
    pub fn barycentric_state(&self) -> (DVec3, DVec3) {
        let plx = if self.parallax_mas > 0.0 {
            self.parallax_mas
        } else {
            MIN_PARALLAX_MAS
        };
        let dist = 1.0 / libm::sin(plx * MAS);
        let (sr, cr) = (libm::sin(self.ra), libm::cos(self.ra));
        let (sd, cd) = (libm::sin(self.dec), libm::cos(self.dec));
        let pos = DVec3::new(cd * cr, cd * sr, sd) * dist;
        let k = 1.0 / (1.0 - self.radial_velocity_km_s / SPEED_OF_LIGHT_KM_S);
        let pmr = self.pm_ra_mas_yr / (plx * DAYS_PER_YEAR) * k;
        let pmd = self.pm_dec_mas_yr / (plx * DAYS_PER_YEAR) * k;
        let rvl = self.radial_velocity_km_s * SECONDS_PER_DAY / KM_PER_AU * k;
        let vel = DVec3::new(
            -pmr * sr - pmd * sd * cr + rvl * cd * cr,
            pmr * cr - pmd * sd * sr + rvl * cd * sr,
            pmd * cd + rvl * sd,
        );
        (pos, vel)
    }

    /// Barycentric (space-motion only) unit direction of the star at
    /// `jd_tt`, ICRS: the catalogue "mean place" of the date, without
    /// parallax, deflection or aberration.
    pub fn direction_at(&self, jd_tt: JulianDay) -> DVec3 {
        let (p, v) = self.barycentric_state();
        (p + v * (jd_tt - self.epoch)).normalize_or_zero()
    }
}

/// The Earth's barycentric state used by the reduction, ICRS axes.
///
/// Position: VSOP87D heliocentric Earth (truncated series, Meeus ch. 32)
/// rotated from the ecliptic and equinox of date to the ICRS (mean obliquity,
/// transposed IAU 1976 precession and frame bias); the Sun's own offset from
/// the barycentre (≤ 0.01 AU) is neglected, ≤ 1 % of a star's parallax.
/// Velocity: Ron & Vondrák (1986), barycentric (Meeus Table 23.A).
fn earth_state(epoch: &Epoch) -> (DVec3, DVec3) {
    let jd = epoch.instant.jd_tt;
    let (l, b, r) = planets::heliocentric(Planet::Earth, jd, Series::Truncated);
    let ecl = frames::spherical_to_vector(l, b, r);
    let eq_of_date = frames::ecliptic_to_equatorial_matrix(epoch.mean_obliquity) * ecl;
    let to_icrs = (frames::precession_matrix(epoch.t) * frames::frame_bias_matrix()).transpose();
    let pos = to_icrs * eq_of_date;
    let vel = frames::earth_velocity_j2000(epoch.t);
    (pos, vel)
}

/// Gravitational deflection of light by the Sun (Explanatory Supplement
/// 1992, eq. 3.252-3 for a source at infinity; SOFA `iauLd` with q = p):
/// p′ = p + (2 GM☉ / (c² |E|)) · (e − (e·p) p) / (1 + e·p), where `e` is the
/// unit vector from the Sun to the observer and `dist_au` = |E|. Returns a
/// unit vector; 1.75″ at the solar limb, 4 mas at 90° from the Sun. Behind
/// the Sun's disc (e·p < −0.99999) the factor is limited to its value at
/// the limb.
pub fn deflect_by_sun(p: DVec3, sun_to_observer_unit: DVec3, dist_au: Au) -> DVec3 {
    let e = sun_to_observer_unit;
    let ep = e.dot(p);
    let denom = (1.0 + ep).max(1.0e-5);
    let g = 2.0 * SUN_GM_OVER_C2_AU / dist_au.max(1e-6);
    (p + (e - p * ep) * (g / denom)).normalize_or_zero()
}

/// What [`StarReduction`] includes beyond space motion, precession and
/// nutation (which are always applied).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct StarEffects {
    /// Annual parallax from the Earth's barycentric position (≤ 0.77″).
    pub parallax: bool,
    /// Light deflection by the Sun (4 mas at 90°, 1.75″ at the limb).
    pub deflection: bool,
    /// Aberration (annual, plus diurnal for a topocentric observer): ~20″.
    pub aberration: bool,
}

impl Default for StarEffects {
    fn default() -> Self {
        StarEffects {
            parallax: true,
            deflection: true,
            aberration: true,
        }
    }
}

/// An apparent geocentric (or topocentric-direction) place of a star: true
/// equator and equinox of date.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct StarApparent {
    /// Unit vector, true equator and equinox of date.
    pub vector: DVec3,
    /// Right ascension, radians in [0, 2π).
    pub ra: Radians,
    /// Declination, radians.
    pub dec: Radians,
}

impl StarApparent {
    fn from_vector(vector: DVec3) -> Self {
        let (ra, dec) = frames::vector_to_equatorial(vector);
        StarApparent { vector, ra, dec }
    }
    /// Right ascension, degrees in [0, 360).
    pub fn ra_deg(&self) -> Degrees {
        self.ra / DEG
    }
    /// Declination, degrees.
    pub fn dec_deg(&self) -> Degrees {
        self.dec / DEG
    }
}

/// A star seen from a place on the Earth: topocentric apparent place and
/// horizontal coordinates (unrefracted unless the name says "refracted").
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct StarTopocentric {
    /// Apparent place (true equator and equinox of date) including diurnal
    /// aberration.
    pub place: StarApparent,
    /// Altitude, radians in [−π/2, π/2] (no refraction).
    pub alt: Radians,
    /// Azimuth from North through East, radians in [0, 2π).
    pub az: Radians,
}

impl StarTopocentric {
    /// Altitude, degrees (unrefracted).
    pub fn alt_deg(&self) -> Degrees {
        self.alt / DEG
    }
    /// Azimuth, degrees in [0, 360).
    pub fn az_deg(&self) -> Degrees {
        wrap_360(self.az / DEG)
    }
    /// Altitude with standard refraction (1010 hPa, 10 °C; Saemundsson,
    /// Meeus eq. 16.4), degrees.
    pub fn alt_refracted_deg(&self) -> Degrees {
        (self.alt
            + frames::refraction_true_to_apparent(
                self.alt,
                frames::STANDARD_PRESSURE_HPA,
                frames::STANDARD_TEMPERATURE_C,
            ))
            / DEG
    }
    /// Unit vector in the horizontal frame (x = East, y = North, z = Zenith).
    pub fn enu(&self) -> DVec3 {
        let (sa, ca) = (libm::sin(self.alt), libm::cos(self.alt));
        DVec3::new(ca * libm::sin(self.az), ca * libm::cos(self.az), sa)
    }
}

/// Rotation from the true equator and equinox of date to the horizontal
/// frame (x = East, y = North, z = Zenith) at local apparent sidereal time
/// `lst` and geodetic latitude `lat` (Meeus eq. 13.5–13.6 as a matrix:
/// R₃(LST) brings the meridian to +x, then the tilt by the latitude).
pub fn equatorial_to_enu_matrix(lst: Radians, lat: Radians) -> DMat3 {
    let (st, ct) = (libm::sin(lst), libm::cos(lst));
    let (sp, cp) = (libm::sin(lat), libm::cos(lat));
    // Rows: East, North, Up of the vector (cos δ cos α, cos δ sin α, sin δ).
    let east = DVec3::new(-st, ct, 0.0);
    let north = DVec3::new(-sp * ct, -sp * st, cp);
    let up = DVec3::new(cp * ct, cp * st, sp);
    DMat3::from_cols(east, north, up).transpose()
}

fn horizontal_from_enu(enu: DVec3) -> (Radians, Radians) {
    let horizontal = libm::hypot(enu.x, enu.y);
    let az = if horizontal == 0.0 {
        0.0
    } else {
        wrap_tau(libm::atan2(enu.x, enu.y))
    };
    (az, libm::atan2(enu.z, horizontal))
}

/// The exact reduction of catalogue stars at one instant. Build it once
/// per instant (it evaluates the Earth's position and velocity and the
/// precession–nutation matrix) and reduce any number of stars with it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StarReduction {
    epoch: Epoch,
    effects: StarEffects,
    earth_pos_au: DVec3,
    earth_vel_au_d: DVec3,
    icrs_to_date: DMat3,
}

impl StarReduction {
    /// Reduction at `epoch` with every effect ([`StarEffects::default`]).
    pub fn new(epoch: &Epoch) -> Self {
        Self::with_effects(epoch, StarEffects::default())
    }

    /// Reduction at `epoch` with the chosen effects.
    pub fn with_effects(epoch: &Epoch, effects: StarEffects) -> Self {
        let (earth_pos_au, earth_vel_au_d) = earth_state(epoch);
        StarReduction {
            epoch: *epoch,
            effects,
            earth_pos_au,
            earth_vel_au_d,
            icrs_to_date: epoch.icrf_to_true_of_date(),
        }
    }

    /// The instant's reduction quantities.
    pub fn epoch(&self) -> &Epoch {
        &self.epoch
    }

    /// The Earth's heliocentric (≈ barycentric) position, AU, ICRS axes.
    pub fn earth_position_au(&self) -> DVec3 {
        self.earth_pos_au
    }

    /// The Earth's barycentric velocity, AU/day, ICRS axes.
    pub fn earth_velocity_au_per_day(&self) -> DVec3 {
        self.earth_vel_au_d
    }

    /// Astrometric direction (ICRS) of `star` seen from an observer at
    /// barycentric position `obs_au`, after space motion (with the Rømer
    /// light-time term of Kaplan et al. 1989 eq. 4), parallax and deflection.
    fn astrometric(&self, star: &Astrometry, obs_au: DVec3) -> DVec3 {
        let (p0, v) = star.barycentric_state();
        let u0 = p0.normalize_or_zero();
        let romer_days = u0.dot(obs_au) / C_AU_PER_DAY;
        let dt = self.epoch.instant.jd_tt - star.epoch - romer_days;
        let mut p = p0 + v * dt;
        if self.effects.parallax {
            p -= obs_au;
        }
        let mut u = p.normalize_or_zero();
        if self.effects.deflection {
            let d = obs_au.length();
            u = deflect_by_sun(u, obs_au / d, d);
        }
        u
    }

    /// Apparent geocentric place of `star`: true equator and equinox of date,
    /// with the effects chosen at construction (Kaplan et al. 1989;
    /// Explanatory Supplement 1992 §3.2).
    pub fn apparent(&self, star: &Astrometry) -> StarApparent {
        let mut u = self.astrometric(star, self.earth_pos_au);
        if self.effects.aberration {
            u = frames::aberrate(u, self.earth_vel_au_d / C_AU_PER_DAY);
        }
        StarApparent::from_vector(self.icrs_to_date * u)
    }

    /// Topocentric place of `star` for `observer`: the apparent place with
    /// the observer's rotation velocity added to the aberration (diurnal
    /// aberration, ≤ 0.32″), then altitude and azimuth (unrefracted). The
    /// geocentric parallax of a star (≤ 6×10⁻³″) is neglected.
    pub fn topocentric(&self, star: &Astrometry, observer: &Observer) -> StarTopocentric {
        self.geocentric_and_topocentric(star, observer).1
    }

    /// Both the apparent geocentric place ([`StarReduction::apparent`]) and
    /// the topocentric place ([`StarReduction::topocentric`]) of `star`,
    /// sharing the space motion, parallax and deflection steps.
    pub fn geocentric_and_topocentric(
        &self,
        star: &Astrometry,
        observer: &Observer,
    ) -> (StarApparent, StarTopocentric) {
        let u = self.astrometric(star, self.earth_pos_au);
        let (geo, topo) = if self.effects.aberration {
            let v_rot_date = observer.velocity_km_s(&self.epoch) * (SECONDS_PER_DAY / KM_PER_AU);
            let v_rot_icrs = self.icrs_to_date.transpose() * v_rot_date;
            let beta = self.earth_vel_au_d / C_AU_PER_DAY;
            (
                frames::aberrate(u, beta),
                frames::aberrate(u, beta + v_rot_icrs / C_AU_PER_DAY),
            )
        } else {
            (u, u)
        };
        let (geo, topo) = (self.icrs_to_date * geo, self.icrs_to_date * topo);
        let lst = observer.local_sidereal_time(&self.epoch);
        let enu = equatorial_to_enu_matrix(lst, observer.lat()) * topo;
        let (az, alt) = horizontal_from_enu(enu);
        (
            StarApparent::from_vector(geo),
            StarTopocentric {
                place: StarApparent::from_vector(topo),
                alt,
                az,
            },
        )
    }
}

/// A star prepared for the fast path: its ICRS unit direction at a refresh
/// epoch and the rate of change of that direction, per day. Space motion is
/// linear in the barycentric frame, so `u + w·Δt` (normalised) reproduces
/// the exact space motion for stars without radial velocity; parallax and
/// deflection are left out.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FastStar {
    /// Unit direction at the refresh epoch, ICRS.
    pub u: DVec3,
    /// Rate of change of the (unnormalised) direction, 1/day, ICRS.
    pub w: DVec3,
}

impl FastStar {
    /// Prepares `star` for the fast path at `refresh_jd_tt`.
    pub fn new(star: &Astrometry, refresh_jd_tt: JulianDay) -> FastStar {
        let (p0, v) = star.barycentric_state();
        let p = p0 + v * (refresh_jd_tt - star.epoch);
        let d = p.length();
        if d > 0.0 && d.is_finite() {
            FastStar { u: p / d, w: v / d }
        } else {
            FastStar {
                u: DVec3::Z,
                w: DVec3::ZERO,
            }
        }
    }

    /// ICRS direction `dt_days` after the refresh epoch (unit vector).
    #[inline]
    pub fn direction(&self, dt_days: f64) -> DVec3 {
        (self.u + self.w * dt_days).normalize_or_zero()
    }
}

/// Everything the fast path needs for one frame: the ICRS → horizon (ENU)
/// rotation (frame bias, precession, nutation, sidereal time, latitude — the
/// seed thesis' eq. 4.19 with full precession and nutation), the observer's
/// velocity for aberration, and the time since the refresh epoch.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FrameRotation {
    /// ICRS → horizontal frame (x = East, y = North, z = Zenith).
    pub icrs_to_enu: DMat3,
    /// Observer velocity over c (annual + diurnal), ICRS axes.
    pub beta: DVec3,
    /// Days of TT since the stars' refresh epoch.
    pub dt_days: f64,
}

impl FrameRotation {
    /// The frame at `epoch` for `observer`, for stars refreshed at
    /// `refresh_jd_tt`.
    pub fn new(epoch: &Epoch, observer: &Observer, refresh_jd_tt: JulianDay) -> FrameRotation {
        let icrs_to_date = epoch.icrf_to_true_of_date();
        let lst = observer.local_sidereal_time(epoch);
        let v_rot_date = observer.velocity_km_s(epoch) * (SECONDS_PER_DAY / KM_PER_AU);
        let v = frames::earth_velocity_j2000(epoch.t) + icrs_to_date.transpose() * v_rot_date;
        FrameRotation {
            icrs_to_enu: equatorial_to_enu_matrix(lst, observer.lat()) * icrs_to_date,
            beta: v / C_AU_PER_DAY,
            dt_days: epoch.instant.jd_tt - refresh_jd_tt,
        }
    }

    /// Horizontal unit vector (East, North, Zenith) of a fast-path star:
    /// space motion, first-order aberration p + β − (p·β)p (second-order
    /// terms ≤ 1 mas), then the frame's rotation.
    #[inline]
    pub fn enu(&self, star: &FastStar) -> DVec3 {
        let p = star.direction(self.dt_days);
        let q = p + self.beta - p * p.dot(self.beta);
        self.icrs_to_enu * q.normalize_or_zero()
    }

    /// Altitude and azimuth (radians; azimuth from North through East in
    /// [0, 2π)) of a fast-path star.
    pub fn alt_az(&self, star: &FastStar) -> (Radians, Radians) {
        let (az, alt) = horizontal_from_enu(self.enu(star));
        (alt, az)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::frames::NutationModel;
    use crate::time::Instant;

    fn sirius() -> Astrometry {
        Astrometry::new(
            1.767_818_535_9,
            -0.291_699_374_8,
            -546.01,
            -1223.07,
            379.21,
            0.0,
            Astrometry::J1991_25,
        )
        .unwrap()
    }

    #[test]
    fn rejects_nan_and_out_of_range() {
        assert!(Astrometry::new(f64::NAN, 0.0, 0.0, 0.0, 1.0, 0.0, 2451545.0).is_err());
        assert!(Astrometry::new(0.0, 2.0, 0.0, 0.0, 1.0, 0.0, 2451545.0).is_err());
        assert!(Astrometry::new(0.0, 0.0, 0.0, f64::INFINITY, 1.0, 0.0, 2451545.0).is_err());
    }

    #[test]
    fn proper_motion_of_sirius_over_a_century() {
        // 100 years of μ = (−546.01, −1223.07) mas/yr moves Sirius by
        // |μ|·100 = 133.9″ (space motion with v_r = 0 is a straight line: the
        // angle differs from |μ|Δt by < 0.01″ over a century at 2.6 pc).
        let s = sirius();
        let a = s.direction_at(s.epoch);
        let b = s.direction_at(s.epoch + 100.0 * 365.25);
        let ang = libm::atan2(a.cross(b).length(), a.dot(b)) / ARCSEC;
        let mu = libm::hypot(546.01, 1223.07) / 10.0;
        assert!((ang - mu).abs() < 0.01, "{ang} {mu}");
    }

    #[test]
    fn enu_matrix_matches_meeus_horizontal() {
        for (lst, lat, ra, dec) in [
            (1.0, 0.7, 2.0, -0.3),
            (5.0, -1.5706, 0.1, 1.2),
            (3.0, 0.0, 3.0, 0.0),
        ] {
            let v = frames::equatorial_to_vector(ra, dec);
            let (az, alt) = horizontal_from_enu(equatorial_to_enu_matrix(lst, lat) * v);
            let (az2, alt2) = frames::equatorial_to_horizontal(wrap_tau(lst - ra), dec, lat);
            assert!((alt - alt2).abs() < 1e-12 && wrap_pi(az - az2).abs() < 1e-9);
        }
    }

    #[test]
    fn deflection_at_limb_and_at_ninety_degrees() {
        let e = DVec3::X;
        // Star 90° from the Sun: 2GM/(c² AU) = 4.07 mas.
        let p = DVec3::Y;
        let q = deflect_by_sun(p, e, 1.0);
        let ang = libm::atan2(p.cross(q).length(), p.dot(q)) / ARCSEC;
        assert!((ang - 0.00407).abs() < 0.00005, "{ang}");
        // At the solar limb (959.6″ from the centre) 1.75″.
        let r = 959.6 * ARCSEC;
        let p = DVec3::new(-libm::cos(r), libm::sin(r), 0.0);
        let q = deflect_by_sun(p, e, 1.0);
        let ang = libm::atan2(p.cross(q).length(), p.dot(q)) / ARCSEC;
        assert!((ang - 1.75).abs() < 0.01, "{ang}");
        assert!(deflect_by_sun(-e, e, 1.0).is_finite());
    }

    #[test]
    fn annual_parallax_of_alpha_centauri_is_bounded_by_its_parallax() {
        // α Cen A, Hipparcos new reduction (HIP 71683).
        let s = Astrometry::new(
            3.838_335_214_2,
            -1.061_773_585_0,
            -3679.25,
            473.67,
            754.81,
            0.0,
            Astrometry::J1991_25,
        )
        .unwrap();
        let mut worst: f64 = 0.0;
        for k in 0..24 {
            let e = Epoch::new(
                &Instant::from_tt(2_451_545.0 + 15.25 * k as f64),
                NutationModel::Iau1980,
            );
            let with = StarReduction::new(&e).apparent(&s).vector;
            let without = StarReduction::with_effects(
                &e,
                StarEffects {
                    parallax: false,
                    ..StarEffects::default()
                },
            )
            .apparent(&s)
            .vector;
            worst = worst.max(libm::atan2(with.cross(without).length(), with.dot(without)));
        }
        let worst = worst / ARCSEC;
        assert!(worst < 0.7548 * 1.02 && worst > 0.6, "{worst}");
    }

    #[test]
    fn finite_ten_centuries_away_and_consistent() {
        let s = sirius();
        let obs = Observer::new(-89.9, -179.9, 0.0).unwrap();
        for jd in [J2000 - 365_250.0, J2000 + 365_250.0, 2_460_000.5] {
            let e = Epoch::new(&Instant::from_tt(jd), NutationModel::Iau1980);
            let red = StarReduction::new(&e);
            let (geo, topo) = red.geocentric_and_topocentric(&s, &obs);
            assert!(geo.vector.is_finite() && topo.alt.is_finite() && topo.az.is_finite());
            assert_eq!(geo, red.apparent(&s));
            assert_eq!(topo, red.topocentric(&s, &obs));
            // Diurnal aberration separates them by at most 0.32″.
            let d = libm::atan2(
                geo.vector.cross(topo.place.vector).length(),
                geo.vector.dot(topo.place.vector),
            );
            assert!(d / ARCSEC < 0.33);
        }
    }

    #[test]
    fn at_the_poles_altitude_is_declination() {
        // At geodetic latitude ±90° the horizon is the equator: alt = ±δ of
        // date (no diurnal aberration there), and everything stays finite.
        let s = sirius();
        let e = Epoch::new(&Instant::from_tt(2_460_000.5), NutationModel::Iau1980);
        let red = StarReduction::new(&e);
        let dec = red.apparent(&s).dec;
        for lat in [90.0, -90.0] {
            let t = red.topocentric(&s, &Observer::new(lat, 123.0, 0.0).unwrap());
            let want = if lat > 0.0 { dec } else { -dec };
            assert!((t.alt - want).abs() < 1e-3 * ARCSEC, "{lat}");
            assert!(t.az.is_finite() && t.alt_refracted_deg().is_finite());
        }
        // A star at the zenith of a −89.9° observer (a celestial-pole star).
        let pole = Astrometry::new(0.0, -TAU / 4.0, 0.0, 0.0, 0.0, 0.0, J2000).unwrap();
        let t = red.topocentric(&pole, &Observer::new(-89.9, 0.0, 0.0).unwrap());
        assert!(t.alt.is_finite() && t.az.is_finite() && t.alt_deg() > 89.5);
    }

    #[test]
    fn fast_path_tracks_exact_path() {
        let s = sirius();
        let obs = Observer::new(-89.9, 10.0, 0.0).unwrap();
        let refresh = 2_451_545.0;
        let fs = FastStar::new(&s, refresh);
        for years in [-50.0, -10.0, 0.0, 0.3, 20.0, 50.0] {
            let e = Epoch::new(
                &Instant::from_tt(refresh + years * 365.25),
                NutationModel::Iau1980,
            );
            let exact = StarReduction::new(&e).topocentric(&s, &obs).enu();
            let fast = FrameRotation::new(&e, &obs, refresh).enu(&fs);
            let err = libm::atan2(exact.cross(fast).length(), exact.dot(fast)) / ARCSEC;
            // Sirius' parallax (0.38″) is the bulk of the difference.
            assert!(err < 0.5, "{years}: {err}″");
        }
    }
}
