//! Reference frames: obliquity, nutation, precession, frame bias,
//! aberration, coordinate rotations, the observer's geocentric position and
//! atmospheric refraction.
//!
//! Vectors are `glam::DVec3`, rotation matrices `glam::DMat3` acting on
//! column vectors (`m * v`). Chain for an apparent place of date:
//! `v_true = N · P · B · v_icrs` ([`nutation_matrix`], [`precession_matrix`],
//! [`frame_bias_matrix`]).

mod aberration;
mod coords;
mod geodesy;
mod nutation;
mod obliquity;
mod precession;
mod refraction;
mod rotation;

pub use aberration::{aberrate, earth_velocity_j2000};
pub use coords::{
    ecliptic_to_equatorial, ecliptic_to_equatorial_matrix, equatorial_to_ecliptic,
    equatorial_to_horizontal, equatorial_to_vector, nutation_matrix, parallactic_angle,
    spherical_to_vector, vector_to_equatorial, vector_to_spherical,
};
pub use geodesy::geocentric_observer;
pub(crate) use nutation::nutation_short_from;
pub use nutation::{fundamental_arguments, nutation, Nutation, NutationModel};
pub use obliquity::mean_obliquity;
pub use precession::{frame_bias_matrix, precession_angles, precession_matrix};
pub use refraction::{
    refraction_apparent_to_true, refraction_true_to_apparent, REFRACTION_FADE_DEG,
    REFRACTION_FLOOR_DEG, STANDARD_PRESSURE_HPA, STANDARD_TEMPERATURE_C,
};

#[cfg(test)]
mod tests {
    use super::*;
    use crate::units::{wrap_pi, ARCSEC, DEG, LIGHT_DAYS_PER_AU};

    /// Full IAU 1980 (106 terms) from SOFA/ERFA eraNut80 at MJD (TT), radians
    /// (tools/gen_frames_refs.py). Meeus' 63 terms drop those below 0.0003″.
    const ERFA_NUT80: [(f64, f64, f64); 7] = [
        (15020.0, 8.448621256378296e-05, -1.1113048496350755e-05),
        (33282.0, -1.602570541676662e-05, 4.031770174572835e-05),
        (44000.0, -2.8167270914050514e-05, -4.31307472596577e-05),
        (51544.5, -6.750247617532478e-05, -2.7992212383770132e-05),
        (55000.0, 6.774639582326654e-05, 2.1500325141890267e-05),
        (60000.0, -4.4966020298924694e-05, 3.7506080807780494e-05),
        (69807.0, 7.353045085093935e-05, -2.5849577175475714e-05),
    ];

    #[test]
    fn nutation_matches_sofa_full_series() {
        let mut worst: f64 = 0.0;
        for (mjd, dpsi, deps) in ERFA_NUT80 {
            let t = (mjd + 2_400_000.5 - 2_451_545.0) / 36_525.0;
            let n = nutation(t, NutationModel::Iau1980);
            worst = worst.max((n.dpsi - dpsi).abs()).max((n.deps - deps).abs());
        }
        assert!(worst < 0.003 * ARCSEC, "{}″", worst / ARCSEC);
    }

    #[test]
    fn meeus_example_23a_apparent_place_of_theta_persei() {
        // θ Persei, 2028 Nov 13.19 TD: Meeus' apparent place (Example 23.a)
        // α = 2h46m14.390s, δ = +49°21′07.45″, from the J2000 mean place with
        // proper motion (Example 21.b): α = 41.054063°, δ = 49.227750°.
        // Meeus uses the low-accuracy aberration formula 23.3 and the 63-term
        // nutation; the Ron–Vondrák velocity here differs by a few mas.
        let t = (2_462_088.69 - 2_451_545.0) / 36_525.0;
        let v0 = equatorial_to_vector(41.054_063 * DEG, 49.227_750 * DEG);
        let beta = earth_velocity_j2000(t) * LIGHT_DAYS_PER_AU;
        let n = nutation(t, NutationModel::Iau1980);
        let m = nutation_matrix(mean_obliquity(t), &n) * precession_matrix(t);
        let (ra, dec) = vector_to_equatorial(m * aberrate(v0, beta));
        let ra_expected = (2.0 + 46.0 / 60.0 + 14.390 / 3600.0) * 15.0 * DEG;
        let dec_expected = (49.0 + 21.0 / 60.0 + 7.45 / 3600.0) * DEG;
        assert!(
            wrap_pi(ra - ra_expected).abs() < 0.1 * ARCSEC,
            "{}″",
            wrap_pi(ra - ra_expected) / ARCSEC
        );
        assert!(
            (dec - dec_expected).abs() < 0.1 * ARCSEC,
            "{}″",
            (dec - dec_expected) / ARCSEC
        );
    }

    #[test]
    fn everything_finite_ten_centuries_away() {
        for t in [-10.0, -5.0, 5.0, 10.0] {
            let n = nutation(t, NutationModel::Iau1980);
            let eps = mean_obliquity(t);
            assert!(n.dpsi.is_finite() && n.deps.is_finite() && eps.is_finite());
            assert!(n.dpsi.abs() < 25.0 * ARCSEC && n.deps.abs() < 15.0 * ARCSEC);
            assert!((eps / DEG - 23.44).abs() < 0.5);
            let m = nutation_matrix(eps, &n) * precession_matrix(t) * frame_bias_matrix();
            assert!(m.is_finite());
            let v = earth_velocity_j2000(t);
            assert!(v.is_finite() && (v.length() - 0.0172).abs() < 0.0005, "{t}");
        }
    }
}
