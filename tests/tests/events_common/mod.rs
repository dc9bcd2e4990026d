//! Helpers shared by the event test binaries: the reference fixtures and
//! time arithmetic.
#![allow(dead_code)]

use std::path::PathBuf;

use himmel_astro::{Instant, Precision, Tiered, UtcDateTime};
use serde_json::Value;

pub const EPH: Tiered = Tiered(Precision::Standard);

pub fn fixture(name: &str) -> Value {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("fixtures")
        .join(name);
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{path:?}: {e}"));
    let v: Value = serde_json::from_str(&text).unwrap();
    v["data"].clone()
}

pub fn utc(y: i32, mo: u8, d: u8, h: u8, mi: u8) -> Instant {
    Instant::from_utc(&UtcDateTime::new(y, mo, d, h, mi, 0.0).unwrap()).unwrap()
}

pub fn secs(a: f64, b: f64) -> f64 {
    (a - b).abs() * 86_400.0
}
