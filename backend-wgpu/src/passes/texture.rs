//! The texture pass (`shaders/texture.wgsl`, its own bind group 1: the
//! [`TextureUniforms`] and the texels): the frame plan's
//! [`TextureFrame`] per pixel as the CPU draws it — the textures' bordered
//! tiles (`SkyTexture`, uploaded when the frame's textures change, three
//! floats per texel), the rotation, the cross-fade gains, the horizon band
//! and the blend over the earlier passes' radiance.

use std::sync::Arc;

use bytemuck::{Pod, Zeroable};
use himmel_skymodel::frame::TextureFrame;
use himmel_skymodel::texture_sky::SkyTexture;
use himmel_skymodel::{FramePlan, RenderError, Unavailable};
use wgpu::util::DeviceExt;

use crate::frame::SkyGroup;
use crate::gpu::{bind_group, storage_entry, uniform_entry, Gpu};
use crate::pass::{Dispatch, Groups};

/// The texture pass: frame.wgsl and texture.wgsl.
pub const TEXTURE_WGSL: &str = concat!(
    include_str!("../shaders/frame.wgsl"),
    include_str!("../shaders/texture.wgsl")
);

/// Mirror of WGSL `struct TexLayer` (src/shaders/texture.wgsl): one
/// texture of the frame.
#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
pub struct TextureLayerUniforms {
    /// `Mapping::id`.
    pub mapping: u32,
    /// Source image width, px.
    pub width: u32,
    /// Source image height, px.
    pub height: u32,
    /// Tiles.
    pub tiles: u32,
    /// Bordered tile width.
    pub tile_w: u32,
    /// Bordered tile height.
    pub tile_h: u32,
    /// First texel in the texel buffer.
    pub offset: u32,
    /// Radiance per texture value (`TextureLayer::gain`).
    pub gain: f32,
}

/// Mirror of WGSL `struct Tex` (src/shaders/texture.wgsl).
#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
pub struct TextureUniforms {
    /// Row 0 of the observer → texture rotation.
    pub rot_x: [f32; 3],
    /// The blend.
    pub blend: f32,
    /// Row 1.
    pub rot_y: [f32; 3],
    /// Layers (1 or 2).
    pub layers: u32,
    /// Row 2.
    pub rot_z: [f32; 3],
    /// 1 with a horizon band.
    pub band_on: u32,
    /// The band's radiance, cd/m².
    pub band_color: [f32; 3],
    /// The band's top, degrees.
    pub band_height_deg: f32,
    /// Its soft edge, degrees.
    pub band_softness_deg: f32,
    /// Padding.
    pub pad: [f32; 3],
    /// The layers.
    pub layer: [TextureLayerUniforms; 2],
}

/// The pass's uniforms of `t` for texels laid out one layer after
/// another.
pub fn texture_uniforms(t: &TextureFrame) -> TextureUniforms {
    let m = t.rotation;
    let row = |i: usize| [m.x_axis[i] as f32, m.y_axis[i] as f32, m.z_axis[i] as f32];
    let mut u = TextureUniforms {
        rot_x: row(0),
        blend: t.blend,
        rot_y: row(1),
        layers: t.layers.len().min(2) as u32,
        rot_z: row(2),
        ..Zeroable::zeroed()
    };
    if let Some(h) = &t.horizon {
        u.band_on = 1;
        u.band_color = h.color;
        u.band_height_deg = h.height_deg;
        u.band_softness_deg = h.softness_deg;
    }
    let mut offset = 0u32;
    for (slot, l) in u.layer.iter_mut().zip(&t.layers) {
        let x = &l.texture;
        *slot = TextureLayerUniforms {
            mapping: x.mapping.id(),
            width: x.width,
            height: x.height,
            tiles: x.tiles,
            tile_w: x.tile_w,
            tile_h: x.tile_h,
            offset,
            gain: l.gain,
        };
        offset += x.texels.len() as u32;
    }
    u
}

/// The texture pass.
pub struct TexturePass {
    layout: wgpu::BindGroupLayout,
    pipeline: wgpu::ComputePipeline,
    /// The uploaded texels and the textures they hold.
    texels: Option<(Vec<Arc<SkyTexture>>, wgpu::Buffer)>,
}

impl TexturePass {
    /// Compiles the pass.
    pub fn new(gpu: &Gpu, sky: &SkyGroup) -> Self {
        let module = gpu.shader("texture.wgsl", TEXTURE_WGSL);
        let layout = gpu
            .device
            .create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some("texture"),
                entries: &[uniform_entry::<TextureUniforms>(0), storage_entry(1, true)],
            });
        let pl = gpu.pipeline_layout("texture", &[&sky.layout, &layout]);
        TexturePass {
            pipeline: gpu.compute_pipeline(&pl, &module, "sky_texture"),
            layout,
            texels: None,
        }
    }

    /// Uploads the frame's textures (when they changed) and its uniforms;
    /// the pass over every band, when the plan draws a sky texture.
    /// Textures beyond the adapter's storage-buffer binding limit are
    /// [`Unavailable::TextureTooLarge`] (`--backend auto` then renders on
    /// the CPU).
    pub fn prepare(
        &mut self,
        gpu: &Gpu,
        plan: &FramePlan,
    ) -> Result<Option<Dispatch>, RenderError> {
        let Some(t) = plan.texture.as_ref() else {
            return Ok(None);
        };
        let textures: Vec<Arc<SkyTexture>> =
            t.layers.iter().take(2).map(|l| l.texture.clone()).collect();
        let same = self.texels.as_ref().is_some_and(|(held, _)| {
            held.len() == textures.len()
                && held.iter().zip(&textures).all(|(a, b)| Arc::ptr_eq(a, b))
        });
        let bytes: u64 = textures.iter().map(|x| 12 * x.texels.len() as u64).sum();
        let limits = gpu.device.limits();
        let max_bytes = limits
            .max_storage_buffer_binding_size
            .min(limits.max_buffer_size);
        if bytes > max_bytes {
            return Err(RenderError::Unavailable(Unavailable::TextureTooLarge {
                bytes,
                max_bytes,
            }));
        }
        if !same {
            let mut data: Vec<f32> = Vec::new();
            for x in &textures {
                data.extend(x.texels.iter().flatten());
            }
            if data.is_empty() {
                data.push(0.0);
            }
            let buf = gpu
                .device
                .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: Some("sky texture texels"),
                    contents: bytemuck::cast_slice(&data),
                    usage: wgpu::BufferUsages::STORAGE,
                });
            self.texels = Some((textures, buf));
        }
        let Some(buf) = self.texels.as_ref().map(|(_, b)| b.clone()) else {
            return Ok(None);
        };
        let u = texture_uniforms(t);
        let uniform = gpu
            .device
            .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("sky texture uniforms"),
                contents: bytemuck::bytes_of(&u),
                usage: wgpu::BufferUsages::UNIFORM,
            });
        let group = bind_group(
            &gpu.device,
            "texture",
            &self.layout,
            &[uniform.as_entire_binding(), buf.as_entire_binding()],
        );
        Ok(Some(Dispatch {
            label: "texture",
            pipeline: self.pipeline.clone(),
            group1: Some(group),
            groups: Groups::Band,
        }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The module validates and the uniform struct's size and offsets are
    /// those naga computes for WGSL `Tex` and `TexLayer`.
    #[test]
    fn the_shader_validates_and_its_uniforms_match() {
        let module = naga::front::wgsl::parse_str(TEXTURE_WGSL).expect("texture.wgsl parses");
        naga::valid::Validator::new(
            naga::valid::ValidationFlags::all(),
            naga::valid::Capabilities::empty(),
        )
        .validate(&module)
        .expect("texture.wgsl validates");
        assert!(module.entry_points.iter().any(|e| e.name == "sky_texture"));
        let mut layouter = naga::proc::Layouter::default();
        layouter.update(module.to_ctx()).unwrap();
        let find = |name: &str| {
            module
                .types
                .iter()
                .find(|(_, t)| t.name.as_deref() == Some(name))
                .unwrap()
        };
        let (h, t) = find("Tex");
        assert_eq!(
            layouter[h].size as usize,
            std::mem::size_of::<TextureUniforms>()
        );
        let naga::TypeInner::Struct { members, .. } = &t.inner else {
            panic!("Tex is a struct")
        };
        let offsets: Vec<(String, u32)> = members
            .iter()
            .map(|m| (m.name.clone().unwrap_or_default(), m.offset))
            .collect();
        let want = [
            ("rot_x", std::mem::offset_of!(TextureUniforms, rot_x)),
            ("blend", std::mem::offset_of!(TextureUniforms, blend)),
            ("rot_y", std::mem::offset_of!(TextureUniforms, rot_y)),
            ("layers", std::mem::offset_of!(TextureUniforms, layers)),
            ("rot_z", std::mem::offset_of!(TextureUniforms, rot_z)),
            ("band_on", std::mem::offset_of!(TextureUniforms, band_on)),
            (
                "band_color",
                std::mem::offset_of!(TextureUniforms, band_color),
            ),
            (
                "band_height_deg",
                std::mem::offset_of!(TextureUniforms, band_height_deg),
            ),
            (
                "band_softness_deg",
                std::mem::offset_of!(TextureUniforms, band_softness_deg),
            ),
            ("layer", std::mem::offset_of!(TextureUniforms, layer)),
        ];
        for (name, off) in want {
            let got = offsets.iter().find(|(n, _)| n == name).map(|(_, o)| *o);
            assert_eq!(got, Some(off as u32), "{name}");
        }
        let (h, _) = find("TexLayer");
        assert_eq!(
            layouter[h].size as usize,
            std::mem::size_of::<TextureLayerUniforms>()
        );
    }
}
