//! The Moon: geocentric position at three accuracy tiers and its physical
//! ephemeris.
//!
//! | tier | function | theory | frame |
//! |---|---|---|---|
//! | Low | [`low`] | 32 largest terms of ELP-2000/82 (Meeus Tables 47.A/B) | mean ecliptic & equinox of date |
//! | Standard | [`meeus47`] | Meeus ch. 47, all terms | mean ecliptic & equinox of date |
//! | High | [`de421`] | Chebyshev refit of JPL DE421 | ICRF/GCRS axes, geometric |
//!
//! Measured accuracy (this module's tests; reference: Skyfield apparent places
//! from JPL DE421 at 2000 random TT instants 1900–2050, fixture written by
//! `tools/gen_moon_check.py`; great-circle error of λ + Δψ, β):
//!
//! | tier | median | p95 | max | distance |
//! |---|---|---|---|---|
//! | [`meeus47`] | 2.0″ | 5.3″ | 12.2″ | median 2.0 km, max 11 km |
//! | [`low`] (vs `meeus47`) | 0.017° | 0.039° | 0.081° | p95 320 km, max 480 km |
//! | [`de421`] (vs DE421 itself) | — | — | 0.021″ (0.038 km) | |
//!
//! Cost per call (x86-64 baseline, release): `low` ≈ 60 ns, `meeus47`
//! ≈ 400 ns, `de421` ≈ 100 ns; the textbook form of Meeus ch. 47 (crate
//! `astro` 2.0.0) ≈ 2000 ns.
//!
//! [`physical`] gives phase angle, illuminated fraction, elongation, bright
//! limb, librations and the axis position angle (Meeus ch. 48, 53).

mod de421;
mod physical;
mod series;

pub use de421::{de421, DE421_SPAN};
pub use physical::{physical, MoonPhysical, MoonSunApparent};
pub use series::{low, meeus47};
pub(crate) use series::{low_terms, LowArguments};
