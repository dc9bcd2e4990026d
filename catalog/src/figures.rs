//! Constellation stick figures and Milky Way outlines (J2000 RA/Dec, from
//! d3-celestial: `constellations.lines.json` and `mw.json`, the latter after
//! J. R. Vieira's Milky Way Outline Catalog).

use glam::DVec3;

use crate::binary::{read_polylines, PolylineGroup};
use crate::error::CatalogError;

const LINES_BIN: &[u8] = include_bytes!("../data/lines.bin");
const MILKYWAY_BIN: &[u8] = include_bytes!("../data/milkyway.bin");

/// A polyline on the sky: (RA, Dec) vertices in degrees, mean equator and
/// equinox of J2000 (≈ ICRS to 0.02″).
#[derive(Debug, Clone, PartialEq)]
pub struct SkyPolyline {
    /// Vertices, [RA in [0, 360), Dec in [−90, 90]] degrees.
    pub points: Vec<[f64; 2]>,
}

impl SkyPolyline {
    /// The vertices as unit vectors (x towards RA 0, z towards the north
    /// pole), ready for the rotation of [`himmel_astro::stars::FrameRotation`].
    pub fn unit_vectors(&self) -> Vec<DVec3> {
        self.points
            .iter()
            .map(|[ra, dec]| {
                let (sr, cr) = ra.to_radians().sin_cos();
                let (sd, cd) = dec.to_radians().sin_cos();
                DVec3::new(cd * cr, cd * sr, sd)
            })
            .collect()
    }
}

/// The stick figure of one constellation.
#[derive(Debug, Clone, PartialEq)]
pub struct ConstellationFigure {
    /// IAU three-letter abbreviation, e.g. "UMa".
    pub abbreviation: String,
    /// The figure's polylines (each joins stars in order).
    pub lines: Vec<SkyPolyline>,
}

/// One brightness step of the Milky Way outlines: closed rings (last vertex
/// joins the first). Level 1 is the faintest, widest outline, 5 the
/// brightest core.
#[derive(Debug, Clone, PartialEq)]
pub struct MilkyWayLevel {
    /// Brightness step, 1 (faint) … 5 (bright).
    pub level: u8,
    /// Outline rings.
    pub rings: Vec<SkyPolyline>,
}

fn to_lines(lines: Vec<Vec<[f64; 2]>>) -> Vec<SkyPolyline> {
    lines
        .into_iter()
        .map(|points| SkyPolyline { points })
        .collect()
}

fn decode_figures(groups: Vec<PolylineGroup>) -> Vec<ConstellationFigure> {
    groups
        .into_iter()
        .map(|(abbreviation, lines)| ConstellationFigure {
            abbreviation,
            lines: to_lines(lines),
        })
        .collect()
}

/// The 88 constellations' stick figures, decoded on first use: 89 entries,
/// as Serpens appears twice (Caput and Cauda, both tagged "Ser").
pub fn constellation_figures() -> Result<&'static [ConstellationFigure], CatalogError> {
    static CELL: std::sync::OnceLock<Result<Vec<ConstellationFigure>, CatalogError>> =
        std::sync::OnceLock::new();
    CELL.get_or_init(|| read_polylines(LINES_BIN, "lines.bin", b"HMCL").map(decode_figures))
        .as_ref()
        .map(|v| v.as_slice())
        .map_err(Clone::clone)
}

/// The Milky Way outlines in five brightness steps, decoded on first use.
pub fn milky_way() -> Result<&'static [MilkyWayLevel], CatalogError> {
    static CELL: std::sync::OnceLock<Result<Vec<MilkyWayLevel>, CatalogError>> =
        std::sync::OnceLock::new();
    CELL.get_or_init(|| {
        let groups = read_polylines(MILKYWAY_BIN, "milkyway.bin", b"HMMW")?;
        groups
            .into_iter()
            .map(|(tag, rings)| {
                let level = tag
                    .strip_prefix("ol")
                    .and_then(|n| n.parse::<u8>().ok())
                    .filter(|n| (1..=5).contains(n))
                    .ok_or(CatalogError::Binary {
                        table: "milkyway.bin",
                        offset: 0,
                        reason: "level tag is not ol1..ol5",
                    })?;
                Ok(MilkyWayLevel {
                    level,
                    rings: to_lines(rings),
                })
            })
            .collect()
    })
    .as_ref()
    .map(|v| v.as_slice())
    .map_err(Clone::clone)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Galactic latitude (degrees) of a J2000 unit vector: the north galactic
    /// pole is at RA 192.85948°, Dec +27.12825° (J2000; Hipparcos vol. 1 §1.5.3).
    fn galactic_latitude(v: DVec3) -> f64 {
        let (ra, dec) = (192.859_48_f64.to_radians(), 27.128_25_f64.to_radians());
        let pole = DVec3::new(dec.cos() * ra.cos(), dec.cos() * ra.sin(), dec.sin());
        v.dot(pole).asin().to_degrees()
    }

    #[test]
    fn milky_way_hugs_the_galactic_plane() {
        let mw = milky_way().unwrap();
        assert_eq!(mw.len(), 5);
        for level in mw {
            let pts: Vec<DVec3> = level.rings.iter().flat_map(|r| r.unit_vectors()).collect();
            assert!(!pts.is_empty());
            let mean_abs_b =
                pts.iter().map(|v| galactic_latitude(*v).abs()).sum::<f64>() / pts.len() as f64;
            // Outlines of a band along b = 0: mean |b| is some degrees, never tens.
            assert!(mean_abs_b < 20.0, "level {}: {mean_abs_b}", level.level);
        }
    }

    #[test]
    fn big_dipper_is_in_ursa_major() {
        let figs = constellation_figures().unwrap();
        let uma = figs.iter().find(|f| f.abbreviation == "UMa").unwrap();
        // Dubhe (RA 165.93°, Dec +61.75°) is a vertex of the figure.
        let has_dubhe = uma
            .lines
            .iter()
            .flat_map(|l| l.points.iter())
            .any(|p| (p[0] - 165.93).abs() < 0.05 && (p[1] - 61.75).abs() < 0.05);
        assert!(has_dubhe);
        let mut abbrs: Vec<&str> = figs.iter().map(|f| f.abbreviation.as_str()).collect();
        abbrs.sort();
        abbrs.dedup();
        assert!(abbrs.len() >= 88, "{}", abbrs.len());
    }
}
