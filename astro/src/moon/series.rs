//! The Moon after Meeus, *Astronomical Algorithms* 2nd ed. (1998), chapter 47:
//! the ELP-2000/82 lunar theory of Chapront-Touzé & Chapront truncated to the
//! 60 + 60 periodic terms of Tables 47.A and 47.B, plus the additive terms
//! in A1, A2, A3 (Venus, Jupiter and the Earth's flattening) and the factor
//! E for the decreasing eccentricity of the Earth's orbit.
//!
//! Evaluation: every periodic term has an argument that is an integer
//! combination of the four Delaunay-type arguments D, M, M′, F with
//! multipliers |D| ≤ 4, |M| ≤ 2, |M′| ≤ 4, |F| ≤ 3. We take sin/cos of the
//! four arguments once, build their multiples as unit complex numbers by
//! repeated multiplication, and form each term's e^{i·arg} as a product of
//! four table entries. A term then costs three complex multiplications
//! instead of a call to `sin` (and one to `cos`). E^|M| is folded into the
//! M multiples, so the eccentricity factor costs nothing per term.

use crate::units::{wrap_360, JulianCenturies, Km, Radians, DEG};

/// One row of Meeus Table 47.A.
struct LonDistTerm {
    /// Multiples of (D, M, M′, F).
    arg: [i8; 4],
    /// Σl coefficient of the sine, 1e-6 degree.
    sigma_l: i32,
    /// Σr coefficient of the cosine, 1e-3 km.
    sigma_r: i32,
}

/// One row of Meeus Table 47.B.
struct LatTerm {
    /// Multiples of (D, M, M′, F).
    arg: [i8; 4],
    /// Σb coefficient of the sine, 1e-6 degree.
    sigma_b: i32,
}

/// Table 47.A: multiples of (D, M, M′, F); Σl coefficient (sine, 1e-6°); Σr coefficient (cosine, 1e-3 km).
#[rustfmt::skip]
static TABLE_47A: [LonDistTerm; 60] = [
    LonDistTerm { arg: [ 0,  0,  1,  0], sigma_l:  6288774, sigma_r: -20905355 },
    LonDistTerm { arg: [ 2,  0, -1,  0], sigma_l:  1274027, sigma_r:  -3699111 },
    LonDistTerm { arg: [ 2,  0,  0,  0], sigma_l:   658314, sigma_r:  -2955968 },
    LonDistTerm { arg: [ 0,  0,  2,  0], sigma_l:   213618, sigma_r:   -569925 },
    LonDistTerm { arg: [ 0,  1,  0,  0], sigma_l:  -185116, sigma_r:     48888 },
    LonDistTerm { arg: [ 0,  0,  0,  2], sigma_l:  -114332, sigma_r:     -3149 },
    LonDistTerm { arg: [ 2,  0, -2,  0], sigma_l:    58793, sigma_r:    246158 },
    LonDistTerm { arg: [ 2, -1, -1,  0], sigma_l:    57066, sigma_r:   -152138 },
    LonDistTerm { arg: [ 2,  0,  1,  0], sigma_l:    53322, sigma_r:   -170733 },
    LonDistTerm { arg: [ 2, -1,  0,  0], sigma_l:    45758, sigma_r:   -204586 },
    LonDistTerm { arg: [ 0,  1, -1,  0], sigma_l:   -40923, sigma_r:   -129620 },
    LonDistTerm { arg: [ 1,  0,  0,  0], sigma_l:   -34720, sigma_r:    108743 },
    LonDistTerm { arg: [ 0,  1,  1,  0], sigma_l:   -30383, sigma_r:    104755 },
    LonDistTerm { arg: [ 2,  0,  0, -2], sigma_l:    15327, sigma_r:     10321 },
    LonDistTerm { arg: [ 0,  0,  1,  2], sigma_l:   -12528, sigma_r:         0 },
    LonDistTerm { arg: [ 0,  0,  1, -2], sigma_l:    10980, sigma_r:     79661 },
    LonDistTerm { arg: [ 4,  0, -1,  0], sigma_l:    10675, sigma_r:    -34782 },
    LonDistTerm { arg: [ 0,  0,  3,  0], sigma_l:    10034, sigma_r:    -23210 },
    LonDistTerm { arg: [ 4,  0, -2,  0], sigma_l:     8548, sigma_r:    -21636 },
    LonDistTerm { arg: [ 2,  1, -1,  0], sigma_l:    -7888, sigma_r:     24208 },
    LonDistTerm { arg: [ 2,  1,  0,  0], sigma_l:    -6766, sigma_r:     30824 },
    LonDistTerm { arg: [ 1,  0, -1,  0], sigma_l:    -5163, sigma_r:     -8379 },
    LonDistTerm { arg: [ 1,  1,  0,  0], sigma_l:     4987, sigma_r:    -16675 },
    LonDistTerm { arg: [ 2, -1,  1,  0], sigma_l:     4036, sigma_r:    -12831 },
    LonDistTerm { arg: [ 2,  0,  2,  0], sigma_l:     3994, sigma_r:    -10445 },
    LonDistTerm { arg: [ 4,  0,  0,  0], sigma_l:     3861, sigma_r:    -11650 },
    LonDistTerm { arg: [ 2,  0, -3,  0], sigma_l:     3665, sigma_r:     14403 },
    LonDistTerm { arg: [ 0,  1, -2,  0], sigma_l:    -2689, sigma_r:     -7003 },
    LonDistTerm { arg: [ 2,  0, -1,  2], sigma_l:    -2602, sigma_r:         0 },
    LonDistTerm { arg: [ 2, -1, -2,  0], sigma_l:     2390, sigma_r:     10056 },
    LonDistTerm { arg: [ 1,  0,  1,  0], sigma_l:    -2348, sigma_r:      6322 },
    LonDistTerm { arg: [ 2, -2,  0,  0], sigma_l:     2236, sigma_r:     -9884 },
    LonDistTerm { arg: [ 0,  1,  2,  0], sigma_l:    -2120, sigma_r:      5751 },
    LonDistTerm { arg: [ 0,  2,  0,  0], sigma_l:    -2069, sigma_r:         0 },
    LonDistTerm { arg: [ 2, -2, -1,  0], sigma_l:     2048, sigma_r:     -4950 },
    LonDistTerm { arg: [ 2,  0,  1, -2], sigma_l:    -1773, sigma_r:      4130 },
    LonDistTerm { arg: [ 2,  0,  0,  2], sigma_l:    -1595, sigma_r:         0 },
    LonDistTerm { arg: [ 4, -1, -1,  0], sigma_l:     1215, sigma_r:     -3958 },
    LonDistTerm { arg: [ 0,  0,  2,  2], sigma_l:    -1110, sigma_r:         0 },
    LonDistTerm { arg: [ 3,  0, -1,  0], sigma_l:     -892, sigma_r:      3258 },
    LonDistTerm { arg: [ 2,  1,  1,  0], sigma_l:     -810, sigma_r:      2616 },
    LonDistTerm { arg: [ 4, -1, -2,  0], sigma_l:      759, sigma_r:     -1897 },
    LonDistTerm { arg: [ 0,  2, -1,  0], sigma_l:     -713, sigma_r:     -2117 },
    LonDistTerm { arg: [ 2,  2, -1,  0], sigma_l:     -700, sigma_r:      2354 },
    LonDistTerm { arg: [ 2,  1, -2,  0], sigma_l:      691, sigma_r:         0 },
    LonDistTerm { arg: [ 2, -1,  0, -2], sigma_l:      596, sigma_r:         0 },
    LonDistTerm { arg: [ 4,  0,  1,  0], sigma_l:      549, sigma_r:     -1423 },
    LonDistTerm { arg: [ 0,  0,  4,  0], sigma_l:      537, sigma_r:     -1117 },
    LonDistTerm { arg: [ 4, -1,  0,  0], sigma_l:      520, sigma_r:     -1571 },
    LonDistTerm { arg: [ 1,  0, -2,  0], sigma_l:     -487, sigma_r:     -1739 },
    LonDistTerm { arg: [ 2,  1,  0, -2], sigma_l:     -399, sigma_r:         0 },
    LonDistTerm { arg: [ 0,  0,  2, -2], sigma_l:     -381, sigma_r:     -4421 },
    LonDistTerm { arg: [ 1,  1,  1,  0], sigma_l:      351, sigma_r:         0 },
    LonDistTerm { arg: [ 3,  0, -2,  0], sigma_l:     -340, sigma_r:         0 },
    LonDistTerm { arg: [ 4,  0, -3,  0], sigma_l:      330, sigma_r:         0 },
    LonDistTerm { arg: [ 2, -1,  2,  0], sigma_l:      327, sigma_r:         0 },
    LonDistTerm { arg: [ 0,  2,  1,  0], sigma_l:     -323, sigma_r:      1165 },
    LonDistTerm { arg: [ 1,  1, -1,  0], sigma_l:      299, sigma_r:         0 },
    LonDistTerm { arg: [ 2,  0,  3,  0], sigma_l:      294, sigma_r:         0 },
    LonDistTerm { arg: [ 2,  0, -1, -2], sigma_l:        0, sigma_r:      8752 },
];

/// Table 47.B: multiples of (D, M, M′, F); Σb coefficient (sine, 1e-6°).
#[rustfmt::skip]
static TABLE_47B: [LatTerm; 60] = [
    LatTerm { arg: [ 0,  0,  0,  1], sigma_b:  5128122 },
    LatTerm { arg: [ 0,  0,  1,  1], sigma_b:   280602 },
    LatTerm { arg: [ 0,  0,  1, -1], sigma_b:   277693 },
    LatTerm { arg: [ 2,  0,  0, -1], sigma_b:   173237 },
    LatTerm { arg: [ 2,  0, -1,  1], sigma_b:    55413 },
    LatTerm { arg: [ 2,  0, -1, -1], sigma_b:    46271 },
    LatTerm { arg: [ 2,  0,  0,  1], sigma_b:    32573 },
    LatTerm { arg: [ 0,  0,  2,  1], sigma_b:    17198 },
    LatTerm { arg: [ 2,  0,  1, -1], sigma_b:     9266 },
    LatTerm { arg: [ 0,  0,  2, -1], sigma_b:     8822 },
    LatTerm { arg: [ 2, -1,  0, -1], sigma_b:     8216 },
    LatTerm { arg: [ 2,  0, -2, -1], sigma_b:     4324 },
    LatTerm { arg: [ 2,  0,  1,  1], sigma_b:     4200 },
    LatTerm { arg: [ 2,  1,  0, -1], sigma_b:    -3359 },
    LatTerm { arg: [ 2, -1, -1,  1], sigma_b:     2463 },
    LatTerm { arg: [ 2, -1,  0,  1], sigma_b:     2211 },
    LatTerm { arg: [ 2, -1, -1, -1], sigma_b:     2065 },
    LatTerm { arg: [ 0,  1, -1, -1], sigma_b:    -1870 },
    LatTerm { arg: [ 4,  0, -1, -1], sigma_b:     1828 },
    LatTerm { arg: [ 0,  1,  0,  1], sigma_b:    -1794 },
    LatTerm { arg: [ 0,  0,  0,  3], sigma_b:    -1749 },
    LatTerm { arg: [ 0,  1, -1,  1], sigma_b:    -1565 },
    LatTerm { arg: [ 1,  0,  0,  1], sigma_b:    -1491 },
    LatTerm { arg: [ 0,  1,  1,  1], sigma_b:    -1475 },
    LatTerm { arg: [ 0,  1,  1, -1], sigma_b:    -1410 },
    LatTerm { arg: [ 0,  1,  0, -1], sigma_b:    -1344 },
    LatTerm { arg: [ 1,  0,  0, -1], sigma_b:    -1335 },
    LatTerm { arg: [ 0,  0,  3,  1], sigma_b:     1107 },
    LatTerm { arg: [ 4,  0,  0, -1], sigma_b:     1021 },
    LatTerm { arg: [ 4,  0, -1,  1], sigma_b:      833 },
    LatTerm { arg: [ 0,  0,  1, -3], sigma_b:      777 },
    LatTerm { arg: [ 4,  0, -2,  1], sigma_b:      671 },
    LatTerm { arg: [ 2,  0,  0, -3], sigma_b:      607 },
    LatTerm { arg: [ 2,  0,  2, -1], sigma_b:      596 },
    LatTerm { arg: [ 2, -1,  1, -1], sigma_b:      491 },
    LatTerm { arg: [ 2,  0, -2,  1], sigma_b:     -451 },
    LatTerm { arg: [ 0,  0,  3, -1], sigma_b:      439 },
    LatTerm { arg: [ 2,  0,  2,  1], sigma_b:      422 },
    LatTerm { arg: [ 2,  0, -3, -1], sigma_b:      421 },
    LatTerm { arg: [ 2,  1, -1,  1], sigma_b:     -366 },
    LatTerm { arg: [ 2,  1,  0,  1], sigma_b:     -351 },
    LatTerm { arg: [ 4,  0,  0,  1], sigma_b:      331 },
    LatTerm { arg: [ 2, -1,  1,  1], sigma_b:      315 },
    LatTerm { arg: [ 2, -2,  0, -1], sigma_b:      302 },
    LatTerm { arg: [ 0,  0,  1,  3], sigma_b:     -283 },
    LatTerm { arg: [ 2,  1,  1, -1], sigma_b:     -229 },
    LatTerm { arg: [ 1,  1,  0, -1], sigma_b:      223 },
    LatTerm { arg: [ 1,  1,  0,  1], sigma_b:      223 },
    LatTerm { arg: [ 0,  1, -2, -1], sigma_b:     -220 },
    LatTerm { arg: [ 2,  1, -1, -1], sigma_b:     -220 },
    LatTerm { arg: [ 1,  0,  1,  1], sigma_b:     -185 },
    LatTerm { arg: [ 2, -1, -2, -1], sigma_b:      181 },
    LatTerm { arg: [ 0,  1,  2,  1], sigma_b:     -177 },
    LatTerm { arg: [ 4,  0, -2, -1], sigma_b:      176 },
    LatTerm { arg: [ 4, -1, -1, -1], sigma_b:      166 },
    LatTerm { arg: [ 1,  0,  1, -1], sigma_b:     -164 },
    LatTerm { arg: [ 4,  0,  1, -1], sigma_b:      132 },
    LatTerm { arg: [ 1,  0, -1, -1], sigma_b:     -119 },
    LatTerm { arg: [ 4, -1,  0, -1], sigma_b:      115 },
    LatTerm { arg: [ 2, -2,  0,  1], sigma_b:      107 },
];

/// Fundamental arguments of the lunar theory at `t` (TT Julian centuries
/// from J2000.0), radians in [0, 2π): Meeus eqs. 47.1–47.5, 47.6 (E) and
/// the arguments A1, A2, A3 of the additive terms (p. 338).
#[derive(Debug, Clone, Copy)]
pub(crate) struct Arguments {
    /// L′, mean longitude of the Moon referred to the mean equinox of date,
    /// including the constant light-time term −0.70″ (eq. 47.1).
    pub l_prime: Radians,
    /// D, mean elongation of the Moon (eq. 47.2).
    pub d: Radians,
    /// M, mean anomaly of the Sun (eq. 47.3).
    pub m: Radians,
    /// M′, mean anomaly of the Moon (eq. 47.4).
    pub m_prime: Radians,
    /// F, argument of latitude of the Moon (eq. 47.5).
    pub f: Radians,
    /// E, eccentricity factor of the Earth's orbit (eq. 47.6), dimensionless.
    pub e: f64,
}

/// Evaluate a degree polynomial c0 + c1·t + … (Horner) and reduce it to
/// [0, 360) before converting to radians, so the large linear rates keep
/// their precision.
#[inline]
fn angle_deg(t: f64, c: &[f64]) -> Radians {
    let mut acc = 0.0;
    for &ci in c.iter().rev() {
        acc = acc * t + ci;
    }
    wrap_360(acc) * DEG
}

impl Arguments {
    /// The arguments at `t`, Julian centuries TT from J2000.0.
    #[inline]
    pub(crate) fn at(t: JulianCenturies) -> Self {
        Arguments {
            l_prime: angle_deg(
                t,
                &[
                    218.316_447_7,
                    481_267.881_234_21,
                    -0.001_578_6,
                    1.0 / 538_841.0,
                    -1.0 / 65_194_000.0,
                ],
            ),
            d: angle_deg(
                t,
                &[
                    297.850_192_1,
                    445_267.111_403_4,
                    -0.001_881_9,
                    1.0 / 545_868.0,
                    -1.0 / 113_065_000.0,
                ],
            ),
            m: angle_deg(
                t,
                &[
                    357.529_109_2,
                    35_999.050_290_9,
                    -0.000_153_6,
                    1.0 / 24_490_000.0,
                ],
            ),
            m_prime: angle_deg(
                t,
                &[
                    134.963_396_4,
                    477_198.867_505_5,
                    0.008_741_4,
                    1.0 / 69_699.0,
                    -1.0 / 14_712_000.0,
                ],
            ),
            f: angle_deg(
                t,
                &[
                    93.272_095_0,
                    483_202.017_523_3,
                    -0.003_653_9,
                    -1.0 / 3_526_000.0,
                    1.0 / 863_310_000.0,
                ],
            ),
            e: 1.0 - t * (0.002_516 + t * 0.000_007_4),
        }
    }
}

/// Longitude of the mean ascending node of the lunar orbit on the ecliptic,
/// mean equinox of date, radians in [0, 2π) (Meeus eq. 47.7).
#[inline]
pub(crate) fn mean_ascending_node(t: JulianCenturies) -> Radians {
    angle_deg(
        t,
        &[
            125.044_547_9,
            -1_934.136_289_1,
            0.002_075_4,
            1.0 / 467_441.0,
            -1.0 / 60_616_000.0,
        ],
    )
}

/// A unit complex number cos x + i sin x (possibly scaled), i.e. e^{ix}.
#[derive(Debug, Clone, Copy)]
struct Phasor {
    cos: f64,
    sin: f64,
}

impl Phasor {
    const ONE: Phasor = Phasor { cos: 1.0, sin: 0.0 };

    #[inline(always)]
    fn of(x: Radians) -> Self {
        let (sin, cos) = libm::sincos(x);
        Phasor { cos, sin }
    }

    /// e^{i(a+b)} from e^{ia} and e^{ib}: the angle-addition formulas.
    #[inline(always)]
    fn mul(self, o: Phasor) -> Phasor {
        Phasor {
            cos: self.cos * o.cos - self.sin * o.sin,
            sin: self.sin * o.cos + self.cos * o.sin,
        }
    }

    #[inline(always)]
    fn scale(self, s: f64) -> Phasor {
        Phasor {
            cos: self.cos * s,
            sin: self.sin * s,
        }
    }
}

/// e^{ikx}·s^|k| for k = −N..=N, stored at index k + N. `s` folds a factor
/// such as Meeus' E^|M| into the multiples.
#[inline(always)]
fn multiples<const N: usize, const LEN: usize>(base: Phasor, s: f64) -> [Phasor; LEN] {
    let mut out = [Phasor::ONE; LEN];
    let mut p = Phasor::ONE;
    let mut sk = 1.0;
    for k in 1..=N {
        p = p.mul(base);
        sk *= s;
        let w = p.scale(sk);
        out[N + k] = w;
        out[N - k] = Phasor {
            cos: w.cos,
            sin: -w.sin,
        };
    }
    out
}

/// Multiples of (D, M, M′, F) with E^|M| folded in.
struct Multiples {
    d: [Phasor; 9],
    m: [Phasor; 5],
    m_prime: [Phasor; 9],
    f: [Phasor; 7],
}

impl Multiples {
    #[inline(always)]
    fn new(a: &Arguments) -> Self {
        Multiples {
            d: multiples::<4, 9>(Phasor::of(a.d), 1.0),
            m: multiples::<2, 5>(Phasor::of(a.m), a.e),
            m_prime: multiples::<4, 9>(Phasor::of(a.m_prime), 1.0),
            f: multiples::<3, 7>(Phasor::of(a.f), 1.0),
        }
    }

    /// E^|k_M| · e^{i(k_D·D + k_M·M + k_M′·M′ + k_F·F)}.
    #[inline(always)]
    fn term(&self, k: [i8; 4]) -> Phasor {
        let d = self.d[(k[0] + 4) as usize];
        let m = self.m[(k[1] + 2) as usize];
        let mp = self.m_prime[(k[2] + 4) as usize];
        let f = self.f[(k[3] + 3) as usize];
        d.mul(m).mul(mp.mul(f))
    }
}

/// Geocentric ecliptic longitude and latitude of the Moon, referred to the
/// mean ecliptic and mean equinox of date, and the distance between the
/// centres of the Earth and the Moon.
///
/// `t`: Julian centuries TT from J2000.0. Returns (λ radians in [0, 2π),
/// β radians, Δ km). λ includes the constant light-time term −0.70″ (it is
/// part of L′) and excludes nutation: the apparent longitude is λ + Δψ.
///
/// Source: Meeus, *Astronomical Algorithms* 2nd ed., ch. 47 (ELP-2000/82
/// truncated): eqs. 47.1–47.6, all 60 terms of Table 47.A and all 60 of
/// Table 47.B with the factor E, and the additive terms in A1, A2, A3, L′.
/// Meeus quotes an accuracy of about 10″ in λ and 4″ in β; this crate's test
/// against JPL DE421 over 1900–2050 measures it (see the module docs).
///
/// Cost: 6 `sincos` and 2 `sin` calls, then three complex multiplications
/// per periodic term.
pub fn meeus47(t: JulianCenturies) -> (Radians, Radians, Km) {
    let a = Arguments::at(t);
    let mult = Multiples::new(&a);

    let mut sigma_l = 0.0;
    let mut sigma_r = 0.0;
    for term in TABLE_47A.iter() {
        let z = mult.term(term.arg);
        sigma_l += f64::from(term.sigma_l) * z.sin;
        sigma_r += f64::from(term.sigma_r) * z.cos;
    }
    let mut sigma_b = 0.0;
    for term in TABLE_47B.iter() {
        sigma_b += f64::from(term.sigma_b) * mult.term(term.arg).sin;
    }

    // Additive terms (Meeus p. 338): A1 from Venus, A2 from Jupiter, the
    // L′ − F and L′ terms from the flattening of the Earth.
    let a1 = Phasor::of(wrap_360(119.75 + 131.849 * t) * DEG);
    let a2 = libm::sin(wrap_360(53.09 + 479_264.290 * t) * DEG);
    let a3 = libm::sin(wrap_360(313.45 + 481_266.484 * t) * DEG);
    let lp = Phasor::of(a.l_prime);
    let f = mult.f[4];
    let mp = mult.m_prime[5];
    let f_conj = mult.f[2];
    let mp_conj = mult.m_prime[3];
    sigma_l += 3958.0 * a1.sin + 1962.0 * lp.mul(f_conj).sin + 318.0 * a2;
    sigma_b += -2235.0 * lp.sin
        + 382.0 * a3
        + 175.0 * (a1.mul(f_conj).sin + a1.mul(f).sin)
        + 127.0 * lp.mul(mp_conj).sin
        - 115.0 * lp.mul(mp).sin;

    let lon = crate::units::wrap_tau(a.l_prime + sigma_l * 1e-6 * DEG);
    let lat = sigma_b * 1e-6 * DEG;
    let dist = 385_000.56 + sigma_r * 1e-3;
    (lon, lat, dist)
}

/// One periodic term of the short series: multiples of (D, M, M′, F) and the
/// coefficient (1e-6° for a sine in λ or β, 1e-3 km for a cosine in Δ).
struct ShortTerm {
    arg: [i8; 4],
    coef: i32,
}

/// The 15 largest Σl terms of Table 47.A (sine, 1e-6°).
#[rustfmt::skip]
static LOW_LON: [ShortTerm; 15] = [
    ShortTerm { arg: [ 0,  0,  1,  0], coef:   6288774 },
    ShortTerm { arg: [ 2,  0, -1,  0], coef:   1274027 },
    ShortTerm { arg: [ 2,  0,  0,  0], coef:    658314 },
    ShortTerm { arg: [ 0,  0,  2,  0], coef:    213618 },
    ShortTerm { arg: [ 0,  1,  0,  0], coef:   -185116 },
    ShortTerm { arg: [ 0,  0,  0,  2], coef:   -114332 },
    ShortTerm { arg: [ 2,  0, -2,  0], coef:     58793 },
    ShortTerm { arg: [ 2, -1, -1,  0], coef:     57066 },
    ShortTerm { arg: [ 2,  0,  1,  0], coef:     53322 },
    ShortTerm { arg: [ 2, -1,  0,  0], coef:     45758 },
    ShortTerm { arg: [ 0,  1, -1,  0], coef:    -40923 },
    ShortTerm { arg: [ 1,  0,  0,  0], coef:    -34720 },
    ShortTerm { arg: [ 0,  1,  1,  0], coef:    -30383 },
    ShortTerm { arg: [ 2,  0,  0, -2], coef:     15327 },
    ShortTerm { arg: [ 0,  0,  1,  2], coef:    -12528 },
];

/// The 8 largest Σr terms of Table 47.A (cosine, 1e-3 km).
#[rustfmt::skip]
static LOW_DIST: [ShortTerm; 8] = [
    ShortTerm { arg: [ 0,  0,  1,  0], coef: -20905355 },
    ShortTerm { arg: [ 2,  0, -1,  0], coef:  -3699111 },
    ShortTerm { arg: [ 2,  0,  0,  0], coef:  -2955968 },
    ShortTerm { arg: [ 0,  0,  2,  0], coef:   -569925 },
    ShortTerm { arg: [ 2,  0, -2,  0], coef:    246158 },
    ShortTerm { arg: [ 2, -1,  0,  0], coef:   -204586 },
    ShortTerm { arg: [ 2,  0,  1,  0], coef:   -170733 },
    ShortTerm { arg: [ 2, -1, -1,  0], coef:   -152138 },
];

/// The 9 largest Σb terms of Table 47.B (sine, 1e-6°).
#[rustfmt::skip]
static LOW_LAT: [ShortTerm; 9] = [
    ShortTerm { arg: [ 0,  0,  0,  1], coef:   5128122 },
    ShortTerm { arg: [ 0,  0,  1,  1], coef:    280602 },
    ShortTerm { arg: [ 0,  0,  1, -1], coef:    277693 },
    ShortTerm { arg: [ 2,  0,  0, -1], coef:    173237 },
    ShortTerm { arg: [ 2,  0, -1,  1], coef:     55413 },
    ShortTerm { arg: [ 2,  0, -1, -1], coef:     46271 },
    ShortTerm { arg: [ 2,  0,  0,  1], coef:     32573 },
    ShortTerm { arg: [ 0,  0,  2,  1], coef:     17198 },
    ShortTerm { arg: [ 2,  0,  1, -1], coef:      9266 },
];

/// Geocentric ecliptic longitude and latitude of the Moon (mean ecliptic and
/// equinox of date) and Earth–Moon distance from a short series: the 15
/// largest longitude, 9 largest latitude and 8 largest distance terms of
/// Meeus Tables 47.A/47.B (ELP-2000/82), without the additive terms.
///
/// `t`: Julian centuries TT from J2000.0. Returns (λ radians in [0, 2π),
/// β radians, Δ km), same frame and conventions as [`meeus47`].
///
/// Error against [`meeus47`] over 1900–2050 (great circle): p95 ≈ 0.04°,
/// max ≈ 0.09°; distance within ≈ 500 km (measured by this module's tests).
/// Cost: 4 `sincos` calls and 32 periodic terms, against 6 `sincos` + 2 `sin`
/// and 189 periodic terms (120 sine + 60 cosine series terms + 9 additive)
/// for [`meeus47`]: 6× fewer term evaluations (the textbook form of ch. 47
/// would make 189 libm trig calls, this one makes 4 `sincos`).
pub fn low(t: JulianCenturies) -> (Radians, Radians, Km) {
    let a = Arguments::at(t);
    let mult = Multiples::new(&a);
    let mut sigma_l = 0.0;
    for term in LOW_LON.iter() {
        sigma_l += f64::from(term.coef) * mult.term(term.arg).sin;
    }
    let mut sigma_b = 0.0;
    for term in LOW_LAT.iter() {
        sigma_b += f64::from(term.coef) * mult.term(term.arg).sin;
    }
    let mut sigma_r = 0.0;
    for term in LOW_DIST.iter() {
        sigma_r += f64::from(term.coef) * mult.term(term.arg).cos;
    }
    let lon = crate::units::wrap_tau(a.l_prime + sigma_l * 1e-6 * DEG);
    (lon, sigma_b * 1e-6 * DEG, 385_000.56 + sigma_r * 1e-3)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::units::{wrap_pi, ARCSEC, J2000};
    use std::vec::Vec;

    /// Textbook evaluation of Meeus ch. 47: one libm `sin`/`cos` per term,
    /// arguments summed in radians.
    fn meeus47_reference(t: f64) -> (f64, f64, f64) {
        let a = Arguments::at(t);
        let argument = |k: [i8; 4]| {
            f64::from(k[0]) * a.d
                + f64::from(k[1]) * a.m
                + f64::from(k[2]) * a.m_prime
                + f64::from(k[3]) * a.f
        };
        let ecc = |k: [i8; 4]| a.e.powi(i32::from(k[1].abs()));
        let (mut sl, mut sr, mut sb) = (0.0, 0.0, 0.0);
        for term in TABLE_47A.iter() {
            let x = argument(term.arg);
            sl += f64::from(term.sigma_l) * ecc(term.arg) * x.sin();
            sr += f64::from(term.sigma_r) * ecc(term.arg) * x.cos();
        }
        for term in TABLE_47B.iter() {
            sb += f64::from(term.sigma_b) * ecc(term.arg) * argument(term.arg).sin();
        }
        let a1 = (119.75 + 131.849 * t) * DEG;
        let a2 = (53.09 + 479_264.290 * t) * DEG;
        let a3 = (313.45 + 481_266.484 * t) * DEG;
        let lp = a.l_prime;
        sl += 3958.0 * a1.sin() + 1962.0 * (lp - a.f).sin() + 318.0 * a2.sin();
        sb += -2235.0 * lp.sin()
            + 382.0 * a3.sin()
            + 175.0 * (a1 - a.f).sin()
            + 175.0 * (a1 + a.f).sin()
            + 127.0 * (lp - a.m_prime).sin()
            - 115.0 * (lp + a.m_prime).sin();
        (
            crate::units::wrap_tau(lp + sl * 1e-6 * DEG),
            sb * 1e-6 * DEG,
            385_000.56 + sr * 1e-3,
        )
    }

    /// Meeus Example 47.a: 1992 April 12, 0h TD (JDE 2448724.5):
    /// λ = 133.162655°, β = −3.229126°, Δ = 368 409.7 km.
    #[test]
    fn meeus_example_47a() {
        let t = (2_448_724.5 - J2000) / 36_525.0;
        let a = Arguments::at(t);
        assert!((a.l_prime / DEG - 134.290_182).abs() < 1e-6);
        assert!((a.d / DEG - 113.842_304).abs() < 1e-6);
        assert!((a.m / DEG - 97.643_514).abs() < 1e-6);
        assert!((a.m_prime / DEG - 5.150_833).abs() < 1e-6);
        assert!((a.f / DEG - 219.889_721).abs() < 1e-6);
        assert!((a.e - 1.000_194).abs() < 1e-6);
        let (lon, lat, dist) = meeus47(t);
        assert!((lon / DEG - 133.162_655).abs() < 1e-6, "{}", lon / DEG);
        assert!((lat / DEG - -3.229_126).abs() < 1e-6, "{}", lat / DEG);
        assert!((dist - 368_409.7).abs() < 0.05, "{dist}");
    }

    /// The phasor evaluation agrees with the textbook one to < 1e-10 rad
    /// (and 1e-6 km) from 1000 BC to AD 3000.
    #[test]
    fn fast_evaluation_matches_reference() {
        let mut worst: [f64; 3] = [0.0; 3];
        for i in 0..=4000 {
            let t = -30.0 + 40.0 * f64::from(i) / 4000.0;
            let (l, b, r) = meeus47(t);
            let (lr, br, rr) = meeus47_reference(t);
            worst[0] = worst[0].max(wrap_pi(l - lr).abs());
            worst[1] = worst[1].max((b - br).abs());
            worst[2] = worst[2].max((r - rr).abs());
        }
        assert!(worst[0] < 1e-10 && worst[1] < 1e-10, "{worst:?}");
        assert!(worst[2] < 1e-6, "{worst:?}");
    }

    pub(crate) struct Stats {
        pub median: f64,
        pub p95: f64,
        pub max: f64,
    }

    pub(crate) fn stats(mut v: Vec<f64>) -> Stats {
        v.sort_by(|a, b| a.partial_cmp(b).unwrap());
        let at = |q: f64| v[((v.len() - 1) as f64 * q).round() as usize];
        Stats {
            median: at(0.5),
            p95: at(0.95),
            max: *v.last().unwrap(),
        }
    }

    /// Great-circle separation of two (lon, lat) places, radians.
    pub(crate) fn separation(l1: f64, b1: f64, l2: f64, b2: f64) -> f64 {
        let dl = l1 - l2;
        let x = b1.cos() * b2.sin() - b1.sin() * b2.cos() * dl.cos();
        let y = b2.cos() * dl.sin();
        let z = b1.sin() * b2.sin() + b1.cos() * b2.cos() * dl.cos();
        libm::atan2(libm::hypot(x, y), z)
    }

    fn fixture() -> Vec<Vec<f64>> {
        super::super::de421::tests::fixture_rows(include_str!("../../data/moon_check.json"))
    }

    /// Against JPL DE421 (Skyfield apparent places of the true ecliptic and
    /// equinox of date, tools/gen_moon_check.py): meeus47 λ + Δψ, β.
    #[test]
    fn meeus47_against_de421() {
        let rows = fixture();
        assert_eq!(rows.len(), 2000);
        let mut sep = Vec::new();
        let mut dist = Vec::new();
        for r in &rows {
            let t = (r[0] - J2000) / 36_525.0;
            let (l, b, d) = meeus47(t);
            sep.push(separation(l + r[4] * ARCSEC, b, r[1] * DEG, r[2] * DEG) / ARCSEC);
            dist.push((d - r[3]).abs());
        }
        let s = stats(sep);
        let d = stats(dist);
        std::println!(
            "meeus47 vs DE421: median {:.2}\" p95 {:.2}\" max {:.2}\"; distance median {:.1} p95 {:.1} max {:.1} km",
            s.median, s.p95, s.max, d.median, d.p95, d.max
        );
        assert!(s.median <= 3.0 && s.p95 <= 6.0 && s.max <= 20.0);
        assert!(d.median < 3.0 && d.max < 15.0);
    }

    /// The short series against meeus47, 1900–2050.
    #[test]
    fn low_against_meeus47() {
        let rows = fixture();
        let mut sep = Vec::new();
        let mut dist = Vec::new();
        for r in &rows {
            let t = (r[0] - J2000) / 36_525.0;
            let (l, b, d) = meeus47(t);
            let (ll, bl, dl) = low(t);
            sep.push(separation(ll, bl, l, b) / DEG);
            dist.push((dl - d).abs());
        }
        let s = stats(sep);
        let d = stats(dist);
        std::println!(
            "low vs meeus47: median {:.4}° p95 {:.4}° max {:.4}°; distance p95 {:.0} max {:.0} km",
            s.median,
            s.p95,
            s.max,
            d.p95,
            d.max
        );
        assert!(s.p95 <= 0.05 && s.max <= 0.12);
        assert!(d.max < 800.0);
    }
}
