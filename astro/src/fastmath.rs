//! Trigonometry without libm calls for the hot paths of the series
//! evaluations. Accurate to 1e-11 (2 µas), far below every tier's budget.

use core::f64::consts::{FRAC_PI_2, FRAC_PI_4, PI, TAU};

/// Splits 2π·`turns` into the nearest quarter turn and a remainder y in
/// [−π/4, π/4] radians, without a branch: adding 1.5·2^52 pushes the
/// fraction bits out (|4·turns| < 2^51).
#[inline(always)]
fn quarter_turns(turns: f64) -> (i64, f64) {
    const ROUND: f64 = 6_755_399_441_055_744.0;
    let q4 = turns * 4.0;
    let shifted = q4 + ROUND;
    let nearest = shifted - ROUND;
    // The shifted value's low mantissa bits are the integer itself (mod
    // 2^51), which spares a saturating float → int conversion.
    (shifted.to_bits() as i64, (q4 - nearest) * FRAC_PI_2)
}

/// (sin, cos) of y + q·π/2 from (sin y, cos y): a product with
/// e^{iqπ/2} = (cos qπ/2, sin qπ/2), read from a table (random quadrants
/// would defeat branch prediction; the products by 0 and ±1 are exact).
#[inline(always)]
fn rotate_quadrant(quadrant: i64, sin: f64, cos: f64) -> (f64, f64) {
    const UNIT: [(f64, f64); 4] = [(1.0, 0.0), (0.0, 1.0), (-1.0, 0.0), (0.0, -1.0)];
    let (c, s) = UNIT[(quadrant & 3) as usize];
    (sin * c + cos * s, cos * c - sin * s)
}

/// (sin, cos) of 2π·`turns`: reduction to the nearest quarter turn, then
/// Taylor polynomials on [−π/4, π/4] to y¹¹ and y¹² (truncation error below
/// 1e-11). Valid for |turns| < 2^49.
#[inline(always)]
pub(crate) fn sincos_turns(turns: f64) -> (f64, f64) {
    let (quadrant, y) = quarter_turns(turns);
    let y2 = y * y;
    // Taylor coefficients 1/n! with alternating signs, as constants (a
    // division per term would cost more than the whole polynomial).
    const S: [f64; 5] = [
        -1.0 / 6.0,
        1.0 / 120.0,
        -1.0 / 5040.0,
        1.0 / 362_880.0,
        -1.0 / 39_916_800.0,
    ];
    const C: [f64; 6] = [
        -1.0 / 2.0,
        1.0 / 24.0,
        -1.0 / 720.0,
        1.0 / 40_320.0,
        -1.0 / 3_628_800.0,
        1.0 / 479_001_600.0,
    ];
    let sin = y + y * y2 * (S[0] + y2 * (S[1] + y2 * (S[2] + y2 * (S[3] + y2 * S[4]))));
    let cos = 1.0 + y2 * (C[0] + y2 * (C[1] + y2 * (C[2] + y2 * (C[3] + y2 * (C[4] + y2 * C[5])))));
    rotate_quadrant(quadrant, sin, cos)
}

/// (sin, cos) of 2π·`turns` to 4e-7 absolute (0.08″), for the low tier,
/// whose budgets are tens of arcseconds: reduction to the nearest eighth
/// turn, Taylor polynomials to y⁵ and y⁶ on [−π/8, π/8] (errors 3e-7 and
/// 2e-8), then a product with e^{ikπ/4} from a table. Valid for
/// |turns| < 2^48.
#[inline(always)]
pub(crate) fn sincos_turns_low(turns: f64) -> (f64, f64) {
    const ROUND: f64 = 6_755_399_441_055_744.0;
    const H: f64 = core::f64::consts::FRAC_1_SQRT_2;
    const UNIT: [(f64, f64); 8] = [
        (1.0, 0.0),
        (H, H),
        (0.0, 1.0),
        (-H, H),
        (-1.0, 0.0),
        (-H, -H),
        (0.0, -1.0),
        (H, -H),
    ];
    let q8 = turns * 8.0;
    let shifted = q8 + ROUND;
    let nearest = shifted - ROUND;
    let y = (q8 - nearest) * FRAC_PI_4;
    let y2 = y * y;
    let sin = y + (y * y2) * (-1.0 / 6.0 + y2 * (1.0 / 120.0));
    let cos = (1.0 - 0.5 * y2) + (y2 * y2) * (1.0 / 24.0 + y2 * (-1.0 / 720.0));
    let (c, s) = UNIT[(shifted.to_bits() & 7) as usize];
    (sin * c + cos * s, cos * c - sin * s)
}

/// (sin, cos) of a small angle |x| ≤ 0.2 rad (11.5°) by its Taylor series to
/// x⁵ and x⁶: error below 3e-9 (0.6 mas), for the low tier.
#[inline(always)]
pub(crate) fn sincos_small(x: f64) -> (f64, f64) {
    // Taylor to x⁵ and x⁶ in Estrin's form.
    let x2 = x * x;
    let x3 = x * x2;
    let sin = x + x3 * (-1.0 / 6.0 + x2 * (1.0 / 120.0));
    let cos = (1.0 - 0.5 * x2) + (x2 * x2) * (1.0 / 24.0 + x2 * (-1.0 / 720.0));
    (sin, cos)
}

/// (sin, cos) of `x` radians, |x| < 1e12; see [`sincos_turns`].
#[inline(always)]
pub(crate) fn sincos(x: f64) -> (f64, f64) {
    sincos_turns(x * (1.0 / TAU))
}

/// atan(mn/mx) for 0 ≤ mn ≤ mx, 0 < mx < ∞: a shift by π/4 above tan(π/8)
/// so that the polynomial only sees |u| ≤ tan(π/8), where a degree-15 odd
/// least-squares fit on Chebyshev nodes (coefficients computed for this
/// crate) holds 3e-13 rad. One division; no data-dependent jumps (random
/// octants would defeat branch prediction).
#[inline(always)]
fn atan_ratio(mn: f64, mx: f64) -> f64 {
    const A: [f64; 8] = [
        0.999_999_999_999_270_7,
        -0.333_333_332_783_843,
        0.199_999_931_888_911_33,
        -0.142_853_912_600_734_96,
        0.111_035_349_337_018_25,
        -0.089_932_174_792_308_5,
        0.069_770_062_681_784_39,
        -0.037_701_758_097_838_78,
    ];
    const TAN_PI_8: f64 = 0.414_213_562_373_095_03;
    let big = if mn > TAN_PI_8 * mx { 1.0 } else { 0.0 };
    // atan(t) = π/4 + atan((t − 1)/(t + 1)) with t = mn/mx, when t > tan(π/8).
    let u = (mn - big * mx) / (mx + big * mn);
    let w = u * u;
    let w2 = w * w;
    let w4 = w2 * w2;
    // Estrin's scheme: shorter dependency chains than Horner.
    let p01 = A[0] + w * A[1];
    let p23 = A[2] + w * A[3];
    let p45 = A[4] + w * A[5];
    let p67 = A[6] + w * A[7];
    big * FRAC_PI_4 + u * ((p01 + w2 * p23) + w4 * (p45 + w2 * p67))
}

/// atan2(y, x) in [−π, π], within 5e-13 rad of the correctly rounded value
/// (octant reduction, then [`atan_ratio`]), for the components of a vector
/// that cannot be zero or infinite (one built from sines and cosines): no
/// guard, so NaN in gives NaN out and the zero vector gives NaN.
#[inline(always)]
pub(crate) fn atan2_unit(y: f64, x: f64) -> f64 {
    let (ax, ay) = (x.abs(), y.abs());
    let steep = ay > ax;
    let (mn, mx) = if steep { (ax, ay) } else { (ay, ax) };
    let r = atan_ratio(mn, mx);
    // Octant, then half plane: r → π/2 − r when |y| > |x|, r → π − r when x < 0.
    let r = if steep { FRAC_PI_2 - r } else { r };
    let r = if x < 0.0 { PI - r } else { r };
    // Sign of y (signed zero included).
    f64::from_bits(r.to_bits() | (y.to_bits() & (1 << 63)))
}

/// atan2(z, rho) for rho ≥ 0 — a latitude from a vector's height and its
/// distance from the axis — in [−π/2, π/2], for vectors that cannot be zero
/// or infinite; see [`atan2_unit`].
#[inline(always)]
pub(crate) fn latitude_unit(z: f64, rho: f64) -> f64 {
    let az = z.abs();
    let steep = az > rho;
    let (mn, mx) = if steep { (rho, az) } else { (az, rho) };
    let r = atan_ratio(mn, mx);
    let r = if steep { FRAC_PI_2 - r } else { r };
    f64::from_bits(r.to_bits() | (z.to_bits() & (1 << 63)))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn matches_libm_over_many_turns() {
        let mut worst: f64 = 0.0;
        let mut x = -5000.0;
        while x < 5000.0 {
            let (s, c) = sincos(x);
            worst = worst
                .max((s - libm::sin(x)).abs())
                .max((c - libm::cos(x)).abs());
            x += 0.012_345_678_9;
        }
        assert!(worst < 2e-11, "{worst:e}");
    }

    #[test]
    fn low_variant_and_small_angles() {
        let mut worst: f64 = 0.0;
        let mut t = -300.0;
        while t < 300.0 {
            let (s, c) = sincos_turns_low(t);
            let x = t * TAU;
            worst = worst
                .max((s - libm::sin(x)).abs())
                .max((c - libm::cos(x)).abs());
            t += 0.000_987_654_3;
        }
        assert!(worst < 4e-7, "{worst:e}");
        let mut x = -0.2;
        while x <= 0.2 {
            let (s, c) = sincos_small(x);
            assert!((s - libm::sin(x)).abs() < 3e-9 && (c - libm::cos(x)).abs() < 3e-10);
            x += 1e-4;
        }
    }

    #[test]
    fn atan2_matches_libm() {
        let mut worst: f64 = 0.0;
        for i in 0..200_000 {
            let a = f64::from(i) * 0.000_314_159_7 - 31.4;
            for r in [1e-300, 1e-5, 1.0, 3.7e8] {
                let (y, x) = (r * libm::sin(a), r * libm::cos(a));
                worst = worst.max((atan2_unit(y, x) - libm::atan2(y, x)).abs());
            }
        }
        assert!(worst < 5e-13, "{worst:e}");
        // Axes and signed zeros exactly as libm.
        for (y, x) in [
            (0.0, 1.0),
            (1.0, 0.0),
            (0.0, -1.0),
            (-0.0, -1.0),
            (-1.0, 0.0),
            (1.0, 1.0),
            (-1.0, -1.0),
        ] {
            assert!(
                (atan2_unit(y, x) - libm::atan2(y, x)).abs() < 1e-15,
                "{y} {x}"
            );
        }
        assert!(atan2_unit(f64::NAN, 1.0).is_nan());
        for i in 0..100_000 {
            let a = f64::from(i) * 0.000_031_415_9 - FRAC_PI_2;
            let (z, rho) = (libm::sin(a), libm::cos(a).abs());
            assert!(
                (latitude_unit(z, rho) - libm::atan2(z, rho)).abs() < 5e-13,
                "{a}"
            );
        }
        assert!((latitude_unit(-1.0, 0.0) + FRAC_PI_2).abs() < 1e-15);
        assert!((latitude_unit(1.0, 0.0) - FRAC_PI_2).abs() < 1e-15);
        assert!(latitude_unit(f64::NAN, 1.0).is_nan() && atan2_unit(1.0, f64::NAN).is_nan());
    }

    #[test]
    fn exact_quadrants() {
        for (t, s, c) in [
            (0.0, 0.0, 1.0),
            (0.25, 1.0, 0.0),
            (0.5, 0.0, -1.0),
            (-0.25, -1.0, 0.0),
        ] {
            let (ss, cc) = sincos_turns(t);
            assert!((ss - s).abs() < 1e-15 && (cc - c).abs() < 1e-15, "{t}");
        }
    }
}
