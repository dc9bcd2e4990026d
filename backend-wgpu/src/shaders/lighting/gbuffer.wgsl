// The G-buffer of a world frame (passes/lighting/gbuffer.rs): per pixel the
// distance from the eye, the shading normal facing the camera with the
// perceptual roughness, the linear base colour with the metalness, the
// material (index + 1; 0 = sky), and the motion since the previous frame in
// pixels. Rasterised with reversed Z and an infinite far plane, through the
// same perspective camera as the sky.

struct GCamera {
    view_proj: mat4x4<f32>,
    prev_view_proj: mat4x4<f32>,
    // xyz: eye (world frame, m).
    eye: vec4<f32>,
    // Image width, height, px; the jitter view_proj draws with (px, x
    // right, y down; prev_view_proj has none).
    size: vec4<f32>,
}

struct MaterialGpu {
    base_color: vec4<f32>,
    // xyz: emitted radiance, cd/m²; w: texture layer + 1 (0: none).
    emissive_texture: vec4<f32>,
    // x: metallic, y: roughness.
    metallic_roughness: vec4<f32>,
}

@group(0) @binding(0) var<uniform> cam: GCamera;
@group(0) @binding(1) var<storage, read> materials: array<MaterialGpu>;
@group(0) @binding(2) var base_tex: texture_2d_array<f32>;
@group(0) @binding(3) var base_sampler: sampler;

struct VOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) uv: vec2<f32>,
    @location(3) @interpolate(flat) material: u32,
    @location(4) prev_clip: vec4<f32>,
}

@vertex
fn vs(
    @location(0) pos: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) uv: vec2<f32>,
    @builtin(instance_index) material: u32,
) -> VOut {
    var o: VOut;
    o.clip = cam.view_proj * vec4<f32>(pos, 1.0);
    o.prev_clip = cam.prev_view_proj * vec4<f32>(pos, 1.0);
    o.world = pos;
    o.normal = normal;
    o.uv = uv;
    o.material = material;
    return o;
}

struct GOut {
    @location(0) distance: f32,
    @location(1) normal_roughness: vec4<f32>,
    @location(2) base_metallic: vec4<f32>,
    @location(3) material: u32,
    @location(4) velocity: vec2<f32>,
}

@fragment
fn fs(v: VOut) -> GOut {
    let m = materials[v.material];
    var base = m.base_color;
    let layer = i32(m.emissive_texture.w) - 1;
    if layer >= 0 {
        base = base * textureSample(base_tex, base_sampler, v.uv, layer);
    }
    if base.a < 0.5 {
        discard;
    }
    var n = normalize(v.normal);
    let to_eye = cam.eye.xyz - v.world;
    // Double-sided: the side the camera sees.
    if dot(n, to_eye) < 0.0 {
        n = -n;
    }
    var o: GOut;
    o.distance = length(to_eye);
    o.normal_roughness = vec4<f32>(n, m.metallic_roughness.y);
    o.base_metallic = vec4<f32>(base.rgb, m.metallic_roughness.x);
    o.material = v.material + 1u;
    let p = v.prev_clip.xy / v.prev_clip.w;
    let prev_px = vec2<f32>((p.x + 1.0) * 0.5 * cam.size.x, (1.0 - p.y) * 0.5 * cam.size.y);
    // The surface's motion without this frame's jitter.
    o.velocity = v.clip.xy - cam.size.zw - prev_px;
    return o;
}
