//! Apparent visual magnitudes (Meeus ch. 41) and Saturn's ring geometry
//! (Meeus ch. 45).

use super::Planet;
use crate::units::{Au, JulianCenturies, Radians, DEG};

/// 5 log₁₀(rΔ), with the product kept away from zero so that a degenerate
/// geometry (Δ → 0) gives a large but finite brightness instead of −∞.
#[inline]
fn distance_term(r_au: Au, delta_au: Au) -> f64 {
    5.0 * libm::log10((r_au * delta_au).abs().max(1e-12))
}

/// Saturn's ring terms common to both sets of formulas (Meeus ch. 41):
/// 0.044 |ΔU| − 2.60 sin|B| + 1.25 sin²B, ΔU in degrees.
#[inline]
fn saturn_rings(delta_u: Radians, ring_tilt: Radians) -> f64 {
    let sin_b = libm::sin(ring_tilt);
    0.044 * (delta_u / DEG).abs() - 2.60 * sin_b.abs() + 1.25 * sin_b * sin_b
}

/// The Earth, which Meeus' lists omit: Mallama & Hilton (2018), "Computing
/// apparent planetary magnitudes for The Astronomical Almanac", eq. for the
/// Earth: −3.99 + 5 log rΔ − 1.060×10⁻³ i + 2.054×10⁻⁴ i² (i in degrees).
#[inline]
fn earth(i: f64) -> f64 {
    -3.99 + i * (-1.060e-3 + i * 2.054e-4)
}

pub(super) fn magnitude_aa(
    planet: Planet,
    r_au: Au,
    delta_au: Au,
    phase_angle: Radians,
    ring_tilt: Radians,
) -> f64 {
    let i = phase_angle.abs() / DEG;
    let phase = match planet {
        Planet::Mercury => -0.42 + i * (0.0380 + i * (-0.000273 + i * 0.000002)),
        Planet::Venus => -4.40 + i * (0.0009 + i * (0.000239 - i * 0.00000065)),
        Planet::Earth => earth(i),
        Planet::Mars => -1.52 + 0.016 * i,
        Planet::Jupiter => -9.40 + 0.005 * i,
        // |ΔU| is approximated by the phase angle (see `magnitude`).
        Planet::Saturn => -8.88 + saturn_rings(phase_angle, ring_tilt),
    };
    phase + distance_term(r_au, delta_au)
}

pub(super) fn magnitude_muller(
    planet: Planet,
    r_au: Au,
    delta_au: Au,
    phase_angle: Radians,
    ring_tilt: Radians,
) -> f64 {
    let i = phase_angle.abs() / DEG;
    let phase = match planet {
        Planet::Mercury => 1.16 + (i - 50.0) * (0.02838 + (i - 50.0) * 0.0001023),
        Planet::Venus => -4.00 + 0.01322 * i + 0.000_000_424_7 * i * i * i,
        Planet::Earth => earth(i),
        Planet::Mars => -1.30 + 0.01486 * i,
        Planet::Jupiter => -8.93,
        Planet::Saturn => -8.68 + saturn_rings(phase_angle, ring_tilt),
    };
    phase + distance_term(r_au, delta_au)
}

pub(super) fn saturn_magnitude(
    r_au: Au,
    delta_au: Au,
    delta_u: Radians,
    ring_tilt: Radians,
) -> f64 {
    -8.88 + distance_term(r_au, delta_au) + saturn_rings(delta_u, ring_tilt)
}

pub(super) fn saturn_ring_plane(t: JulianCenturies) -> (Radians, Radians) {
    let inclination = 28.075216 - t * (0.012998 - t * 0.000004);
    let node = 169.508470 + t * (1.394681 + t * 0.000412);
    (inclination * DEG, node * DEG)
}

pub(super) fn saturn_ring_tilt(lon: Radians, lat: Radians, t: JulianCenturies) -> Radians {
    let (i, node) = saturn_ring_plane(t);
    let (sin_i, cos_i) = libm::sincos(i);
    let (sin_b, cos_b) = libm::sincos(lat);
    crate::units::safe_asin(sin_i * cos_b * libm::sin(lon - node) - cos_i * sin_b)
}
