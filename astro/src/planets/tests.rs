use super::*;
use crate::units::{wrap_pi, DAYS_PER_CENTURY};
use std::vec::Vec;

fn arcsec(a: f64) -> f64 {
    a / ARCSEC
}

/// Angle between two directions given as (λ, β).
fn separation(a: (f64, f64), b: (f64, f64)) -> f64 {
    let (s1, c1) = libm::sincos(a.1);
    let (s2, c2) = libm::sincos(b.1);
    let x = c1 * libm::cos(a.0) - c2 * libm::cos(b.0);
    let y = c1 * libm::sin(a.0) - c2 * libm::sin(b.0);
    let z = s1 - s2;
    2.0 * safe_half_chord(libm::sqrt(x * x + y * y + z * z))
}

fn safe_half_chord(chord: f64) -> f64 {
    crate::units::safe_asin(chord / 2.0)
}

/// Deterministic pseudo-random dates (64-bit LCG, Knuth's MMIX constants).
fn random_dates(n: usize, jd0: f64, jd1: f64) -> Vec<f64> {
    let mut s: u64 = 0x2545_F491_4F6C_DD1D;
    (0..n)
        .map(|_| {
            s = s
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            let u = (s >> 11) as f64 / (1u64 << 53) as f64;
            jd0 + u * (jd1 - jd0)
        })
        .collect()
}

fn percentile(v: &mut [f64], p: f64) -> f64 {
    v.sort_by(|a, b| a.partial_cmp(b).unwrap());
    v[((v.len() - 1) as f64 * p).round() as usize]
}

const JD_1900: f64 = 2_415_020.5;
const JD_2050: f64 = 2_469_807.5;

/// The truncation thresholds of `tools/gen_vsop87.py` must keep the geocentric
/// error of `Series::Truncated` against `Series::Full` (Earth's truncation
/// included) within 1″ for the Sun and 3″ for the planets, 95th percentile over
/// 500 dates in 1900–2050. Run with `--nocapture` to see the figures.
#[test]
fn truncation_error_1900_2050() {
    let dates = random_dates(500, JD_1900, JD_2050);
    for planet in Planet::ALL {
        let mut err: Vec<f64> = dates
            .iter()
            .map(|&jd| {
                let (l1, b1, _) = geocentric(planet, jd, Series::Truncated);
                let (l2, b2, _) = geocentric(planet, jd, Series::Full);
                arcsec(separation((l1, b1), (l2, b2)))
            })
            .collect();
        let p95 = percentile(&mut err, 0.95);
        let max = err[err.len() - 1];
        let (nt, nf) = vsop87d::term_counts(vsop87_body(planet));
        std::println!("{planet:?}: terms {nt}/{nf}, geocentric error p95 {p95:.3}″ max {max:.3}″");
        let limit = if planet == Planet::Earth { 1.0 } else { 3.0 };
        assert!(p95 <= limit, "{planet:?}: p95 {p95}″ > {limit}″");
    }
}

/// Heliocentric geometric positions from JPL DE421, ecliptic and mean equinox
/// of date: (planet, JD TT, L°, B°, R AU). Produced by `tools/check_vsop87.py`.
const DE421: [(Planet, f64, f64, f64, f64); 42] = [
    (
        Planet::Mercury,
        2415020.5,
        201.3796520,
        3.0565867,
        0.420737497,
    ),
    (
        Planet::Mercury,
        2433282.5,
        16.4793839,
        -3.6476236,
        0.336544873,
    ),
    (
        Planet::Mercury,
        2448908.5,
        260.7570845,
        -3.7783270,
        0.466456215,
    ),
    (
        Planet::Mercury,
        2448976.5,
        202.2564035,
        3.0821065,
        0.419939703,
    ),
    (
        Planet::Mercury,
        2451545.0,
        253.7829290,
        -3.0227737,
        0.466471474,
    ),
    (
        Planet::Mercury,
        2460000.5,
        283.3118603,
        -5.7273628,
        0.455047840,
    ),
    (
        Planet::Mercury,
        2469807.5,
        124.5329318,
        6.7881167,
        0.324682966,
    ),
    (
        Planet::Venus,
        2415020.5,
        343.1335681,
        -3.3901560,
        0.727434623,
    ),
    (Planet::Venus, 2433282.5, 81.7785464, 0.3283833, 0.720099476),
    (
        Planet::Venus,
        2448908.5,
        278.2543226,
        -1.2530308,
        0.727399910,
    ),
    (
        Planet::Venus,
        2448976.5,
        26.1141043,
        -2.6205995,
        0.724601672,
    ),
    (
        Planet::Venus,
        2451545.0,
        182.6028993,
        3.2646114,
        0.720212924,
    ),
    (
        Planet::Venus,
        2460000.5,
        48.3915203,
        -1.6212349,
        0.722727379,
    ),
    (
        Planet::Venus,
        2469807.5,
        281.9393961,
        -1.4259441,
        0.727560419,
    ),
    (
        Planet::Earth,
        2415020.5,
        100.1543336,
        -0.0000532,
        0.983266244,
    ),
    (
        Planet::Earth,
        2433282.5,
        100.0112189,
        0.0000204,
        0.983243645,
    ),
    (
        Planet::Earth,
        2448908.5,
        19.9072816,
        -0.0002070,
        0.997608513,
    ),
    (Planet::Earth, 2448976.5, 88.3569900, 0.0001657, 0.983824159),
    (
        Planet::Earth,
        2451545.0,
        100.3778246,
        -0.0002274,
        0.983327679,
    ),
    (
        Planet::Earth,
        2460000.5,
        156.1144653,
        0.0000491,
        0.989714001,
    ),
    (
        Planet::Earth,
        2469807.5,
        100.7491331,
        -0.0001026,
        0.983349323,
    ),
    (
        Planet::Mars,
        2415020.5,
        286.4464272,
        -1.5634471,
        1.421393543,
    ),
    (Planet::Mars, 2433282.5, 146.3559691, 1.8354111, 1.663836689),
    (Planet::Mars, 2448908.5, 64.3982798, 0.4757994, 1.506574722),
    (Planet::Mars, 2448976.5, 98.7058341, 1.4006290, 1.590873165),
    (
        Planet::Mars,
        2451545.0,
        359.4472835,
        -1.4196743,
        1.391207674,
    ),
    (Planet::Mars, 2460000.5, 114.2893714, 1.6703459, 1.622718253),
    (Planet::Mars, 2469807.5, 198.7712352, 0.9574338, 1.623547472),
    (
        Planet::Jupiter,
        2415020.5,
        234.5362740,
        0.9244105,
        5.384903902,
    ),
    (
        Planet::Jupiter,
        2433282.5,
        311.4745258,
        -0.6831118,
        5.074471646,
    ),
    (
        Planet::Jupiter,
        2448908.5,
        177.0258491,
        1.2695011,
        5.439943189,
    ),
    (
        Planet::Jupiter,
        2448976.5,
        182.1852471,
        1.2914979,
        5.446764973,
    ),
    (
        Planet::Jupiter,
        2451545.0,
        36.2946002,
        -1.1745913,
        4.965380997,
    ),
    (
        Planet::Jupiter,
        2460000.5,
        17.5558604,
        -1.2934889,
        4.951378430,
    ),
    (
        Planet::Jupiter,
        2469807.5,
        117.8405765,
        0.3768160,
        5.241358896,
    ),
    (
        Planet::Saturn,
        2415020.5,
        266.5140152,
        1.1035134,
        10.066868310,
    ),
    (
        Planet::Saturn,
        2433282.5,
        163.7868547,
        1.9226018,
        9.353254284,
    ),
    (
        Planet::Saturn,
        2448908.5,
        317.1984159,
        -0.9965800,
        9.881438600,
    ),
    (
        Planet::Saturn,
        2448976.5,
        319.3183526,
        -1.0801469,
        9.867003650,
    ),
    (
        Planet::Saturn,
        2451545.0,
        45.7222359,
        -2.3031952,
        9.183847531,
    ),
    (
        Planet::Saturn,
        2460000.5,
        328.0105885,
        -1.3956454,
        9.821608230,
    ),
    (
        Planet::Saturn,
        2469807.5,
        299.2110640,
        -0.2227847,
        9.984813513,
    ),
];

/// Worst heliocentric direction error (″) and relative distance error of a
/// position function against the DE421 table, per planet.
fn worst_vs_de421(planet: Planet, f: impl Fn(Planet, f64) -> (f64, f64, f64)) -> (f64, f64) {
    DE421
        .iter()
        .filter(|row| row.0 == planet)
        .map(|&(p, jd, l, b, r)| {
            let (ll, bb, rr) = f(p, jd);
            (
                arcsec(separation((ll, bb), (l * DEG, b * DEG))),
                ((rr - r) / r).abs(),
            )
        })
        .fold((0.0, 0.0), |acc, e| (acc.0.max(e.0), acc.1.max(e.1)))
}

/// Full VSOP87D against DE421. The differences are dominated by a drift in
/// longitude common to all planets, −0.2″ in 1900 to +0.2″ in 2050: VSOP87's
/// mean equinox of date follows an older precession constant than the IAU 2006
/// precession of the reference (0.3″ per century apart). Limits: 0.3″ for the
/// Earth, 0.6″ for the planets; distance to 3×10⁻⁷ (relative).
#[test]
fn full_series_against_de421() {
    for planet in Planet::ALL {
        let (dir, dist) = worst_vs_de421(planet, |p, jd| heliocentric(p, jd, Series::Full));
        std::println!("Full {planet:?}: {dir:.3}″, dR/R {dist:.2e}");
        let limit = if planet == Planet::Earth { 0.3 } else { 0.6 };
        assert!(dir <= limit, "{planet:?}: {dir}″");
        assert!(dist <= 3e-7, "{planet:?}: dR/R {dist}");
    }
}

/// Truncated VSOP87D against DE421: heliocentric direction within 3″ (Earth
/// 1″), distance within 2×10⁻⁵ (relative).
#[test]
fn truncated_series_against_de421() {
    for planet in Planet::ALL {
        let (dir, dist) = worst_vs_de421(planet, |p, jd| heliocentric(p, jd, Series::Truncated));
        std::println!("Truncated {planet:?}: {dir:.3}″, dR/R {dist:.2e}");
        let limit = if planet == Planet::Earth { 1.0 } else { 3.0 };
        assert!(dir <= limit, "{planet:?}: {dir}″");
        assert!(dist <= 2e-5, "{planet:?}: dR/R {dist}");
    }
}

/// Mean elements against DE421 at the table's dates, and against the full
/// VSOP87D (itself within 0.6″ of DE421, see above) at 500 dates in 1900–2050.
/// Meeus (ch. 31) warns that the mean elements ignore the planetary
/// perturbations; the limits (worst heliocentric direction error, arcminutes)
/// are what an unperturbed ellipse of Table 31.A achieves — Jupiter and Saturn
/// suffer from their great inequality (amplitudes ~20′ and ~48′).
#[test]
fn low_tier_accuracy() {
    let dates = random_dates(500, JD_1900, JD_2050);
    for (planet, limit_arcmin, limit_dist) in [
        (Planet::Mercury, 1.0, 1e-4),
        (Planet::Venus, 1.0, 1e-4),
        (Planet::Earth, 1.0, 1e-4),
        (Planet::Mars, 3.0, 5e-4),
        (Planet::Jupiter, 25.0, 3e-3),
        (Planet::Saturn, 60.0, 8e-3),
    ] {
        let (dir, dist) = worst_vs_de421(planet, heliocentric_low);
        let mut err: Vec<f64> = dates
            .iter()
            .map(|&jd| {
                let (l1, b1, _) = heliocentric_low(planet, jd);
                let (l2, b2, _) = heliocentric(planet, jd, Series::Full);
                arcsec(separation((l1, b1), (l2, b2))) / 60.0
            })
            .collect();
        let p95 = percentile(&mut err, 0.95);
        let max = err[err.len() - 1];
        std::println!(
            "Low {planet:?}: vs DE421 {:.2}′ dR/R {dist:.1e}; vs VSOP87 p95 {p95:.2}′ max {max:.2}′",
            dir / 60.0
        );
        assert!(dir / 60.0 <= limit_arcmin, "{planet:?}: {}′", dir / 60.0);
        assert!(max <= limit_arcmin, "{planet:?}: {max}′");
        assert!(dist <= limit_dist, "{planet:?}: dR/R {dist}");
    }
}

/// Meeus example 25.b: the Earth, 1992 October 13.0 TD (JDE 2448908.5), from
/// Meeus' truncated VSOP87 (Appendix III): L = 19.907372°, B = −0.000179°,
/// R = 0.99760775. The full series differs from these by ~0.3″ (PyMeeus, full
/// series: L = 19.907297°, B = −0.744″, R = 0.99760852).
#[test]
fn meeus_example_25b_earth() {
    let jd = 2_448_908.5;
    let (l, b, r) = heliocentric(Planet::Earth, jd, Series::Truncated);
    assert!(
        arcsec(wrap_pi(l - 19.907372 * DEG)).abs() < 0.5,
        "L {}",
        l / DEG
    );
    assert!(arcsec(b + 0.000179 * DEG).abs() < 0.2, "B {}", b / DEG);
    // Our truncation keeps fewer R1 terms than Meeus': 1.7e-6 AU (250 km) from the full R.
    assert!((r - 0.99760775).abs() < 2e-6, "R {r}");
    let (l, b, r) = heliocentric(Planet::Earth, jd, Series::Full);
    assert!(
        arcsec(wrap_pi(l - 19.907297 * DEG)).abs() < 0.05,
        "L {}",
        l / DEG
    );
    assert!((arcsec(b) + 0.744).abs() < 0.01, "B {}", arcsec(b));
    assert!((r - 0.99760852).abs() < 1e-8, "R {r}");
}

/// Meeus example 32.a: Venus, 1992 December 20.0 TD (JDE 2448976.5). Meeus'
/// truncated series: L = 26.11428°, B = −2.62070°, R = 0.724603; with the
/// complete VSOP87 (PyMeeus, and Meeus' own remark): L = 26.11412°,
/// B = −2.62060°, R = 0.724602.
#[test]
fn meeus_example_32a_venus() {
    let jd = 2_448_976.5;
    let (l, b, r) = heliocentric(Planet::Venus, jd, Series::Full);
    assert!((l / DEG - 26.11412).abs() < 0.00001, "L {}", l / DEG);
    assert!((b / DEG + 2.62060).abs() < 0.00001, "B {}", b / DEG);
    assert!((r - 0.724602).abs() < 1e-6, "R {r}");
    let (l, b, r) = heliocentric(Planet::Venus, jd, Series::Truncated);
    assert!(
        arcsec(wrap_pi(l - 26.11428 * DEG)).abs() < 1.5,
        "L {}",
        l / DEG
    );
    assert!(arcsec(b + 2.62070 * DEG).abs() < 1.0, "B {}", b / DEG);
    assert!((r - 0.724603).abs() < 3e-6, "R {r}");
}

/// FK5 correction, Meeus eq. 32.3, against PyMeeus 0.5.12
/// (`geometric_heliocentric_position(tofk5=True)` minus `tofk5=False`): (λ°, β°,
/// T, Δλ″, Δβ″).
#[test]
fn fk5_correction_against_pymeeus() {
    for (lon, lat, t, dl, db) in [
        (
            19.907297242050845,
            -0.00020664594475074732,
            -0.07218343600273786,
            -0.09033018103110635,
            0.023397726835279756,
        ),
        (
            26.114119595135435,
            -2.6206031211961927,
            -0.07032169746748802,
            -0.09272971834235477,
            0.017835960978551668,
        ),
        (
            15.204967842531914,
            -1.0502802638550892,
            0.30161533196440793,
            -0.09120734075196424,
            0.0278712613772214,
        ),
    ] {
        let (d_lon, d_lat) = fk5_correction(lon * DEG, lat * DEG, t);
        assert!(
            (arcsec(d_lon) - dl).abs() < 1e-6,
            "{} vs {dl}",
            arcsec(d_lon)
        );
        assert!(
            (arcsec(d_lat) - db).abs() < 1e-6,
            "{} vs {db}",
            arcsec(d_lat)
        );
    }
    let (d_lon, d_lat) = fk5_correction(1.0, core::f64::consts::FRAC_PI_2, 0.0);
    assert!(d_lon.is_finite() && d_lat.is_finite());
}

/// At J2000.0, where the precession models agree, the FK5 correction (whose
/// −0.09033″ is the offset of the VSOP87 equinox from the FK5 one) must bring
/// the Earth's full-series longitude closer to DE421's (0.069″ → 0.02″).
#[test]
fn fk5_correction_moves_vsop87_toward_de421_at_j2000() {
    let (_, jd, l_de, _, _) = DE421[18];
    assert_eq!(jd, J2000);
    let (l, b, _) = heliocentric(Planet::Earth, jd, Series::Full);
    let (dl, _) = fk5_correction(l, b, 0.0);
    let before = arcsec(wrap_pi(l - l_de * DEG)).abs();
    let after = arcsec(wrap_pi(l + dl - l_de * DEG)).abs();
    assert!(after < 0.03 && after < before, "{before}″ → {after}″");
}

/// Meeus example 25.a: the Sun 1992 October 13.0 TD, low accuracy:
/// apparent λ = 199.90895°, R = 0.99766.
#[test]
fn sun_low_meeus_example_25a() {
    let (lon, r) = sun_low(2_448_908.5);
    assert!((lon / DEG - 199.90895).abs() < 0.00001, "{}", lon / DEG);
    assert!((r - 0.99766).abs() < 0.000005, "{r}");
}

/// The low-accuracy Sun against DE421: the apparent longitude is the Earth's
/// heliocentric L + 180° − 20.5″ (aberration) + Δψ (nutation, ≤ 17.2″); Meeus
/// claims 0.01° for the ch. 25 formulas, so nutation is left out of the
/// reference and absorbed by the 0.01° (36″) limit.
#[test]
fn sun_low_against_de421() {
    for &(p, jd, l, _, r) in DE421.iter().filter(|row| row.0 == Planet::Earth) {
        let (lon, rr) = sun_low(jd);
        let expected = (l + 180.0) * DEG - 20.4898 * ARCSEC;
        let err = arcsec(wrap_pi(lon - expected)).abs();
        assert!(err < 36.0, "{p:?} {jd}: {err}″");
        assert!((rr - r).abs() < 1e-4, "{jd}: R {rr} vs {r}");
    }
}

#[test]
fn kepler_equation_is_solved() {
    for e in [0.0, 0.0167, 0.0934, 0.2056, 0.5] {
        for k in 0..72 {
            let m = (k as f64 * 5.0 - 180.0) * DEG;
            let ecc = kepler::eccentric_anomaly(m, e);
            let residual = ecc - e * libm::sin(ecc) - wrap_pi(m);
            assert!(residual.abs() < 1e-14, "e {e} M {m}: {residual}");
        }
    }
}

/// Meeus example 41.a: Venus 1992 December 20, r = 0.724604, Δ = 0.910947,
/// i = 72.96°: m = −3.8 with Müller's formula (Meeus' first set). The
/// Astronomical Almanac formula for the same geometry is compared with
/// Astronomy Engine (−4.267 at that date, see `tools/check_vsop87.py`; its
/// Venus model is Hilton's 2005 one, hence the loose 0.1 mag).
#[test]
fn magnitude_meeus_example_41a() {
    let m = magnitude_muller(Planet::Venus, 0.724604, 0.910947, 72.96 * DEG, 0.0);
    assert!((m + 3.8).abs() < 0.05, "{m}");
    let m = magnitude(Planet::Venus, 0.724604, 0.910947, 72.96 * DEG, 0.0);
    assert!((m + 4.267).abs() < 0.1, "{m}");
}

/// Meeus example 45.a: Saturn 1992 December 16.00068 TD (JDE 2448972.50068):
/// ring plane i = 28.076131°, Ω = 169.410243°; B = 16.442°; r = 9.867882,
/// Δ = 10.464606. Our λ, β come from the full VSOP87D with light-time.
#[test]
fn saturn_rings_meeus_example_45a() {
    let jd = 2_448_972.500_68;
    let t = (jd - J2000) / DAYS_PER_CENTURY;
    let (i, node) = saturn_ring_plane(t);
    assert!((i / DEG - 28.076131).abs() < 1e-6);
    assert!((node / DEG - 169.410243).abs() < 1e-6);
    let (lon, lat, delta) = geocentric(Planet::Saturn, jd, Series::Full);
    assert!((delta - 10.464606).abs() < 2e-6, "Δ {delta}");
    let r = heliocentric(Planet::Saturn, jd - delta * LIGHT_DAYS_PER_AU, Series::Full).2;
    assert!((r - 9.867882).abs() < 2e-6, "r {r}");
    let b = saturn_ring_tilt(lon, lat, t);
    assert!((b / DEG - 16.442).abs() < 0.0005, "B {}", b / DEG);
}

/// Astronomy Engine 2.1 `Illumination(body, time).mag` for the same r, Δ, phase
/// angle and ring tilt (values from `tools/check_vsop87.py`). Its models are
/// those of Mallama & Hilton (2018) and differ from the 1984 ones, so the
/// comparison is loose: 0.3 mag for phase angles below 120°. At larger phase
/// angles (Mercury near inferior conjunction) the 1984 cubic is outside its
/// fitted range and only sanity (within 1 mag) is asked.
#[test]
fn magnitudes_against_astronomy_engine() {
    const AE: [(Planet, f64, f64, f64, f64, f64); 30] = [
        (Planet::Mercury, 0.419943, 1.215955, 47.7247, 0.0000, -0.466),
        (Planet::Mercury, 0.466479, 1.415522, 18.2217, 0.0000, -0.738),
        (Planet::Mercury, 0.395219, 0.910753, 93.7162, 0.0000, 0.048),
        (Planet::Mercury, 0.343771, 0.727138, 137.7647, 0.0000, 1.885),
        (Planet::Mercury, 0.455038, 1.314705, 36.9672, 0.0000, -0.389),
        (Planet::Mercury, 0.309456, 0.679427, 174.7844, 0.0000, 5.935),
        (Planet::Venus, 0.724602, 0.910833, 72.9620, 0.0000, -4.267),
        (Planet::Venus, 0.720213, 1.137686, 58.9139, 0.0000, -4.071),
        (Planet::Venus, 0.728208, 0.798336, 83.3176, 0.0000, -4.319),
        (Planet::Venus, 0.719988, 1.360308, 46.3625, 0.0000, -3.902),
        (Planet::Venus, 0.722727, 1.391834, 42.6383, 0.0000, -3.904),
        (Planet::Venus, 0.722471, 1.664634, 15.5887, 0.0000, -3.894),
        (Planet::Mars, 1.590879, 0.648350, 15.9623, 0.0000, -1.197),
        (Planet::Mars, 1.391202, 1.849582, 31.4667, 0.0000, 1.036),
        (Planet::Mars, 1.404442, 1.940332, 30.3132, 0.0000, 1.142),
        (Planet::Mars, 1.660397, 2.629961, 7.6140, 0.0000, 1.803),
        (Planet::Mars, 1.622734, 1.104645, 36.7127, 0.0000, 0.335),
        (Planet::Mars, 1.476658, 2.422403, 8.6681, 0.0000, 1.386),
        (Planet::Jupiter, 5.446719, 5.599084, 10.0972, 0.0000, -1.928),
        (Planet::Jupiter, 4.965489, 4.621234, 11.0340, 0.0000, -2.541),
        (Planet::Jupiter, 5.057826, 4.474008, 10.0286, 0.0000, -2.577),
        (Planet::Jupiter, 5.447032, 6.169032, 6.9637, 0.0000, -1.733),
        (Planet::Jupiter, 4.951375, 5.730720, 6.5654, 0.0000, -2.102),
        (Planet::Jupiter, 5.197060, 4.580616, 9.0764, 0.0000, -2.471),
        (Planet::Saturn, 9.866835, 10.514200, 4.1683, -16.2822, 0.629),
        (Planet::Saturn, 9.183636, 8.652545, 5.3210, 19.0868, 0.013),
        (Planet::Saturn, 9.416174, 9.559328, 6.0776, 3.6491, 0.878),
        (Planet::Saturn, 10.061968, 9.844741, 5.6717, -26.9006, 0.298),
        (Planet::Saturn, 9.822037, 10.802505, 0.7509, -10.8807, 0.714),
        (Planet::Saturn, 9.531404, 9.053183, 5.3345, 0.3811, 0.897),
    ];
    let mut worst = 0.0f64;
    for (planet, r, delta, phase, tilt, mag) in AE {
        let m = magnitude(planet, r, delta, phase * DEG, tilt * DEG);
        let limit = if phase < 120.0 { 0.3 } else { 1.0 };
        std::println!("{planet:?} i={phase:.1}°: AA {m:.3} AE {mag:.3}");
        assert!(
            (m - mag).abs() < limit,
            "{planet:?} i={phase}: {m} vs {mag}"
        );
        if phase < 120.0 {
            worst = worst.max((m - mag).abs());
        }
    }
    std::println!("worst |AA − AE| for i < 120°: {worst:.3} mag");
}

#[test]
fn edges_stay_finite() {
    for planet in Planet::ALL {
        for (r, d, i, b) in [
            (0.0, 0.0, 0.0, 0.0),
            (
                1.0,
                1e-30,
                core::f64::consts::PI,
                core::f64::consts::FRAC_PI_2,
            ),
            (-1.0, 5.0, -1.0, -2.0),
        ] {
            assert!(magnitude(planet, r, d, i, b).is_finite());
            assert!(magnitude_muller(planet, r, d, i, b).is_finite());
        }
        for jd in [0.0, J2000, 5_000_000.0] {
            let (l, b, r) = heliocentric_low(planet, jd);
            assert!(l.is_finite() && b.is_finite() && r.is_finite());
            assert!((0.0..crate::units::TAU).contains(&l));
        }
    }
    let b = saturn_ring_tilt(0.0, core::f64::consts::FRAC_PI_2, 0.0);
    assert!(b.is_finite());
}
