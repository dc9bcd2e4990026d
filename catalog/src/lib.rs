//! # himmel-catalog
//!
//! The stars of the naked-eye sky, embedded: every Hipparcos star with
//! V ≤ 6.5 (8 874 stars, 324 kB), with Hipparcos number, proper name,
//! Bayer/Flamsteed designation, ICRS astrometry at J1991.25 (new reduction,
//! van Leeuwen 2007), V and B−V; star colours from B−V; constellation stick
//! figures; Milky Way outlines. Sources, licences and credits:
//! `catalog/README.md`.
//!
//! ```
//! use himmel_catalog::Catalog;
//! let cat = Catalog::embedded()?;
//! let sirius = cat.by_name("Sirius").ok_or("Sirius is missing")?;
//! assert_eq!(sirius.hip, 32349);
//! assert!(cat.brighter_than(6.5).len() >= 8800);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! Apparent places come from [`himmel_astro::stars`]: exact per star
//! ([`himmel_astro::stars::StarReduction`]) or the per-frame fast path
//! ([`StarField`]).
#![forbid(unsafe_code)]
#![warn(missing_docs)]

mod binary;
pub mod color;
pub mod constellations;
mod error;
pub mod field;
pub mod figures;
pub mod sources;
mod star;

pub use error::CatalogError;
pub use field::StarField;
pub use star::{Catalog, Star};
