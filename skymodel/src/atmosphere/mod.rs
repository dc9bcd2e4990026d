//! The atmosphere model: Rayleigh + aerosol (Cornette–Shanks) scattering,
//! ozone absorption, the Earth's shadow, multiple scattering.
//!
//! * [`params`] — physical parameters and LUT settings (documented defaults);
//! * [`medium`] — density profiles, spectral coefficients, phase functions,
//!   spherical geometry;
//! * [`lut`] — Hillaire (2020) transmittance, multiple-scattering and
//!   sky-view LUTs; `march` — their view-ray march (the sky view's rows,
//!   [`aerial_perspective`]);
//! * [`mod@reference`] — the brute-force reference (ray marching + Monte-Carlo
//!   orders ≥ 2), for tests and the accuracy table.
//!
//! Why Hillaire rather than Bruneton & Neyret: a parameter change costs a
//! transmittance LUT (256×64) and a 48×48 multiple-scattering LUT — tens of
//! milliseconds — instead of Bruneton's 4D scattering textures for every
//! order; the per-frame sky-view LUT handles any Sun position, including
//! twilight. The accuracy table in the README measures what this costs
//! against the brute-force reference.

mod at_radius;
pub mod lut;
mod march;
pub mod medium;
pub mod params;
pub mod reference;

pub use lut::{AtmosphereLuts, Lut2, SkyView, SkyViewInput};
pub use march::aerial_perspective;
pub use medium::Medium;
pub use params::{AtmosphereParams, LutConfig, ParamError};
