//! Star colours: B−V → effective temperature → blackbody spectrum →
//! CIE 1931 XYZ → linear sRGB (Rec. 709 primaries, D65 white).
//!
//! 1. B−V → T_eff: Ballesteros (2012), *EPL* 97, 34008, eq. 14 — a
//!    blackbody fit to the Johnson B and V passbands:
//!    T = 4600 K · (1/(0.92 (B−V) + 1.7) + 1/(0.92 (B−V) + 0.62)).
//! 2. T → chromaticity: Planck's law B_λ(T) integrated against the CIE 1931
//!    2° colour-matching functions (5 nm table, 360–830 nm, [`cmf_data`]).
//!    The seed thesis' alternative, the Kim et al. (2002) cubic fit of the
//!    Planckian locus (x(1/T) and y(x) in three segments), is
//!    [`kim_chromaticity`]; the tests hold the two within 0.0025.
//! 3. (x, y) → linear sRGB at luminance Y = 1 with the IEC 61966-2-1
//!    matrix. Colours outside the sRGB gamut (the bluest stars) are clipped
//!    at zero and rescaled to Y = 1.
//!
//! **White.** sRGB's white is D65 (x, y = 0.3127, 0.3290), a 6504 K
//! daylight. A star is rendered white when its blackbody chromaticity is
//! D65's, at B−V ≈ 0.35 (6 500 K). A Sun-like star (B−V = 0.65, 5 780 K)
//! sits 0.0153 from D65 (it is slightly yellow on an sRGB display) but 0.0073
//! from the equal-energy white E (1/3, 1/3); [`WHITE_E`] is the reference the
//! colour tests call "white" for the Sun.

pub mod cmf_data;

use crate::error::CatalogError;
use cmf_data::{CIE1931_2DEG, CMF_START_NM, CMF_STEP_NM};

/// A temperature in kelvin.
pub type Kelvin = f64;

/// CIE standard illuminant D65 white point (CIE 015:2004), the white of sRGB.
pub const WHITE_D65: (f64, f64) = (0.3127, 0.3290);
/// The equal-energy white point E.
pub const WHITE_E: (f64, f64) = (1.0 / 3.0, 1.0 / 3.0);

/// Second radiation constant c₂ = hc/k, m·K (CODATA 2018).
const C2_M_K: f64 = 1.438_776_877e-2;

/// Effective temperature (K) of a star of colour index `bv` (Johnson B−V,
/// mag), Ballesteros (2012) eq. 14. Accepts B−V in [−0.5, 3.0] (the formula
/// has a pole at −0.674); anything else, or NaN, is an error.
pub fn temperature_from_bv(bv: f64) -> Result<Kelvin, CatalogError> {
    let bv = CatalogError::check_range("B-V", bv, -0.5, 3.0)?;
    Ok(4600.0 * (1.0 / (0.92 * bv + 1.7) + 1.0 / (0.92 * bv + 0.62)))
}

/// Relative spectral radiance of a blackbody at wavelength `lambda_nm`
/// (Planck's law, B_λ up to a constant factor).
fn planck_relative(lambda_nm: f64, t: Kelvin) -> f64 {
    let l = lambda_nm * 1e-9;
    let x = C2_M_K / (l * t);
    // λ⁻⁵/(eˣ − 1) in units where λ is in µm, to stay in range.
    let lu = lambda_nm * 1e-3;
    1.0 / (lu.powi(5) * x.exp_m1())
}

/// CIE 1931 XYZ of a blackbody at `t` kelvin, normalised to Y = 1: Planck's
/// law summed against the 5 nm CIE 1931 2° colour-matching functions
/// (CIE 015:2004 §7.1, rectangle rule at 5 nm). `t` in [500, 10⁶] K.
pub fn planck_xyz(t: Kelvin) -> Result<[f64; 3], CatalogError> {
    let t = CatalogError::check_range("temperature", t, 500.0, 1e6)?;
    let mut xyz = [0.0f64; 3];
    for (i, cmf) in CIE1931_2DEG.iter().enumerate() {
        let b = planck_relative(CMF_START_NM + CMF_STEP_NM * i as f64, t);
        for k in 0..3 {
            xyz[k] += b * cmf[k];
        }
    }
    let y = xyz[1];
    Ok([xyz[0] / y, 1.0, xyz[2] / y])
}

/// CIE 1931 chromaticity (x, y) of a blackbody at `t` kelvin ([`planck_xyz`]).
pub fn planck_chromaticity(t: Kelvin) -> Result<(f64, f64), CatalogError> {
    let [x, y, z] = planck_xyz(t)?;
    let s = x + y + z;
    Ok((x / s, y / s))
}

/// The Planckian locus by the cubic fits of Kim et al. (2002), US patent
/// 7,024,034 ("Color temperature conversion"), as used by the seed thesis
/// (Table A.1): x(T) a cubic in 10³/T on 1 667–4 000 K and 4 000–25 000 K,
/// y(x) a cubic on 1 667–2 222, 2 222–4 000 and 4 000–25 000 K. `t` outside
/// [1667, 25000] K is an error.
pub fn kim_chromaticity(t: Kelvin) -> Result<(f64, f64), CatalogError> {
    let t = CatalogError::check_range("temperature", t, 1667.0, 25_000.0)?;
    let u = 1e3 / t;
    let x = if t <= 4000.0 {
        ((-0.266_123_9 * u - 0.234_358_9) * u + 0.877_695_6) * u + 0.179_910
    } else {
        ((-3.025_846_9 * u + 2.107_037_9) * u + 0.222_634_7) * u + 0.240_390
    };
    let y = if t <= 2222.0 {
        ((-1.106_381_4 * x - 1.348_110_20) * x + 2.185_558_32) * x - 0.202_196_83
    } else if t <= 4000.0 {
        ((-0.954_947_6 * x - 1.374_185_93) * x + 2.091_370_15) * x - 0.167_488_67
    } else {
        ((3.081_758_0 * x - 5.873_386_70) * x + 3.751_129_97) * x - 0.370_014_83
    };
    Ok((x, y))
}

/// Linear sRGB (Rec. 709 primaries, D65 white; IEC 61966-2-1 matrix) of
/// the chromaticity (x, y) at luminance Y = 1. Components may be negative
/// outside the sRGB gamut. `y` must be positive.
pub fn xy_to_linear_srgb(x: f64, y: f64) -> Result<[f64; 3], CatalogError> {
    let y = CatalogError::check_range("chromaticity y", y, 1e-6, 1.0)?;
    let x = CatalogError::check_range("chromaticity x", x, 0.0, 1.0)?;
    let (cx, cy, cz) = (x / y, 1.0, (1.0 - x - y) / y);
    Ok([
        3.2406 * cx - 1.5372 * cy - 0.4986 * cz,
        -0.9689 * cx + 1.8758 * cy + 0.0415 * cz,
        0.0557 * cx - 0.2040 * cy + 1.0570 * cz,
    ])
}

/// Luminance Y of linear sRGB (Rec. 709 coefficients).
pub fn luminance(rgb: [f64; 3]) -> f64 {
    0.2126 * rgb[0] + 0.7152 * rgb[1] + 0.0722 * rgb[2]
}

/// Which model turns a temperature into a chromaticity.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum LocusModel {
    /// Planck's law against the CIE 1931 CMFs (the reference).
    #[default]
    Blackbody,
    /// Kim et al. (2002) cubic fits (the seed thesis' choice).
    Kim,
}

/// The colour of a star of colour index `bv` as linear sRGB with luminance
/// Y = 1 (multiply by the star's luminance or illuminance): B−V → T
/// ([`temperature_from_bv`], B−V clamped to [−0.4, 2.5]) → chromaticity
/// (`model`; Kim's fit clamps T to its range) → sRGB, negative components
/// clipped and the result rescaled to Y = 1. `None` (unknown colour) and
/// NaN give D65 white, [1, 1, 1].
pub fn star_rgb(bv: Option<f64>, model: LocusModel) -> [f64; 3] {
    let Some(bv) = bv.filter(|b| b.is_finite()) else {
        return [1.0, 1.0, 1.0];
    };
    let bv = bv.clamp(-0.4, 2.5);
    let t = match temperature_from_bv(bv) {
        Ok(t) => t,
        Err(_) => return [1.0, 1.0, 1.0],
    };
    let xy = match model {
        LocusModel::Blackbody => planck_chromaticity(t),
        LocusModel::Kim => kim_chromaticity(t.clamp(1667.0, 25_000.0)),
    };
    let rgb = match xy.and_then(|(x, y)| xy_to_linear_srgb(x, y)) {
        Ok(c) => c,
        Err(_) => return [1.0, 1.0, 1.0],
    };
    let clipped = rgb.map(|c| c.max(0.0));
    let y = luminance(clipped);
    if y > 0.0 {
        clipped.map(|c| c / y)
    } else {
        [1.0, 1.0, 1.0]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn dist(a: (f64, f64), b: (f64, f64)) -> f64 {
        (a.0 - b.0).hypot(a.1 - b.1)
    }

    #[test]
    fn illuminant_a_is_a_2856_k_planckian_radiator() {
        // CIE illuminant A (CIE 015:2004 eq. 3.1): Planck's law with
        // c₂/T = 1.435e-2 m·K / 2848 K (≈ 2856 K with c₂ = 1.4388e-2),
        // chromaticity (0.44757, 0.40745) (CIE 015:2004 Table T.3).
        let t = 2848.0 * C2_M_K / 1.435e-2;
        let xy = planck_chromaticity(t).unwrap();
        assert!(dist(xy, (0.44757, 0.40745)) < 2e-4, "{xy:?}");
    }

    #[test]
    fn d65_white_maps_to_equal_rgb() {
        let rgb = xy_to_linear_srgb(WHITE_D65.0, WHITE_D65.1).unwrap();
        for c in rgb {
            assert!((c - 1.0).abs() < 2e-3, "{rgb:?}");
        }
    }

    #[test]
    fn kim_fit_agrees_with_blackbody_integration() {
        let mut worst: f64 = 0.0;
        let mut t = 1700.0;
        while t <= 25_000.0 {
            let d = dist(
                kim_chromaticity(t).unwrap(),
                planck_chromaticity(t).unwrap(),
            );
            worst = worst.max(d);
            t *= 1.05;
        }
        assert!(worst < 2.5e-3, "{worst}");
    }

    #[test]
    fn ballesteros_reference_values() {
        // The Sun: B−V = 0.65 → 5 780 K within 1 % (Ballesteros 2012 §4).
        let t = temperature_from_bv(0.65).unwrap();
        assert!((t - 5778.0).abs() < 60.0, "{t}");
        assert!(temperature_from_bv(f64::NAN).is_err());
        assert!(temperature_from_bv(-0.7).is_err());
    }

    #[test]
    fn sun_like_star_is_white() {
        let xy = planck_chromaticity(temperature_from_bv(0.65).unwrap()).unwrap();
        assert!(dist(xy, WHITE_E) < 0.01, "{xy:?}");
        // …and 0.012–0.018 from D65 (a 5 780 K blackbody is yellower than
        // 6 504 K daylight): documented, not hidden.
        let d = dist(xy, WHITE_D65);
        assert!(d > 0.012 && d < 0.018, "{d}");
        // The blackbody of ~6 500 K is D65 white within 0.01.
        assert!(dist(planck_chromaticity(6504.0).unwrap(), WHITE_D65) < 0.01);
    }

    #[test]
    fn betelgeuse_red_rigel_blue() {
        // Catalogue B−V: Betelgeuse 1.85, Rigel −0.03.
        for model in [LocusModel::Blackbody, LocusModel::Kim] {
            let b = star_rgb(Some(1.85), model);
            assert!(b[0] > b[1] && b[1] > b[2], "{b:?}");
            let r = star_rgb(Some(-0.03), model);
            assert!(r[2] > r[0], "{r:?}");
            for c in [b, r] {
                assert!((luminance(c) - 1.0).abs() < 1e-9);
            }
        }
        assert_eq!(star_rgb(None, LocusModel::Blackbody), [1.0, 1.0, 1.0]);
        assert_eq!(star_rgb(Some(f64::NAN), LocusModel::Kim), [1.0, 1.0, 1.0]);
        assert!(star_rgb(Some(99.0), LocusModel::Kim)
            .iter()
            .all(|c| c.is_finite()));
    }
}
