//! Low-accuracy tier: Keplerian orbits from mean elements (Meeus ch. 30–31) and
//! the low-accuracy Sun (Meeus ch. 25).

use super::Planet;
use crate::units::{Au, JulianDay, Radians, DAYS_PER_CENTURY, DEG, J2000};

/// Mean orbital elements referred to the mean equinox of date, as cubic
/// polynomials in T (Julian centuries TT from J2000.0), degrees except a (AU):
/// [L, a, e, i, Ω, ϖ] × [c0, c1, c2, c3].
/// Source: Meeus, Astronomical Algorithms 2nd ed., Table 31.A.
type Elements = [[f64; 4]; 6];

const MERCURY: Elements = [
    [252.250906, 149474.0722491, 0.00030350, 0.000000018],
    [0.387098310, 0.0, 0.0, 0.0],
    [0.20563175, 0.000020407, -0.0000000283, -0.00000000018],
    [7.004986, 0.0018215, -0.00001810, 0.000000056],
    [48.330893, 1.1861883, 0.00017542, 0.000000215],
    [77.456119, 1.5564776, 0.00029544, 0.000000009],
];
const VENUS: Elements = [
    [181.979801, 58519.2130302, 0.00031014, 0.000000015],
    [0.723329820, 0.0, 0.0, 0.0],
    [0.00677192, -0.000047765, 0.0000000981, 0.00000000046],
    [3.394662, 0.0010037, -0.00000088, -0.000000007],
    [76.679920, 0.9011206, 0.00040618, -0.000000093],
    [131.563703, 1.4022288, -0.00107618, -0.000005678],
];
const EARTH: Elements = [
    [100.466457, 36000.7698278, 0.00030322, 0.000000020],
    [1.000001018, 0.0, 0.0, 0.0],
    [0.01670863, -0.000042037, -0.0000001267, 0.00000000014],
    [0.0, 0.0, 0.0, 0.0],
    [174.873176, -0.2410908, 0.00004262, 0.000000001],
    [102.937348, 1.7195366, 0.00045688, -0.000000018],
];
const MARS: Elements = [
    [355.433000, 19141.6964471, 0.00031052, 0.000000016],
    [1.523679342, 0.0, 0.0, 0.0],
    [0.09340065, 0.000090484, -0.0000000806, -0.00000000025],
    [1.849726, -0.0006011, 0.00001276, -0.000000007],
    [49.558093, 0.7720959, 0.00001557, 0.000002267],
    [336.060234, 1.8410449, 0.00013477, 0.000000536],
];
const JUPITER: Elements = [
    [34.351519, 3036.3027748, 0.00022330, 0.000000037],
    [5.202603209, 0.0000001913, 0.0, 0.0],
    [0.04849793, 0.000163225, -0.0000004714, -0.00000000201],
    [1.303267, -0.0054965, 0.00000466, -0.000000002],
    [100.464407, 1.0209774, 0.00040315, 0.000000404],
    [14.331207, 1.6126352, 0.00103042, -0.000004464],
];
const SATURN: Elements = [
    [50.077444, 1223.5110686, 0.00051908, -0.000000030],
    [9.554909192, -0.0000021390, 0.000000004, 0.0],
    [0.05554814, -0.000346641, -0.0000006436, 0.0000000034],
    [2.488879, -0.0037362, -0.00001519, 0.000000087],
    [113.665503, 0.8770880, -0.00012176, -0.000002249],
    [93.057237, 1.9637613, 0.00083753, 0.000004928],
];

#[inline]
fn poly(c: &[f64; 4], t: f64) -> f64 {
    c[0] + t * (c[1] + t * (c[2] + t * c[3]))
}

/// Eccentric anomaly E (radians) from mean anomaly M (radians) and
/// eccentricity e < 1: Kepler's equation E − e sin E = M solved by Newton's
/// method (Meeus ch. 30, "second method", eq. 30.7), started from
/// E₀ = M + e sin M; converges to machine precision in ≤ 5 steps for e ≤ 0.21.
pub(super) fn eccentric_anomaly(mean_anomaly: Radians, e: f64) -> Radians {
    let m = crate::units::wrap_pi(mean_anomaly);
    let mut ecc = m + e * libm::sin(m);
    for _ in 0..12 {
        let (sin_e, cos_e) = libm::sincos(ecc);
        let step = (m + e * sin_e - ecc) / (1.0 - e * cos_e);
        ecc += step;
        // Newton converges quadratically: once a step is below 1e-8 rad the
        // next would be below 1e-15, so stop here with E exact to 1e-15.
        if step.abs() < 1e-8 {
            break;
        }
    }
    ecc
}

pub(super) fn heliocentric_low(planet: Planet, jd_tt: JulianDay) -> (Radians, Radians, Au) {
    crate::frames::vector_to_spherical(heliocentric_low_vector(planet, jd_tt))
}

/// The same ellipse as [`heliocentric_low`] as a rectangular vector, AU,
/// ecliptic and mean equinox of date: the position in the orbital plane
/// (x = a(cos E − e), y = a√(1 − e²) sin E) turned by the argument of
/// perihelion ω = ϖ − Ω, the inclination i and the node Ω (Meeus ch. 33,
/// eq. 33.7 with the ecliptic in place of the equator). Three sine–cosine
/// pairs and no inverse trigonometry.
pub(super) fn heliocentric_low_vector(planet: Planet, jd_tt: JulianDay) -> glam::DVec3 {
    let el = match planet {
        Planet::Mercury => &MERCURY,
        Planet::Venus => &VENUS,
        Planet::Earth => &EARTH,
        Planet::Mars => &MARS,
        Planet::Jupiter => &JUPITER,
        Planet::Saturn => &SATURN,
    };
    let t = (jd_tt - J2000) * (1.0 / DAYS_PER_CENTURY);
    let mean_anomaly = crate::units::reduce_deg(poly(&el[0], t) - poly(&el[5], t)) * DEG;
    let a = poly(&el[1], t);
    let e = poly(&el[2], t);
    let inclination = poly(&el[3], t) * DEG;
    let node = poly(&el[4], t) * DEG;
    let perihelion = poly(&el[5], t) * DEG;

    let ecc = eccentric_anomaly(mean_anomaly, e);
    let (sin_e, cos_e) = libm::sincos(ecc);
    // In the orbital plane, x towards perihelion.
    let px = a * (cos_e - e);
    let py = a * libm::sqrt(1.0 - e * e) * sin_e;
    let (sw, cw) = libm::sincos(perihelion - node);
    let (si, ci) = libm::sincos(inclination);
    let (sn, cn) = libm::sincos(node);
    // Turned by ω in the plane, then by i about the node line, then by Ω.
    let (xw, yw) = (px * cw - py * sw, px * sw + py * cw);
    let (yi, zi) = (yw * ci, yw * si);
    glam::DVec3::new(xw * cn - yi * sn, xw * sn + yi * cn, zi)
}

pub(super) fn sun_low(jd_tt: JulianDay) -> (Radians, Au) {
    let t = (jd_tt - J2000) / DAYS_PER_CENTURY;
    // Geometric mean longitude L0 (25.2), mean anomaly M (25.3), eccentricity e (25.4).
    let l0 = 280.46646 + t * (36000.76983 + t * 0.0003032);
    let m = (357.52911 + t * (35999.05029 - t * 0.0001537)) * DEG;
    let e = 0.016708634 - t * (0.000042037 + t * 0.0000001267);
    // Equation of the centre C.
    let c = (1.914602 - t * (0.004817 + t * 0.000014)) * libm::sin(m)
        + (0.019993 - t * 0.000101) * libm::sin(2.0 * m)
        + 0.000289 * libm::sin(3.0 * m);
    let true_longitude = l0 + c;
    let nu = m + c * DEG;
    // Radius vector (25.5).
    let r = 1.000001018 * (1.0 - e * e) / (1.0 + e * libm::cos(nu));
    // Apparent longitude: −20.5″ aberration and the principal nutation term
    // through Ω (Meeus, text after eq. 25.5).
    let omega = (125.04 - 1934.136 * t) * DEG;
    let apparent = true_longitude - 0.00569 - 0.00478 * libm::sin(omega);
    (crate::units::wrap_tau(apparent * DEG), r)
}
