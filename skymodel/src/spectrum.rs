//! Spectral bands, the extraterrestrial solar spectrum, the CIE 1931
//! colour-matching functions and the conversion of band radiances to
//! linear sRGB in cd/m².
//!
//! The atmosphere is computed in [`BANDS`] wavelength bands of 40 nm that
//! tile 380–780 nm. Every atmospheric quantity is evaluated at the band's
//! centre wavelength and expressed *per unit extraterrestrial solar
//! irradiance* (a "transfer factor", sr⁻¹ for radiance). The photometric
//! weight of a band is the integral of the solar spectral irradiance times
//! the colour-matching functions over the band (1 nm steps), times
//! K_m = 683 lm/W, so that
//!
//! XYZ = Σ_b f_b · W_b   (cd/m² when f_b is a radiance transfer factor in sr⁻¹)
//!
//! and Σ_b W_b.Y is the solar illuminance at 1 AU.

use std::ops::{Add, AddAssign, Div, Mul, MulAssign, Sub};

use crate::units::{Lux, Nanometres};

/// Number of wavelength bands.
pub const BANDS: usize = 10;
/// Lower edge of the first band, nm.
pub const BAND_START_NM: Nanometres = 380.0;
/// Width of one band, nm.
pub const BAND_WIDTH_NM: Nanometres = 40.0;

/// Centre wavelength of band `b`, nm.
pub fn band_centre_nm(b: usize) -> Nanometres {
    BAND_START_NM + BAND_WIDTH_NM * (b as f64 + 0.5)
}

/// A quantity sampled in the [`BANDS`] wavelength bands.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Spectrum(pub [f32; BANDS]);

impl Spectrum {
    /// All bands zero.
    pub const ZERO: Spectrum = Spectrum([0.0; BANDS]);
    /// All bands one.
    pub const ONE: Spectrum = Spectrum([1.0; BANDS]);
    /// All bands equal to `v`.
    pub fn splat(v: f32) -> Self {
        Spectrum([v; BANDS])
    }
    /// `f(band centre in nm)` for every band.
    pub fn from_fn(f: impl Fn(Nanometres) -> f64) -> Self {
        let mut s = [0.0; BANDS];
        for (b, v) in s.iter_mut().enumerate() {
            *v = f(band_centre_nm(b)) as f32;
        }
        Spectrum(s)
    }
    /// Applies `f` to every band.
    pub fn map(self, f: impl Fn(f32) -> f32) -> Self {
        let mut s = self.0;
        for v in s.iter_mut() {
            *v = f(*v);
        }
        Spectrum(s)
    }
    /// e^(−self), band by band (transmittance of an optical depth).
    pub fn exp_neg(self) -> Self {
        self.map(|x| (-x).exp())
    }
    /// Largest band value.
    pub fn max_value(&self) -> f32 {
        self.0.iter().copied().fold(f32::MIN, f32::max)
    }
    /// Whether every band is finite.
    pub fn is_finite(&self) -> bool {
        self.0.iter().all(|v| v.is_finite())
    }
}

impl Default for Spectrum {
    fn default() -> Self {
        Spectrum::ZERO
    }
}

macro_rules! bandwise {
    ($tr:ident, $f:ident, $op:tt) => {
        impl $tr for Spectrum {
            type Output = Spectrum;
            #[inline]
            #[allow(clippy::assign_op_pattern)]
            fn $f(self, o: Spectrum) -> Spectrum {
                let mut s = self.0;
                for b in 0..BANDS {
                    s[b] = s[b] $op o.0[b];
                }
                Spectrum(s)
            }
        }
        impl $tr<f32> for Spectrum {
            type Output = Spectrum;
            #[inline]
            #[allow(clippy::assign_op_pattern)]
            fn $f(self, o: f32) -> Spectrum {
                let mut s = self.0;
                for v in s.iter_mut() {
                    *v = *v $op o;
                }
                Spectrum(s)
            }
        }
    };
}
bandwise!(Add, add, +);
bandwise!(Sub, sub, -);
bandwise!(Mul, mul, *);
bandwise!(Div, div, /);

impl AddAssign for Spectrum {
    #[inline]
    fn add_assign(&mut self, o: Spectrum) {
        for b in 0..BANDS {
            self.0[b] += o.0[b];
        }
    }
}
impl MulAssign for Spectrum {
    #[inline]
    fn mul_assign(&mut self, o: Spectrum) {
        for b in 0..BANDS {
            self.0[b] *= o.0[b];
        }
    }
}

/// Maximum luminous efficacy of radiation, lm/W (CIE).
pub const K_M: f64 = 683.0;

/// Total solar irradiance at 1 AU, W/m² (Kopp & Lean 2011, 1360.8 ± 0.5).
pub const SOLAR_CONSTANT_W_M2: f64 = 1361.0;

/// Effective temperature of the Sun's photosphere, K (IAU 2015 B3 nominal 5772 K;
/// 5778 K is the classical value used here).
pub const SUN_TEMPERATURE_K: f64 = 5778.0;

/// Planck's law: spectral radiance of a black body, W m⁻² sr⁻¹ nm⁻¹, at
/// wavelength `nm` and temperature `t_k` (Planck 1901).
pub fn planck_radiance(nm: Nanometres, t_k: f64) -> f64 {
    const H: f64 = 6.626_070_15e-34;
    const C: f64 = 2.997_924_58e8;
    const KB: f64 = 1.380_649e-23;
    let l = nm * 1e-9;
    let x = H * C / (l * KB * t_k);
    2.0 * H * C * C / (l.powi(5) * (x.exp() - 1.0)) * 1e-9
}

/// Extraterrestrial solar spectral irradiance at 1 AU, W m⁻² nm⁻¹: a
/// 5778 K black body scaled so that its integral over all wavelengths is
/// the solar constant [`SOLAR_CONSTANT_W_M2`]. (A black body is within
/// ~10 % of the measured ASTM E-490 spectrum over 450–780 nm and brighter
/// below 420 nm, where Fraunhofer lines absorb; this is documented as the
/// model's main colour uncertainty.)
pub fn solar_irradiance(nm: Nanometres) -> f64 {
    // ∫ π B dλ = σ T⁴.
    const SIGMA: f64 = 5.670_374_419e-8;
    let total = SIGMA * SUN_TEMPERATURE_K.powi(4);
    std::f64::consts::PI * planck_radiance(nm, SUN_TEMPERATURE_K) * SOLAR_CONSTANT_W_M2 / total
}

fn lobe(l: f64, mu: f64, s1: f64, s2: f64) -> f64 {
    let s = if l < mu { s1 } else { s2 };
    let t = (l - mu) / s;
    (-0.5 * t * t).exp()
}

/// The CIE 1931 2° colour-matching functions x̄, ȳ, z̄ at `nm`, from the
/// multi-lobe Gaussian fit of Wyman, Sloan & Shirley (2013), "Simple
/// analytic approximations to the CIE XYZ colour matching functions",
/// JCGT 2(2), eq. 2 (error below 1 % of the peak).
pub fn cie_xyz_cmf(nm: Nanometres) -> [f64; 3] {
    let x = 1.056 * lobe(nm, 599.8, 37.9, 31.0) + 0.362 * lobe(nm, 442.0, 16.0, 26.7)
        - 0.065 * lobe(nm, 501.1, 20.4, 26.2);
    let y = 0.821 * lobe(nm, 568.8, 46.9, 40.5) + 0.286 * lobe(nm, 530.9, 16.3, 31.1);
    let z = 1.217 * lobe(nm, 437.0, 11.8, 36.0) + 0.681 * lobe(nm, 459.0, 26.0, 13.8);
    [x, y, z]
}

/// Linear sRGB (Rec. 709 primaries, D65) from CIE XYZ (IEC 61966-2-1).
/// Its Y row inverse is Y = 0.2126 R + 0.7152 G + 0.0722 B.
pub fn xyz_to_linear_srgb(xyz: [f64; 3]) -> [f64; 3] {
    let [x, y, z] = xyz;
    [
        3.240_454_2 * x - 1.537_138_5 * y - 0.498_531_4 * z,
        -0.969_266_0 * x + 1.876_010_8 * y + 0.041_556_0 * z,
        0.055_643_4 * x - 0.204_025_9 * y + 1.057_225_2 * z,
    ]
}

/// CIE XYZ from linear sRGB (inverse of [`xyz_to_linear_srgb`]).
pub fn linear_srgb_to_xyz(rgb: [f64; 3]) -> [f64; 3] {
    let [r, g, b] = rgb;
    [
        0.412_456_4 * r + 0.357_576_1 * g + 0.180_437_5 * b,
        0.212_672_9 * r + 0.715_152_2 * g + 0.072_175_0 * b,
        0.019_333_9 * r + 0.119_192_0 * g + 0.950_304_1 * b,
    ]
}

/// Luminance of linear sRGB in the units of its components
/// (conventions.md: Y = 0.2126 R + 0.7152 G + 0.0722 B).
pub fn luminance(rgb: [f32; 3]) -> f32 {
    0.2126 * rgb[0] + 0.7152 * rgb[1] + 0.0722 * rgb[2]
}

/// Brings an out-of-gamut linear sRGB colour (a negative component, e.g.
/// the saturated orange of the horizon at sunset) into the gamut by
/// desaturating it towards the grey of the same luminance; Y is kept.
#[inline]
pub fn clip_to_gamut(rgb: [f32; 3]) -> [f32; 3] {
    let min = rgb[0].min(rgb[1]).min(rgb[2]);
    if min >= 0.0 {
        return rgb;
    }
    let y = luminance(rgb);
    if y <= 0.0 {
        return [0.0; 3];
    }
    let t = y / (y - min);
    [
        (y + t * (rgb[0] - y)).max(0.0),
        (y + t * (rgb[1] - y)).max(0.0),
        (y + t * (rgb[2] - y)).max(0.0),
    ]
}

/// Photometric weights of the bands: for each band, the linear sRGB
/// (cd/m² per sr⁻¹ of transfer factor, i.e. lux) that a band transfer
/// factor of 1 produces under the 1 AU solar spectrum.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BandWeights {
    /// Linear sRGB weight of each band, lux.
    pub rgb: [[f32; 3]; BANDS],
    /// Luminance (Y) weight of each band, lux.
    pub y: [f32; BANDS],
}

impl BandWeights {
    /// The weights of the 1 AU solar spectrum ([`solar_irradiance`]),
    /// integrated over each band at 1 nm with the CIE 1931 functions.
    pub fn solar() -> Self {
        let mut rgb = [[0.0f32; 3]; BANDS];
        let mut yw = [0.0f32; BANDS];
        for b in 0..BANDS {
            let mut xyz = [0.0f64; 3];
            let lo = BAND_START_NM + BAND_WIDTH_NM * b as f64;
            let steps = BAND_WIDTH_NM as usize;
            for i in 0..steps {
                let nm = lo + i as f64 + 0.5;
                let e = solar_irradiance(nm) * K_M;
                let c = cie_xyz_cmf(nm);
                for k in 0..3 {
                    xyz[k] += e * c[k];
                }
            }
            let lin = xyz_to_linear_srgb(xyz);
            rgb[b] = [lin[0] as f32, lin[1] as f32, lin[2] as f32];
            yw[b] = xyz[1] as f32;
        }
        BandWeights { rgb, y: yw }
    }

    /// Linear sRGB of a band transfer factor `f` (sr⁻¹ → cd/m², or
    /// dimensionless → lux).
    #[inline]
    pub fn to_rgb(&self, f: &Spectrum) -> [f32; 3] {
        let mut out = [0.0f32; 3];
        for b in 0..BANDS {
            for (k, o) in out.iter_mut().enumerate() {
                *o += f.0[b] * self.rgb[b][k];
            }
        }
        out
    }

    /// Luminance of a band transfer factor.
    #[inline]
    pub fn to_y(&self, f: &Spectrum) -> f32 {
        let mut out = 0.0f32;
        for b in 0..BANDS {
            out += f.0[b] * self.y[b];
        }
        out
    }

    /// Solar illuminance at 1 AU, lux (≈ 127 klx for this spectrum).
    pub fn solar_illuminance_lux(&self) -> Lux {
        self.y.iter().map(|&v| v as f64).sum()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn solar_illuminance_near_published_constant() {
        // Published solar illuminance constants range 127.5 klx (Littlefair
        // 1985) to 133.8 klx (Darula et al. 2005).
        let e = BandWeights::solar().solar_illuminance_lux();
        assert!((124_000.0..134_000.0).contains(&e), "{e}");
    }

    #[test]
    fn black_body_integral_is_solar_constant() {
        let mut s = 0.0;
        let mut nm = 100.0;
        while nm < 100_000.0 {
            s += solar_irradiance(nm + 0.5);
            nm += 1.0;
        }
        assert!((s / SOLAR_CONSTANT_W_M2 - 1.0).abs() < 0.01, "{s}");
    }

    #[test]
    fn cmf_peaks() {
        // ȳ peaks at 555 nm with value 1.0 (CIE 1931).
        let y = cie_xyz_cmf(555.0)[1];
        assert!((y - 1.0).abs() < 0.02, "{y}");
        // Equal-energy white gives x ≈ y ≈ 1/3.
        let mut xyz = [0.0; 3];
        for nm in 380..781 {
            let c = cie_xyz_cmf(nm as f64);
            for k in 0..3 {
                xyz[k] += c[k];
            }
        }
        let s = xyz[0] + xyz[1] + xyz[2];
        assert!((xyz[0] / s - 1.0 / 3.0).abs() < 0.01);
        assert!((xyz[1] / s - 1.0 / 3.0).abs() < 0.01);
    }

    #[test]
    fn gamut_clip_keeps_luminance() {
        let c = [3.0f32, 1.0, -0.4];
        let g = clip_to_gamut(c);
        assert!(g.iter().all(|&v| v >= 0.0));
        assert!((luminance(g) - luminance(c)).abs() < 1e-5);
        assert!(g[0] > g[1] && g[1] >= g[2]);
        assert_eq!(clip_to_gamut([0.1, 0.2, 0.3]), [0.1, 0.2, 0.3]);
    }

    #[test]
    fn srgb_round_trip_and_luminance_row() {
        let rgb = [0.3, 0.5, 0.9];
        let back = xyz_to_linear_srgb(linear_srgb_to_xyz(rgb));
        for k in 0..3 {
            assert!((back[k] - rgb[k]).abs() < 1e-5);
        }
        let y = linear_srgb_to_xyz(rgb)[1] as f32;
        assert!((y - luminance([0.3, 0.5, 0.9])).abs() < 1e-4);
    }
}
