//! Nutation in longitude and obliquity.

use crate::units::{JulianCenturies, Radians, ARCSEC, DEG};

/// Nutation in longitude Δψ and in obliquity Δε, radians.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Nutation {
    /// Nutation in longitude Δψ, radians.
    pub dpsi: Radians,
    /// Nutation in obliquity Δε, radians.
    pub deps: Radians,
}

/// Which nutation series to evaluate.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum NutationModel {
    /// IAU 1980 theory, the 63 terms of Meeus Table 22.A (terms below
    /// 0.0003″ omitted); ~0.001″ from the full 106-term series.
    Iau1980,
    /// Meeus' low-accuracy expressions (four terms each): 0.5″ in Δψ,
    /// 0.1″ in Δε.
    Short,
}

/// One row of Meeus Table 22.A: multiples of D, M, M′, F, Ω; then the
/// coefficients of sin (Δψ) and cos (Δε) in units of 0.0001″, constant and
/// per Julian century.
type Term = ([i8; 5], f64, f64, f64, f64);

/// IAU 1980 nutation, periodic terms of Meeus, *Astronomical Algorithms*
/// 2nd ed., Table 22.A (from Seidelmann 1982 / Wahr 1981).
#[rustfmt::skip]
const TERMS: [Term; 63] = [
    ([ 0,  0,  0,  0, 1], -171996.0, -174.2, 92025.0,  8.9),
    ([-2,  0,  0,  2, 2],  -13187.0,   -1.6,  5736.0, -3.1),
    ([ 0,  0,  0,  2, 2],   -2274.0,   -0.2,   977.0, -0.5),
    ([ 0,  0,  0,  0, 2],    2062.0,    0.2,  -895.0,  0.5),
    ([ 0,  1,  0,  0, 0],    1426.0,   -3.4,    54.0, -0.1),
    ([ 0,  0,  1,  0, 0],     712.0,    0.1,    -7.0,  0.0),
    ([-2,  1,  0,  2, 2],    -517.0,    1.2,   224.0, -0.6),
    ([ 0,  0,  0,  2, 1],    -386.0,   -0.4,   200.0,  0.0),
    ([ 0,  0,  1,  2, 2],    -301.0,    0.0,   129.0, -0.1),
    ([-2, -1,  0,  2, 2],     217.0,   -0.5,   -95.0,  0.3),
    ([-2,  0,  1,  0, 0],    -158.0,    0.0,     0.0,  0.0),
    ([-2,  0,  0,  2, 1],     129.0,    0.1,   -70.0,  0.0),
    ([ 0,  0, -1,  2, 2],     123.0,    0.0,   -53.0,  0.0),
    ([ 2,  0,  0,  0, 0],      63.0,    0.0,     0.0,  0.0),
    ([ 0,  0,  1,  0, 1],      63.0,    0.1,   -33.0,  0.0),
    ([ 2,  0, -1,  2, 2],     -59.0,    0.0,    26.0,  0.0),
    ([ 0,  0, -1,  0, 1],     -58.0,   -0.1,    32.0,  0.0),
    ([ 0,  0,  1,  2, 1],     -51.0,    0.0,    27.0,  0.0),
    ([-2,  0,  2,  0, 0],      48.0,    0.0,     0.0,  0.0),
    ([ 0,  0, -2,  2, 1],      46.0,    0.0,   -24.0,  0.0),
    ([ 2,  0,  0,  2, 2],     -38.0,    0.0,    16.0,  0.0),
    ([ 0,  0,  2,  2, 2],     -31.0,    0.0,    13.0,  0.0),
    ([ 0,  0,  2,  0, 0],      29.0,    0.0,     0.0,  0.0),
    ([-2,  0,  1,  2, 2],      29.0,    0.0,   -12.0,  0.0),
    ([ 0,  0,  0,  2, 0],      26.0,    0.0,     0.0,  0.0),
    ([-2,  0,  0,  2, 0],     -22.0,    0.0,     0.0,  0.0),
    ([ 0,  0, -1,  2, 1],      21.0,    0.0,   -10.0,  0.0),
    ([ 0,  2,  0,  0, 0],      17.0,   -0.1,     0.0,  0.0),
    ([ 2,  0, -1,  0, 1],      16.0,    0.0,    -8.0,  0.0),
    ([-2,  2,  0,  2, 2],     -16.0,    0.1,     7.0,  0.0),
    ([ 0,  1,  0,  0, 1],     -15.0,    0.0,     9.0,  0.0),
    ([-2,  0,  1,  0, 1],     -13.0,    0.0,     7.0,  0.0),
    ([ 0, -1,  0,  0, 1],     -12.0,    0.0,     6.0,  0.0),
    ([ 0,  0,  2, -2, 0],      11.0,    0.0,     0.0,  0.0),
    ([ 2,  0, -1,  2, 1],     -10.0,    0.0,     5.0,  0.0),
    ([ 2,  0,  1,  2, 2],      -8.0,    0.0,     3.0,  0.0),
    ([ 0,  1,  0,  2, 2],       7.0,    0.0,    -3.0,  0.0),
    ([-2,  1,  1,  0, 0],      -7.0,    0.0,     0.0,  0.0),
    ([ 0, -1,  0,  2, 2],      -7.0,    0.0,     3.0,  0.0),
    ([ 2,  0,  0,  2, 1],      -7.0,    0.0,     3.0,  0.0),
    ([ 2,  0,  1,  0, 0],       6.0,    0.0,     0.0,  0.0),
    ([-2,  0,  2,  2, 2],       6.0,    0.0,    -3.0,  0.0),
    ([-2,  0,  1,  2, 1],       6.0,    0.0,    -3.0,  0.0),
    ([ 2,  0, -2,  0, 1],      -6.0,    0.0,     3.0,  0.0),
    ([ 2,  0,  0,  0, 1],      -6.0,    0.0,     3.0,  0.0),
    ([ 0, -1,  1,  0, 0],       5.0,    0.0,     0.0,  0.0),
    ([-2, -1,  0,  2, 1],      -5.0,    0.0,     3.0,  0.0),
    ([-2,  0,  0,  0, 1],      -5.0,    0.0,     3.0,  0.0),
    ([ 0,  0,  2,  2, 1],      -5.0,    0.0,     3.0,  0.0),
    ([-2,  0,  2,  0, 1],       4.0,    0.0,     0.0,  0.0),
    ([-2,  1,  0,  2, 1],       4.0,    0.0,     0.0,  0.0),
    ([ 0,  0,  1, -2, 0],       4.0,    0.0,     0.0,  0.0),
    ([-1,  0,  1,  0, 0],      -4.0,    0.0,     0.0,  0.0),
    ([-2,  1,  0,  0, 0],      -4.0,    0.0,     0.0,  0.0),
    ([ 1,  0,  0,  0, 0],      -4.0,    0.0,     0.0,  0.0),
    ([ 0,  0,  1,  2, 0],       3.0,    0.0,     0.0,  0.0),
    ([ 0,  0, -2,  2, 2],      -3.0,    0.0,     0.0,  0.0),
    ([-1, -1,  1,  0, 0],      -3.0,    0.0,     0.0,  0.0),
    ([ 0,  1,  1,  0, 0],      -3.0,    0.0,     0.0,  0.0),
    ([ 0, -1,  1,  2, 2],      -3.0,    0.0,     0.0,  0.0),
    ([ 2, -1, -1,  2, 2],      -3.0,    0.0,     0.0,  0.0),
    ([ 0,  0,  3,  2, 2],      -3.0,    0.0,     0.0,  0.0),
    ([ 2, -1,  0,  2, 2],      -3.0,    0.0,     0.0,  0.0),
];

/// Largest multiple of any fundamental argument in [`TERMS`].
const MAX_MULTIPLE: usize = 3;

/// Units of the table, 0.0001″, in radians.
const UNIT: f64 = 1e-4 * ARCSEC;

/// The five fundamental arguments D, M, M′, F, Ω (radians) of Meeus ch. 22:
/// the Moon's mean elongation from the Sun, the Sun's and the Moon's mean
/// anomalies, the Moon's argument of latitude and the longitude of the
/// ascending node of the Moon's mean orbit on the ecliptic, measured from the
/// mean equinox of date.
pub fn fundamental_arguments(t: JulianCenturies) -> [Radians; 5] {
    let d = 297.850_36 + t * (445_267.111_480 + t * (-0.001_914_2 + t / 189_474.0));
    let m = 357.527_72 + t * (35_999.050_340 + t * (-0.000_160_3 - t / 300_000.0));
    let mp = 134.962_98 + t * (477_198.867_398 + t * (0.008_697_2 + t / 56_250.0));
    let f = 93.271_91 + t * (483_202.017_538 + t * (-0.003_682_5 + t / 327_270.0));
    let om = 125.044_52 + t * (-1_934.136_261 + t * (0.002_070_8 + t / 450_000.0));
    [d, m, mp, f, om].map(|deg| crate::units::reduce_deg(deg) * DEG)
}

/// Nutation at `t` Julian centuries of TT from J2000.0, radians.
///
/// * [`NutationModel::Iau1980`]: the 63-term series of Meeus, *Astronomical
///   Algorithms* 2nd ed., Table 22.A. The sine and cosine of each fundamental
///   argument are computed once; every term's argument is then built with
///   angle-addition products (cos, sin of k·x by recurrence), so the series
///   costs 10 trigonometric calls instead of 126.
/// * [`NutationModel::Short`]: Meeus ch. 22, low-accuracy expressions in the
///   mean longitudes of Sun and Moon and Ω (0.5″ in Δψ, 0.1″ in Δε).
pub fn nutation(t: JulianCenturies, model: NutationModel) -> Nutation {
    match model {
        NutationModel::Iau1980 => nutation_iau1980(t),
        NutationModel::Short => nutation_short(t),
    }
}

/// Complex product (cos a, sin a)·(cos b, sin b) = (cos(a+b), sin(a+b)).
#[inline(always)]
fn mul(a: (f64, f64), b: (f64, f64)) -> (f64, f64) {
    (a.0 * b.0 - a.1 * b.1, a.0 * b.1 + a.1 * b.0)
}

// Kept out of line: inlined into its callers it bloats their frames and
// slows the short path that shares them.
#[inline(never)]
fn nutation_iau1980(t: JulianCenturies) -> Nutation {
    let args = fundamental_arguments(t);
    // powers[j][k] = (cos k·xⱼ, sin k·xⱼ), k = 0..=MAX_MULTIPLE.
    let mut powers = [[(1.0, 0.0); MAX_MULTIPLE + 1]; 5];
    for (j, &x) in args.iter().enumerate() {
        let unit = (libm::cos(x), libm::sin(x));
        for k in 1..=MAX_MULTIPLE {
            powers[j][k] = mul(powers[j][k - 1], unit);
        }
    }
    let mut dpsi = 0.0;
    let mut deps = 0.0;
    // Smallest terms first, for a slightly better sum.
    for &(mult, a, b, c, d) in TERMS.iter().rev() {
        let mut z = (1.0, 0.0);
        for (j, &m) in mult.iter().enumerate() {
            if m != 0 {
                let p = powers[j][m.unsigned_abs() as usize];
                // Negative multiple: complex conjugate.
                let p = if m < 0 { (p.0, -p.1) } else { p };
                z = mul(z, p);
            }
        }
        dpsi += (a + b * t) * z.1;
        deps += (c + d * t) * z.0;
    }
    Nutation {
        dpsi: dpsi * UNIT,
        deps: deps * UNIT,
    }
}

fn nutation_short(t: JulianCenturies) -> Nutation {
    // 4e-7 relative on terms of at most 17″: far below the series' own 0.5″.
    use crate::fastmath::sincos_turns_low as sincos_turns;
    // Twice the mean longitudes of Sun and Moon, and Ω (Meeus ch. 22), in
    // turns: the polynomial sincos reduces whole turns itself.
    let two_l_sun = (280.4665 + 36_000.769_8 * t) * (1.0 / 180.0);
    let two_l_moon = (218.3165 + 481_267.881_3 * t) * (1.0 / 180.0);
    let om =
        (125.044_52 + t * (-1_934.136_261 + t * (0.002_070_8 + t / 450_000.0))) * (1.0 / 360.0);
    nutation_short_from(
        sincos_turns(om),
        sincos_turns(two_l_sun),
        sincos_turns(two_l_moon),
    )
}

/// Meeus' low-accuracy nutation (ch. 22) from (sin, cos) of Ω, of twice the
/// Sun's mean longitude and of twice the Moon's mean longitude, for callers
/// that already hold these phasors (the low tier's [`crate::Epoch`]).
#[inline]
pub(crate) fn nutation_short_from(
    (s_om, c_om): (f64, f64),
    (s_ls, c_ls): (f64, f64),
    (s_lm, c_lm): (f64, f64),
) -> Nutation {
    // sin 2Ω = 2 sin Ω cos Ω, cos 2Ω = 1 − 2 sin² Ω.
    let (s_2om, c_2om) = (2.0 * s_om * c_om, 1.0 - 2.0 * s_om * s_om);
    let dpsi = -17.20 * s_om - 1.32 * s_ls - 0.23 * s_lm + 0.21 * s_2om;
    let deps = 9.20 * c_om + 0.57 * c_ls + 0.10 * c_lm - 0.09 * c_2om;
    Nutation {
        dpsi: dpsi * ARCSEC,
        deps: deps * ARCSEC,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Straightforward evaluation: one sin and one cos per term.
    fn reference(t: f64) -> Nutation {
        let x = fundamental_arguments(t);
        let (mut dpsi, mut deps) = (0.0, 0.0);
        for &(m, a, b, c, d) in TERMS.iter() {
            let arg: f64 = (0..5).map(|j| m[j] as f64 * x[j]).sum();
            dpsi += (a + b * t) * libm::sin(arg);
            deps += (c + d * t) * libm::cos(arg);
        }
        Nutation {
            dpsi: dpsi * UNIT,
            deps: deps * UNIT,
        }
    }

    #[test]
    fn fast_path_matches_reference() {
        let mut t = -30.0;
        while t <= 30.0 {
            let a = nutation(t, NutationModel::Iau1980);
            let b = reference(t);
            assert!((a.dpsi - b.dpsi).abs() < 1e-12, "{t}");
            assert!((a.deps - b.deps).abs() < 1e-12, "{t}");
            t += 0.0137;
        }
    }

    #[test]
    fn multiples_within_precomputed_range() {
        for (m, ..) in TERMS.iter() {
            assert!(m.iter().all(|&k| k.unsigned_abs() as usize <= MAX_MULTIPLE));
        }
    }

    #[test]
    fn meeus_example_22a() {
        // 1987 April 10, 0h TD: Δψ = −3.788″, Δε = +9.443″.
        let t = -0.127_296_372_348;
        let n = nutation(t, NutationModel::Iau1980);
        assert!(
            (n.dpsi / ARCSEC + 3.788).abs() < 5e-4,
            "{}",
            n.dpsi / ARCSEC
        );
        assert!(
            (n.deps / ARCSEC - 9.443).abs() < 5e-4,
            "{}",
            n.deps / ARCSEC
        );
        // True obliquity ε = 23°26′36.850″.
        let eps = super::super::mean_obliquity(t) + n.deps;
        assert!((eps / ARCSEC - (23.0 * 3600.0 + 26.0 * 60.0 + 36.850)).abs() < 1e-3);
        let s = nutation(t, NutationModel::Short);
        assert!((s.dpsi - n.dpsi).abs() < 0.5 * ARCSEC);
        assert!((s.deps - n.deps).abs() < 0.1 * ARCSEC);
    }

    #[test]
    fn short_model_accuracy_over_two_centuries() {
        let mut t = -1.0;
        while t <= 1.0 {
            let s = nutation(t, NutationModel::Short);
            let f = nutation(t, NutationModel::Iau1980);
            assert!((s.dpsi - f.dpsi).abs() < 0.6 * ARCSEC, "{t}");
            assert!((s.deps - f.deps).abs() < 0.15 * ARCSEC, "{t}");
            t += 0.00731;
        }
    }
}
