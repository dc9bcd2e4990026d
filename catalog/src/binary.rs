//! The compact binary tables embedded in the crate (written by
//! `tools/gen_catalog.py`). All integers little-endian.
//!
//! `stars.bin`:
//!
//! | bytes | content |
//! |---|---|
//! | 4 | magic `HMSC` |
//! | 2, 2 | format version (1), record size (32) |
//! | 4, 4, 4 | number of stars *n*, of name entries *m*, length of the string section |
//! | 8 | catalogue epoch, JD (TT), f64 (J1991.25 = 2448349.0625) |
//! | 32 × *n* | star records, brightest first (below) |
//! | … | *m* name entries: proper name, Bayer letter, Flamsteed number, constellation — four strings, each a length byte and UTF-8 |
//!
//! A star record: `u32` HIP; `u16` HR (0 = none); `u16` name entry (0xFFFF =
//! none); `u32` ICRS right ascension in units of 2⁻³² turn; `i32`
//! declination in units of π·2⁻³² rad; `i32` μα* and `i32` μδ in
//! 0.01 mas/yr; `i32` parallax in 0.01 mas; `i16` V in millimag; `i16` B−V
//! in millimag (−32768 = unknown). Quantisation: 0.3 mas in position, far
//! below the catalogue's own errors.
//!
//! `lines.bin` (constellation figures, magic `HMCL`) and `milkyway.bin`
//! (outlines, magic `HMMW`): magic; `u16` version; `u16` number of groups;
//! per group a tag (length byte + ASCII), `u32` number of polylines, per
//! polyline `u32` number of points, per point `i32` RA and `i32` Dec (J2000)
//! in units of 10⁻⁵ degree.

use crate::error::CatalogError;

/// A bounds-checked little-endian reader over a byte slice.
pub(crate) struct Reader<'a> {
    bytes: &'a [u8],
    pos: usize,
    table: &'static str,
}

impl<'a> Reader<'a> {
    pub(crate) fn new(bytes: &'a [u8], table: &'static str) -> Self {
        Reader {
            bytes,
            pos: 0,
            table,
        }
    }

    pub(crate) fn error(&self, reason: &'static str) -> CatalogError {
        CatalogError::Binary {
            table: self.table,
            offset: self.pos,
            reason,
        }
    }

    pub(crate) fn take(&mut self, n: usize) -> Result<&'a [u8], CatalogError> {
        let end = self
            .pos
            .checked_add(n)
            .filter(|&e| e <= self.bytes.len())
            .ok_or_else(|| self.error("unexpected end of data"))?;
        let s = &self.bytes[self.pos..end];
        self.pos = end;
        Ok(s)
    }

    fn array<const N: usize>(&mut self) -> Result<[u8; N], CatalogError> {
        let mut a = [0u8; N];
        a.copy_from_slice(self.take(N)?);
        Ok(a)
    }

    pub(crate) fn u8(&mut self) -> Result<u8, CatalogError> {
        Ok(self.take(1)?[0])
    }
    pub(crate) fn u16(&mut self) -> Result<u16, CatalogError> {
        Ok(u16::from_le_bytes(self.array()?))
    }
    pub(crate) fn i16(&mut self) -> Result<i16, CatalogError> {
        Ok(i16::from_le_bytes(self.array()?))
    }
    pub(crate) fn u32(&mut self) -> Result<u32, CatalogError> {
        Ok(u32::from_le_bytes(self.array()?))
    }
    pub(crate) fn i32(&mut self) -> Result<i32, CatalogError> {
        Ok(i32::from_le_bytes(self.array()?))
    }
    pub(crate) fn f64(&mut self) -> Result<f64, CatalogError> {
        Ok(f64::from_le_bytes(self.array()?))
    }
    pub(crate) fn short_str(&mut self) -> Result<&'a str, CatalogError> {
        let n = self.u8()? as usize;
        let b = self.take(n)?;
        std::str::from_utf8(b).map_err(|_| self.error("string is not UTF-8"))
    }
    pub(crate) fn remaining(&self) -> usize {
        self.bytes.len() - self.pos
    }
}

/// One group of polylines of `lines.bin` / `milkyway.bin`: a tag and its
/// polylines as (RA, Dec) pairs in degrees, J2000.
pub(crate) type PolylineGroup = (String, Vec<Vec<[f64; 2]>>);

/// Decodes `lines.bin` / `milkyway.bin`.
pub(crate) fn read_polylines(
    bytes: &[u8],
    table: &'static str,
    magic: &[u8; 4],
) -> Result<Vec<PolylineGroup>, CatalogError> {
    let mut r = Reader::new(bytes, table);
    if r.take(4)? != magic {
        return Err(r.error("bad magic"));
    }
    if r.u16()? != 1 {
        return Err(r.error("unsupported version"));
    }
    let groups = r.u16()? as usize;
    let mut out = Vec::with_capacity(groups);
    for _ in 0..groups {
        let tag = r.short_str()?.to_string();
        let nlines = r.u32()? as usize;
        if nlines > r.remaining() / 4 {
            return Err(r.error("polyline count exceeds the data"));
        }
        let mut lines = Vec::with_capacity(nlines);
        for _ in 0..nlines {
            let npts = r.u32()? as usize;
            if npts > r.remaining() / 8 {
                return Err(r.error("point count exceeds the data"));
            }
            let mut pts = Vec::with_capacity(npts);
            for _ in 0..npts {
                let ra = r.i32()? as f64 * 1e-5;
                let dec = r.i32()? as f64 * 1e-5;
                if !(0.0..=360.0).contains(&ra) || !(-90.0..=90.0).contains(&dec) {
                    return Err(r.error("coordinate out of range"));
                }
                pts.push([ra, dec]);
            }
            lines.push(pts);
        }
        out.push((tag, lines));
    }
    if r.remaining() != 0 {
        return Err(r.error("trailing bytes"));
    }
    Ok(out)
}
