//! # himmel-astro
//!
//! Where is the Sun, the Moon, that planet — from here, now? This crate answers
//! with three measured accuracy tiers (see the project README for the error and
//! cost table against JPL DE421):
//!
//! | tier | Sun | Moon | planets |
//! |---|---|---|---|
//! | `Precision::Low` | Meeus ch. 25 low accuracy | short ELP series | mean Keplerian elements |
//! | `Precision::Standard` | VSOP87D truncated | Meeus ch. 47, all terms | VSOP87D truncated |
//! | `Precision::High` | VSOP87D full | Chebyshev fit to DE421 (1900–2050) | VSOP87D full |
//!
//! Conventions (time scales, frames, units) follow the project's
//! `spec/conventions.md`: apparent geocentric places are referred to the true
//! equator and equinox of date, azimuth is measured from North through East,
//! refraction is never part of an altitude unless a name says "refracted".
//!
//! The crate is `no_std` (math through `libm`); the `std` feature (default)
//! adds `std::error::Error` impls, `chrono` converts from `chrono::DateTime`,
//! `serde` derives serialisation for the public value types.
#![no_std]
#![forbid(unsafe_code)]
#![warn(missing_docs)]

#[cfg(any(feature = "std", test))]
extern crate std;

pub mod error;
mod fastmath;
pub mod units;

pub mod frames;
pub mod moon;
pub mod planets;
pub mod time;

pub use error::AstroError;

pub mod ephemeris;
pub mod events;
pub mod observe;
pub mod stars;

pub use ephemeris::{Apparent, Body, Cached, Ephemeris, Epoch, Manual, Precision, Tiered};
pub use observe::{Observer, Sky, Topocentric};
pub use time::{Instant, UtcDateTime};
