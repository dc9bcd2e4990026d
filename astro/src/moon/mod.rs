//! The Moon: geocentric position at three accuracy tiers and its physical
//! ephemeris.
//!
//! | tier | function | theory | frame |
//! |---|---|---|---|
//! | Low | [`low`] | 32 largest terms of ELP-2000/82 (Meeus Tables 47.A/B) | mean ecliptic & equinox of date |
//! | Standard | [`meeus47`] | Meeus ch. 47, all terms | mean ecliptic & equinox of date |
//! | High | [`de421`] | Chebyshev refit of JPL DE421 | ICRF/GCRS axes, geometric |
//!
//! Measured accuracy (tests in this module, against Skyfield + DE421 apparent
//! places, 2000 random TT instants 1900–2050, `meeus47` λ + Δψ, β, great
//! circle): see the report in `series` tests; the figures are repeated in the
//! docs of each function.
//!
//! [`physical`] gives phase angle, illuminated fraction, elongation, bright
//! limb, librations and the axis position angle (Meeus ch. 48, 53).

mod de421;
mod physical;
mod series;

pub use de421::{de421, DE421_SPAN};
pub use physical::{physical, MoonPhysical, MoonSunApparent};
pub use series::{low, meeus47};
