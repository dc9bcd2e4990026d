//! Physical ephemeris of the Moon: phase, illumination, bright limb, the
//! librations and the position angle of the axis (Meeus, *Astronomical
//! Algorithms* 2nd ed., chapters 48 and 53).

use super::series::{mean_ascending_node, Arguments};
use crate::units::{safe_asin, wrap_pi, wrap_tau, JulianCenturies, Km, Radians, DEG};
use glam::DVec3;
use libm::{atan2, cos, sin, tan};

/// Apparent geocentric places of the Moon and the Sun at one instant, the
/// inputs of [`physical`]. Ecliptic coordinates refer to the true ecliptic
/// and equinox of date, equatorial ones to the true equator and equinox of
/// date; "apparent" means with light time, aberration and nutation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MoonSunApparent {
    /// Apparent ecliptic longitude of the Moon λ, radians.
    pub moon_lon: Radians,
    /// Apparent ecliptic latitude of the Moon β, radians.
    pub moon_lat: Radians,
    /// Apparent right ascension of the Moon α, radians.
    pub moon_ra: Radians,
    /// Apparent declination of the Moon δ, radians.
    pub moon_dec: Radians,
    /// Earth–Moon distance between centres Δ, km.
    pub moon_distance_km: Km,
    /// Apparent ecliptic longitude of the Sun λ0, radians.
    pub sun_lon: Radians,
    /// Apparent ecliptic latitude of the Sun β0, radians.
    pub sun_lat: Radians,
    /// Apparent right ascension of the Sun α0, radians.
    pub sun_ra: Radians,
    /// Apparent declination of the Sun δ0, radians.
    pub sun_dec: Radians,
    /// Earth–Sun distance R, km.
    pub sun_distance_km: Km,
    /// Nutation in longitude Δψ, radians.
    pub dpsi: Radians,
    /// True obliquity of the ecliptic ε = ε0 + Δε, radians.
    pub true_obliquity: Radians,
    /// Julian centuries TT from J2000.0 of the instant.
    pub t: JulianCenturies,
}

/// The Moon's physical ephemeris seen from the centre of the Earth.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MoonPhysical {
    /// Phase angle i, the Sun–Moon–Earth angle at the Moon, radians in
    /// [0, π] (Meeus eqs. 48.2/48.3 in exact vector form).
    pub phase_angle: Radians,
    /// Illuminated fraction of the disk k = (1 + cos i)/2 (Meeus eq. 48.1).
    pub illuminated_fraction: f64,
    /// Geocentric elongation of the Moon from the Sun ψ, radians in [0, π].
    pub elongation: Radians,
    /// Position angle of the midpoint of the bright limb χ, from celestial
    /// North through East, radians in [0, 2π) (Meeus eq. 48.5).
    pub bright_limb_pa: Radians,
    /// Total geocentric libration in longitude l = l′ + l″, radians in
    /// [−π, π) (Meeus ch. 53): the selenographic longitude of the
    /// sub-Earth point; positive when the east limb (Mare Crisium side) is
    /// turned towards the Earth.
    pub libration_lon: Radians,
    /// Total geocentric libration in latitude b = b′ + b″, radians (Meeus
    /// ch. 53); the selenographic latitude of the sub-Earth point.
    pub libration_lat: Radians,
    /// Position angle of the Moon's axis of rotation P (its north pole),
    /// from celestial North through East, radians in [0, 2π) (Meeus ch. 53).
    pub axis_pa: Radians,
}

/// Inclination of the mean lunar equator to the ecliptic, I = 1°32′32.7″
/// (Meeus ch. 53, the IAU value).
const LUNAR_EQUATOR_INCLINATION: Radians = (1.0 + 32.0 / 60.0 + 32.7 / 3600.0) * DEG;

/// Unit vector towards right ascension `ra`, declination `dec`.
#[inline]
fn unit(ra: Radians, dec: Radians) -> DVec3 {
    let (sd, cd) = libm::sincos(dec);
    let (sa, ca) = libm::sincos(ra);
    DVec3::new(cd * ca, cd * sa, sd)
}

/// Position angle (North through East, [0, 2π)) of direction `target`
/// at the place `at` (unit vector towards α, δ) on the celestial sphere.
#[inline]
fn position_angle(ra: Radians, dec: Radians, target: DVec3) -> Radians {
    let (sd, cd) = libm::sincos(dec);
    let (sa, ca) = libm::sincos(ra);
    let east = DVec3::new(-sa, ca, 0.0);
    let north = DVec3::new(-sd * ca, -sd * sa, cd);
    wrap_tau(atan2(target.dot(east), target.dot(north)))
}

/// The librations split into their parts (Meeus ch. 53), all radians, and
/// the quantities the axis position angle needs.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Librations {
    /// Optical libration in longitude l′.
    pub optical_lon: Radians,
    /// Optical libration in latitude b′.
    pub optical_lat: Radians,
    /// Physical libration in longitude l″.
    pub physical_lon: Radians,
    /// Physical libration in latitude b″.
    pub physical_lat: Radians,
    /// ρ, the physical libration in inclination, radians.
    rho: Radians,
    /// σ, the physical libration in node, radians.
    sigma: Radians,
    /// Ω, mean ascending node of the lunar orbit, radians.
    node: Radians,
}

/// Meeus ch. 53: optical librations from the apparent place, physical
/// librations from the series in ρ, σ, τ (coefficients in degrees, Meeus
/// p. 373, after D. H. Eckhardt's theory of the lunar rotation).
pub(crate) fn librations(a: &MoonSunApparent) -> Librations {
    let t = a.t;
    let arg = Arguments::at(t);
    let node = mean_ascending_node(t);
    let (si, ci) = libm::sincos(LUNAR_EQUATOR_INCLINATION);

    // Optical librations: the Moon's position referred to the mean lunar
    // equator. W uses the longitude of the mean equinox, λ − Δψ.
    let w = a.moon_lon - a.dpsi - node;
    let (sw, cw) = libm::sincos(w);
    let (sb, cb) = libm::sincos(a.moon_lat);
    let big_a = atan2(sw * cb * ci - sb * si, cw * cb);
    let optical_lon = wrap_pi(big_a - arg.f);
    let optical_lat = safe_asin(-sw * cb * si - sb * ci);

    // Physical librations, degrees.
    let (d, m, mp, f, e) = (arg.d, arg.m, arg.m_prime, arg.f, arg.e);
    let k1 = (119.75 + 131.849 * t) * DEG;
    let k2 = (72.56 + 20.186 * t) * DEG;
    let rho = -0.027_52 * cos(mp) - 0.022_45 * sin(f) + 0.006_84 * cos(mp - 2.0 * f)
        - 0.002_93 * cos(2.0 * f)
        - 0.000_85 * cos(2.0 * f - 2.0 * d)
        - 0.000_54 * cos(mp - 2.0 * d)
        - 0.000_20 * sin(mp + f)
        - 0.000_20 * cos(mp + 2.0 * f)
        - 0.000_20 * cos(mp - f)
        + 0.000_14 * cos(mp + 2.0 * f - 2.0 * d);
    let sigma = -0.028_16 * sin(mp) + 0.022_44 * cos(f)
        - 0.006_82 * sin(mp - 2.0 * f)
        - 0.002_79 * sin(2.0 * f)
        - 0.000_83 * sin(2.0 * f - 2.0 * d)
        + 0.000_69 * sin(mp - 2.0 * d)
        + 0.000_40 * cos(mp + f)
        - 0.000_25 * sin(2.0 * mp)
        - 0.000_23 * sin(mp + 2.0 * f)
        + 0.000_20 * cos(mp - f)
        + 0.000_19 * sin(mp - f)
        + 0.000_13 * sin(mp + 2.0 * f - 2.0 * d)
        - 0.000_10 * cos(mp - 3.0 * f);
    let tau = 0.025_20 * e * sin(m) + 0.004_73 * sin(2.0 * mp - 2.0 * f) - 0.004_67 * sin(mp)
        + 0.003_96 * sin(k1)
        + 0.002_76 * sin(2.0 * mp - 2.0 * d)
        + 0.001_96 * sin(node)
        - 0.001_83 * cos(mp - f)
        + 0.001_15 * sin(mp - 2.0 * d)
        - 0.000_96 * sin(mp - d)
        + 0.000_46 * sin(2.0 * f - 2.0 * d)
        - 0.000_39 * sin(mp - f)
        - 0.000_32 * sin(mp - m - d)
        + 0.000_27 * sin(2.0 * mp - m - 2.0 * d)
        + 0.000_23 * sin(k2)
        - 0.000_14 * sin(2.0 * d)
        + 0.000_14 * cos(2.0 * mp - 2.0 * f)
        - 0.000_12 * sin(mp - 2.0 * f)
        - 0.000_12 * sin(2.0 * mp)
        + 0.000_11 * sin(2.0 * mp - 2.0 * m - 2.0 * d);
    let (sa, ca) = libm::sincos(big_a);
    let physical_lon = (-tau + (rho * ca + sigma * sa) * tan(optical_lat)) * DEG;
    let physical_lat = (sigma * ca - rho * sa) * DEG;

    Librations {
        optical_lon,
        optical_lat,
        physical_lon,
        physical_lat,
        rho: rho * DEG,
        sigma: sigma * DEG,
        node,
    }
}

/// Phase, illumination, bright limb, librations and axis of the Moon as seen
/// from the centre of the Earth.
///
/// Input: apparent places of date of the Moon and the Sun ([`MoonSunApparent`]).
/// Phase angle and elongation: Meeus eqs. 48.2–48.3 written with vectors,
/// i = ∠(Moon→Sun, Moon→Earth), ψ = ∠(Earth→Sun, Earth→Moon), both by
/// atan2(|a×b|, a·b) so they stay exact and finite at new and full Moon.
/// Bright limb: Meeus eq. 48.5. Librations and position angle of the axis:
/// Meeus ch. 53 (optical + physical, geocentric); P is computed as the
/// position angle at the Moon of the lunar pole vector (the X, Y of Meeus
/// with its third component), which is Meeus' sin P formula without the
/// division by cos b and the arcsine's quadrant ambiguity.
/// All position angles are from celestial North through East in the true
/// equator of date; results are finite at the celestial poles.
pub fn physical(a: &MoonSunApparent) -> MoonPhysical {
    let moon_dir = unit(a.moon_ra, a.moon_dec);
    let sun_dir = unit(a.sun_ra, a.sun_dec);
    let moon = moon_dir * a.moon_distance_km;
    let sun = sun_dir * a.sun_distance_km;

    let elongation = atan2(sun_dir.cross(moon_dir).length(), sun_dir.dot(moon_dir));
    // Vectors at the Moon: towards the Sun (sun − moon) and the Earth (−moon);
    // |(sun − moon) × (−moon)| = |sun × moon|.
    let phase_angle = atan2(
        sun.cross(moon).length(),
        moon.length_squared() - sun.dot(moon),
    );
    let illuminated_fraction = 0.5 * (1.0 + cos(phase_angle));
    let bright_limb_pa = position_angle(a.moon_ra, a.moon_dec, sun_dir);

    let lib = librations(a);
    let libration_lon = wrap_pi(lib.optical_lon + lib.physical_lon);
    let libration_lat = lib.optical_lat + lib.physical_lat;

    // The lunar north pole in the true equator of date: Meeus' V, X, Y, with
    // X taken with the sign of the equatorial x axis and Z completing it.
    let v = lib.node + a.dpsi + lib.sigma / sin(LUNAR_EQUATOR_INCLINATION);
    let (s_ir, c_ir) = libm::sincos(LUNAR_EQUATOR_INCLINATION + lib.rho);
    let (sv, cv) = libm::sincos(v);
    let (se, ce) = libm::sincos(a.true_obliquity);
    let pole = DVec3::new(
        -s_ir * sv,
        s_ir * cv * ce - c_ir * se,
        s_ir * cv * se + c_ir * ce,
    );
    let axis_pa = position_angle(a.moon_ra, a.moon_dec, pole);

    MoonPhysical {
        phase_angle,
        illuminated_fraction,
        elongation,
        bright_limb_pa,
        libration_lon,
        libration_lat,
        axis_pa,
    }
}
