//! The camera stage of a PNG row ([`super::develop_row`]) with night
//! vision: the mesopic blend of a block of pixels computed without
//! branches over channel arrays, so that the compiler evaluates it for
//! several pixels per instruction, then each pixel's exposure, tone curve
//! and dithered quantisation from the tone table. Every operation is the
//! one [`super::night_vision`] applies, in the same order (its branches
//! become selects of values computed either way), so each pixel's bytes
//! are those of [`super::develop_pixel`], bit for bit (test
//! `blocks_equal_the_pixel_function`).

use super::{ToneTable, BAYER8, ROD_TINT, UNDITHERED};
use crate::spectrum::luminance;

/// Pixels per block: three channel arrays of 1 kB, in the first-level cache.
const BLOCK: usize = 256;

/// [`super::log10_mesopic`] without its branch (the mantissa's fold into
/// [√½, √2) as a select): the same value for every input.
#[inline(always)]
fn log10_lanes(y: f32) -> f32 {
    let bits = y.to_bits();
    let e = ((bits >> 23) & 0xff) as i32 - 127;
    let m = f32::from_bits((bits & 0x007f_ffff) | 0x3f80_0000);
    let fold = m > std::f32::consts::SQRT_2;
    let m = if fold { m * 0.5 } else { m };
    let e = e + i32::from(fold);
    let z = (m - 1.0) / (m + 1.0);
    let z2 = z * z;
    let ln_m = 2.0 * z * (1.0 + z2 * (1.0 / 3.0 + z2 * (0.2 + z2 * (1.0 / 7.0))));
    (e as f32 * std::f32::consts::LN_2 + ln_m) * std::f32::consts::LOG10_E
}

/// [`super::night_vision`] of one pixel with selects instead of branches.
#[inline(always)]
fn night_vision_lanes(r: f32, g: f32, b: f32) -> (f32, f32, f32) {
    let yl = luminance([r, g, b]);
    // photopic_weight: the clamp decides outside 0.0099–3.17.
    let tm = ((log10_lanes(yl) + 2.0) / 2.5).clamp(0.0, 1.0);
    let t = if yl >= 3.17 {
        1.0
    } else if yl <= 0.0099 {
        0.0
    } else {
        tm
    };
    let s = t * t * (3.0 - 2.0 * t);
    let x = 0.412_456_4 * r + 0.357_576_1 * g + 0.180_437_5 * b;
    let y = 0.212_672_9 * r + 0.715_152_2 * g + 0.072_175_0 * b;
    let z = 0.019_333_9 * r + 0.119_192 * g + 0.950_304_1 * b;
    let rod = (y * (1.33 * (1.0 + (y + z) / x) - 1.68)).max(0.0);
    let v = if x <= 0.0 || y <= 0.0 {
        y.max(0.0)
    } else {
        rod
    };
    let tl = luminance(ROD_TINT);
    let k = (1.0 - s) * v;
    let out = (
        s * r + k * (ROD_TINT[0] / tl),
        s * g + k * (ROD_TINT[1] / tl),
        s * b + k * (ROD_TINT[2] / tl),
    );
    if s >= 1.0 {
        (r, g, b)
    } else {
        out
    }
}

/// Night vision over a block of channel arrays, in place.
#[inline(never)]
fn night_vision_block(r: &mut [f32; BLOCK], g: &mut [f32; BLOCK], b: &mut [f32; BLOCK]) {
    for ((r, g), b) in r.iter_mut().zip(g.iter_mut()).zip(b.iter_mut()) {
        (*r, *g, *b) = night_vision_lanes(*r, *g, *b);
    }
}

/// [`super::develop_row`] with night vision on: `dither` says whether the
/// Bayer matrix applies.
pub(super) fn develop_row_night(
    pixels: &[[f32; 3]],
    valid: &[bool],
    y: usize,
    k: f32,
    dither: bool,
    out: &mut [u8],
) {
    let table = ToneTable::get();
    let bayer = &BAYER8[y & 7];
    let (mut r, mut g, mut b) = ([0.0f32; BLOCK], [0.0f32; BLOCK], [0.0f32; BLOCK]);
    let blocks = pixels
        .chunks(BLOCK)
        .zip(valid.chunks(BLOCK))
        .zip(out.chunks_mut(3 * BLOCK));
    for (c, ((px, val), o)) in blocks.enumerate() {
        let dither_at = |i: usize| {
            if dither {
                bayer[(c * BLOCK + i) & 7] as usize
            } else {
                UNDITHERED
            }
        };
        let first = px[0].map(f32::to_bits);
        if px.iter().all(|p| p.map(f32::to_bits) == first) {
            // One colour (the ground): its night vision once and its
            // bytes once per dither level (a block starts at a multiple
            // of 8, so its first 8 pixels hold every level).
            let (nr, ng, nb) = night_vision_lanes(px[0][0], px[0][1], px[0][2]);
            let mut levels = [[0u8; 3]; 8];
            for (i, l) in levels.iter_mut().enumerate().take(px.len()) {
                let d = dither_at(i);
                *l = [
                    table.quantize(nr * k, d),
                    table.quantize(ng * k, d),
                    table.quantize(nb * k, d),
                ];
            }
            for (i, (&v, o)) in val.iter().zip(o.chunks_exact_mut(3)).enumerate() {
                if v {
                    o.copy_from_slice(&levels[i & 7]);
                }
            }
            continue;
        }
        for (i, p) in px.iter().enumerate() {
            (r[i], g[i], b[i]) = (p[0], p[1], p[2]);
        }
        // A block all above the mesopic range (s = 1: daylight) keeps
        // its colours, as night vision would leave them; NaN is not above.
        let photopic = (0..px.len()).all(|i| luminance([r[i], g[i], b[i]]) >= 3.17);
        if !photopic {
            night_vision_block(&mut r, &mut g, &mut b);
        }
        for (i, (&v, o)) in val.iter().zip(o.chunks_exact_mut(3)).enumerate() {
            if v {
                let d = dither_at(i);
                o[0] = table.quantize(r[i] * k, d);
                o[1] = table.quantize(g[i] * k, d);
                o[2] = table.quantize(b[i] * k, d);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::camera::{develop_pixel, night_vision, CameraSettings, Exposure};

    /// Colours from starlight to daylight, the special values of the
    /// branches (zero, negative, the clamp's edges), and a few awkward
    /// floats.
    fn colours() -> Vec<[f32; 3]> {
        let mut v = Vec::new();
        for i in 0..3000 {
            let y = 10f32.powf(-9.0 + 14.0 * i as f32 / 3000.0);
            for (r, g, b) in [
                (1.0, 1.0, 1.0),
                (0.3, 0.6, 1.4),
                (1.5, 0.8, 0.2),
                (0.0, 1.0, 0.5),
                (1.0, 0.0, 0.0),
                (-0.1, 1.0, 0.3),
                (0.2, -0.05, 1.0),
            ] {
                v.push([r * y, g * y, b * y]);
            }
        }
        for s in [
            0.0099f32,
            3.17,
            0.0,
            -0.0,
            -1.0,
            1e-38,
            1e-45,
            f32::MAX,
            1e30,
        ] {
            v.push([s, s, s]);
            v.push([s, 0.0, 0.0]);
            v.push([0.0, s, 0.0]);
        }
        v.push([f32::NAN, 1.0, 1.0]);
        v.push([f32::INFINITY, 1.0, 1.0]);
        v
    }

    #[test]
    fn lanes_equal_the_pixel_function() {
        for c in colours() {
            let (r, g, b) = night_vision_lanes(c[0], c[1], c[2]);
            let want = night_vision(c);
            for (got, want) in [r, g, b].iter().zip(want) {
                assert!(
                    got.to_bits() == want.to_bits() || (got.is_nan() && want.is_nan()),
                    "{c:?}: {got} vs {want}"
                );
            }
        }
    }

    #[test]
    fn blocks_equal_the_pixel_function() {
        // Rows of 600 pixels (two full blocks and a partial one), some not
        // valid, with and without the dither, at two exposures.
        // Rows of one colour too (the ground), one with a pixel apart.
        let mut all = colours();
        for c in [[0.002f32, 0.003, 0.004], [5.0, 4.0, 3.0], [0.0; 3]] {
            all.extend(std::iter::repeat_n(c, 1200));
            let n = all.len();
            all[n - 700] = [0.1, 0.2, 0.3];
        }
        let w = 600;
        for dither in [true, false] {
            for ev in [-4.0, 3.0] {
                let settings = CameraSettings {
                    exposure: Exposure::Ev100(ev),
                    night_vision: true,
                    dither,
                };
                let k = crate::camera::exposure_scale(ev);
                for (y, row) in all.chunks(w).enumerate() {
                    let valid: Vec<bool> = (0..row.len()).map(|x| (x * 7 + y) % 11 != 0).collect();
                    let mut out = vec![7u8; row.len() * 3];
                    develop_row_night(row, &valid, y, k, dither, &mut out);
                    for (x, p) in row.iter().enumerate() {
                        let want = if valid[x] {
                            develop_pixel(*p, x, y, k, &settings)
                        } else {
                            [7; 3]
                        };
                        assert_eq!(out[x * 3..x * 3 + 3], want, "{p:?} at {x}, {y}");
                    }
                }
            }
        }
    }
}
