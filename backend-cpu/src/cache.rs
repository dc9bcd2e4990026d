//! On-disk cache of the parameter-dependent atmosphere LUTs.
//!
//! Directory: `$HIMMEL_CACHE_DIR` if set (an empty value disables the
//! cache), else `$XDG_CACHE_HOME/himmel`, else `$HOME/.cache/himmel`.
//! File name: `atmosphere-<key>.bin`, where the key is the FNV-1a 64-bit
//! hash of the format version, the band count and the JSON of the
//! parameters and LUT configuration. Content: a magic line, then the
//! direct and δ-scaled transmittance and the multiple-scattering texels as
//! little-endian f32.
//! A file that does not match exactly is ignored (recomputed).

use std::path::{Path, PathBuf};

use himmel_skymodel::atmosphere::{AtmosphereLuts, AtmosphereParams, Lut2, LutConfig};
use himmel_skymodel::spectrum::{Spectrum, BANDS};

const MAGIC: &[u8; 8] = b"HMLUT004";

/// The default cache directory (see the module documentation), or `None`
/// when disabled or no home directory is known.
pub fn default_dir() -> Option<PathBuf> {
    if let Some(v) = std::env::var_os("HIMMEL_CACHE_DIR") {
        return if v.is_empty() {
            None
        } else {
            Some(PathBuf::from(v))
        };
    }
    if let Some(v) = std::env::var_os("XDG_CACHE_HOME").filter(|v| !v.is_empty()) {
        return Some(PathBuf::from(v).join("himmel"));
    }
    std::env::var_os("HOME")
        .filter(|v| !v.is_empty())
        .map(|h| PathBuf::from(h).join(".cache").join("himmel"))
}

/// FNV-1a 64-bit hash.
fn fnv1a(bytes: &[u8]) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for &b in bytes {
        h ^= b as u64;
        h = h.wrapping_mul(0x0100_0000_01b3);
    }
    h
}

/// The cache key of a parameter set.
pub fn key(params: &AtmosphereParams, config: &LutConfig) -> String {
    let text = format!(
        "{}|{}|{}|{}",
        String::from_utf8_lossy(MAGIC),
        BANDS,
        serde_json::to_string(params).unwrap_or_default(),
        serde_json::to_string(config).unwrap_or_default()
    );
    format!("{:016x}", fnv1a(text.as_bytes()))
}

fn path(dir: &Path, params: &AtmosphereParams, config: &LutConfig) -> PathBuf {
    dir.join(format!("atmosphere-{}.bin", key(params, config)))
}

/// Writes the LUTs into `dir` (created if needed).
pub fn store(dir: &Path, luts: &AtmosphereLuts) -> std::io::Result<()> {
    std::fs::create_dir_all(dir)?;
    let mut out = Vec::with_capacity(
        16 + (2 * luts.transmittance.data.len() + luts.multiscatter.data.len()) * BANDS * 4,
    );
    out.extend_from_slice(MAGIC);
    for s in luts
        .transmittance
        .data
        .iter()
        .chain(&luts.scattering_transmittance.data)
        .chain(&luts.multiscatter.data)
    {
        for v in s.0 {
            out.extend_from_slice(&v.to_le_bytes());
        }
    }
    let p = path(dir, &luts.params, &luts.config);
    let tmp = p.with_extension(format!("tmp{}", std::process::id()));
    std::fs::write(&tmp, out)?;
    std::fs::rename(tmp, p)
}

/// Reads the LUTs of `params`/`config` from `dir`, if present and intact.
pub fn load(dir: &Path, params: &AtmosphereParams, config: &LutConfig) -> Option<AtmosphereLuts> {
    let bytes = std::fs::read(path(dir, params, config)).ok()?;
    let nt = config.transmittance_w * config.transmittance_h;
    let nm = config.multiscatter_n * config.multiscatter_n;
    if bytes.len() != 8 + (2 * nt + nm) * BANDS * 4 || &bytes[..8] != MAGIC {
        return None;
    }
    let mut spectra = bytes[8..].chunks_exact(BANDS * 4).map(|c| {
        let mut s = Spectrum::ZERO;
        for (b, v) in c.chunks_exact(4).enumerate() {
            s.0[b] = f32::from_le_bytes([v[0], v[1], v[2], v[3]]);
        }
        s
    });
    let t: Vec<Spectrum> = spectra.by_ref().take(nt).collect();
    let ts: Vec<Spectrum> = spectra.by_ref().take(nt).collect();
    let m: Vec<Spectrum> = spectra.collect();
    if t.iter().chain(&ts).chain(&m).any(|s| !s.is_finite()) {
        return None;
    }
    Some(AtmosphereLuts::from_parts(
        params,
        config,
        Lut2 {
            w: config.transmittance_w,
            h: config.transmittance_h,
            data: t,
        },
        Lut2 {
            w: config.transmittance_w,
            h: config.transmittance_h,
            data: ts,
        },
        m.chunks(config.multiscatter_n.max(1))
            .map(<[Spectrum]>::to_vec)
            .collect(),
    ))
}
