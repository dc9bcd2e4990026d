//! `himmel render` with a 3D world (`shared/spec/world.md`): a world file
//! that cannot be read or parsed exits 2 naming the file and the fault;
//! `--backend cpu` with a world exits 3 naming `--backend wgpu`; a scene
//! file's `world.gltf` is relative to the scene file.

use std::process::Command;

fn himmel(args: &[&str]) -> (i32, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_himmel"))
        .args(args)
        .env("HIMMEL_CACHE_DIR", "")
        .env("NODEVICE_SELECT", "1")
        .output()
        .expect("run himmel");
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

fn dir(name: &str) -> std::path::PathBuf {
    let d = std::env::temp_dir().join(format!("himmel-world-cli-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
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
        r#"{"time": {"utc": "2024-06-21T12:00:00Z"}, "world": {"gltf": "room.glb", "ground": true}}"#,
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
