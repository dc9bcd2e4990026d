//! Heliocentric positions of the Earth and the planets Mercury–Saturn, the
//! low-accuracy Sun, the VSOP87 → FK5 correction and planetary magnitudes.
//!
//! Three tiers of heliocentric position, all referred to the ecliptic and mean
//! equinox of date:
//!
//! | tier | function | source | cost |
//! |---|---|---|---|
//! | low | [`heliocentric_low`] | mean elements, Meeus Table 31.A + Kepler | a few `sin`/`cos` |
//! | standard | [`heliocentric`] with [`Series::Truncated`] | VSOP87D, leading terms | 70–350 terms |
//! | high | [`heliocentric`] with [`Series::Full`] | VSOP87D, every term | 1 700–6 800 terms |
//!
//! Measured accuracy (tests in this module, 1900–2050): the full series agree
//! with JPL DE421 within 0.3″ (Earth) and 0.6″ (planets) in heliocentric
//! direction, mostly a drift from VSOP87's older precession constant; the
//! truncated series stay within 0.33″ (Sun) and 0.6–2.0″ (planets) of the full
//! series, 95th percentile of the light-time corrected geocentric direction;
//! the mean elements are good to ~0.5′ (Mercury–Earth), 2.5′ (Mars), 18′
//! (Jupiter) and 45′ (Saturn).

mod kepler;
mod magnitude;
mod vsop87d;
#[rustfmt::skip]
mod vsop87d_data;

#[cfg(test)]
mod tests;

use crate::units::{
    Au, JulianCenturies, JulianDay, Radians, ARCSEC, DEG, J2000, LIGHT_DAYS_PER_AU,
};

/// A body whose heliocentric position this module computes (VSOP87D has no
/// separate series for the Sun: it is the origin).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Planet {
    /// Mercury.
    Mercury,
    /// Venus.
    Venus,
    /// The Earth (its centre, not the Earth–Moon barycentre).
    Earth,
    /// Mars.
    Mars,
    /// Jupiter.
    Jupiter,
    /// Saturn.
    Saturn,
}

impl Planet {
    /// All bodies of this module, in order of distance from the Sun.
    pub const ALL: [Planet; 6] = [
        Planet::Mercury,
        Planet::Venus,
        Planet::Earth,
        Planet::Mars,
        Planet::Jupiter,
        Planet::Saturn,
    ];
}

/// How much of the VSOP87D series to evaluate.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Series {
    /// The leading terms only: every term whose amplitude A is at least ε
    /// (radians for L and B; ε times the planet's mean distance, AU, for R),
    /// with ε = 1×10⁻⁶ for Mercury–Saturn except the Earth, ε = 3×10⁻⁷ —
    /// see `tools/gen_vsop87.py`. This is the level of Meeus' Appendix III;
    /// the measured geocentric error against [`Series::Full`] over 1900–2050
    /// is ≤ 1″ for the Sun and ≤ 3″ for the planets (95th percentile).
    Truncated,
    /// Every term of VSOP87D.
    Full,
}

fn vsop87_body(planet: Planet) -> &'static vsop87d::Vsop87Body {
    match planet {
        Planet::Mercury => &vsop87d_data::MERCURY,
        Planet::Venus => &vsop87d_data::VENUS,
        Planet::Earth => &vsop87d_data::EARTH,
        Planet::Mars => &vsop87d_data::MARS,
        Planet::Jupiter => &vsop87d_data::JUPITER,
        Planet::Saturn => &vsop87d_data::SATURN,
    }
}

/// Heliocentric ecliptic spherical coordinates (L, B radians; R AU) referred to
/// the dynamical ecliptic and mean equinox of date — VSOP87D (Bretagnon &
/// Francou 1988), Meeus, Astronomical Algorithms 2nd ed., ch. 32 (eqs. 32.1–32.2).
///
/// Geometric (no light-time, aberration or nutation); L is reduced to [0, 2π).
/// `jd_tt` is TT, used for TDB. To refer λ, β to FK5 add [`fk5_correction`].
pub fn heliocentric(planet: Planet, jd_tt: JulianDay, series: Series) -> (Radians, Radians, Au) {
    let tau = (jd_tt - J2000) / 365_250.0;
    let (l, b, r) = vsop87d::evaluate(vsop87_body(planet), tau, series == Series::Full);
    (crate::units::wrap_tau(l), b, r)
}

/// Low tier: heliocentric ecliptic (L, B radians; R AU) referred to the mean
/// equinox of date, from the mean orbital elements of Meeus, Astronomical
/// Algorithms 2nd ed., ch. 31, Table 31.A, with Kepler's equation solved by
/// Newton's method (Meeus ch. 30).
///
/// An unperturbed ellipse: the worst heliocentric direction error over
/// 1900–2050 (measured against the full VSOP87D) is 0.4′ Mercury, 0.45′ Venus,
/// 0.6′ Earth, 2.5′ Mars, 18′ Jupiter and 45′ Saturn — the last two from their
/// mutual perturbation (the "great inequality"), which mean elements omit.
pub fn heliocentric_low(planet: Planet, jd_tt: JulianDay) -> (Radians, Radians, Au) {
    kepler::heliocentric_low(planet, jd_tt)
}

/// [`heliocentric_low`] as a rectangular vector, AU, ecliptic and mean
/// equinox of date (x towards the equinox, z towards the ecliptic pole):
/// cheaper when the caller needs a vector anyway.
pub fn heliocentric_low_vector(planet: Planet, jd_tt: JulianDay) -> glam::DVec3 {
    kepler::heliocentric_low_vector(planet, jd_tt)
}

/// The Sun, low accuracy (Meeus, Astronomical Algorithms 2nd ed., ch. 25,
/// eqs. 25.2–25.5 and the Ω correction for nutation and aberration that follows
/// them): (apparent longitude, referred to the true equinox of date, radians
/// in [0, 2π); distance R, AU). The latitude β is taken as 0.
///
/// Accuracy ~0.01° (Meeus). `jd_tt` is TT.
pub fn sun_low(jd_tt: JulianDay) -> (Radians, Au) {
    kepler::sun_low(jd_tt)
}

/// Conversion of VSOP87 (dynamical ecliptic and equinox) λ, β to the FK5 system
/// (Meeus, Astronomical Algorithms 2nd ed., eq. 32.3): returns (Δλ, Δβ) in
/// radians, to ADD to λ, β. `t` in Julian centuries TT from J2000.0.
///
/// Δλ = −0.09033″ + 0.03916″ (cos λ′ + sin λ′) tan β,
/// Δβ = +0.03916″ (cos λ′ − sin λ′), with λ′ = λ − 1.397° T − 0.00031° T².
/// β is clamped to ±89° so that tan β stays finite near the poles (no planet
/// comes near them).
pub fn fk5_correction(lon: Radians, lat: Radians, t: JulianCenturies) -> (Radians, Radians) {
    let lon_prime = lon - (1.397 * t + 0.00031 * t * t) * DEG;
    let (s, c) = libm::sincos(lon_prime);
    let tan_lat = libm::tan(lat.clamp(-89.0 * DEG, 89.0 * DEG));
    let d_lon = (-0.09033 + 0.03916 * (c + s) * tan_lat) * ARCSEC;
    let d_lat = 0.03916 * (c - s) * ARCSEC;
    (d_lon, d_lat)
}

/// Apparent visual magnitude (Meeus, Astronomical Algorithms 2nd ed., ch. 41,
/// the second set of formulas — those of the Astronomical Almanac since 1984,
/// p. 286; Meeus does not number them):
///
/// | | V = 5 log₁₀(rΔ) + … (i in degrees) |
/// |---|---|
/// | Mercury | −0.42 + 0.0380 i − 0.000273 i² + 0.000002 i³ |
/// | Venus | −4.40 + 0.0009 i + 0.000239 i² − 0.00000065 i³ |
/// | Mars | −1.52 + 0.016 i |
/// | Jupiter | −9.40 + 0.005 i |
/// | Saturn | −8.88 + 0.044 \|ΔU\| − 2.60 sin\|B\| + 1.25 sin²B |
///
/// `r_au` heliocentric and `delta_au` geocentric distance, `phase_angle` i
/// (Sun–planet–Earth) in radians; `saturn_ring_tilt` is B of
/// [`saturn_ring_tilt`] and is ignored for the other planets. For Saturn the
/// difference ΔU of the Saturnicentric longitudes of Sun and Earth is taken
/// as the phase angle (|ΔU| ≤ i/cos B, and 0.044 |ΔU| is at most 0.3 mag);
/// [`saturn_magnitude`] takes ΔU itself. The Earth, absent from Meeus, follows
/// Mallama & Hilton (2018): −3.99 − 1.060×10⁻³ i + 2.054×10⁻⁴ i².
///
/// rΔ is kept ≥ 10⁻¹² so that the result is finite for any input.
pub fn magnitude(
    planet: Planet,
    r_au: Au,
    delta_au: Au,
    phase_angle: Radians,
    saturn_ring_tilt: Radians,
) -> f64 {
    magnitude::magnitude_aa(planet, r_au, delta_au, phase_angle, saturn_ring_tilt)
}

/// Apparent visual magnitude from the first set of formulas of Meeus ch. 41
/// (G. Müller's, used by the Astronomical Almanac before 1984; Meeus' example
/// 41.a). Same arguments and conventions as [`magnitude`].
pub fn magnitude_muller(
    planet: Planet,
    r_au: Au,
    delta_au: Au,
    phase_angle: Radians,
    saturn_ring_tilt: Radians,
) -> f64 {
    magnitude::magnitude_muller(planet, r_au, delta_au, phase_angle, saturn_ring_tilt)
}

/// Saturn's apparent visual magnitude with the rings (Astronomical Almanac
/// 1984 formula, Meeus ch. 41):
/// V = −8.88 + 5 log₁₀(rΔ) + 0.044 |ΔU| − 2.60 sin|B| + 1.25 sin²B, with ΔU (radians) the difference between the Saturnicentric
/// longitudes of the Sun and the Earth measured in the ring plane and B the
/// ring tilt toward the Earth (Meeus ch. 45).
pub fn saturn_magnitude(r_au: Au, delta_au: Au, delta_u: Radians, ring_tilt: Radians) -> f64 {
    magnitude::saturn_magnitude(r_au, delta_au, delta_u, ring_tilt)
}

/// Inclination i and ascending node Ω (radians) of the plane of Saturn's
/// rings, referred to the ecliptic and mean equinox of date (Meeus,
/// Astronomical Algorithms 2nd ed., ch. 45, first formulas):
/// i = 28.075216° − 0.012998° T + 0.000004° T²,
/// Ω = 169.508470° + 1.394681° T + 0.000412° T²; `t` Julian centuries TT.
pub fn saturn_ring_plane(t: JulianCenturies) -> (Radians, Radians) {
    magnitude::saturn_ring_plane(t)
}

/// Saturn's ring tilt B toward the Earth — the Saturnicentric latitude of the
/// Earth referred to the ring plane, radians, positive when the Earth is north
/// of it — from Saturn's geocentric ecliptic λ, β (radians, ecliptic and
/// equinox of date, light-time corrected) and `t` (Julian centuries TT):
/// sin B = sin i cos β sin(λ − Ω) − cos i sin β, with i, Ω of
/// [`saturn_ring_plane`] (Meeus, Astronomical Algorithms 2nd ed., ch. 45,
/// step 6 of the procedure; the formula is unnumbered).
pub fn saturn_ring_tilt(lon: Radians, lat: Radians, t: JulianCenturies) -> Radians {
    magnitude::saturn_ring_tilt(lon, lat, t)
}

/// Rectangular ecliptic coordinates (AU) of spherical (L, B, R).
#[inline]
fn rectangular(l: Radians, b: Radians, r: Au) -> [f64; 3] {
    let (sl, cl) = libm::sincos(l);
    let (sb, cb) = libm::sincos(b);
    [r * cb * cl, r * cb * sl, r * sb]
}

/// Geometric geocentric ecliptic coordinates (λ, β radians, λ in [0, 2π);
/// Δ AU) of a planet, referred to the dynamical ecliptic and mean equinox of
/// date, corrected for light-time: the planet is taken at t − τ with
/// τ = Δ · LIGHT_DAYS_PER_AU (three iterations; Meeus ch. 33), the Earth at t.
/// No aberration, nutation or FK5 correction. For [`Planet::Earth`] this is
/// the direction of the Sun's centre (geometric, β = −B).
pub fn geocentric(planet: Planet, jd_tt: JulianDay, series: Series) -> (Radians, Radians, Au) {
    let (le, be, re) = heliocentric(Planet::Earth, jd_tt, series);
    let earth = rectangular(le, be, re);
    if planet == Planet::Earth {
        let x = -earth[0];
        let y = -earth[1];
        let z = -earth[2];
        return spherical(x, y, z);
    }
    let mut tau = 0.0;
    let mut v = [0.0; 3];
    for _ in 0..3 {
        let (l, b, r) = heliocentric(planet, jd_tt - tau, series);
        let p = rectangular(l, b, r);
        v = [p[0] - earth[0], p[1] - earth[1], p[2] - earth[2]];
        let delta = libm::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
        tau = delta * LIGHT_DAYS_PER_AU;
    }
    spherical(v[0], v[1], v[2])
}

#[inline]
fn spherical(x: f64, y: f64, z: f64) -> (Radians, Radians, Au) {
    let rho = libm::sqrt(x * x + y * y);
    let r = libm::sqrt(rho * rho + z * z);
    (
        crate::units::wrap_tau(libm::atan2(y, x)),
        libm::atan2(z, rho),
        r,
    )
}
