//! Helpers of the 3D-world reference tests: the Mitsuba 3 references in
//! `tests/fixtures/world_ref/` (made by `tools/world_reference.py` for the
//! cases of `tools/world_cases.json`) and the metrics they are judged by.
//! Include with `mod world_common;` from a file of `tests/tests/`.
#![allow(dead_code)]

pub mod cases;
pub mod changes;
pub mod cloud_sequence;
pub mod metrics;
pub mod render;
pub mod shafts;
pub mod view;
