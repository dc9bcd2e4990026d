//! A case's frame by the wgpu renderer, and the Mitsuba references of
//! `tests/fixtures/world_ref/` it is measured against.

use himmel_skymodel::{RenderOutput, Scene, SkyRenderer, SkyState};
use himmel_wgpu::WgpuRenderer;

use super::cases::root;
use super::metrics::{read_exr, RgbImage};

/// The frame of scene `s` by `r`, after handing `r` the scene's world (its
/// glTF file, relative to the repository's root).
pub fn render_world(r: &mut WgpuRenderer, s: &Scene) -> RenderOutput {
    let gltf = &s.world.as_ref().expect("a scene with a world").gltf;
    let world = himmel_world::gltf_io::load(&root().join(gltf.as_str())).unwrap();
    let state = SkyState::at(s).unwrap();
    r.set_world(&world);
    r.render(s, &state).unwrap()
}

/// Mitsuba's render of the case `name` of `tools/world_cases.json` and its
/// mask image (channels [`super::metrics::SUNLIT`], `SKYLIT`, … for
/// [`super::metrics::mask_channel`]).
pub fn world_reference(name: &str) -> (RgbImage, RgbImage) {
    let dir = root().join("tests/fixtures/world_ref");
    let reference = read_exr(dir.join(format!("{name}.exr"))).unwrap();
    let mask = read_exr(dir.join(format!("{name}_mask.exr"))).unwrap();
    (reference, mask)
}
