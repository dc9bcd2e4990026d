//! Stars and the catalogue that holds them.

use himmel_astro::stars::Astrometry;
use himmel_astro::units::TAU;

use crate::binary::Reader;
use crate::error::CatalogError;

/// One catalogue star.
#[derive(Debug, Clone, PartialEq)]
pub struct Star {
    /// Hipparcos catalogue number.
    pub hip: u32,
    /// Bright Star Catalogue (HR) number, when the source has one (the
    /// embedded sources carry none: always `None` for the embedded table).
    pub hr: Option<u16>,
    /// IAU proper name (e.g. "Sirius").
    pub name: Option<String>,
    /// Bayer letter (Greek, e.g. "α"), with its superscript when the source has one.
    pub bayer: Option<String>,
    /// Flamsteed number (e.g. "9").
    pub flamsteed: Option<String>,
    /// IAU constellation abbreviation (e.g. "CMa").
    pub constellation: Option<String>,
    /// Position, proper motion and parallax (ICRS, catalogue epoch).
    pub astrometry: Astrometry,
    /// Johnson V magnitude.
    pub vmag: f64,
    /// Johnson B−V colour index, magnitudes (`None` when unknown).
    pub bv: Option<f64>,
}

impl Star {
    /// Bayer or Flamsteed designation with the constellation, e.g. "α CMa"
    /// or "61 Cyg"; `None` when the source gives neither.
    pub fn designation(&self) -> Option<String> {
        let c = self.constellation.as_deref()?;
        let d = self.bayer.as_deref().or(self.flamsteed.as_deref())?;
        Some(format!("{d} {c}"))
    }

    /// The proper name, else the designation, else "HIP n".
    pub fn label(&self) -> String {
        self.name
            .clone()
            .or_else(|| self.designation())
            .unwrap_or_else(|| format!("HIP {}", self.hip))
    }
}

/// A star catalogue, brightest star first.
#[derive(Debug, Clone, PartialEq)]
pub struct Catalog {
    stars: Vec<Star>,
}

const STARS_BIN: &[u8] = include_bytes!("../data/stars.bin");
#[cfg(feature = "faint")]
const STARS_V8_BIN: &[u8] = include_bytes!("../data/stars_v8.bin");

impl Catalog {
    /// The embedded catalogue: every Hipparcos star with V ≤ 6.5 (8 874
    /// stars; see the crate README for sources and epoch). Decoded on first
    /// use (about a millisecond) and shared afterwards.
    pub fn embedded() -> Result<&'static Catalog, CatalogError> {
        static CELL: std::sync::OnceLock<Result<Catalog, CatalogError>> =
            std::sync::OnceLock::new();
        CELL.get_or_init(|| Catalog::from_bytes(STARS_BIN))
            .as_ref()
            .map_err(Clone::clone)
    }

    /// The faint-background table (feature `faint`, adds 1.4 MB): every
    /// star of d3-celestial's `stars.8.json`, 41 411 stars to V = 8.0, same
    /// sources and epoch as [`Catalog::embedded`] (a superset of it).
    #[cfg(feature = "faint")]
    pub fn embedded_faint() -> Result<&'static Catalog, CatalogError> {
        static CELL: std::sync::OnceLock<Result<Catalog, CatalogError>> =
            std::sync::OnceLock::new();
        CELL.get_or_init(|| Catalog::from_bytes(STARS_V8_BIN))
            .as_ref()
            .map_err(Clone::clone)
    }

    /// A catalogue from stars in any order (sorted here, brightest first).
    pub fn from_stars(mut stars: Vec<Star>) -> Catalog {
        stars.sort_by(|a, b| a.vmag.total_cmp(&b.vmag).then(a.hip.cmp(&b.hip)));
        Catalog { stars }
    }

    /// Decodes a table in the `stars.bin` format (`catalog/src/binary.rs`
    /// documents it).
    pub fn from_bytes(bytes: &[u8]) -> Result<Catalog, CatalogError> {
        let mut r = Reader::new(bytes, "stars.bin");
        if r.take(4)? != b"HMSC" {
            return Err(r.error("bad magic"));
        }
        if r.u16()? != 1 {
            return Err(r.error("unsupported version"));
        }
        if r.u16()? != 32 {
            return Err(r.error("unexpected record size"));
        }
        let n = r.u32()? as usize;
        let m = r.u32()? as usize;
        let strings_len = r.u32()? as usize;
        let epoch = r.f64()?;
        if !(epoch.is_finite() && epoch > 0.0) {
            return Err(r.error("bad epoch"));
        }
        if r.remaining() != n.saturating_mul(32).saturating_add(strings_len) {
            return Err(r.error("table length does not match its header"));
        }
        let mut raw = Vec::with_capacity(n);
        for _ in 0..n {
            let hip = r.u32()?;
            let hr = r.u16()?;
            let name_idx = r.u16()?;
            let ra = r.u32()? as f64 * (TAU / 4_294_967_296.0);
            let dec = r.i32()? as f64 * (std::f64::consts::PI / 4_294_967_296.0);
            let pmra = r.i32()? as f64 * 0.01;
            let pmdec = r.i32()? as f64 * 0.01;
            let plx = r.i32()? as f64 * 0.01;
            let v = r.i16()? as f64 * 0.001;
            let bv = r.i16()?;
            let astrometry = Astrometry::new(ra, dec, pmra, pmdec, plx, 0.0, epoch)
                .map_err(|_| r.error("astrometry out of range"))?;
            raw.push((hip, hr, name_idx, astrometry, v, bv));
        }
        let mut names = Vec::with_capacity(m);
        for _ in 0..m {
            let mut e: [Option<String>; 4] = Default::default();
            for s in e.iter_mut() {
                let t = r.short_str()?;
                *s = (!t.is_empty()).then(|| t.to_string());
            }
            names.push(e);
        }
        let mut stars = Vec::with_capacity(n);
        for (hip, hr, name_idx, astrometry, vmag, bv) in raw {
            let [name, bayer, flamsteed, constellation] = if name_idx == 0xFFFF {
                Default::default()
            } else {
                // Each entry belongs to one star: move it out, no copy.
                names
                    .get_mut(name_idx as usize)
                    .map(std::mem::take)
                    .ok_or_else(|| r.error("name index out of range"))?
            };
            stars.push(Star {
                hip,
                hr: (hr != 0).then_some(hr),
                name,
                bayer,
                flamsteed,
                constellation,
                astrometry,
                vmag,
                bv: (bv != i16::MIN).then_some(bv as f64 * 0.001),
            });
        }
        Ok(Catalog::from_stars(stars))
    }

    /// All stars, brightest first.
    pub fn stars(&self) -> &[Star] {
        &self.stars
    }

    /// Number of stars.
    pub fn len(&self) -> usize {
        self.stars.len()
    }

    /// Whether the catalogue is empty.
    pub fn is_empty(&self) -> bool {
        self.stars.is_empty()
    }

    /// The stars with V ≤ `limit_mag`, brightest first.
    pub fn brighter_than(&self, limit_mag: f64) -> &[Star] {
        let n = self.stars.partition_point(|s| s.vmag <= limit_mag);
        &self.stars[..n]
    }

    /// The star with Hipparcos number `hip`.
    pub fn by_hip(&self, hip: u32) -> Option<&Star> {
        self.stars.iter().find(|s| s.hip == hip)
    }

    /// The star with this proper name (case-insensitive), e.g. "Vega".
    pub fn by_name(&self, name: &str) -> Option<&Star> {
        self.stars.iter().find(|s| {
            s.name
                .as_deref()
                .is_some_and(|n| n.eq_ignore_ascii_case(name))
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[cfg(feature = "faint")]
    #[test]
    fn faint_table_is_a_superset_to_v8() {
        let faint = Catalog::embedded_faint().unwrap();
        let bright = Catalog::embedded().unwrap();
        assert_eq!(faint.len(), 41_411);
        assert!(faint.stars().iter().all(|s| s.vmag <= 8.0));
        assert_eq!(faint.brighter_than(6.5), bright.stars());
    }

    #[test]
    fn corrupt_tables_are_errors_not_panics() {
        // Every truncation of the real table, and a few corrupted bytes.
        for cut in [0, 3, 4, 10, 31, 32, 100, STARS_BIN.len() - 1] {
            assert!(Catalog::from_bytes(&STARS_BIN[..cut]).is_err(), "{cut}");
        }
        let mut bad = STARS_BIN.to_vec();
        bad[0] = b'X';
        assert!(Catalog::from_bytes(&bad).is_err());
        let mut bad = STARS_BIN.to_vec();
        // Declination of the first star set to an impossible value.
        bad[28 + 12..28 + 16].copy_from_slice(&i32::MIN.to_le_bytes());
        let _ = Catalog::from_bytes(&bad); // −90° exactly is legal; must not panic
        let mut bad = STARS_BIN.to_vec();
        // Name index of the first star beyond the names table.
        bad[28 + 6..28 + 8].copy_from_slice(&0xFFFEu16.to_le_bytes());
        assert!(Catalog::from_bytes(&bad).is_err());
    }
}
