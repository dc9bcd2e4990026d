//! Renders a procedural world several times in one renderer and prints
//! each frame's per-pass times (the first frame builds the pipelines, the
//! environment light and the visibility maps; later frames reuse them).
//!
//! `cargo run --release -p himmel-wgpu --example world_frames -- [atrium|sun_room|plane_and_boxes] [W H] [FRAMES]`

use himmel_skymodel::{Effect, Projection, Scene, SkyRenderer, SkyState, WorldSpec};
use himmel_wgpu::WgpuRenderer;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().collect();
    let name = args.get(1).map_or("atrium", String::as_str);
    let w: u32 = args.get(2).and_then(|v| v.parse().ok()).unwrap_or(640);
    let h: u32 = args.get(3).and_then(|v| v.parse().ok()).unwrap_or(360);
    let frames: usize = args.get(4).and_then(|v| v.parse().ok()).unwrap_or(3);
    let (world, eye, at) = match name {
        "sun_room" => (
            himmel_world::procedural::sun_room(),
            [2.5, 1.6, -2.0],
            [-0.5, 0.3, 1.5],
        ),
        "plane_and_boxes" => (
            himmel_world::procedural::plane_and_boxes(),
            [8.0, 3.0, 8.0],
            [0.0, 0.5, -2.0],
        ),
        _ => (
            himmel_world::procedural::atrium(),
            [11.0, 1.7, 11.0],
            [-2.0, 2.0, -4.0],
        ),
    };
    let mut s = Scene::default();
    s.time.utc = "2024-06-21T15:00:00Z".into();
    s.camera.projection = Projection::Perspective;
    s.camera.width = w;
    s.camera.height = h;
    s.camera.fov_deg = 60.0;
    s.camera.position_m = Some(eye);
    s.camera.look_at_m = Some(at);
    s.effects.retain(|e| !matches!(e, Effect::Clouds));
    s.world = Some(WorldSpec {
        gltf: name.into(),
        ground: true,
    });
    let mut r = WgpuRenderer::new(himmel_skymodel::frame::luts::default_cache_dir())?;
    println!(
        "adapter: {} ({:?})",
        r.adapter_info().name,
        r.adapter_info().device_type
    );
    r.set_world(&world);
    for k in 0..frames {
        let state = SkyState::at(&s)?;
        let t = std::time::Instant::now();
        let out = r.render(&s, &state)?;
        let total = t.elapsed().as_secs_f64() * 1e3;
        let passes: Vec<String> = out
            .passes
            .iter()
            .filter(|p| {
                p.ms.is_some() || p.reason.as_deref().is_some_and(|r| r.starts_with("reused"))
            })
            .map(|p| match p.ms {
                Some(ms) => format!("{} {ms:.1}", p.name),
                None => format!("{} reused", p.name),
            })
            .collect();
        println!("frame {k}: {total:.1} ms — {}", passes.join(", "));
    }
    Ok(())
}
