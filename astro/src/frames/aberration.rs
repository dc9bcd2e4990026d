//! Annual aberration: the Earth's velocity (Ron & Vondrák) and the
//! aberrated direction seen by a moving observer.

use glam::DVec3;

use crate::units::JulianCenturies;

/// One term of Meeus Table 23.A: integer multiples of
/// (L2, L3, L4, L5, L6, L7, L8, L′, D, M′, F) and the coefficients of
/// (X sin, X cos, Y sin, Y cos, Z sin, Z cos), units 1e-8 AU/day.
type Term = ([i8; 11], [f64; 6]);

/// Ron & Vondrák (1986) series for the velocity of the Earth with respect to
/// the solar-system barycentre, equator and equinox J2000.0, as abridged by
/// Meeus, *Astronomical Algorithms* 2nd ed., Table 23.A (36 terms). The time
/// dependence of the first, second and fifth terms is in [`T_TERMS`].
#[rustfmt::skip]
const TERMS: [Term; 36] = [
    //  L2  L3  L4  L5 L6 L7 L8 L′  D  M′ F     Xsin      Xcos     Ysin      Ycos     Zsin     Zcos
    ([0,  1,  0,  0, 0, 0, 0, 0, 0, 0, 0], [-1719914.0, -25.0,   25.0, 1578089.0,    10.0, 684185.0]),
    ([0,  2,  0,  0, 0, 0, 0, 0, 0, 0, 0], [    6434.0, 28007.0, 25697.0, -5904.0, 11141.0, -2559.0]),
    ([0,  0,  0,  1, 0, 0, 0, 0, 0, 0, 0], [     715.0,     0.0,     6.0,  -657.0,   -15.0,  -282.0]),
    ([0,  0,  0,  0, 0, 0, 0, 1, 0, 0, 0], [     715.0,     0.0,     0.0,  -656.0,     0.0,  -285.0]),
    ([0,  3,  0,  0, 0, 0, 0, 0, 0, 0, 0], [     486.0,  -236.0,  -216.0,  -446.0,   -94.0,  -193.0]),
    ([0,  0,  0,  0, 1, 0, 0, 0, 0, 0, 0], [     159.0,     0.0,     2.0,  -147.0,    -6.0,   -61.0]),
    ([0,  0,  0,  0, 0, 0, 0, 0, 0, 0, 1], [       0.0,     0.0,     0.0,    26.0,     0.0,   -59.0]),
    ([0,  0,  0,  0, 0, 0, 0, 1, 0, 1, 0], [      39.0,     0.0,     0.0,   -36.0,     0.0,   -16.0]),
    ([0,  0,  0,  2, 0, 0, 0, 0, 0, 0, 0], [      33.0,   -10.0,    -9.0,   -30.0,    -5.0,   -13.0]),
    ([0,  2,  0, -1, 0, 0, 0, 0, 0, 0, 0], [      31.0,     1.0,     1.0,   -28.0,     0.0,   -12.0]),
    ([0,  3, -8,  3, 0, 0, 0, 0, 0, 0, 0], [       8.0,   -28.0,    25.0,     8.0,    11.0,     3.0]),
    ([0,  5, -8,  3, 0, 0, 0, 0, 0, 0, 0], [       8.0,   -28.0,   -25.0,    -8.0,   -11.0,    -3.0]),
    ([2, -1,  0,  0, 0, 0, 0, 0, 0, 0, 0], [      21.0,     0.0,     0.0,   -19.0,     0.0,    -8.0]),
    ([1,  0,  0,  0, 0, 0, 0, 0, 0, 0, 0], [     -19.0,     0.0,     0.0,    17.0,     0.0,     8.0]),
    ([0,  0,  0,  0, 0, 1, 0, 0, 0, 0, 0], [      17.0,     0.0,     0.0,   -16.0,     0.0,    -7.0]),
    ([0,  1,  0, -2, 0, 0, 0, 0, 0, 0, 0], [      16.0,     0.0,     0.0,    15.0,     1.0,     7.0]),
    ([0,  0,  0,  0, 0, 0, 1, 0, 0, 0, 0], [      16.0,     0.0,     1.0,   -15.0,    -3.0,    -6.0]),
    ([0,  1,  0,  1, 0, 0, 0, 0, 0, 0, 0], [      11.0,    -1.0,    -1.0,   -10.0,    -1.0,    -5.0]),
    ([2, -2,  0,  0, 0, 0, 0, 0, 0, 0, 0], [       0.0,   -11.0,   -10.0,     0.0,    -4.0,     0.0]),
    ([0,  1,  0, -1, 0, 0, 0, 0, 0, 0, 0], [     -11.0,    -2.0,    -2.0,     9.0,    -1.0,     4.0]),
    ([0,  4,  0,  0, 0, 0, 0, 0, 0, 0, 0], [      -7.0,    -8.0,    -8.0,     6.0,    -3.0,     3.0]),
    ([0,  3,  0, -2, 0, 0, 0, 0, 0, 0, 0], [     -10.0,     0.0,     0.0,     9.0,     0.0,     4.0]),
    ([1, -2,  0,  0, 0, 0, 0, 0, 0, 0, 0], [      -9.0,     0.0,     0.0,    -9.0,     0.0,    -4.0]),
    ([2, -3,  0,  0, 0, 0, 0, 0, 0, 0, 0], [      -9.0,     0.0,     0.0,    -8.0,     0.0,    -4.0]),
    ([0,  0,  0,  0, 2, 0, 0, 0, 0, 0, 0], [       0.0,    -9.0,    -8.0,     0.0,    -3.0,     0.0]),
    ([2, -4,  0,  0, 0, 0, 0, 0, 0, 0, 0], [       0.0,    -9.0,     8.0,     0.0,     3.0,     0.0]),
    ([0,  3, -2,  0, 0, 0, 0, 0, 0, 0, 0], [       8.0,     0.0,     0.0,    -8.0,     0.0,    -3.0]),
    ([0,  0,  0,  0, 0, 0, 0, 1, 2,-1, 0], [       8.0,     0.0,     0.0,    -7.0,     0.0,    -3.0]),
    ([8,-12,  0,  0, 0, 0, 0, 0, 0, 0, 0], [      -4.0,    -7.0,    -6.0,     4.0,    -3.0,     2.0]),
    ([8,-14,  0,  0, 0, 0, 0, 0, 0, 0, 0], [      -4.0,    -7.0,     6.0,    -4.0,     3.0,    -2.0]),
    ([0,  0,  2,  0, 0, 0, 0, 0, 0, 0, 0], [      -6.0,    -5.0,    -4.0,     5.0,    -2.0,     2.0]),
    ([3, -4,  0,  0, 0, 0, 0, 0, 0, 0, 0], [      -1.0,    -1.0,    -2.0,    -7.0,     1.0,    -4.0]),
    ([0,  2,  0, -2, 0, 0, 0, 0, 0, 0, 0], [       4.0,    -6.0,    -5.0,    -4.0,    -2.0,    -2.0]),
    ([3, -3,  0,  0, 0, 0, 0, 0, 0, 0, 0], [       0.0,    -7.0,    -6.0,     0.0,    -3.0,     0.0]),
    ([0,  2, -2,  0, 0, 0, 0, 0, 0, 0, 0], [       5.0,    -5.0,    -4.0,    -5.0,    -2.0,    -2.0]),
    ([0,  0,  0,  0, 0, 0, 0, 1,-2, 0, 0], [       5.0,     0.0,     0.0,    -5.0,     0.0,    -2.0]),
];

/// Per-century rates of the coefficients of terms 0 (L3), 1 (2L3) and
/// 4 (3L3) of [`TERMS`], same layout, 1e-8 AU/day per Julian century.
#[rustfmt::skip]
const T_TERMS: [(usize, [f64; 6]); 3] = [
    (0, [ -2.0,    0.0,  -13.0,  156.0,  32.0, -358.0]),
    (1, [141.0, -107.0,  -95.0, -130.0, -48.0,  -55.0]),
    (4, [ -5.0,   -4.0,   -4.0,    5.0,   0.0,    0.0]),
];

/// Velocity of the Earth with respect to the solar-system **barycentre**
/// (the series includes the Sun's reflex motion about the barycentre, e.g.
/// the 13 m/s Jupiter term), AU/day, referred to the mean equator and
/// equinox of J2000.0, at `t` Julian centuries of TT (≈ TDB) from J2000.0.
///
/// Source: C. Ron & J. Vondrák, *Bull. Astron. Inst. Czechosl.* 37, 96 (1986),
/// abridged by Meeus, *Astronomical Algorithms* 2nd ed., ch. 23, Table 23.A.
/// Agrees with JPL DE421 to 2e-7 AU/day (0.004″ of aberration) over
/// 1900–2050 (see tests).
pub fn earth_velocity_j2000(t: JulianCenturies) -> DVec3 {
    // Mean longitudes of Venus … Neptune and lunar arguments, radians
    // (Meeus ch. 23).
    let args = [
        3.176_146_7 + 1_021.328_554_6 * t, // L2
        1.753_470_3 + 628.307_584_9 * t,   // L3
        6.203_480_9 + 334.061_243_1 * t,   // L4
        0.599_546_5 + 52.969_096_5 * t,    // L5
        0.874_016_8 + 21.329_909_5 * t,    // L6
        5.481_293_9 + 7.478_159_9 * t,     // L7
        5.311_886_3 + 3.813_303_6 * t,     // L8
        3.810_344_4 + 8_399.684_733_7 * t, // L′
        5.198_466_7 + 7_771.377_148_6 * t, // D
        2.355_555_9 + 8_328.691_428_9 * t, // M′
        1.627_905_2 + 8_433.466_160_1 * t, // F
    ];
    let mut v = [0.0f64; 3];
    for (i, (mult, c)) in TERMS.iter().enumerate() {
        let mut c = *c;
        if let Some((_, rate)) = T_TERMS.iter().find(|(k, _)| *k == i) {
            for (cj, rj) in c.iter_mut().zip(rate.iter()) {
                *cj += rj * t;
            }
        }
        let a: f64 = mult
            .iter()
            .zip(args.iter())
            .map(|(&m, &x)| m as f64 * x)
            .sum();
        let (s, co) = (libm::sin(a), libm::cos(a));
        for (axis, vj) in v.iter_mut().enumerate() {
            *vj += c[2 * axis] * s + c[2 * axis + 1] * co;
        }
    }
    DVec3::new(v[0], v[1], v[2]) * 1e-8
}

/// Direction of a source as seen by an observer moving with velocity
/// `velocity_over_c` (the velocity divided by the speed of light, in the
/// frame of `direction`), given its direction `direction` for an observer at
/// rest. Returns a unit vector.
///
/// Full special-relativistic aberration (Lorentz transformation of the light
/// direction; e.g. Explanatory Supplement 1992 eq. 3.252-3, SOFA `iauAb`
/// without the light-deflection factor):
/// p′ = (γ⁻¹ p + (1 + p·β/(1 + γ⁻¹)) β) / (1 + p·β), γ⁻¹ = √(1 − β²).
/// First order in β it is p + β − (p·β) p; second-order terms are ~1 mas.
/// `direction` need not be normalised; a zero vector is returned unchanged.
pub fn aberrate(direction: DVec3, velocity_over_c: DVec3) -> DVec3 {
    let len = direction.length();
    if len.is_nan() || len <= 0.0 {
        return direction;
    }
    let p = direction / len;
    let beta = velocity_over_c;
    let gamma_inv = libm::sqrt((1.0 - beta.length_squared()).max(0.0));
    let pb = p.dot(beta);
    let q = (p * gamma_inv + beta * (1.0 + pb / (1.0 + gamma_inv))) / (1.0 + pb);
    q.normalize_or_zero()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::frames::{equatorial_to_vector, vector_to_equatorial};
    use crate::units::{wrap_pi, ARCSEC, DEG, LIGHT_DAYS_PER_AU};

    /// Barycentric velocity of the Earth, AU/day, ICRS, from JPL DE421 via
    /// Skyfield 1.55 (printed by tools/gen_frames_refs.py).
    const DE421: [(f64, f64, f64, f64); 7] = [
        (
            2415020.5,
            -0.017152407884215404,
            -0.003215056891846034,
            -0.0013956856293250014,
        ),
        (
            2440000.5,
            0.0150992040037437,
            -0.007143892604882699,
            -0.00309853529740437,
        ),
        (
            2446895.5,
            0.005544827095781713,
            -0.014913844065943484,
            -0.006465792728081412,
        ),
        (
            2451545.0,
            -0.017202246610766636,
            -0.002904925889435517,
            -0.0012594279198539636,
        ),
        (
            2455000.5,
            0.016895797603034085,
            -0.000956224981296046,
            -0.00041455272452112983,
        ),
        (
            2460000.5,
            -0.007329056511000787,
            -0.014470161756705978,
            -0.006273306467394563,
        ),
        (
            2469000.5,
            -0.006965130437278201,
            0.01448563930563451,
            0.006278618694349526,
        ),
    ];

    #[test]
    fn velocity_matches_de421() {
        let mut worst: f64 = 0.0;
        for (jd, x, y, z) in DE421 {
            let v = earth_velocity_j2000((jd - 2_451_545.0) / 36_525.0);
            worst = worst.max((v - DVec3::new(x, y, z)).length());
        }
        // Measured 1.8e-7 AU/day (the omitted Ron–Vondrák terms); 2e-7 AU/day
        // is 0.004″ of aberration. The ICRS↔J2000 bias is negligible here.
        assert!(worst < 2e-7, "{worst}");
    }

    #[test]
    fn theta_persei_2028_aberration() {
        // θ Persei, 2028 Nov 13.19 TD, mean place of J2000 with proper motion
        // α = 41.054063°, δ = 49.227750° (Meeus Example 21.b). With the DE421
        // barycentric velocity (tools/gen_frames_refs.py) the annual
        // aberration is Δα = +29.9614″, Δδ = +6.7485″. Meeus' Example 23.a,
        // using the low-accuracy expression 23.3 (no barycentric terms), has
        // +30.045″ and +6.697″.
        let t = (2_462_088.69 - 2_451_545.0) / 36_525.0;
        let (ra, dec) = (41.054_063 * DEG, 49.227_750 * DEG);
        let beta = earth_velocity_j2000(t) * LIGHT_DAYS_PER_AU;
        let (ra2, dec2) = vector_to_equatorial(aberrate(equatorial_to_vector(ra, dec), beta));
        let dra = wrap_pi(ra2 - ra) / ARCSEC;
        let ddec = (dec2 - dec) / ARCSEC;
        assert!((dra - 29.9614).abs() < 0.002, "{dra}");
        assert!((ddec - 6.7485).abs() < 0.002, "{ddec}");
        assert!((dra - 30.045).abs() < 0.1 && (ddec - 6.697).abs() < 0.1);
    }

    #[test]
    fn aberrate_is_unit_and_first_order() {
        let beta = DVec3::new(1e-4, -0.5e-4, 0.2e-4);
        for p in [DVec3::X, DVec3::new(0.3, -0.4, 0.866), DVec3::Z * 5.0] {
            let q = aberrate(p, beta);
            assert!((q.length() - 1.0).abs() < 1e-15);
            let pu = p.normalize();
            let first = pu + beta - pu * pu.dot(beta);
            assert!((q - first).length() < 2e-8);
        }
        assert_eq!(aberrate(DVec3::ZERO, beta), DVec3::ZERO);
    }
}
