//! Inverse trigonometry in `f32` for the per-pixel lookups (sky view, Milky
//! Way): the same angles as the C library's `atan2f`/`asinf` within a few
//! units in the last place, in straight-line arithmetic that the compiler
//! inlines (no call, no table, branches that become selects).
//!
//! The arctangent of a ∈ [0, 1] is a · P(a²), where P is the degree-9
//! truncated Chebyshev series of atan(√s)/√s on s ∈ [0, 1], expanded into
//! monomials and rounded to `f32` (coefficients computed for this module;
//! the series converges like (3 + √8)⁻ⁿ, as atan(√s)/√s has its nearest
//! singularity at s = −1): its truncation error, 2 × 10⁻⁹, is below
//! `f32` rounding. With the octant reduction (the quotient of the smaller
//! by the larger magnitude, π/2 − θ, π − θ) and the `f32` evaluation the
//! angle is within 4 ulp of the exact one (test
//! `atan2_and_asin_match_the_library`, a dense sweep against `f64`).

use std::f32::consts::{FRAC_PI_2, PI};

/// P(s) ≈ atan(√s)/√s on [0, 1]: monomial coefficients, constant first.
const ATAN_POLY: [f32; 10] = [
    1.0,
    -0.333_332_84,
    0.199_982_3,
    -0.142_615_74,
    0.109_401_99,
    -0.083_720_64,
    0.057_463_557,
    -0.030_717_509,
    0.010_680_719,
    -0.001_743_701_2,
];

/// atan(a) for a ∈ [0, 1]. P is evaluated by Estrin's scheme (pairs, then
/// powers s², s⁴, s⁸): four dependent multiply–add levels instead of
/// Horner's nine, so that the lookups' latency does not bound a pixel.
#[inline]
fn atan_unit(a: f32) -> f32 {
    let c = &ATAN_POLY;
    let s = a * a;
    let s2 = s * s;
    let s4 = s2 * s2;
    let s8 = s4 * s4;
    let p01 = c[0] + c[1] * s;
    let p23 = c[2] + c[3] * s;
    let p45 = c[4] + c[5] * s;
    let p67 = c[6] + c[7] * s;
    let p89 = c[8] + c[9] * s;
    let p03 = p01 + p23 * s2;
    let p47 = p45 + p67 * s2;
    a * (p03 + p47 * s4 + p89 * s8)
}

/// The angle of the vector (x, y) from the +x axis, radians in [−π, π]
/// (the quadrants and signs of `f32::atan2`; (0, 0) gives 0).
#[inline]
pub fn atan2(y: f32, x: f32) -> f32 {
    let (ay, ax) = (y.abs(), x.abs());
    let (lo, hi) = if ay > ax { (ax, ay) } else { (ay, ax) };
    let a = if hi > 0.0 { lo / hi } else { 0.0 };
    let mut t = atan_unit(a);
    if ay > ax {
        t = FRAC_PI_2 - t;
    }
    if x < 0.0 {
        t = PI - t;
    }
    if y < 0.0 {
        -t
    } else {
        t
    }
}

/// arcsin(z) for z ∈ [−1, 1] (clamped), radians: the angle of
/// (√((1 − z)(1 + z)), z), which keeps the complement's precision near ±1.
#[inline]
pub fn asin(z: f32) -> f32 {
    let z = z.clamp(-1.0, 1.0);
    atan2(z, ((1.0 - z) * (1.0 + z)).sqrt())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Units in the last place of `f32` at the magnitude of `v` (at least
    /// the smallest normal spacing near zero).
    fn ulp(v: f64) -> f64 {
        let v = v.abs().max(f32::MIN_POSITIVE as f64);
        2f64.powi(v.log2().floor() as i32 - 23)
    }

    #[test]
    fn atan2_and_asin_match_the_library() {
        // A dense sweep of directions on the circle (every quadrant, the
        // axes, the diagonals) at three radii: within 4 ulp of the exact
        // angle (the C library's atan2f: 1 ulp).
        let mut worst = 0.0f64;
        for r in [1e-3f32, 1.0, 1e4] {
            for k in 0..=400_000 {
                let phi = -std::f64::consts::PI + std::f64::consts::TAU * k as f64 / 400_000.0;
                let (y, x) = ((r as f64 * phi.sin()) as f32, (r as f64 * phi.cos()) as f32);
                let exact = (y as f64).atan2(x as f64);
                let e = (atan2(y, x) as f64 - exact).abs() / ulp(exact);
                worst = worst.max(e);
            }
        }
        assert!(worst <= 4.0, "atan2: {worst} ulp");
        // Exact at the axes and the signs of zero and the quadrants.
        assert_eq!(atan2(0.0, 1.0), 0.0);
        assert_eq!(atan2(0.0, 0.0), 0.0);
        assert_eq!(atan2(1.0, 0.0), FRAC_PI_2);
        assert_eq!(atan2(-1.0, 0.0), -FRAC_PI_2);
        assert_eq!(atan2(0.0, -1.0), PI);
        assert!((atan2(-1.0, -1.0) + 0.75 * PI).abs() <= 2.5e-7);
        // asin: within 4 ulp of the exact arcsine of the f32 argument.
        let mut worst = 0.0f64;
        for k in 0..=400_000 {
            let z = (-1.0 + 2.0 * k as f64 / 400_000.0) as f32;
            let exact = (z as f64).asin();
            worst = worst.max((asin(z) as f64 - exact).abs() / ulp(exact));
        }
        assert!(worst <= 4.0, "asin: {worst} ulp");
        assert_eq!(asin(1.0), FRAC_PI_2);
        assert_eq!(asin(-1.0), -FRAC_PI_2);
        assert_eq!(asin(2.0), FRAC_PI_2);
        assert!(asin(0.0) == 0.0 && atan2(1e-30, 1.0) > 0.0);
    }
}
