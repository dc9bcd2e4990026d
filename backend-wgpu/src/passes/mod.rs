//! The passes, one module each beside its WGSL file under `shaders/`,
//! under the contract of [`crate::pass`].

pub mod atmosphere;
pub mod clouds;
pub mod clouds_amortise;
pub mod clouds_history;
pub mod lighting;
pub mod luts;
pub mod milkyway;
pub mod moon;
pub mod points;
pub mod sky_view;
pub mod store;
pub mod sun;
pub mod texture;
