//! Atmospheric refraction of ENU directions, in one place: a direction's
//! altitude raised (true → apparent, Meeus eq. 16.4, Saemundsson) or
//! lowered (apparent → true, Meeus eq. 16.3, Bennett) by the standard
//! refraction at 1010 hPa and 10 °C, its azimuth kept. The formulas, their
//! validity below the horizon and the fade that keeps them monotonic are
//! `himmel_astro::frames::refraction`'s; the stars and planets are lifted
//! with [`refracted`], the Milky Way map and a low Moon's disk looked up in
//! the airless frame with [`unrefracted`].

use glam::{DVec3, Vec3};
use himmel_astro::frames::{
    refraction_apparent_to_true, refraction_true_to_apparent, STANDARD_PRESSURE_HPA,
    STANDARD_TEMPERATURE_C,
};

/// The refraction (rad) that [`unrefracted`] takes off the apparent
/// altitude `alt` (rad): Bennett's formula (Meeus eq. 16.3) at the
/// standard 1010 hPa and 10 °C.
#[inline]
pub fn refraction_of_apparent(alt: f32) -> f32 {
    refraction_apparent_to_true(alt as f64, STANDARD_PRESSURE_HPA, STANDARD_TEMPERATURE_C) as f32
}

/// Raises the altitude of the true (airless) ENU direction `enu` by the
/// standard refraction (Meeus eq. 16.4), keeping the azimuth.
pub fn refracted(enu: DVec3) -> DVec3 {
    let horizontal = enu.x.hypot(enu.y);
    let alt = enu.z.atan2(horizontal);
    let r = refraction_true_to_apparent(alt, STANDARD_PRESSURE_HPA, STANDARD_TEMPERATURE_C);
    if horizontal < 1e-12 {
        return enu;
    }
    let (s, c) = (alt + r).sin_cos();
    DVec3::new(enu.x / horizontal * c, enu.y / horizontal * c, s)
}

/// The true (airless) direction of the apparent ENU direction `d` (unit):
/// its altitude lowered by the standard refraction (Meeus eq. 16.3),
/// keeping the azimuth. In f32 with the altitude from asin z, as the WGSL
/// Moon pass evaluates it (a low Moon and the Milky Way near the horizon
/// use it; both are below 15° of altitude, where asin is well conditioned).
#[inline]
pub fn unrefracted(d: Vec3) -> Vec3 {
    let horizontal = (d.x * d.x + d.y * d.y).sqrt();
    if horizontal < 1e-9 {
        return d;
    }
    let alt = d.z.clamp(-1.0, 1.0).asin();
    let (s, c) = (alt - refraction_of_apparent(alt)).sin_cos();
    Vec3::new(d.x / horizontal * c, d.y / horizontal * c, s)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The two directions invert each other within the formulas' mutual
    /// consistency (≈ 4″ near the horizon, Meeus ch. 16), keep the
    /// azimuth, and leave the zenith alone.
    #[test]
    fn refraction_round_trip_azimuth_and_zenith() {
        for alt_deg in [-0.5f64, 0.0, 0.5, 2.0, 10.0, 45.0, 89.0] {
            let az = 1.2f64;
            let a = alt_deg.to_radians();
            let d = DVec3::new(a.cos() * az.sin(), a.cos() * az.cos(), a.sin());
            let up = refracted(d);
            assert!(up.z > d.z, "{alt_deg}");
            assert!((up.x.atan2(up.y) - az).abs() < 1e-12, "{alt_deg}");
            let back = unrefracted(up.as_vec3()).as_dvec3();
            let err = (back.z.asin() - a).abs().to_degrees() * 3600.0;
            assert!(err < 6.0, "{alt_deg}°: {err}″");
        }
        assert_eq!(refracted(DVec3::Z), DVec3::Z);
        assert_eq!(unrefracted(Vec3::Z), Vec3::Z);
        // Bennett at the horizon: 34.5′ (Meeus eq. 16.3 at h = 0).
        let r = refraction_of_apparent(0.0).to_degrees() * 60.0;
        assert!((r - 34.5).abs() < 0.5, "{r}′");
    }
}
