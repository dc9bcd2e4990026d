//! Lunar eclipses: the Earth's shadow relative to the Moon
//! ([`LunarShadow`]) and the per-band sunlight that reaches a point of the
//! Moon through and past the Earth's limb ([`eclipse_transfer`]; the model
//! is derived in the [module documentation](crate::moon)).

use serde::Serialize;

use super::photometry::EARTH_RADIUS_KM;
use crate::atmosphere::Medium;
use crate::spectrum::Spectrum;
use crate::units::Radians;

/// Lunar-eclipse geometry for the shader: the Earth's shadow relative to
/// the Moon (from
/// [`ShadowGeometry`](himmel_astro::events::ShadowGeometry), geocentric).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct LunarShadow {
    /// The Moon centre's offset from the shadow axis toward celestial east
    /// and north, radians (gnomonic, geocentric).
    pub offset_east: Radians,
    /// See `offset_east`.
    pub offset_north: Radians,
    /// The Moon's geocentric semidiameter, radians.
    pub moon_semidiameter: Radians,
    /// Danjon umbra radius at the Moon's distance, radians.
    pub umbra_radius: Radians,
    /// Danjon penumbra radius at the Moon's distance, radians.
    pub penumbra_radius: Radians,
    /// Umbral magnitude.
    pub umbral_magnitude: f64,
    /// Penumbral magnitude.
    pub penumbral_magnitude: f64,
    /// The Earth's geometric angular radius seen from the Moon (R⊕/d), radians.
    pub earth_radius: Radians,
    /// The Sun's horizontal parallax, radians.
    pub sun_parallax: Radians,
    /// The Sun's angular radius seen from the Moon, radians.
    pub sun_radius: Radians,
    /// Rows 0/1: the geocentric sky east/north unit vectors expressed in the
    /// Moon's topocentric sky frame (east, north, towards the observer).
    pub sky_to_geo: [[f64; 3]; 2],
}

/// Number of axis-distance samples of the eclipse table.
pub const ECLIPSE_TABLE_N: usize = 160;

/// Refraction of a ray grazing the Earth at sea level, from space to
/// space: twice the horizontal refraction 34.5′ (Bennett 1982), radians.
pub const GRAZING_REFRACTION: f64 = 2.0 * 34.5 / 60.0 * std::f64::consts::PI / 180.0;

/// Band transmittance of a ray grazing the Earth's limb at tangent height
/// `h` km through `medium` (both halves of the path), times the cloud
/// factor (half of the limb opaque below 10 km, fading over 10–12 km).
pub fn grazing_transmittance(medium: &Medium, h: f64) -> Spectrum {
    let r_t = medium.bottom as f64 + h.max(0.0);
    let top = medium.top as f64;
    let s_max = (top * top - r_t * r_t).max(0.0).sqrt();
    let n = 400;
    let mut od = Spectrum::ZERO;
    // Quadratic spacing: most of the column is near the tangent point.
    let mut s_prev = 0.0;
    for k in 0..n {
        let xk = (k as f64 + 1.0) / n as f64;
        let s1 = s_max * xk * xk;
        let sm = 0.5 * (s_prev + s1);
        let ds = s1 - s_prev;
        s_prev = s1;
        let r = (r_t * r_t + sm * sm).sqrt() as f32;
        let ext = medium.extinction(medium.densities(r));
        od += ext * (2.0 * ds) as f32;
    }
    let cloud = if h < 10.0 {
        0.5
    } else if h < 12.0 {
        0.5 + 0.25 * (h - 10.0)
    } else {
        1.0
    };
    od.exp_neg() * cloud as f32
}

/// Per-band sunlight (relative to the uneclipsed Sun, 1 = full sunlight)
/// reaching lunar points at axis distances `d = d_max · k / (N − 1)`,
/// `k = 0..N` (see the [module documentation](crate::moon)), integrated
/// over the solar disk (uniform) with 16 × 32 samples.
pub fn eclipse_transfer(s: &LunarShadow, medium: &Medium, d_max: f64) -> Vec<Spectrum> {
    let pe = s.earth_radius;
    let r_e = EARTH_RADIUS_KM;
    let h_scale = 1.0 / medium.inv_h_r as f64;
    // Tangent-height table: σ(h) = pe (1 + h/R) − δ(h), its derivative and
    // the transmittance.
    let nh = 240;
    let h_top = 60.0;
    let hs: Vec<f64> = (0..nh)
        .map(|k| h_top * k as f64 / (nh - 1) as f64)
        .collect();
    let sig: Vec<f64> = hs
        .iter()
        .map(|&h| pe * (1.0 + h / r_e) - GRAZING_REFRACTION * (-h / h_scale).exp())
        .collect();
    let trans: Vec<Spectrum> = hs
        .iter()
        .map(|&h| grazing_transmittance(medium, h))
        .collect();
    let sig_top = sig[nh - 1];
    let (nr, na) = (16usize, 32usize);
    let rs = s.sun_radius;
    (0..ECLIPSE_TABLE_N)
        .map(|k| {
            let d = d_max * k as f64 / (ECLIPSE_TABLE_N - 1) as f64;
            let sigma = (d - s.sun_parallax).max(0.0);
            let mut acc = Spectrum::ZERO;
            let mut wsum = 0.0f64;
            for ir in 0..nr {
                let rr = rs * ((ir as f64 + 0.5) / nr as f64).sqrt();
                for ia in 0..na {
                    let a = std::f64::consts::TAU * (ia as f64 + 0.5) / na as f64;
                    let (u, v) = (sigma + rr * a.cos(), rr * a.sin());
                    let sp = (u * u + v * v).sqrt();
                    wsum += 1.0;
                    if sp >= sig_top {
                        // Above the atmosphere's refracting layers: direct.
                        acc += if sp > pe * (1.0 + h_top / r_e) {
                            Spectrum::ONE
                        } else {
                            trans[nh - 1]
                        };
                        continue;
                    }
                    if sp <= sig[0] {
                        continue; // would need more bending than the ground ray
                    }
                    // σ(h) is increasing: binary search.
                    let (mut lo, mut hi) = (0usize, nh - 1);
                    while hi - lo > 1 {
                        let mid = (lo + hi) / 2;
                        if sig[mid] <= sp {
                            lo = mid;
                        } else {
                            hi = mid;
                        }
                    }
                    let f = (sp - sig[lo]) / (sig[hi] - sig[lo]);
                    let h = hs[lo] + f * (hs[hi] - hs[lo]);
                    let delta = GRAZING_REFRACTION * (-h / h_scale).exp();
                    let app = pe * (1.0 + h / r_e);
                    let dapp = pe / r_e;
                    let dilution = (app / sp.max(1e-9)) * dapp / (dapp + delta / h_scale);
                    let t = trans[lo] * (1.0 - f as f32) + trans[hi] * f as f32;
                    acc += t * dilution.min(50.0) as f32;
                }
            }
            acc * (1.0 / wsum) as f32
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::moon::lunar_reflectance_spectrum;
    use crate::spectrum::{clip_to_gamut, luminance, BandWeights};

    /// A central eclipse at the mean distance: Danjon radii ρu ≈ 0.70°, ρp ≈ 1.23°.
    #[test]
    fn shadow_profile_red_umbra_blue_fringe_penumbra() {
        let d_moon = 384_400.0f64;
        let s = LunarShadow {
            offset_east: 0.0,
            offset_north: 0.0,
            moon_semidiameter: (1737.4 / d_moon).asin(),
            umbra_radius: 0.0121,
            penumbra_radius: 0.0215,
            umbral_magnitude: 1.0,
            penumbral_magnitude: 2.0,
            earth_radius: (EARTH_RADIUS_KM / d_moon).asin(),
            sun_parallax: 4.26e-5,
            sun_radius: 0.00465,
            sky_to_geo: [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
        };
        let m = Medium::new(&crate::atmosphere::AtmosphereParams::default());
        let d_max = 0.025;
        let t = eclipse_transfer(&s, &m, d_max);
        let w = BandWeights::solar();
        let r = lunar_reflectance_spectrum();
        let c0 = w.to_rgb(&r);
        let at = |deg: f64| {
            let k = ((deg.to_radians() / d_max) * (ECLIPSE_TABLE_N - 1) as f64).round() as usize;
            let c = clip_to_gamut(w.to_rgb(&(t[k] * r)));
            (
                luminance(c) / luminance(c0),
                (c[0] / c[2].max(1e-30)) / (c0[0] / c0[2]),
            )
        };
        // Outside the penumbra: full sunlight; inside it: the visible part of the Sun.
        assert!((at(1.3).0 - 1.0).abs() < 1e-3);
        let mid = at(0.96).0;
        assert!((0.3..0.75).contains(&mid), "{mid}");
        // The umbra: dark, red, darker towards the centre.
        let (y_centre, rb_centre) = at(0.0);
        let (y_half, rb_half) = at(0.35);
        assert!(y_centre < y_half && y_half < 1e-3, "{y_centre} {y_half}");
        assert!(y_centre > 1e-7, "{y_centre}");
        assert!(rb_centre > 5.0 && rb_half > 5.0, "{rb_centre} {rb_half}");
        // The umbra's edge sits near Danjon's radius (the light jumps by 10×
        // between 0.66° and 0.73°), and there the light is bluer than
        // sunlight: the ozone fringe.
        assert!(at(0.73).0 > 10.0 * at(0.66).0);
        let bluest = (660..730)
            .map(|k| at(k as f64 / 1000.0).1)
            .fold(f32::MAX, f32::min);
        assert!(bluest < 0.95, "{bluest}");
        // Monotonic brightening outwards.
        for k in 1..ECLIPSE_TABLE_N {
            assert!(w.to_y(&t[k]) >= w.to_y(&t[k - 1]) * 0.999, "{k}");
        }
    }
}
