// What the light-shaft passes share (godrays.wgsl, radial.wgsl; after
// common.wgsl): the fog's phase function, its interval along a view ray and a directional light's
// visibility from its cascaded shadow maps (bindings 3 and 4 in both).

@group(0) @binding(3) var shadows: texture_depth_2d_array;
@group(0) @binding(4) var cmp_sampler: sampler_comparison;

// The fog's phase function at cos θ, 1/sr.
fn phase(c: f32) -> f32 {
    let kind = u.shafts.y;
    if kind < 0.5 {
        return 1.0 / (4.0 * PI);
    }
    if kind < 1.5 {
        return 3.0 / (16.0 * PI) * (1.0 + c * c);
    }
    let g = u.shafts.z;
    let d = 1.0 + g * g - 2.0 * g * c;
    return (1.0 - g * g) / (4.0 * PI * d * sqrt(d));
}

// The part [lo, hi] of [a, b] along the view ray from the eye that lies in
// the fog (y ≤ top): one interval, empty (hi = lo) when there is none.
fn fog_interval(a: f32, b: f32, ray: vec3<f32>) -> vec2<f32> {
    let top = u.fog.y;
    let y0 = u.eye.y;
    var lo = a;
    var hi = b;
    if ray.y > 1e-6 {
        hi = min(hi, (top - y0) / ray.y);
    } else if ray.y < -1e-6 {
        lo = max(lo, (top - y0) / ray.y);
    } else if y0 > top {
        hi = lo;
    }
    return vec2<f32>(lo, max(hi, lo));
}

// Visibility of a directional light (cascades first..first+count) at a
// point x in the air, view depth view_depth.
fn light_visibility(first: u32, count: u32, x: vec3<f32>, view_depth: f32) -> f32 {
    if count == 0u {
        return 1.0;
    }
    let layer = cascade_layer(first, count, view_depth);
    let info = u.cascade_info[layer];
    let s = u.cascade[layer] * vec4<f32>(x, 1.0);
    let uv = light_uv(s);
    if !inside(uv) || s.z <= 0.0 {
        return 1.0;
    }
    let z = min(s.z, 1.0) - info.x / info.y;
    return textureSampleCompareLevel(shadows, cmp_sampler, uv, i32(layer), z);
}
