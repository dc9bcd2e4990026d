// What the lighting passes share (shade.wgsl, godrays.wgsl): the
// uniforms (`ShadeUniforms` in passes/lighting/mod.rs), the light maps'
// coordinates and the view ray through a pixel.

struct Shade {
    // xyz: eye; w: tan(fov / 2).
    eye: vec4<f32>,
    // xyz: forward; w: width / height.
    forward: vec4<f32>,
    // xyz: right; w: width, px.
    right: vec4<f32>,
    // xyz: up; w: height, px.
    up: vec4<f32>,
    // xyz: towards the Sun (world frame); w: 1 when it lights.
    sun_dir: vec4<f32>,
    // rgb: transmitted illuminance, lux; w: tan(angular radius).
    sun_rgb: vec4<f32>,
    moon_dir: vec4<f32>,
    moon_rgb: vec4<f32>,
    // σt (1/m), top (m), 1 when there is fog, 0.
    fog: vec4<f32>,
    // Scale of the f16 environment maps, of the f16 air table, the air
    // table's largest distance (m), its slices.
    scales: vec4<f32>,
    // Sky cells, Sun cascades, Moon cascades, filter (0 off, 1 pcf, 2 soft).
    counts: vec4<u32>,
    // Whether the sky light is on, the first Moon layer, the interleave
    // side, the aureoles' cells.
    flags: vec4<u32>,
    cascade: array<mat4x4<f32>, 8>,
    // texel (m), depth range (m), split view depth (m; 1e30: the last), 0.
    cascade_info: array<vec4<f32>, 8>,
    // Light shafts: σ_s (1/m), the phase (0 isotropic, 1 Rayleigh, 2 HG),
    // its g, 1 when the godrays pass ran.
    shafts: vec4<f32>,
    // March steps, interleave N, resolution divisor, sky cells per step.
    shaft_q: vec4<u32>,
    // The cloud-shadow map (cloud_shadow.rs): least corner x, z (m),
    // 1 / side (1/m), texels per side (0: no clouds).
    clouds: vec4<f32>,
    // The frame's jitter (px, x right, y down; temporal.rs), its index in
    // the temporal run (turns the per-pixel noise), 0.
    jitter: vec4<f32>,
    // The sky's radiance on the SH of l ≤ 2 (env.rs `sh9`, cd/m²): rgb per
    // coefficient, in `sh9_basis` order.
    sky_sh: array<vec4<f32>, 9>,
    // x: 1 when `lighting.sky.occlusion` is `ao` (no visibility maps: the
    // cells are open, the ao pass occludes); y: the ao pass's S3HO image
    // when bound: 1 its B_lm (`sh_sky` `sh2`), 2 its blocked light E_b
    // (`radiance`), else 0; 0, 0.
    occlusion: vec4<u32>,
}

struct SkyCell {
    // xyz: direction (world); w: its visibility map's texel, m.
    dir: vec4<f32>,
    // xyz: ∫ L ω dω of the red channel; w: the cell's solid angle, sr.
    r: vec4<f32>,
    g: vec4<f32>,
    b: vec4<f32>,
    // x: its first part, y: its parts, z: the tangent of the cone around
    // dir that holds the cell (env.rs `SkyCell`), w: 1 when it has parts
    // in bands along the horizon.
    parts: vec4<f32>,
}

@group(0) @binding(0) var<uniform> u: Shade;

// The cascade of a directional light (cascades first..first+count) that
// covers view depth view_depth: the first whose far depth reaches it, else
// the last.
fn cascade_layer(first: u32, count: u32, view_depth: f32) -> u32 {
    var c = 0u;
    loop {
        if c + 1u >= count || view_depth <= u.cascade_info[first + c].z {
            break;
        }
        c = c + 1u;
    }
    return first + c;
}

const PI: f32 = 3.14159265358979;

fn light_uv(s: vec4<f32>) -> vec2<f32> {
    return vec2<f32>(s.x * 0.5 + 0.5, 0.5 - s.y * 0.5);
}

fn inside(uv: vec2<f32>) -> bool {
    return all(uv >= vec2<f32>(0.0)) && all(uv <= vec2<f32>(1.0));
}

// The view ray through pixel q's sample: its centre moved back by the
// frame's jitter (the G-buffer is drawn jittered).
fn pixel_ray(q: vec2<i32>, w: u32, h: u32) -> vec3<f32> {
    let t = u.eye.w;
    let nx = (f32(q.x) + 0.5 - u.jitter.x - 0.5 * f32(w)) / (0.5 * f32(h)) * t;
    let ny = -(f32(q.y) + 0.5 - u.jitter.y - 0.5 * f32(h)) / (0.5 * f32(h)) * t;
    return normalize(u.forward.xyz + u.right.xyz * nx + u.up.xyz * ny);
}
