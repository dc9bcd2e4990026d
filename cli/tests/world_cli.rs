//! `himmel render` with a 3D world (`shared/spec/world.md`): a world file
//! that cannot be read or parsed exits 2 naming the file and the fault;
//! `--backend cpu` with a world exits 3 naming `--backend wgpu`; a scene
//! file's `world.gltf` is relative to the scene file; `wgpu` and `auto`
//! render the world (lavapipe here) and `--stats` reports its passes.

mod common;

fn himmel(args: &[&str]) -> (i32, String) {
    let (code, _, err) = common::run(args);
    (code, err)
}

fn dir(name: &str) -> std::path::PathBuf {
    common::fresh_dir("himmel-world-cli", name)
}

fn render(world: &str, backend: &str) -> (i32, String) {
    let out = std::env::temp_dir().join("himmel-world-cli.png");
    himmel(&[
        "render",
        "--time",
        "2024-06-21T12:00:00Z",
        "--lat",
        "48.14",
        "--lon",
        "11.58",
        "--width",
        "8",
        "--height",
        "8",
        "--backend",
        backend,
        "--world",
        world,
        "--output",
        out.to_str().unwrap(),
    ])
}

#[test]
fn bad_world_files_exit_2_naming_the_file() {
    let d = dir("bad");
    let good = himmel_world::gltf_io::to_glb(&himmel_world::procedural::plane_and_boxes());
    let cases: [(&str, Vec<u8>); 3] = [
        ("garbage.glb", b"certainly not glTF".to_vec()),
        ("truncated.glb", good[..good.len() / 3].to_vec()),
        ("empty.glb", Vec::new()),
    ];
    for (name, bytes) in cases {
        let p = d.join(name);
        std::fs::write(&p, bytes).unwrap();
        for backend in ["cpu", "wgpu", "auto"] {
            let (code, err) = render(p.to_str().unwrap(), backend);
            assert_eq!(code, 2, "{name} {backend}: {err}");
            assert!(err.starts_with("error: --world "), "{err}");
            assert!(err.contains(name), "{err}");
            assert_eq!(err.lines().count(), 1, "{err}");
        }
    }
    let (code, err) = render(d.join("missing.glb").to_str().unwrap(), "cpu");
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("missing.glb") && err.contains("cannot read"),
        "{err}"
    );
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn a_world_on_the_cpu_backend_exits_3_naming_wgpu() {
    let d = dir("cpu");
    let p = d.join("room.glb");
    let room = himmel_world::procedural::sun_room();
    std::fs::write(&p, himmel_world::gltf_io::to_glb(&room)).unwrap();
    let (code, err) = render(p.to_str().unwrap(), "cpu");
    assert_eq!(code, 3, "{err}");
    assert!(err.contains("--backend wgpu"), "{err}");
    // The scene file's world is relative to the scene file.
    let scene = d.join("scene.json");
    std::fs::write(
        &scene,
        r#"{"time": {"utc": "2024-06-21T12:00:00Z"}, "camera": {"projection": "perspective"}, "world": {"gltf": "room.glb", "ground": true}}"#,
    )
    .unwrap();
    let out = d.join("x.png");
    let (code, err) = himmel(&[
        "render",
        "--scene",
        scene.to_str().unwrap(),
        "--output",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 3, "{err}");
    assert!(err.contains("--backend wgpu"), "{err}");
    // A world key the contract does not know is refused naming it.
    std::fs::write(&scene, r#"{"world": {"gltf": "room.glb", "grund": true}}"#).unwrap();
    let (code, err) = himmel(&[
        "render",
        "--scene",
        scene.to_str().unwrap(),
        "--output",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("grund"), "{err}");
    // --ground without a world.
    let (code, err) = himmel(&[
        "render",
        "--time",
        "now",
        "--lat",
        "0",
        "--lon",
        "0",
        "--ground",
        "--output",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("--ground"), "{err}");
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn wgpu_and_auto_render_a_world_with_its_stats() {
    let d = dir("wgpu");
    let p = d.join("boxes.glb");
    std::fs::write(
        &p,
        himmel_world::gltf_io::to_glb(&himmel_world::procedural::plane_and_boxes()),
    )
    .unwrap();
    for (backend, pos) in [("wgpu", "--camera-pos=-3,1.5,2"), ("auto", "--camera-pos")] {
        let out = d.join(format!("{backend}.exr"));
        let stats = d.join(format!("{backend}.json"));
        let mut args = vec![
            "render",
            "--time",
            "2024-06-21T15:00:00Z",
            "--lat",
            "48.14",
            "--lon",
            "11.58",
            "--width",
            "48",
            "--height",
            "32",
            "--backend",
            backend,
            "--world",
            p.to_str().unwrap(),
            "--look-at",
            "0,0.5,-2",
            "--ground",
        ];
        // A negative triple, as `--flag=value` and as a separate value.
        args.push(pos);
        if pos == "--camera-pos" {
            args.push("-3,1.5,2");
        }
        args.extend([
            "--stats",
            stats.to_str().unwrap(),
            "--output",
            out.to_str().unwrap(),
        ]);
        let (code, err) = himmel(&args);
        assert_eq!(code, 0, "{backend}: {err}");
        let s: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(&stats).unwrap()).unwrap();
        assert_eq!(s["backend"], "wgpu", "{backend}");
        assert_eq!(s["world"]["triangles"], 50);
        assert_eq!(s["world"]["materials"], 3);
        assert!(s["world"]["load_ms"].as_f64().unwrap() >= 0.0);
        let lux = s["sun"]["direct_illuminance_lux"].as_f64().unwrap();
        assert!(lux > 10_000.0 && lux < 130_000.0, "{lux}");
        let sky = s["sky"]["horizontal_illuminance_lux"].as_f64().unwrap();
        assert!(sky > 1_000.0 && sky < 40_000.0, "{sky}");
        assert_eq!(s["moon"]["direct_illuminance_lux"], 0.0);
        let passes = s["passes"].as_array().unwrap();
        for name in [
            "world",
            "shadows",
            "world/gbuffer",
            "world/lighting",
            "world/sky-light",
        ] {
            let p = passes
                .iter()
                .find(|p| p["name"] == name)
                .unwrap_or_else(|| panic!("no {name} in {passes:?}"));
            assert_eq!(p["ran"], true, "{name}");
            assert!(p["ms"].as_f64().unwrap() > 0.0, "{name}");
        }
        let godrays = passes.iter().find(|p| p["name"] == "godrays").unwrap();
        assert_eq!(godrays["ran"], false);
    }
    // A bad triple exits 2 naming the flag.
    let out = d.join("bad.png");
    let (code, err) = himmel(&[
        "render",
        "--time",
        "now",
        "--lat",
        "0",
        "--lon",
        "0",
        "--backend",
        "wgpu",
        "--world",
        p.to_str().unwrap(),
        "--camera-pos",
        "1,2",
        "--output",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("--camera-pos"), "{err}");
    let _ = std::fs::remove_dir_all(&d);
}
