// The sky's light in the fog, for the marched shafts (godrays.wgsl,
// froxel.wgsl; after common.wgsl and shafts.wgsl): the environment
// light's cells (env.rs), their visibility maps' matrices and the maps,
// bindings 6–8 in both.

@group(0) @binding(6) var<storage, read> cells: array<SkyCell>;
@group(0) @binding(7) var<storage, read> cell_view: array<mat4x4<f32>>;
@group(0) @binding(8) var visibility: texture_depth_2d_array;


// Whether sky cell k's light reaches x (its visibility map's nearest
// texel; 1 outside the map).
fn sky_visibility(k: u32, x: vec3<f32>) -> f32 {
    let s = cell_view[k] * vec4<f32>(x, 1.0);
    let uv = light_uv(s);
    if !inside(uv) || s.z <= 0.0 {
        return 1.0;
    }
    let size = vec2<f32>(textureDimensions(visibility));
    let t = vec2<i32>(clamp(uv * size, vec2<f32>(0.0), size - 1.0));
    return select(0.0, 1.0, s.z - 1e-4 <= textureLoad(visibility, t, i32(k), 0));
}

// The sky's in-scattering at x (depth below the fog's top), per unit σ_s
// and step weight: cells j ≡ first (mod stride) of the texel's set and the
// aureoles', × stride.
fn sky_light(x: vec3<f32>, depth: f32, ray: vec3<f32>, cell_set: u32, first: u32, stride: u32) -> vec3<f32> {
    let per = u.counts.x;
    let total = per + u.flags.w;
    let aureole_first = u.flags.z * u.flags.z * per;
    var e = vec3<f32>(0.0);
    for (var j = first; j < total; j += stride) {
        var k = cell_set * per + j;
        if j >= per {
            k = aureole_first + j - per;
        }
        let c = cells[k];
        if c.dir.y <= 0.0 {
            continue;
        }
        let s = vec3<f32>(length(c.r.xyz), length(c.g.xyz), length(c.b.xyz));
        let t = exp(-u.fog.x * depth / max(c.dir.y, 1e-3));
        e += s * (phase(dot(ray, c.dir.xyz)) * t * sky_visibility(k, x));
    }
    return e * f32(stride);
}
