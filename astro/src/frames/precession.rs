//! Precession (IAU 1976) and the ICRS frame bias.

use glam::DMat3;

use super::rotation::{rot_x, rot_y, rot_z};
use crate::units::{JulianCenturies, ARCSEC};

/// Equatorial precession angles ζ, z, θ (radians) from J2000.0 to `t`
/// Julian centuries of TT after it.
///
/// Source: Lieske et al. (1977), IAU 1976, as in Meeus, *Astronomical
/// Algorithms* 2nd ed., eq. 21.3 (starting epoch J2000.0, so T = 0 there).
pub fn precession_angles(t: JulianCenturies) -> (f64, f64, f64) {
    let zeta = t * (2306.2181 + t * (0.30188 + t * 0.017_998));
    let z = t * (2306.2181 + t * (1.094_68 + t * 0.018_203));
    let theta = t * (2004.3109 + t * (-0.426_65 - t * 0.041_833));
    (zeta * ARCSEC, z * ARCSEC, theta * ARCSEC)
}

/// Precession matrix P: multiplies a vector referred to the mean equator and
/// equinox of J2000.0 to give it referred to the mean equator and equinox of
/// the date `t` (Julian centuries of TT from J2000.0).
///
/// P = R₃(−z)·R₂(θ)·R₃(−ζ) with the IAU 1976 angles of
/// [`precession_angles`] (Lieske et al. 1977; Meeus eq. 21.3–21.4 in matrix
/// form). Accurate to a few 0.01″ within a few centuries of J2000; the
/// polynomial degrades slowly beyond (it is still a rotation).
pub fn precession_matrix(t: JulianCenturies) -> DMat3 {
    let (zeta, z, theta) = precession_angles(t);
    rot_z(-z) * rot_y(theta) * rot_z(-zeta)
}

/// Frame bias between the ICRS and the mean dynamical equator and equinox of
/// J2000.0: v_J2000 = B · v_ICRS.
///
/// B = R₁(−η₀)·R₂(ξ₀)·R₃(dα₀) with ξ₀ = −16.6170 mas, η₀ = −6.8192 mas,
/// dα₀ = −14.6 mas (IERS Conventions 2003, ch. 5, eq. 28 and Table 5.1;
/// the same rotation as SOFA `iauBp00`'s `rb`). The correction is ~23 mas.
pub fn frame_bias_matrix() -> DMat3 {
    let xi0 = -0.016_617_0 * ARCSEC;
    let eta0 = -0.006_819_2 * ARCSEC;
    let da0 = -0.014_6 * ARCSEC;
    rot_x(-eta0) * rot_y(xi0) * rot_z(da0)
}

#[cfg(test)]
mod tests {
    use super::super::{equatorial_to_vector, vector_to_equatorial};
    use super::*;
    use crate::units::DEG;

    #[test]
    fn meeus_example_21b_theta_persei() {
        // θ Persei at J2000.0 with proper motion applied to 2028 Nov 13.19 TD
        // (JDE 2462088.69): α = 41.054063°, δ = 49.227750°. Precessed:
        // α = 41.547214°, δ = 49.348483° (Meeus Example 21.b).
        let t = (2_462_088.69 - 2_451_545.0) / 36_525.0;
        let v = equatorial_to_vector(41.054_063 * DEG, 49.227_750 * DEG);
        let (ra, dec) = vector_to_equatorial(precession_matrix(t) * v);
        assert!((ra / DEG - 41.547_214).abs() < 2e-6, "{}", ra / DEG);
        assert!((dec / DEG - 49.348_483).abs() < 2e-6, "{}", dec / DEG);
    }

    #[test]
    fn sofa_reference_matrices() {
        // SOFA/ERFA eraPmat76(2400000.5, 61000.0) (MJD 61000 TT) and eraBp00's rb,
        // printed by tools/gen_frames_refs.py.
        let t = (2_400_000.5 + 61_000.0 - 2_451_545.0) / 36_525.0;
        let p = precession_matrix(t);
        let expected = [
            [
                0.9999800778245183,
                -0.005789361499785571,
                -0.002515402054361757,
            ],
            [
                0.005789361498970595,
                0.9999832414797817,
                -7.281682428899775e-06,
            ],
            [
                0.002515402056237479,
                -7.281034446008869e-06,
                0.9999968363447367,
            ],
        ];
        for (i, row) in expected.iter().enumerate() {
            for (j, e) in row.iter().enumerate() {
                assert!((p.row(i)[j] - e).abs() < 1e-14, "P[{i}][{j}]");
            }
        }
        let b = frame_bias_matrix();
        let rb = [
            [
                0.9999999999999942,
                -7.078279744199198e-08,
                8.056217146976134e-08,
            ],
            [
                7.078279477857338e-08,
                0.9999999999999969,
                3.3060414542221364e-08,
            ],
            [
                -8.056217380986972e-08,
                -3.306040883980552e-08,
                0.9999999999999962,
            ],
        ];
        for (i, row) in rb.iter().enumerate() {
            for (j, e) in row.iter().enumerate() {
                // SOFA derives ξ₀ from dψ_bias·sin ε₀ = −16.617141 mas; the
                // rounded IERS value −16.6170 mas differs by 0.7e-12 rad.
                assert!((b.row(i)[j] - e).abs() < 1e-12, "B[{i}][{j}]");
            }
        }
    }

    #[test]
    fn finite_and_orthonormal_far_from_j2000() {
        for t in [-10.0, -3.0, 0.0, 3.0, 10.0] {
            let p = precession_matrix(t);
            let should_be_identity = p * p.transpose();
            assert!(
                should_be_identity.abs_diff_eq(DMat3::IDENTITY, 1e-14),
                "{t}"
            );
            assert!(p.is_finite());
        }
    }
}
