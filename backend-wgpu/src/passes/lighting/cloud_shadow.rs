//! Cloud shadows on a 3D world (issue 18): the cloud layers'
//! transmittance towards the Sun and the Moon over the world's footprint
//! on the ground plane ([`CloudFrame::shadow_map`], computed on the CPU
//! from the frame plan's clouds), uploaded as an `rg32float` texture that
//! the lighting pass (`shade.wgsl` `cloud_transmittance`) looks up
//! bilinearly where a surface point's ray towards the light crosses y = 0.
//!
//! The map covers the world's bounds as their shadows fall (each corner
//! projected along each light onto the ground) and, with `world.ground`,
//! the ground plane out to [`GROUND_REACH_M`] around the eye; beyond it
//! the ground takes the map's mean transmittance (kept in an extra row of
//! the texture), where the aerial perspective already veils the ground.
//! Its texels are at most [`TEXEL_M`] wide (cumulus cells are hundreds of
//! metres across), at most [`MAX_TEXELS`] per side. It is rebuilt only
//! when the clouds, the lights or the footprint changed.

use glam::Vec3;
use himmel_skymodel::clouds::{HighField, LowField, MarchSettings, Shell};
use himmel_skymodel::frame::CloudFrame;
use himmel_skymodel::renderer::PassStat;
use himmel_world::Aabb;

use crate::gpu::Gpu;

/// The widest texel of the map, m.
pub const TEXEL_M: f32 = 25.0;
/// The most texels per side.
pub const MAX_TEXELS: usize = 128;
/// How far around the eye the map covers a ground plane, m.
pub const GROUND_REACH_M: f32 = 8000.0;
/// The lowest light (sine of its altitude) whose shadow is projected.
const MIN_SIN_ALT: f32 = 0.02;

/// What a map was built for.
#[derive(Debug, Clone, PartialEq)]
struct MapKey {
    low: Option<LowField>,
    high: Option<HighField>,
    shell: Shell,
    march: MarchSettings,
    lights: [Option<Vec3>; 2],
    origin_m: [f32; 2],
    size_m: f32,
    n: usize,
}

/// The cloud-shadow map of the lighting pass and what it was built for.
#[derive(Default)]
pub struct CloudShadows {
    key: Option<MapKey>,
    texture: Option<(wgpu::Texture, wgpu::TextureView)>,
    white: Option<(wgpu::Texture, wgpu::TextureView)>,
    uniform: [f32; 4],
}

/// The square (least x, z corner and side, m) that the shadows of `bounds`
/// fall on along `lights` (world frame, towards the light), with the
/// ground plane's reach around `eye` when `ground`.
pub fn footprint(
    bounds: Option<Aabb>,
    ground: bool,
    eye: Vec3,
    lights: &[Vec3],
) -> Option<([f32; 2], f32)> {
    let mut lo = [f32::INFINITY; 2];
    let mut hi = [f32::NEG_INFINITY; 2];
    let mut add = |x: f32, z: f32| {
        lo = [lo[0].min(x), lo[1].min(z)];
        hi = [hi[0].max(x), hi[1].max(z)];
    };
    if let Some(b) = bounds {
        for c in crate::passes::lighting::view::aabb_corners(&b) {
            for l in lights {
                let q = c - *l * (c.y / l.y.max(MIN_SIN_ALT));
                add(q.x, q.z);
            }
        }
    }
    if ground {
        add(eye.x - GROUND_REACH_M, eye.z - GROUND_REACH_M);
        add(eye.x + GROUND_REACH_M, eye.z + GROUND_REACH_M);
    }
    if !(lo[0].is_finite() && hi[0].is_finite()) {
        return None;
    }
    let size = (hi[0] - lo[0]).max(hi[1] - lo[1]).max(1.0) * 1.02;
    let centre = [(lo[0] + hi[0]) * 0.5, (lo[1] + hi[1]) * 0.5];
    Some(([centre[0] - size * 0.5, centre[1] - size * 0.5], size))
}

impl CloudShadows {
    /// Builds (or keeps) the map for `clouds` and the lights `[sun, moon]`
    /// (world frame, towards the light; `None`: does not light the world),
    /// over the footprint of `bounds` (and the ground plane around `eye`).
    /// Returns its `--stats` entry; `None` when there are no clouds.
    pub fn update(
        &mut self,
        gpu: &Gpu,
        clouds: Option<&CloudFrame>,
        lights: [Option<Vec3>; 2],
        bounds: Option<Aabb>,
        ground: bool,
        eye: Vec3,
    ) -> Option<PassStat> {
        let t = std::time::Instant::now();
        let stat = |ran: bool, ms: Option<f64>, why: Option<&str>| PassStat {
            name: "world/cloud-shadows".into(),
            ran,
            ms,
            reason: why.map(str::to_string),
        };
        let Some(c) = clouds.filter(|c| c.low.is_some() || c.high.is_some()) else {
            self.uniform = [0.0; 4];
            return None;
        };
        let lit: Vec<Vec3> = lights.iter().flatten().copied().collect();
        let Some((origin_m, size_m)) =
            footprint(bounds, ground, eye, &lit).filter(|_| !lit.is_empty())
        else {
            self.uniform = [0.0; 4];
            return Some(stat(false, None, Some("no Sun or Moon lights the world")));
        };
        let n = ((size_m / TEXEL_M).ceil() as usize).clamp(2, MAX_TEXELS);
        let key = MapKey {
            low: c.low,
            high: c.high,
            shell: c.shell,
            march: c.march,
            lights,
            origin_m,
            size_m,
            n,
        };
        self.uniform = [origin_m[0], origin_m[1], 1.0 / size_m, n as f32];
        if self.key.as_ref() == Some(&key) && self.texture.is_some() {
            let why = "reused: the clouds, the lights and the world have not moved";
            return Some(stat(false, None, Some(why)));
        }
        let dirs = lights.map(|l| l.unwrap_or(Vec3::NEG_Y));
        let map = c.shadow_map(&dirs, origin_m, size_m, n);
        let mut texels: Vec<f32> = map.texels.iter().flatten().copied().collect();
        // The extra row: the mean transmittance, for the ground beyond.
        let mean = map
            .texels
            .iter()
            .fold([0.0f64; 2], |m, t| [m[0] + t[0] as f64, m[1] + t[1] as f64]);
        let count = map.texels.len().max(1) as f64;
        for _ in 0..n {
            texels.extend(mean.map(|m| (m / count) as f32));
        }
        let tex = rg_texture(gpu, "cloud shadows", [n as u32, n as u32 + 1], &texels);
        self.texture = Some(tex);
        self.key = Some(key);
        Some(stat(true, Some(t.elapsed().as_secs_f64() * 1e3), None))
    }

    /// The map's uniform for `shade.wgsl`: least corner x, z (m), 1/side
    /// (1/m), texels per side (0: no clouds, transmittance 1).
    pub fn uniform(&self) -> [f32; 4] {
        self.uniform
    }

    /// The map's view (a 1 × 1 white stand-in without clouds).
    pub fn view(&mut self, gpu: &Gpu) -> &wgpu::TextureView {
        if self.uniform[3] > 0.0 {
            if let Some((_, v)) = &self.texture {
                return v;
            }
        }
        &self
            .white
            .get_or_insert_with(|| rg_texture(gpu, "no cloud shadows", [1, 1], &[1.0, 1.0]))
            .1
    }
}

/// A `w` × `h` rg32float texture holding `texels` (row-major pairs).
fn rg_texture(
    gpu: &Gpu,
    label: &str,
    [w, h]: [u32; 2],
    texels: &[f32],
) -> (wgpu::Texture, wgpu::TextureView) {
    let size = wgpu::Extent3d {
        width: w,
        height: h,
        depth_or_array_layers: 1,
    };
    let tex = gpu.device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size,
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: wgpu::TextureFormat::Rg32Float,
        usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
        view_formats: &[],
    });
    gpu.queue.write_texture(
        wgpu::TexelCopyTextureInfo {
            texture: &tex,
            mip_level: 0,
            origin: wgpu::Origin3d::ZERO,
            aspect: wgpu::TextureAspect::All,
        },
        bytemuck::cast_slice(texels),
        wgpu::TexelCopyBufferLayout {
            offset: 0,
            bytes_per_row: Some(8 * w),
            rows_per_image: Some(h),
        },
        size,
    );
    let view = tex.create_view(&Default::default());
    (tex, view)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A box's shadow footprint reaches along the light, away from it.
    #[test]
    fn the_footprint_follows_the_shadows() {
        let b = Aabb {
            min: Vec3::new(-1.0, 0.0, -1.0),
            max: Vec3::new(1.0, 10.0, 1.0),
        };
        // The Sun in the South-East at 45°: the top corners' shadows fall
        // 10 m to the North-West, 7.07 m West and 7.07 m North.
        let sun = Vec3::new(1.0, std::f32::consts::SQRT_2, 1.0).normalize();
        let (o, s) = footprint(Some(b), false, Vec3::ZERO, &[sun]).expect("footprint");
        let reach = 10.0 / std::f32::consts::SQRT_2;
        assert!(
            o[0] <= -1.0 - reach + 0.01 && o[1] <= -1.0 - reach + 0.01,
            "{o:?}"
        );
        assert!(o[0] + s >= 1.0 && o[1] + s >= 1.0, "{o:?} {s}");
        assert!(footprint(None, false, Vec3::ZERO, &[sun]).is_none());
        let (og, sg) = footprint(None, true, Vec3::new(5.0, 1.7, 0.0), &[sun]).expect("ground");
        assert!(og[0] <= 5.0 - GROUND_REACH_M && sg >= 2.0 * GROUND_REACH_M);
    }
}
