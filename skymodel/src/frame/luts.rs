//! The LUT store: the parameter-dependent atmosphere LUTs (Hillaire 2020:
//! transmittance, its δ-scaled twin, multiple scattering) of the last
//! parameters in memory and, with the `std` feature, in an on-disk cache
//! that later processes read in about a millisecond.
//!
//! **Cache files.** Directory: `$HIMMEL_CACHE_DIR` if set (an empty value
//! disables the cache), else `$XDG_CACHE_HOME/himmel`, else
//! `$HOME/.cache/himmel` ([`default_cache_dir`]). File name
//! `atmosphere-<key>.bin`, the key being the FNV-1a 64-bit hash of the
//! format version, the band count and the JSON of the parameters and LUT
//! configuration. Content: the 8-byte format magic, the CRC-32 (IEEE) of
//! the key text followed by the payload, then the payload — the direct and
//! δ-scaled transmittance and the multiple-scattering texels as
//! little-endian f32. A file of another format version or length, with a
//! non-finite value, or whose checksum does not match (altered texels, or
//! a file written for other parameters under a colliding name) is never
//! used: the LUTs are recomputed and the file replaced.

#[cfg(feature = "std")]
use std::path::{Path, PathBuf};
use std::sync::Arc;

use crate::atmosphere::{AtmosphereLuts, AtmosphereParams, Lut2, LutConfig};
use crate::spectrum::{Spectrum, BANDS};

/// Where a frame's LUTs came from (`lut_source` in `--stats`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LutOrigin {
    /// The frame needs no LUTs (no atmosphere pass).
    None,
    /// Kept in memory from an earlier frame with the same parameters.
    Memory,
    /// Read from the on-disk cache.
    DiskCache,
    /// Computed on the CPU for this frame.
    Computed,
    /// Computed by a GPU backend's compute shaders for this frame.
    Gpu,
}

impl LutOrigin {
    /// The `--stats` name: `none`, `memory`, `disk-cache`, `computed`, `gpu`.
    pub fn name(self) -> &'static str {
        match self {
            LutOrigin::None => "none",
            LutOrigin::Memory => "memory",
            LutOrigin::DiskCache => "disk-cache",
            LutOrigin::Computed => "computed",
            LutOrigin::Gpu => "gpu",
        }
    }
}

impl std::fmt::Display for LutOrigin {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

impl serde::Serialize for LutOrigin {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(self.name())
    }
}

/// Progress of a long precomputation (a terminal progress bar, a log).
pub trait LutProgress: Send + Sync {
    /// `total` units of work start.
    fn start(&self, total: usize);
    /// One unit is done (called from worker threads).
    fn advance(&self);
    /// The work is done.
    fn finish(&self);
}

/// Computes the parameter-dependent LUTs on all cores (the
/// multiple-scattering rows in parallel), reporting each row to
/// `progress`.
pub fn precompute(
    params: &AtmosphereParams,
    config: &LutConfig,
    progress: Option<&dyn LutProgress>,
) -> AtmosphereLuts {
    use rayon::prelude::*;
    let medium = crate::atmosphere::Medium::new(params);
    let t = AtmosphereLuts::transmittance_lut(&medium, config, Spectrum::ZERO);
    let fwd = crate::atmosphere::lut::forward_scattering(&medium, config);
    let ts = AtmosphereLuts::transmittance_lut(&medium, config, fwd);
    let n = config.multiscatter_n;
    if let Some(p) = progress {
        p.start(n);
    }
    let rows: Vec<Vec<Spectrum>> = (0..n)
        .into_par_iter()
        .map(|j| {
            let r = AtmosphereLuts::multiscatter_row(&medium, config, &ts, j);
            if let Some(p) = progress {
                p.advance();
            }
            r
        })
        .collect();
    if let Some(p) = progress {
        p.finish();
    }
    AtmosphereLuts::from_parts(params, config, t, ts, rows)
}

/// The LUTs of the last parameters in memory, backed by the disk cache.
#[derive(Default, Clone)]
pub struct LutStore {
    #[cfg(feature = "std")]
    dir: Option<PathBuf>,
    progress: Option<Arc<dyn LutProgress>>,
    current: Option<Arc<AtmosphereLuts>>,
    /// The sky textures of the last frames and their decoder
    /// (`crate::texture_sky::TextureStore`).
    pub textures: crate::texture_sky::TextureStore,
    /// The low clouds' diffusion grids of the last frame
    /// (`super::clouds::GridStore`).
    pub cloud_grids: super::clouds::GridStore,
}

impl std::fmt::Debug for LutStore {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let mut d = f.debug_struct("LutStore");
        #[cfg(feature = "std")]
        d.field("dir", &self.dir);
        d.field("holds", &self.current.is_some()).finish()
    }
}

impl LutStore {
    /// A store with memory only.
    pub fn in_memory() -> Self {
        LutStore::default()
    }

    /// A store with the disk cache in `dir` (none: memory only; see
    /// [`default_cache_dir`]).
    #[cfg(feature = "std")]
    pub fn new(dir: Option<PathBuf>) -> Self {
        LutStore {
            dir,
            ..LutStore::default()
        }
    }

    /// The disk cache's directory.
    #[cfg(feature = "std")]
    pub fn cache_dir(&self) -> Option<&Path> {
        self.dir.as_deref()
    }

    /// Reports long precomputations to `progress` (none: silent).
    pub fn set_progress(&mut self, progress: Option<Arc<dyn LutProgress>>) {
        self.progress = progress;
    }

    /// The LUTs for `params`/`config`: from memory, else the disk cache,
    /// else computed on all cores (and written to the cache; a cache that
    /// cannot be written only costs time next run). Returns them with
    /// their origin.
    pub fn get(
        &mut self,
        params: &AtmosphereParams,
        config: &LutConfig,
    ) -> (Arc<AtmosphereLuts>, LutOrigin) {
        if let Some(l) = &self.current {
            if l.params == *params && l.config == *config {
                return (l.clone(), LutOrigin::Memory);
            }
            if l.params == *params && l.config.same_tables(config) {
                // Only the per-frame sky view differs (a sequence's small
                // metering previews): the held tables serve as they are.
                let luts = AtmosphereLuts {
                    config: *config,
                    ..AtmosphereLuts::clone(l)
                };
                return (Arc::new(luts), LutOrigin::Memory);
            }
        }
        #[cfg(feature = "std")]
        if let Some(l) = self.dir.as_deref().and_then(|d| load(d, params, config)) {
            return (self.insert(l), LutOrigin::DiskCache);
        }
        let l = precompute(params, config, self.progress.as_deref());
        #[cfg(feature = "std")]
        if let Some(d) = &self.dir {
            let _ = store(d, &l);
        }
        (self.insert(l), LutOrigin::Computed)
    }

    /// Holds `luts` (e.g. computed by a GPU backend) for the next frames
    /// with their parameters; returns the shared handle.
    pub fn insert(&mut self, luts: AtmosphereLuts) -> Arc<AtmosphereLuts> {
        self.current.insert(Arc::new(luts)).clone()
    }

    /// The LUTs held in memory, if any.
    pub fn current(&self) -> Option<&Arc<AtmosphereLuts>> {
        self.current.as_ref()
    }

    /// Forgets the LUTs held in memory (the disk cache stays).
    pub fn clear(&mut self) {
        self.current = None;
    }
}

/// The cache file format; a file of another version is recomputed.
const MAGIC: &[u8; 8] = b"HMLUT005";

/// The default cache directory (see the module documentation), or `None`
/// when disabled or no home directory is known.
#[cfg(feature = "std")]
pub fn default_cache_dir() -> Option<PathBuf> {
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

/// FNV-1a 64-bit hash (the file name's key only; the content is checked
/// with CRC-32).
fn fnv1a(bytes: &[u8]) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for &b in bytes {
        h ^= b as u64;
        h = h.wrapping_mul(0x0100_0000_01b3);
    }
    h
}

/// The text that identifies a parameter set: format, bands, parameters
/// and LUT configuration as JSON.
fn key_text(params: &AtmosphereParams, config: &LutConfig) -> String {
    format!(
        "{}|{}|{}|{}",
        String::from_utf8_lossy(MAGIC),
        BANDS,
        serde_json::to_string(params).unwrap_or_default(),
        serde_json::to_string(config).unwrap_or_default()
    )
}

/// The cache key (file name part) of a parameter set.
pub fn cache_key(params: &AtmosphereParams, config: &LutConfig) -> String {
    format!("{:016x}", fnv1a(key_text(params, config).as_bytes()))
}

/// The cache file of a parameter set in `dir`.
#[cfg(feature = "std")]
pub fn cache_path(dir: &Path, params: &AtmosphereParams, config: &LutConfig) -> PathBuf {
    dir.join(format!("atmosphere-{}.bin", cache_key(params, config)))
}

fn checksum(key: &str, payload: &[u8]) -> u32 {
    let mut h = crc32fast::Hasher::new();
    h.update(key.as_bytes());
    h.update(payload);
    h.finalize()
}

/// Writes the LUTs into `dir` (created if needed), through a synced
/// temporary file renamed into place ([`crate::file::write_file`]).
#[cfg(feature = "std")]
pub fn store(dir: &Path, luts: &AtmosphereLuts) -> std::io::Result<()> {
    std::fs::create_dir_all(dir)?;
    let n = 2 * luts.transmittance.data.len() + luts.multiscatter.data.len();
    let mut payload = Vec::with_capacity(n * BANDS * 4);
    for s in luts
        .transmittance
        .data
        .iter()
        .chain(&luts.scattering_transmittance.data)
        .chain(&luts.multiscatter.data)
    {
        for v in s.0 {
            payload.extend_from_slice(&v.to_le_bytes());
        }
    }
    let sum = checksum(&key_text(&luts.params, &luts.config), &payload);
    let mut out = Vec::with_capacity(12 + payload.len());
    out.extend_from_slice(MAGIC);
    out.extend_from_slice(&sum.to_le_bytes());
    out.extend_from_slice(&payload);
    let p = cache_path(dir, &luts.params, &luts.config);
    crate::file::write_bytes(&p, &out).map_err(std::io::Error::other)
}

/// Reads the LUTs of `params`/`config` from `dir`: `None` when the file is
/// absent, of another format version or length, altered (checksum), or
/// holds a non-finite value.
#[cfg(feature = "std")]
pub fn load(dir: &Path, params: &AtmosphereParams, config: &LutConfig) -> Option<AtmosphereLuts> {
    let bytes = std::fs::read(cache_path(dir, params, config)).ok()?;
    let nt = config.transmittance_w * config.transmittance_h;
    let nm = config.multiscatter_n * config.multiscatter_n;
    if bytes.len() != 12 + (2 * nt + nm) * BANDS * 4 || &bytes[..8] != MAGIC {
        return None;
    }
    let sum = u32::from_le_bytes([bytes[8], bytes[9], bytes[10], bytes[11]]);
    let payload = &bytes[12..];
    if checksum(&key_text(params, config), payload) != sum {
        return None;
    }
    let mut spectra = payload.chunks_exact(BANDS * 4).map(|c| {
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
    let lut = |data| Lut2 {
        w: config.transmittance_w,
        h: config.transmittance_h,
        data,
    };
    Some(AtmosphereLuts::from_parts(
        params,
        config,
        lut(t),
        lut(ts),
        m.chunks(config.multiscatter_n.max(1))
            .map(<[Spectrum]>::to_vec)
            .collect(),
    ))
}

#[cfg(all(test, feature = "std"))]
mod tests {
    use super::*;

    fn scratch(name: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("himmel-lut-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        d
    }

    /// A damaged file is never used: each damage is detected, the LUTs are
    /// recomputed (origin `computed`, equal to a clean computation) and
    /// the file replaced by an intact one.
    #[test]
    fn damaged_cache_files_are_recomputed_and_replaced() {
        let (params, config) = (AtmosphereParams::default(), LutConfig::small());
        let dir = scratch("damage");
        let clean = precompute(&params, &config, None);
        store(&dir, &clean).unwrap();
        let path = cache_path(&dir, &params, &config);
        let intact = std::fs::read(&path).unwrap();
        let (l, origin) = LutStore::new(Some(dir.clone())).get(&params, &config);
        assert_eq!(origin, LutOrigin::DiskCache);
        assert_eq!(l.multiscatter.data, clean.multiscatter.data);
        type Damage = fn(&mut Vec<u8>);
        let damages: [(&str, Damage); 4] = [
            ("1000 texels changed to other finite values", |b| {
                for k in 0..1000 {
                    let at = 12 + 4 * (k * 97 % ((b.len() - 12) / 4));
                    let v = f32::from_le_bytes([b[at], b[at + 1], b[at + 2], b[at + 3]]);
                    b[at..at + 4].copy_from_slice(&(v * 0.5 + 1e-3).to_le_bytes());
                }
            }),
            ("one texel changed by one ulp", |b| {
                let at = b.len() - 4;
                let v = f32::from_le_bytes([b[at], b[at + 1], b[at + 2], b[at + 3]]);
                b[at..].copy_from_slice(&f32::from_bits(v.to_bits() + 1).to_le_bytes());
            }),
            ("truncated", |b| b.truncate(b.len() / 2)),
            ("another format version", |b| {
                b[..8].copy_from_slice(b"HMLUT004")
            }),
        ];
        for (what, damage) in damages {
            let mut bytes = intact.clone();
            damage(&mut bytes);
            std::fs::write(&path, &bytes).unwrap();
            assert!(load(&dir, &params, &config).is_none(), "{what}: loaded");
            let (l, origin) = LutStore::new(Some(dir.clone())).get(&params, &config);
            assert_eq!(origin, LutOrigin::Computed, "{what}");
            assert_eq!(l.transmittance.data, clean.transmittance.data, "{what}");
            assert_eq!(l.multiscatter.data, clean.multiscatter.data, "{what}");
            assert_eq!(
                std::fs::read(&path).unwrap(),
                intact,
                "{what}: not replaced"
            );
        }
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn memory_serves_the_same_parameters_only() {
        let mut s = LutStore::in_memory();
        let config = LutConfig::small();
        let a = AtmosphereParams::default();
        assert_eq!(s.get(&a, &config).1, LutOrigin::Computed);
        assert_eq!(s.get(&a, &config).1, LutOrigin::Memory);
        let b = AtmosphereParams {
            aerosol_density: a.aerosol_density * 2.0,
            ..a.clone()
        };
        assert_eq!(s.get(&b, &config).1, LutOrigin::Computed);
        assert_eq!(LutOrigin::DiskCache.name(), "disk-cache");
    }

    /// The sky view's size and steps are no part of the precomputed
    /// tables: another sky view is served from memory with the tables a
    /// fresh computation for its configuration gives, bit for bit; any
    /// other field is computed anew.
    #[test]
    fn another_sky_view_reuses_the_tables() {
        let mut s = LutStore::in_memory();
        let (a, config) = (AtmosphereParams::default(), LutConfig::small());
        s.get(&a, &config);
        let preview = LutConfig {
            sky_view_w: 24,
            sky_view_h: 14,
            sky_view_steps: 12,
            ..config
        };
        let (l, origin) = s.get(&a, &preview);
        assert_eq!(origin, LutOrigin::Memory);
        assert_eq!(l.config, preview);
        let fresh = precompute(&a, &preview, None);
        assert_eq!(l.transmittance.data, fresh.transmittance.data);
        assert_eq!(l.multiscatter.data, fresh.multiscatter.data);
        // The store still holds the frame's own configuration.
        assert_eq!(s.current().map(|l| l.config), Some(config));
        let other = LutConfig {
            multiscatter_steps: config.multiscatter_steps + 1,
            ..config
        };
        assert_eq!(s.get(&a, &other).1, LutOrigin::Computed);
    }
}
