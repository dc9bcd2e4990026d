//! The embedded catalogue against its sources: completeness per magnitude
//! bin, named stars, the source parsers on real excerpts, and malformed input.

use std::collections::BTreeMap;

use himmel_catalog::sources::{parse_d3_starnames, parse_d3_stars, parse_hip2, parse_hip2_line};
use himmel_catalog::{Catalog, CatalogError};

const HIP2: &str = include_str!("data/hip2_excerpt.dat");
const STARS8: &str = include_str!("data/stars8_excerpt.json");
const NAMES: &str = include_str!("data/starnames_excerpt.json");

#[test]
fn complete_to_v_6_5_bin_by_bin() {
    // Counts per 0.5 mag bin of d3-celestial's stars.8.json (V ≤ 6.5),
    // written by tools/gen_catalog.py from the source file.
    let src: serde_json::Value =
        serde_json::from_str(include_str!("../data/source_counts.json")).unwrap();
    let cat = Catalog::embedded().unwrap();
    let mut ours: BTreeMap<String, u64> = BTreeMap::new();
    for s in cat.brighter_than(6.5) {
        let k = (s.vmag * 2.0).floor() / 2.0;
        *ours.entry(format!("{k:.1}")).or_default() += 1;
    }
    let bins = src["bins"].as_object().unwrap();
    assert_eq!(bins.len(), ours.len());
    for (k, n) in bins {
        assert_eq!(ours.get(k).copied(), n.as_u64(), "bin {k}");
    }
    let total = cat.brighter_than(6.5).len();
    assert!(total >= 8800, "{total}");
    assert_eq!(total, cat.len());
    // Brightest first.
    assert!(cat.stars().windows(2).all(|w| w[0].vmag <= w[1].vmag));
}

#[test]
fn famous_stars_are_present_with_names() {
    let cat = Catalog::embedded().unwrap();
    for (name, hip, vmag) in [
        ("Sirius", 32349, -1.44),
        ("Canopus", 30438, -0.62),
        ("Arcturus", 69673, -0.05),
        ("Vega", 91262, 0.03),
        ("Polaris", 11767, 1.97),
        ("Dubhe", 54061, 1.81),
        ("Acrux", 60718, 0.77),
    ] {
        let s = cat
            .by_name(name)
            .unwrap_or_else(|| panic!("{name} missing"));
        assert_eq!(s.hip, hip, "{name}");
        assert!((s.vmag - vmag).abs() < 0.1, "{name} V = {}", s.vmag);
        assert!(s.bv.is_some());
        assert!(cat.by_hip(hip).is_some());
    }
    let dubhe = cat.by_name("dubhe").unwrap();
    assert_eq!(dubhe.designation().as_deref(), Some("α UMa"));
    // Dubhe is orange (B−V ≈ 1.07), Merak (β UMa) white (≈ 0.03).
    let merak = cat.by_hip(53910).unwrap();
    assert!(dubhe.bv.unwrap() > 0.9 && merak.bv.unwrap() < 0.1);
}

#[test]
fn parsers_rebuild_the_embedded_records() {
    let hip2 = parse_hip2(HIP2).unwrap();
    assert_eq!(hip2.len(), 12);
    let d3 = parse_d3_stars(STARS8).unwrap();
    let names = parse_d3_starnames(NAMES).unwrap();
    let built = Catalog::from_sources(&hip2, &d3, &names, 6.5).unwrap();
    let emb = Catalog::embedded().unwrap();
    assert!(built.len() >= 10);
    for s in built.stars() {
        let e = emb.by_hip(s.hip).unwrap();
        assert_eq!(
            (&s.name, &s.bayer, &s.constellation),
            (&e.name, &e.bayer, &e.constellation)
        );
        let (a, b) = (&s.astrometry, &e.astrometry);
        // Quantisation of the binary table: 2⁻³² turn, 0.01 mas(/yr).
        assert!((a.ra - b.ra).abs() < 2e-9 && (a.dec - b.dec).abs() < 2e-9);
        assert!((a.pm_ra_mas_yr - b.pm_ra_mas_yr).abs() < 0.006);
        assert!((a.parallax_mas - b.parallax_mas).abs() < 0.006);
        assert!((s.vmag - e.vmag).abs() < 6e-4);
        assert!((s.bv.unwrap() - e.bv.unwrap()).abs() < 6e-4);
    }
}

fn line_of(e: &CatalogError) -> usize {
    match e {
        CatalogError::TruncatedLine { line, .. }
        | CatalogError::BadField { line, .. }
        | CatalogError::Json { line, .. } => *line,
        other => panic!("unexpected {other:?}"),
    }
}

#[test]
fn malformed_hip2_lines_name_the_line() {
    let lines: Vec<&str> = HIP2.lines().collect();
    // Truncated third line.
    let mut t: Vec<String> = lines.iter().map(|s| s.to_string()).collect();
    t[2].truncate(100);
    let e = parse_hip2(&t.join("\n")).unwrap_err();
    assert!(
        matches!(e, CatalogError::TruncatedLine { line: 3, .. }),
        "{e}"
    );
    // Shifted columns on line 5.
    let mut t: Vec<String> = lines.iter().map(|s| s.to_string()).collect();
    t[4] = format!(" {}", t[4]);
    let e = parse_hip2(&t.join("\n")).unwrap_err();
    assert_eq!(line_of(&e), 5, "{e}");
    // NaN parallax on line 7 (columns 44–50).
    let mut t: Vec<String> = lines.iter().map(|s| s.to_string()).collect();
    t[6].replace_range(43..50, "    NaN");
    let e = parse_hip2(&t.join("\n")).unwrap_err();
    assert!(
        matches!(
            e,
            CatalogError::BadField {
                line: 7,
                field: "Plx",
                ..
            }
        ),
        "{e}"
    );
    assert!(e.to_string().contains("line 7"));
    // Letters in a numeric field, declination beyond the pole.
    let mut l = lines[0].to_string();
    l.replace_range(15..28, " 1.76x8185359");
    assert!(parse_hip2_line(&l, 9).is_err());
    let mut l = lines[0].to_string();
    l.replace_range(29..42, " 1.9000000000");
    assert!(matches!(
        parse_hip2_line(&l, 9),
        Err(CatalogError::BadField { field: "DErad", .. })
    ));
    // Every prefix of the file and non-ASCII bytes: errors, never panics.
    for cut in (0..HIP2.len()).step_by(7) {
        let _ = parse_hip2(&HIP2[..cut]);
    }
    assert!(parse_hip2_line("é".repeat(200).as_str(), 1).is_err());
}

#[test]
fn malformed_d3_json_names_the_line() {
    let good = r#"{"type":"FeatureCollection","features":[
{"type":"Feature","id":32349,"properties":{"mag":-1.44,"bv":"0.009"},"geometry":{"type":"Point","coordinates":[101.2872,-16.7161]}},
{"type":"Feature","id":30438,"properties":{"mag":-0.62,"bv":"0.164"},"geometry":{"type":"Point","coordinates":[95.988,-52.6957]}},
{"type":"Feature","id":88,"properties":{"mag":5.71,"bv":""},"geometry":{"type":"Point","coordinates":[0.2691,-48.8099]}}
]}"#;
    let ok = parse_d3_stars(good).unwrap();
    assert_eq!(ok.len(), 3);
    assert_eq!(ok[2].bv, None);
    let bad = |from: &str, to: &str| parse_d3_stars(&good.replace(from, to)).unwrap_err();
    // NaN is not JSON: the syntax error names line 3.
    assert_eq!(line_of(&bad("\"mag\":-0.62", "\"mag\":NaN")), 3);
    // Wrong member type / value.
    assert_eq!(line_of(&bad("\"mag\":5.71", "\"mag\":\"bright\"")), 4);
    assert_eq!(line_of(&bad("[95.988,-52.6957]", "[95.988,-95.0]")), 3);
    assert_eq!(line_of(&bad("[0.2691,-48.8099]", "[0.2691]")), 4);
    assert_eq!(line_of(&bad("\"bv\":\"0.164\"", "\"bv\":\"0.1.6\"")), 3);
    // Missing member, truncated document.
    assert!(parse_d3_stars(&good.replace("\"properties\"", "\"props\"")).is_err());
    for cut in (0..good.len()).step_by(5) {
        assert!(parse_d3_stars(&good[..cut]).is_err());
    }
    let names =
        "{\n\"32349\": {\"name\": \"Sirius\", \"c\": \"CMa\"},\n\"x1\": {\"name\": \"\"}\n}";
    assert_eq!(line_of(&parse_d3_starnames(names).unwrap_err()), 3);
    assert!(parse_d3_starnames(&names[..20]).is_err());
}

#[test]
fn colours_of_reference_stars() {
    use himmel_catalog::color::{
        planck_chromaticity, star_rgb, temperature_from_bv, LocusModel, WHITE_D65, WHITE_E,
    };
    let cat = Catalog::embedded().unwrap();
    for model in [LocusModel::Blackbody, LocusModel::Kim] {
        let betelgeuse = star_rgb(cat.by_name("Betelgeuse").unwrap().bv, model);
        assert!(
            betelgeuse[0] > betelgeuse[1] && betelgeuse[1] > betelgeuse[2],
            "{betelgeuse:?}"
        );
        let rigel = star_rgb(cat.by_name("Rigel").unwrap().bv, model);
        assert!(rigel[2] > rigel[0], "{rigel:?}");
        let dubhe = star_rgb(cat.by_name("Dubhe").unwrap().bv, model);
        let merak = star_rgb(cat.by_hip(53910).unwrap().bv, model);
        // Dubhe's orange next to Merak's white: redder relative to blue.
        assert!(dubhe[0] / dubhe[2] > 2.0 * merak[0] / merak[2]);
    }
    let (x, y) = planck_chromaticity(temperature_from_bv(0.65).unwrap()).unwrap();
    let d_e = (x - WHITE_E.0).hypot(y - WHITE_E.1);
    let d_65 = (x - WHITE_D65.0).hypot(y - WHITE_D65.1);
    println!("B-V 0.65: x = {x:.4}, y = {y:.4}; from E {d_e:.4}, from D65 {d_65:.4}");
    assert!(d_e < 0.01);
}

#[test]
fn constellation_figures_join_catalogue_stars() {
    // Every vertex of the stick figures should be a catalogue star at J2000
    // (the figures come from a different file of the same source).
    let cat = Catalog::embedded().unwrap();
    let j2000: Vec<[f64; 3]> = cat
        .stars()
        .iter()
        .map(|s| s.astrometry.direction_at(2_451_545.0).to_array())
        .collect();
    let figs = himmel_catalog::figures::constellation_figures().unwrap();
    let (mut n, mut matched) = (0, 0);
    for fig in figs {
        for line in &fig.lines {
            for v in line.unit_vectors() {
                n += 1;
                let best = j2000
                    .iter()
                    .map(|s| s[0] * v.x + s[1] * v.y + s[2] * v.z)
                    .fold(-1.0f64, f64::max);
                if best.min(1.0).acos().to_degrees() < 0.01 {
                    matched += 1;
                }
            }
        }
    }
    println!("{matched} of {n} figure vertices within 0.01° of a catalogue star");
    assert!(
        n > 800 && matched as f64 >= 0.98 * n as f64,
        "{matched}/{n}"
    );
}

#[test]
fn propagated_positions_match_the_j2000_positions_of_the_source() {
    // d3-celestial lists J2000 positions (0.0001° rounding, from XHIP); the
    // embedded J1991.25 astrometry carried to J2000 must land on them, which
    // checks the epoch and the proper-motion units (Sirius moves 11″ in the
    // 8.75 years).
    let d3 = parse_d3_stars(STARS8).unwrap();
    let cat = Catalog::embedded().unwrap();
    for s in &d3 {
        let star = cat.by_hip(s.hip).unwrap();
        let v = star.astrometry.direction_at(2_451_545.0);
        let (ra, dec) = (s.ra_deg.to_radians(), s.dec_deg.to_radians());
        let w = glam::DVec3::new(dec.cos() * ra.cos(), dec.cos() * ra.sin(), dec.sin());
        let sep = v.cross(w).length().atan2(v.dot(w)).to_degrees() * 3600.0;
        assert!(sep < 0.5, "HIP {}: {sep}″", s.hip);
    }
}
