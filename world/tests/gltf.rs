//! glTF loading: the procedural worlds survive a `.glb` round trip exactly;
//! node transforms are applied (translation, rotation, scale, mirroring);
//! garbage, truncated and index- or accessor-corrupted files are errors
//! that name the file and what is wrong, never panics (every single-byte
//! corruption of a small file is tried).

use glam::Vec3;
use himmel_world::gltf_io::{from_slice, load, to_glb};
use himmel_world::{procedural, Material, World, WorldErrorKind};

fn round_trip(w: &World) -> World {
    let glb = to_glb(w);
    from_slice(&glb, "round-trip.glb").unwrap()
}

#[test]
fn procedural_worlds_round_trip_through_glb() {
    for (name, w) in [
        ("plane+boxes", procedural::plane_and_boxes()),
        ("sun room", procedural::sun_room()),
        ("atrium", procedural::atrium()),
    ] {
        let back = round_trip(&w);
        assert_eq!(back.meshes.len(), w.meshes.len(), "{name}");
        for (a, b) in back.meshes.iter().zip(&w.meshes) {
            assert_eq!(a.material, b.material, "{name}");
            assert_eq!(a.indices, b.indices, "{name}");
            assert_eq!(a.positions, b.positions, "{name}");
            assert_eq!(a.uvs, b.uvs, "{name}");
            // The loader renormalises normals: equal within f32 rounding.
            for (i, (n, m)) in a.normals.iter().zip(&b.normals).enumerate() {
                let d = (Vec3::from_array(*n) - Vec3::from_array(*m)).length();
                assert!(d < 1e-6, "{name}: normal {i}: {n:?} vs {m:?}");
            }
        }
        assert_eq!(back.materials, w.materials, "{name}");
        assert!(back.warnings.is_empty(), "{name}: {:?}", back.warnings);
        eprintln!(
            "{name}: {} triangles, {} materials, {:.1} m², bounds {:?}",
            w.triangles(),
            w.materials.len(),
            w.area(),
            w.bounds()
        );
    }
}

#[test]
fn emission_above_one_uses_the_strength_extension() {
    let mut b = procedural::Builder::default();
    let lamp = b.material(Material {
        emissive: [2000.0, 1500.0, 1000.0],
        ..Material::diffuse("lamp", [0.8; 3])
    });
    b.cuboid(lamp, Vec3::ZERO, Vec3::ONE);
    let w = b.build();
    let back = round_trip(&w);
    for (a, b) in back.materials[0]
        .emissive
        .iter()
        .zip(&w.materials[0].emissive)
    {
        assert!((a / b - 1.0).abs() < 1e-6, "{a} vs {b}");
    }
}

/// A hand-written glTF: one triangle mesh used by two nodes, one translated
/// by (10, 0, −5) and rotated 90° about y, one mirrored in x (scale −1).
fn transformed_gltf() -> String {
    // Three vertices (0,0,0), (1,0,0), (0,0,1) and indices 0 1 2; a normal
    // of +y at each vertex: 36 + 36 + 12 bytes.
    let mut bytes = Vec::new();
    for v in [[0.0f32, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]] {
        for c in v {
            bytes.extend(c.to_le_bytes());
        }
    }
    for _ in 0..3 {
        for c in [0.0f32, 1.0, 0.0] {
            bytes.extend(c.to_le_bytes());
        }
    }
    for i in [0u32, 2, 1] {
        bytes.extend(i.to_le_bytes());
    }
    let b64 = base64_encode(&bytes);
    let s = std::f32::consts::FRAC_1_SQRT_2;
    format!(
        r#"{{"asset":{{"version":"2.0"}},"scene":0,"scenes":[{{"nodes":[0,1]}}],
        "nodes":[{{"mesh":0,"translation":[10,0,-5],"rotation":[0,{s},0,{s}]}},{{"mesh":0,"scale":[-1,1,1]}}],
        "meshes":[{{"primitives":[{{"attributes":{{"POSITION":0,"NORMAL":1}},"indices":2}}]}}],
        "accessors":[
          {{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,0,1]}},
          {{"bufferView":1,"componentType":5126,"count":3,"type":"VEC3"}},
          {{"bufferView":2,"componentType":5125,"count":3,"type":"SCALAR"}}],
        "bufferViews":[{{"buffer":0,"byteOffset":0,"byteLength":36}},{{"buffer":0,"byteOffset":36,"byteLength":36}},{{"buffer":0,"byteOffset":72,"byteLength":12}}],
        "buffers":[{{"byteLength":84,"uri":"data:application/octet-stream;base64,{b64}"}}]}}"#
    )
}

fn base64_encode(b: &[u8]) -> String {
    const T: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut out = String::new();
    for c in b.chunks(3) {
        let n = (c[0] as u32) << 16
            | (*c.get(1).unwrap_or(&0) as u32) << 8
            | *c.get(2).unwrap_or(&0) as u32;
        for k in 0..4 {
            if k <= c.len() {
                out.push(T[(n >> (18 - 6 * k) & 63) as usize] as char);
            } else {
                out.push('=');
            }
        }
    }
    out
}

#[test]
fn node_transforms_are_applied() {
    let w = from_slice(transformed_gltf().as_bytes(), "transformed.gltf").unwrap();
    assert_eq!(w.meshes.len(), 2);
    let close =
        |a: [f32; 3], b: [f32; 3]| (Vec3::from_array(a) - Vec3::from_array(b)).length() < 1e-5;
    // Rotation by +90° about y maps x → −z: (1,0,0) → (0,0,−1), then the translation.
    let m = &w.meshes[0];
    assert!(
        close(m.positions[0], [10.0, 0.0, -5.0]),
        "{:?}",
        m.positions
    );
    assert!(
        close(m.positions[1], [10.0, 0.0, -6.0]),
        "{:?}",
        m.positions
    );
    assert!(
        close(m.positions[2], [11.0, 0.0, -5.0]),
        "{:?}",
        m.positions
    );
    assert!(close(m.normals[0], [0.0, 1.0, 0.0]));
    // The mirrored copy keeps its triangle facing its normal (+y).
    let m = &w.meshes[1];
    assert!(close(m.positions[1], [-1.0, 0.0, 0.0]));
    for t in m.indices.chunks_exact(3) {
        let p = |i: u32| Vec3::from_array(m.positions[i as usize]);
        let n = (p(t[1]) - p(t[0])).cross(p(t[2]) - p(t[0]));
        assert!(n.y > 0.0, "mirrored triangle faces {n:?}");
    }
    // No material: the glTF default one is appended.
    assert_eq!(w.materials.len(), 1);
    assert_eq!(w.meshes[0].material, 0);
}

#[test]
fn bad_files_name_the_file_and_the_fault() {
    let err = |bytes: &[u8]| from_slice(bytes, "bad.glb").unwrap_err();
    let e = err(b"this is not a glTF file at all");
    assert_eq!(e.file, "bad.glb");
    assert!(matches!(e.kind, WorldErrorKind::Parse(_)), "{e}");
    assert!(e.to_string().starts_with("bad.glb: "), "{e}");
    let glb = to_glb(&procedural::plane_and_boxes());
    let e = err(&glb[..glb.len() / 2]);
    assert!(matches!(e.kind, WorldErrorKind::Parse(_)), "truncated: {e}");
    // An index past the vertices.
    let text = transformed_gltf().replace(",\"indices\":2", ",\"indices\":3");
    let text = text.replace(
        r#"{"bufferView":2,"componentType":5125,"count":3,"type":"SCALAR"}]"#,
        r#"{"bufferView":2,"componentType":5125,"count":3,"type":"SCALAR"},{"bufferView":1,"componentType":5125,"count":3,"type":"SCALAR"}]"#,
    );
    let e = from_slice(text.as_bytes(), "index.gltf").unwrap_err();
    assert!(matches!(e.kind, WorldErrorKind::Index { .. }), "{e}");
    eprintln!("{e}");
    // An accessor running past its view.
    let text = transformed_gltf().replace(
        r#""count":3,"type":"VEC3","min""#,
        r#""count":30,"type":"VEC3","min""#,
    );
    let e = from_slice(text.as_bytes(), "accessor.gltf").unwrap_err();
    assert!(
        matches!(e.kind, WorldErrorKind::Accessor { accessor: 0, .. }),
        "{e}"
    );
    eprintln!("{e}");
    // A missing file.
    let e = load(std::path::Path::new("/nonexistent/world.glb")).unwrap_err();
    assert!(matches!(e.kind, WorldErrorKind::Io(_)), "{e}");
}

/// Every single-byte corruption of a small `.glb` (each byte set to 0x00,
/// 0xFF and flipped) loads or fails with an error; none panics.
#[test]
fn no_single_byte_corruption_panics() {
    let mut b = procedural::Builder::default();
    let m = b.material(Material::diffuse("box", [0.5; 3]));
    b.cuboid(m, Vec3::ZERO, Vec3::ONE);
    let glb = to_glb(&b.build());
    let (mut ok, mut failed) = (0, 0);
    for i in 0..glb.len() {
        for v in [0x00u8, 0xFF, !glb[i]] {
            let mut c = glb.clone();
            c[i] = v;
            match std::panic::catch_unwind(|| from_slice(&c, "fuzz.glb")) {
                Ok(Ok(_)) => ok += 1,
                Ok(Err(_)) => failed += 1,
                Err(_) => panic!("byte {i} set to {v:#04x} panics"),
            }
        }
    }
    eprintln!(
        "{} corruptions of a {}-byte file: {ok} load, {failed} errors",
        3 * glb.len(),
        glb.len()
    );
}

/// A node hierarchy that is not a forest is an error, found in one walk:
/// a node that lists itself twice as a child (before, the walk went
/// 64 levels deep with two branches per level, 2⁶⁴ visits: the fuzzer's
/// glTF target would hang on it), a cycle of two nodes, and a node with
/// two parents.
#[test]
fn cycles_and_shared_children_are_errors() {
    let scene = r#""scenes":[{"nodes":[0,1]}]"#;
    let first = r#""nodes":[{"mesh":0,"#;
    for (what, scenes, nodes) in [
        (
            "self, twice",
            r#""scenes":[{"nodes":[0]}]"#,
            r#""nodes":[{"children":[0,0],"mesh":0,"#,
        ),
        (
            "two-node cycle",
            r#""scenes":[{"nodes":[0]}]"#,
            r#""nodes":[{"children":[1],"mesh":0,"#,
        ),
        (
            "second parent",
            scene,
            r#""nodes":[{"children":[1],"mesh":0,"#,
        ),
    ] {
        let mut text = transformed_gltf()
            .replace(scene, scenes)
            .replace(first, nodes);
        if what == "two-node cycle" {
            text = text.replace(
                r#"{"mesh":0,"scale""#,
                r#"{"children":[0],"mesh":0,"scale""#,
            );
        }
        let t = std::time::Instant::now();
        let e = from_slice(text.as_bytes(), "nodes.gltf").unwrap_err();
        assert!(e.to_string().contains("reached twice"), "{what}: {e}");
        assert!(t.elapsed().as_secs_f64() < 1.0, "{what}");
    }
    // The same node listed by two scenes (no default scene) is drawn once.
    let text = transformed_gltf()
        .replace(r#""scene":0,"#, "")
        .replace(scene, r#""scenes":[{"nodes":[0,1]},{"nodes":[1]}]"#);
    let w = from_slice(text.as_bytes(), "scenes.gltf").unwrap();
    assert_eq!(w.meshes.len(), 2);
}

/// A primitive whose POSITION names an accessor that does not exist is an
/// error (glTF's own validation indexed the accessors unchecked and
/// panicked; found by `himmel-fuzz gltf`).
#[test]
fn a_missing_position_accessor_is_an_error() {
    for position in ["3", "99"] {
        let text =
            transformed_gltf().replace(r#""POSITION":0"#, &format!(r#""POSITION":{position}"#));
        let e = from_slice(text.as_bytes(), "position.gltf").unwrap_err();
        assert!(
            e.to_string()
                .contains(&format!("POSITION names accessor {position}")),
            "{e}"
        );
    }
}

/// Accessors whose format glTF does not allow for their use are errors
/// naming the accessor: float indices, signed texture coordinates (the
/// reader panicked on both; found by `himmel-fuzz gltf`), byte positions.
#[test]
fn accessor_formats_are_checked() {
    let with_uvs = transformed_gltf().replace(r#""NORMAL":1}"#, r#""NORMAL":1,"TEXCOORD_0":3}"#);
    let with_uvs = with_uvs.replace(
        r#"{"bufferView":2,"componentType":5125,"count":3,"type":"SCALAR"}]"#,
        r#"{"bufferView":2,"componentType":5125,"count":3,"type":"SCALAR"},{"bufferView":1,"componentType":5122,"count":3,"type":"VEC2"}]"#,
    );
    let cases = [
        (
            transformed_gltf().replace(
                r#""componentType":5125,"count":3,"type":"SCALAR""#,
                r#""componentType":5126,"count":3,"type":"SCALAR""#,
            ),
            "indices must be Scalar",
        ),
        (with_uvs, "TEXCOORD_0 must be Vec2"),
        (
            transformed_gltf().replace(
                r#""componentType":5126,"count":3,"type":"VEC3","min""#,
                r#""componentType":5121,"count":3,"type":"VEC3","min""#,
            ),
            "POSITION must be Vec3 of [F32]",
        ),
    ];
    for (text, expected) in cases {
        let e = from_slice(text.as_bytes(), "format.gltf").unwrap_err();
        assert!(e.to_string().contains(expected), "{e}");
    }
}

/// A GLB whose header declares fewer bytes than the 12-byte header is an
/// error (the gltf crate subtracted unchecked: an overflow panic with
/// overflow checks on; found by the fuzz smoke run in the dev profile).
#[test]
fn a_glb_shorter_than_its_header_is_an_error() {
    let glb = to_glb(&procedural::plane_and_boxes());
    for n in [0u32, 11] {
        let mut c = glb.clone();
        c[8..12].copy_from_slice(&n.to_le_bytes());
        let e = from_slice(&c, "short.glb").unwrap_err();
        assert!(
            e.to_string().contains(&format!("declares {n} bytes")),
            "{e}"
        );
    }
}

/// Munich's Marienplatz (`tests/fixtures/worlds/munich_marienplatz.glb`,
/// made by `tools/sionna_world.py` from sionna-rt's OpenStreetMap-derived
/// scene, centred on the Mariensäule): a real city loads, with its ground
/// at y = 0 cut to ±100 m, and its two towers stand where the map puts
/// them in Himmel's frame (x East, y Up, z South) — St. Peter's 91 m tower
/// 89 m south and 25 m east of the column, the Neues Rathaus' 85 m tower
/// 28 m north and 14 m east (their WGS84 positions, to ±10 m: the
/// meshes' tops are not the towers' survey points).
#[test]
fn a_real_city_loads_in_the_world_frame() {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../tests/fixtures/worlds/munich_marienplatz.glb"
    );
    let w = load(std::path::Path::new(path)).unwrap();
    assert!(w.warnings.is_empty(), "{:?}", w.warnings);
    assert_eq!(w.triangles(), 2432);
    let mut names: Vec<_> = w.materials.iter().filter_map(|m| m.name.clone()).collect();
    names.sort();
    assert_eq!(names, ["concrete", "marble", "metal"]);
    let b = w.bounds().unwrap();
    assert!(b.min.y.abs() < 1e-3, "{b:?}");
    assert!(b.min.x <= -100.0 && b.max.x >= 100.0 && b.min.z <= -100.0 && b.max.z >= 100.0);
    // The highest point within a height band, and where it stands.
    let top_in = |lo: f32, hi: f32| {
        w.meshes
            .iter()
            .flat_map(|m| &m.positions)
            .filter(|p| (lo..=hi).contains(&p[1]))
            .max_by(|a, b| a[1].total_cmp(&b[1]))
            .copied()
            .unwrap()
    };
    let peter = top_in(88.0, 95.0);
    let rathaus = top_in(80.0, 88.0);
    for (name, p, east, south, height) in [
        ("St. Peter", peter, 25.0, 89.0, 91.0),
        ("Neues Rathaus", rathaus, 14.0, -28.0, 85.0),
    ] {
        let off = ((p[0] - east).powi(2) + (p[2] - south).powi(2)).sqrt();
        assert!(
            off < 10.0,
            "{name}: top at {p:?}, {off:.1} m from ({east}, {south})"
        );
        assert!((p[1] - height).abs() < 1.0, "{name}: {} m high", p[1]);
    }
}
