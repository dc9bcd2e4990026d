//! Parsers for the source formats the embedded table is built from, so that
//! a user can build a catalogue from the original files (e.g. to a fainter
//! limit): `hip2.dat` of the Hipparcos new reduction (CDS I/311) and the
//! GeoJSON star and name files of d3-celestial. Every error names the line.

use std::collections::HashMap;

use himmel_astro::stars::Astrometry;
use serde::Deserialize;
use serde_json::value::RawValue;

use crate::error::CatalogError;
use crate::star::{Catalog, Star};

/// One record of `hip2.dat`: the fields Himmel uses.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Hip2Record {
    /// Hipparcos number.
    pub hip: u32,
    /// ICRS right ascension at J1991.25, radians.
    pub ra: f64,
    /// ICRS declination at J1991.25, radians.
    pub dec: f64,
    /// Parallax, mas.
    pub parallax_mas: f64,
    /// Proper motion μα* (times cos δ), mas/yr.
    pub pm_ra_mas_yr: f64,
    /// Proper motion μδ, mas/yr.
    pub pm_dec_mas_yr: f64,
    /// Hipparcos magnitude Hp, mag.
    pub hp_mag: f64,
    /// B−V colour index, mag.
    pub bv: f64,
}

const HIP2: &str = "hip2.dat";

/// Columns (1-based, inclusive) of `hip2.dat`, per the CDS ReadMe of I/311
/// (van Leeuwen 2007) as laid out in the distributed file.
const HIP2_FIELDS: [(&str, usize, usize); 8] = [
    ("HIP", 1, 6),
    ("RArad", 16, 28),
    ("DErad", 30, 42),
    ("Plx", 44, 50),
    ("pmRA", 52, 59),
    ("pmDE", 61, 68),
    ("Hpmag", 130, 136),
    ("B-V", 153, 158),
];
/// Columns that separate fields and must be blank: a shifted line fails here.
const HIP2_BLANKS: [usize; 7] = [7, 15, 29, 43, 51, 60, 129];

/// Parses one line of `hip2.dat` (`line_no` is 1-based, for the error).
///
/// Rejects lines shorter than 158 characters, non-ASCII lines, fields that
/// do not parse, are not finite (`NaN`, `inf`) or lie outside their range,
/// and lines whose separating columns are not blank (shifted columns).
pub fn parse_hip2_line(line: &str, line_no: usize) -> Result<Hip2Record, CatalogError> {
    let line = line.trim_end_matches(['\n', '\r']);
    let needed = 158;
    if line.len() < needed || !line.is_ascii() {
        return Err(CatalogError::TruncatedLine {
            source: HIP2,
            line: line_no,
            len: line.chars().count(),
            needed,
        });
    }
    let bytes = line.as_bytes();
    for col in HIP2_BLANKS {
        if bytes[col - 1] != b' ' {
            return Err(CatalogError::BadField {
                source: HIP2,
                line: line_no,
                field: "separator",
                text: format!("column {col}: '{}'", bytes[col - 1] as char),
                reason: "expected a blank: columns are shifted",
            });
        }
    }
    let mut v = [0.0f64; 8];
    for (k, (name, a, b)) in HIP2_FIELDS.iter().enumerate() {
        let text = line[a - 1..*b].trim();
        let bad = |reason| CatalogError::BadField {
            source: HIP2,
            line: line_no,
            field: name,
            text: text.to_string(),
            reason,
        };
        let x: f64 = text.parse().map_err(|_| bad("not a number"))?;
        if !x.is_finite() {
            return Err(bad("not finite"));
        }
        v[k] = x;
    }
    let field_err = |k: usize, reason| CatalogError::BadField {
        source: HIP2,
        line: line_no,
        field: HIP2_FIELDS[k].0,
        text: v[k].to_string(),
        reason,
    };
    if v[0] < 1.0 || v[0] > 200_000.0 || v[0].fract() != 0.0 {
        return Err(field_err(0, "not a Hipparcos number"));
    }
    if !(0.0..=std::f64::consts::TAU).contains(&v[1]) {
        return Err(field_err(1, "outside [0, 2π]"));
    }
    if v[2].abs() > std::f64::consts::FRAC_PI_2 {
        return Err(field_err(2, "outside [−π/2, π/2]"));
    }
    Ok(Hip2Record {
        hip: v[0] as u32,
        ra: v[1],
        dec: v[2],
        parallax_mas: v[3],
        pm_ra_mas_yr: v[4],
        pm_dec_mas_yr: v[5],
        hp_mag: v[6],
        bv: v[7],
    })
}

/// Parses a whole `hip2.dat` (blank lines are skipped).
pub fn parse_hip2(text: &str) -> Result<Vec<Hip2Record>, CatalogError> {
    text.lines()
        .enumerate()
        .filter(|(_, l)| !l.trim().is_empty())
        .map(|(i, l)| parse_hip2_line(l, i + 1))
        .collect()
}

/// One star of d3-celestial's `stars.*.json`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct D3Star {
    /// Hipparcos number.
    pub hip: u32,
    /// V magnitude.
    pub vmag: f64,
    /// B−V, mag (`None` when the file has an empty string).
    pub bv: Option<f64>,
    /// Right ascension, degrees in [0, 360) (the file's longitude, wrapped).
    pub ra_deg: f64,
    /// Declination, degrees.
    pub dec_deg: f64,
}

/// Names and designations of one star (d3-celestial `starnames.json`).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct StarNames {
    /// Proper name.
    pub name: Option<String>,
    /// Bayer letter.
    pub bayer: Option<String>,
    /// Flamsteed number.
    pub flamsteed: Option<String>,
    /// Constellation abbreviation.
    pub constellation: Option<String>,
}

/// 1-based line of byte `offset` in `text`.
fn line_of(text: &str, offset: usize) -> usize {
    text.as_bytes()[..offset.min(text.len())]
        .iter()
        .filter(|&&b| b == b'\n')
        .count()
        + 1
}

fn offset_in(text: &str, part: &str) -> usize {
    (part.as_ptr() as usize).saturating_sub(text.as_ptr() as usize)
}

fn json_err(source: &'static str, text: &str, e: &serde_json::Error, base: usize) -> CatalogError {
    // serde_json's line is relative to the slice it parsed.
    let line = if base == 0 {
        e.line()
    } else {
        line_of(text, base) + e.line().saturating_sub(1)
    };
    CatalogError::Json {
        source,
        line,
        message: e.to_string(),
    }
}

#[derive(Deserialize)]
struct Collection<'a> {
    #[serde(borrow)]
    features: Vec<&'a RawValue>,
}

#[derive(Deserialize)]
struct Feature {
    id: serde_json::Value,
    properties: Properties,
    geometry: Geometry,
}

#[derive(Deserialize)]
struct Properties {
    mag: serde_json::Value,
    #[serde(default)]
    bv: serde_json::Value,
}

#[derive(Deserialize)]
struct Geometry {
    coordinates: Vec<f64>,
}

fn number(v: &serde_json::Value) -> Option<f64> {
    match v {
        serde_json::Value::Number(n) => n.as_f64(),
        serde_json::Value::String(s) => s.trim().parse().ok(),
        _ => None,
    }
    .filter(|x: &f64| x.is_finite())
}

/// Parses d3-celestial's `stars.6.json` / `stars.8.json` / `stars.14.json`
/// (GeoJSON points: `id` = HIP, `properties.mag`, `properties.bv`,
/// `geometry.coordinates` = [RA, Dec] in degrees).
pub fn parse_d3_stars(text: &str) -> Result<Vec<D3Star>, CatalogError> {
    const SRC: &str = "stars.json";
    let coll: Collection = serde_json::from_str(text).map_err(|e| json_err(SRC, text, &e, 0))?;
    let mut out = Vec::with_capacity(coll.features.len());
    for raw in coll.features {
        let base = offset_in(text, raw.get());
        let line = line_of(text, base);
        let f: Feature =
            serde_json::from_str(raw.get()).map_err(|e| json_err(SRC, text, &e, base))?;
        let bad = |field: &'static str, text: String, reason| CatalogError::BadField {
            source: SRC,
            line,
            field,
            text,
            reason,
        };
        let hip = number(&f.id)
            .filter(|h| *h >= 1.0 && *h <= 1e7 && h.fract() == 0.0)
            .ok_or_else(|| bad("id", f.id.to_string(), "not a Hipparcos number"))?
            as u32;
        let vmag = number(&f.properties.mag)
            .filter(|m| (-2.0..=30.0).contains(m))
            .ok_or_else(|| {
                bad(
                    "mag",
                    f.properties.mag.to_string(),
                    "not a magnitude in [-2, 30]",
                )
            })?;
        let bv = match &f.properties.bv {
            serde_json::Value::Null => None,
            serde_json::Value::String(s) if s.trim().is_empty() => None,
            v => Some(
                number(v)
                    .filter(|b| (-1.0..=5.0).contains(b))
                    .ok_or_else(|| bad("bv", v.to_string(), "not a B-V index in [-1, 5]"))?,
            ),
        };
        let c = &f.geometry.coordinates;
        if c.len() != 2 || !(-360.0..=360.0).contains(&c[0]) || !(-90.0..=90.0).contains(&c[1]) {
            return Err(bad(
                "coordinates",
                format!("{c:?}"),
                "expected [lon in [-360, 360], lat in [-90, 90]]",
            ));
        }
        out.push(D3Star {
            hip,
            vmag,
            bv,
            ra_deg: c[0].rem_euclid(360.0),
            dec_deg: c[1],
        });
    }
    Ok(out)
}

#[derive(Deserialize)]
struct RawNames {
    #[serde(default)]
    name: String,
    #[serde(default)]
    bayer: String,
    #[serde(default)]
    flam: String,
    #[serde(default)]
    c: String,
}

/// Parses d3-celestial's `starnames.json` (an object keyed by HIP number).
pub fn parse_d3_starnames(text: &str) -> Result<HashMap<u32, StarNames>, CatalogError> {
    const SRC: &str = "starnames.json";
    let map: HashMap<&str, &RawValue> =
        serde_json::from_str(text).map_err(|e| json_err(SRC, text, &e, 0))?;
    let mut out = HashMap::with_capacity(map.len());
    for (key, raw) in map {
        let base = offset_in(text, raw.get());
        let hip: u32 = key.trim().parse().map_err(|_| CatalogError::BadField {
            source: SRC,
            line: line_of(text, base),
            field: "key",
            text: key.to_string(),
            reason: "not a Hipparcos number",
        })?;
        let n: RawNames =
            serde_json::from_str(raw.get()).map_err(|e| json_err(SRC, text, &e, base))?;
        let opt = |s: String| (!s.trim().is_empty()).then_some(s);
        out.insert(
            hip,
            StarNames {
                name: opt(n.name),
                bayer: opt(n.bayer),
                flamsteed: opt(n.flam),
                constellation: opt(n.c),
            },
        );
    }
    Ok(out)
}

impl Catalog {
    /// Builds a catalogue the way `tools/gen_catalog.py` builds the embedded
    /// one: every star of the d3-celestial file with V ≤ `limit_mag`, with
    /// astrometry from `hip2.dat` (epoch J1991.25), V and B−V from
    /// d3-celestial (B−V from hip2 when d3 has none), names from
    /// `starnames.json`. A star missing from `hip2.dat` keeps the
    /// d3-celestial position (J2000) without proper motion or parallax.
    pub fn from_sources(
        hip2: &[Hip2Record],
        d3_stars: &[D3Star],
        names: &HashMap<u32, StarNames>,
        limit_mag: f64,
    ) -> Result<Catalog, CatalogError> {
        let by_hip: HashMap<u32, &Hip2Record> = hip2.iter().map(|r| (r.hip, r)).collect();
        let mut stars = Vec::new();
        for s in d3_stars.iter().filter(|s| s.vmag <= limit_mag) {
            let astro_err = |_| CatalogError::OutOfRange {
                what: "astrometry of a source star",
                value: s.hip as f64,
                min: 0.0,
                max: 0.0,
            };
            let (astrometry, bv_fallback) = match by_hip.get(&s.hip) {
                Some(r) => (
                    Astrometry::new(
                        r.ra,
                        r.dec,
                        r.pm_ra_mas_yr,
                        r.pm_dec_mas_yr,
                        r.parallax_mas,
                        0.0,
                        Astrometry::J1991_25,
                    )
                    .map_err(astro_err)?,
                    (r.bv != 0.0).then_some(r.bv),
                ),
                None => (
                    Astrometry::new(
                        s.ra_deg.to_radians(),
                        s.dec_deg.to_radians(),
                        0.0,
                        0.0,
                        0.0,
                        0.0,
                        Astrometry::J1991_25,
                    )
                    .map_err(astro_err)?,
                    None,
                ),
            };
            let n = names.get(&s.hip).cloned().unwrap_or_default();
            stars.push(Star {
                hip: s.hip,
                hr: None,
                name: n.name,
                bayer: n.bayer,
                flamsteed: n.flamsteed,
                constellation: n.constellation,
                astrometry,
                vmag: s.vmag,
                bv: s.bv.or(bv_fallback),
            });
        }
        Ok(Catalog::from_stars(stars))
    }
}
