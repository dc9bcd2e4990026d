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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::units::{J2000, TAU};
    use std::vec::Vec;

    /// Ecliptic (λ, β) of date from (α, δ) and the obliquity (Meeus eqs.
    /// 13.1, 13.2), to fill the Sun's ecliptic place of the Meeus examples.
    fn ecliptic(ra: f64, dec: f64, eps: f64) -> (f64, f64) {
        let lon = libm::atan2(ra.sin() * eps.cos() + dec.tan() * eps.sin(), ra.cos());
        let lat = safe_asin(dec.sin() * eps.cos() - dec.cos() * eps.sin() * ra.sin());
        (wrap_tau(lon), lat)
    }

    /// Meeus Examples 48.a and 53.a: the Moon on 1992 April 12, 0h TD.
    fn example_1992_april_12() -> MoonSunApparent {
        let eps = 23.440_636 * DEG;
        let (sun_ra, sun_dec) = (20.6579 * DEG, 8.6964 * DEG);
        let (sun_lon, sun_lat) = ecliptic(sun_ra, sun_dec, eps);
        MoonSunApparent {
            moon_lon: 133.167_265 * DEG,
            moon_lat: -3.229_126 * DEG,
            moon_ra: 134.688_470 * DEG,
            moon_dec: 13.768_368 * DEG,
            moon_distance_km: 368_409.7,
            sun_lon,
            sun_lat,
            sun_ra,
            sun_dec,
            sun_distance_km: 149_971_520.0,
            dpsi: 0.004_610 * DEG,
            true_obliquity: eps,
            t: (2_448_724.5 - J2000) / 36_525.0,
        }
    }

    #[test]
    fn meeus_example_48a() {
        let p = physical(&example_1992_april_12());
        // Meeus: ψ = 110.7929°, i = 69.0756°, k = 0.6786, χ = 285.0°.
        assert!(
            (p.elongation / DEG - 110.7929).abs() < 2e-4,
            "{}",
            p.elongation / DEG
        );
        assert!(
            (p.phase_angle / DEG - 69.0756).abs() < 2e-4,
            "{}",
            p.phase_angle / DEG
        );
        assert!((p.illuminated_fraction - 0.6786).abs() < 5e-5);
        assert!(
            (p.bright_limb_pa / DEG - 285.0).abs() < 0.05,
            "{}",
            p.bright_limb_pa / DEG
        );
    }

    #[test]
    fn meeus_example_53a() {
        let a = example_1992_april_12();
        let lib = librations(&a);
        // Meeus: l′ = −1.206°, b′ = +4.194°, l″ = −0.025°, b″ = +0.006°.
        assert!(
            (lib.optical_lon / DEG - -1.206).abs() < 5e-4,
            "{}",
            lib.optical_lon / DEG
        );
        assert!(
            (lib.optical_lat / DEG - 4.194).abs() < 5e-4,
            "{}",
            lib.optical_lat / DEG
        );
        assert!(
            (lib.physical_lon / DEG - -0.025).abs() < 5e-4,
            "{}",
            lib.physical_lon / DEG
        );
        assert!(
            (lib.physical_lat / DEG - 0.006).abs() < 5e-4,
            "{}",
            lib.physical_lat / DEG
        );
        // Meeus: l = −1.23°, b = +4.20°, P = 15.08°.
        let p = physical(&a);
        assert!((p.libration_lon / DEG - -1.23).abs() < 5e-3);
        assert!((p.libration_lat / DEG - 4.20).abs() < 5e-3);
        assert!(
            (p.axis_pa / DEG - 15.08).abs() < 5e-3,
            "{}",
            p.axis_pa / DEG
        );
    }

    /// Against Astronomy Engine 2.1.19 (`Libration`: Meeus ch. 53 optical +
    /// physical librations from its own lunar theory; `Illumination`: phase
    /// angle and fraction from its own Sun and Moon), with our inputs from
    /// Skyfield + DE421 — both written by tools/gen_moon_check.py into
    /// astro/data/moon_libration_check.json (20 instants 1900–2050).
    #[test]
    fn against_astronomy_engine() {
        let rows = super::super::de421::tests::fixture_rows(include_str!(
            "../../data/moon_libration_check.json"
        ));
        assert_eq!(rows.len(), 20);
        let (mut dl, mut db, mut di, mut dk): (Vec<f64>, Vec<f64>, Vec<f64>, Vec<f64>) =
            Default::default();
        for r in &rows {
            let a = MoonSunApparent {
                moon_lon: r[1],
                moon_lat: r[2],
                moon_ra: r[3],
                moon_dec: r[4],
                moon_distance_km: r[5],
                sun_lon: r[6],
                sun_lat: r[7],
                sun_ra: r[8],
                sun_dec: r[9],
                sun_distance_km: r[10],
                dpsi: r[11],
                true_obliquity: r[12],
                t: r[13],
            };
            let p = physical(&a);
            // Geocentric librations never exceed about 8° in l and 7° in b.
            assert!(p.libration_lon.abs() < 9.0 * DEG && p.libration_lat.abs() < 8.0 * DEG);
            dl.push(wrap_pi(p.libration_lon - r[14] * DEG).abs() / DEG);
            db.push((p.libration_lat - r[15] * DEG).abs() / DEG);
            di.push((p.phase_angle / DEG - r[16]).abs());
            dk.push((p.illuminated_fraction - r[17]).abs());
        }
        let max = |v: &Vec<f64>| v.iter().cloned().fold(0.0, f64::max);
        std::println!(
            "vs Astronomy Engine: max |Δl| {:.4}°, |Δb| {:.4}°, |Δi| {:.4}°, |Δk| {:.5}",
            max(&dl),
            max(&db),
            max(&di),
            max(&dk)
        );
        assert!(max(&dl) < 0.003 && max(&db) < 0.003);
        assert!(max(&di) < 0.02 && max(&dk) < 2e-4);
    }

    fn with_places(moon_ra: f64, moon_dec: f64, sun_ra: f64, sun_dec: f64) -> MoonSunApparent {
        let eps = 23.44 * DEG;
        let (moon_lon, moon_lat) = ecliptic(moon_ra, moon_dec, eps);
        let (sun_lon, sun_lat) = ecliptic(sun_ra, sun_dec, eps);
        MoonSunApparent {
            moon_lon,
            moon_lat,
            moon_ra,
            moon_dec,
            moon_distance_km: 384_400.0,
            sun_lon,
            sun_lat,
            sun_ra,
            sun_dec,
            sun_distance_km: 1.496e8,
            dpsi: 0.0,
            true_obliquity: eps,
            t: 0.1,
        }
    }

    fn assert_sane(p: &MoonPhysical) {
        for v in [
            p.phase_angle,
            p.illuminated_fraction,
            p.elongation,
            p.bright_limb_pa,
            p.libration_lon,
            p.libration_lat,
            p.axis_pa,
        ] {
            assert!(v.is_finite(), "{p:?}");
        }
        assert!((0.0..=core::f64::consts::PI).contains(&p.phase_angle));
        assert!((0.0..=core::f64::consts::PI).contains(&p.elongation));
        assert!((0.0..=1.0).contains(&p.illuminated_fraction));
        assert!((0.0..TAU).contains(&p.bright_limb_pa));
        assert!((0.0..TAU).contains(&p.axis_pa));
        assert!((-core::f64::consts::PI..core::f64::consts::PI).contains(&p.libration_lon));
        assert!(p.libration_lat.abs() < 1.6);
    }

    /// New and full Moon exactly (Sun and Moon collinear with the Earth):
    /// i = 180° / 0°, k = 0 / 1, everything finite.
    #[test]
    fn new_and_full_moon_are_finite() {
        let (ra, dec) = (1.0, 0.3);
        let new = physical(&with_places(ra, dec, ra, dec));
        assert_sane(&new);
        assert!((new.phase_angle - core::f64::consts::PI).abs() < 1e-12);
        assert!(new.illuminated_fraction < 1e-12 && new.elongation < 1e-12);
        let full = physical(&with_places(ra, dec, ra + core::f64::consts::PI, -dec));
        assert_sane(&full);
        assert!(full.phase_angle < 1e-7 && full.illuminated_fraction > 1.0 - 1e-12);
    }

    /// The Moon at a celestial pole (outside its real range, but the
    /// formulas must not break there) and near it.
    #[test]
    fn moon_at_the_celestial_poles_is_finite() {
        for dec in [90.0, -90.0, 89.999_999, -89.999_999] {
            for ra in [0.0, 1.0, 4.0] {
                assert_sane(&physical(&with_places(ra, dec * DEG, 0.5, 0.2)));
            }
        }
    }

    /// χ is the position angle of the Sun seen from the Moon: a Sun due
    /// east of the Moon on the equator gives 90°, due west 270°.
    #[test]
    fn bright_limb_points_to_the_sun() {
        let east = physical(&with_places(1.0, 0.0, 1.5, 0.0));
        assert!((east.bright_limb_pa - 90.0 * DEG).abs() < 1e-12);
        let west = physical(&with_places(1.0, 0.0, 0.5, 0.0));
        assert!((west.bright_limb_pa - 270.0 * DEG).abs() < 1e-12);
    }
}
