//! Deterministic lattice noise for the cloud fields, written with u32
//! wrapping arithmetic and f32 only so that WGSL computes the same numbers
//! (no tables, no platform hash).
//!
//! * [`hash_u32`] — an integer finaliser (the "lowbias32" constants of
//!   C. Wellons' hash prospector: two multiply–xorshift rounds);
//! * [`lattice`] — the value at an integer lattice point, in [0, 1);
//! * [`value_noise`] — trilinear interpolation of the lattice values with
//!   the quintic fade 6t⁵ − 15t⁴ + 10t³ (Perlin 2002), periodic with
//!   `period` cells on every axis;
//! * [`fbm`] — fractional Brownian motion: octaves of doubling frequency
//!   and halving amplitude, normalised to [0, 1), periodic with the base
//!   octave's period in space (each octave's lattice period doubles).

use glam::Vec3;

/// Integer hash (lowbias32): each input bit flips about half of the output bits.
#[inline]
pub fn hash_u32(mut x: u32) -> u32 {
    x ^= x >> 16;
    x = x.wrapping_mul(0x7feb_352d);
    x ^= x >> 15;
    x = x.wrapping_mul(0x846c_a68b);
    x ^= x >> 16;
    x
}

/// The noise value at lattice point `(i, j, k)` for `seed`, in [0, 1)
/// (24 bits, exact in f32).
#[inline]
pub fn lattice(i: u32, j: u32, k: u32, seed: u32) -> f32 {
    let h = hash_u32(
        i.wrapping_mul(0x8da6_b343)
            ^ j.wrapping_mul(0xd816_3841)
            ^ k.wrapping_mul(0xcb1a_b31f)
            ^ hash_u32(seed),
    );
    (h >> 8) as f32 * (1.0 / 16_777_216.0)
}

/// Quintic fade: C² continuous interpolation weight.
#[inline]
fn fade(t: f32) -> f32 {
    t * t * t * (t * (t * 6.0 - 15.0) + 10.0)
}

#[inline]
fn lerp(a: f32, b: f32, t: f32) -> f32 {
    a + (b - a) * t
}

/// Value noise at `p` (lattice units), in [0, 1), periodic with `period`
/// cells on each axis (`period` a power of two).
pub fn value_noise(p: Vec3, period: u32, seed: u32) -> f32 {
    let f = p.floor();
    let t = p - f;
    let mask = period.wrapping_sub(1);
    // Two's complement keeps floor(−0.5) = −1 ≡ period − 1 (mod period).
    let i0 = (f.x as i32) as u32 & mask;
    let j0 = (f.y as i32) as u32 & mask;
    let k0 = (f.z as i32) as u32 & mask;
    let (i1, j1, k1) = (
        i0.wrapping_add(1) & mask,
        j0.wrapping_add(1) & mask,
        k0.wrapping_add(1) & mask,
    );
    let (u, v, w) = (fade(t.x), fade(t.y), fade(t.z));
    let c = |i, j, k| lattice(i, j, k, seed);
    let x00 = lerp(c(i0, j0, k0), c(i1, j0, k0), u);
    let x10 = lerp(c(i0, j1, k0), c(i1, j1, k0), u);
    let x01 = lerp(c(i0, j0, k1), c(i1, j0, k1), u);
    let x11 = lerp(c(i0, j1, k1), c(i1, j1, k1), u);
    lerp(lerp(x00, x10, v), lerp(x01, x11, v), w)
}

/// Offset of octave `k` (lattice units of that octave) so that the
/// octaves' lattices do not line up at the origin (the wgpu clouds pass
/// reads it from its uniforms).
pub const OCTAVE_SHIFT: Vec3 = Vec3::new(17.31, 5.77, 11.13);

/// Fractional Brownian motion of `octaves` value-noise octaves at `p`
/// (base-octave lattice units), in [0, 1): octave k has frequency 2^k,
/// amplitude 2^−k and its own seed; periodic with `period` base cells.
pub fn fbm(p: Vec3, octaves: u32, period: u32, seed: u32) -> f32 {
    let mut sum = 0.0;
    let mut norm = 0.0;
    let mut amp = 1.0;
    let mut freq = 1.0;
    for k in 0..octaves {
        let q = p * freq + OCTAVE_SHIFT * k as f32;
        sum += amp * value_noise(q, period << k, seed.wrapping_add(k));
        norm += amp;
        amp *= 0.5;
        freq *= 2.0;
    }
    if norm > 0.0 {
        sum / norm
    } else {
        0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lattice_values_are_uniform_in_unit_interval() {
        let mut sum = 0.0f64;
        let n = 64u32;
        for i in 0..n {
            for j in 0..n {
                let v = lattice(i, j, 3, 7);
                assert!((0.0..1.0).contains(&v));
                sum += v as f64;
            }
        }
        let mean = sum / (n * n) as f64;
        assert!((mean - 0.5).abs() < 0.02, "{mean}");
    }

    #[test]
    fn noise_interpolates_the_lattice_and_is_periodic() {
        // At lattice points the noise is the lattice value.
        let v = value_noise(Vec3::new(3.0, 5.0, 1.0), 256, 4);
        assert_eq!(v, lattice(3, 5, 1, 4));
        // Periodic: one period away on any axis (negative coordinates too).
        let p = Vec3::new(2.3, -4.7, 0.6);
        for d in [Vec3::X, Vec3::Y, Vec3::Z] {
            let a = value_noise(p, 16, 1);
            let b = value_noise(p + d * 16.0, 16, 1);
            assert!((a - b).abs() < 1e-5, "{a} {b}");
        }
        // fBm is periodic with the base period in space.
        let a = fbm(p, 4, 16, 9);
        let b = fbm(p + Vec3::X * 16.0, 4, 16, 9);
        assert!((a - b).abs() < 1e-4, "{a} {b}");
    }

    #[test]
    fn noise_is_continuous_across_cells() {
        let e = 1e-4;
        for x in [0.0f32, 1.0, 2.0, -1.0] {
            let a = value_noise(Vec3::new(x - e, 0.3, 0.7), 256, 2);
            let b = value_noise(Vec3::new(x + e, 0.3, 0.7), 256, 2);
            assert!((a - b).abs() < 1e-3, "{x}: {a} {b}");
        }
    }

    #[test]
    fn seeds_differ() {
        let p = Vec3::new(1.5, 2.5, 0.5);
        assert_ne!(fbm(p, 3, 256, 0), fbm(p, 3, 256, 1));
    }
}
