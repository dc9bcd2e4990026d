//! Writes the procedural test worlds as `.glb` files for the reference
//! tools (Mitsuba): `plane_and_boxes.glb`, `sun_room.glb`, `atrium.glb`,
//! and the plane with boxes on a metal floor of roughness 0.05 and 0.3
//! (`glossy_floor_005.glb`, `glossy_floor_030.glb`).
//!
//! ```sh
//! cargo run -p himmel-world --example export_worlds -- OUT_DIR
//! ```

use himmel_world::{gltf_io, procedural};

fn main() {
    let dir = std::env::args().nth(1).unwrap_or_else(|| ".".into());
    let dir = std::path::Path::new(&dir);
    if let Err(e) = std::fs::create_dir_all(dir) {
        eprintln!("error: {}: {e}", dir.display());
        std::process::exit(1);
    }
    for (name, world) in [
        ("plane_and_boxes", procedural::plane_and_boxes()),
        ("sun_room", procedural::sun_room()),
        ("atrium", procedural::atrium()),
        ("glossy_floor_005", procedural::glossy_plane_and_boxes(0.05)),
        ("glossy_floor_030", procedural::glossy_plane_and_boxes(0.3)),
    ] {
        let path = dir.join(format!("{name}.glb"));
        if let Err(e) = std::fs::write(&path, gltf_io::to_glb(&world)) {
            eprintln!("error: {}: {e}", path.display());
            std::process::exit(1);
        }
        println!("{}: {} triangles", path.display(), world.triangles());
    }
}
