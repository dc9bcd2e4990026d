// Himmel wgpu backend: the low layer's height-field tier
// (`clouds.low.tier = "heightfield"`), concatenated after clouds.wgsl and
// clouds_diffusion.wgsl. A port of skymodel's clouds/height_field.rs
// function by function under the same names. The maps themselves
// (`HeightField::build`: per column bottom, top, mean extinction, vertical
// optical depth) are built once per frame in skymodel and bound as
// `hf_columns`; `clouds.hf_map` holds (`PROBE_DIVISOR`, 0 when the tier is
// off; texels per side; half-width km; texel km).

@group(1) @binding(5) var<storage, read> hf_columns: array<vec4<f32>>;

// height_field.rs `column_depth`.
fn column_depth(c: vec4<f32>, h0: f32, h1: f32, len: f32) -> f32 {
    if (c.z <= 0.0) {
        return 0.0;
    }
    let lo = min(h0, h1);
    let hi = max(h0, h1);
    var inside = 0.0;
    if (hi - lo > 1e-6) {
        inside = max((min(hi, c.y) - max(lo, c.x)) / (hi - lo), 0.0);
    } else if (lo >= c.x && lo <= c.y) {
        inside = 1.0;
    }
    return c.z * len * inside;
}

// height_field.rs `HeightField::texel`: clear outside the maps.
fn hf_texel(i: i32, j: i32) -> vec4<f32> {
    let n = i32(clouds.hf_map.y);
    if (i < 0 || j < 0 || i >= n || j >= n) {
        return vec4<f32>(0.0);
    }
    return hf_columns[j * n + i];
}

// height_field.rs `HeightField::segment_depth`.
fn segment_depth(xy: vec2<f32>, h0: f32, h1: f32, len: f32) -> f32 {
    let u = (xy + vec2<f32>(clouds.hf_map.z)) / clouds.hf_map.w - vec2<f32>(0.5);
    let f = floor(u);
    let fx = u.x - f.x;
    let fy = u.y - f.y;
    let i = i32(f.x);
    let j = i32(f.y);
    let d00 = column_depth(hf_texel(i, j), h0, h1, len);
    let d10 = column_depth(hf_texel(i + 1, j), h0, h1, len);
    let d01 = column_depth(hf_texel(i, j + 1), h0, h1, len);
    let d11 = column_depth(hf_texel(i + 1, j + 1), h0, h1, len);
    return (1.0 - fy) * ((1.0 - fx) * d00 + fx * d10) + fy * ((1.0 - fx) * d01 + fx * d11);
}

// height_field.rs `HeightField::ray_depth` (gap < 0: no gap test).
fn hf_ray_depth(pos: vec3<f32>, dir: vec3<f32>, t0: f32, t1: f32, n: u32, gap: f32) -> f32 {
    let ds = (t1 - t0) / f32(n);
    var tau = 0.0;
    for (var k = 0u; k < n; k = k + 1u) {
        let ta = t0 + f32(k) * ds;
        let mid = pos + dir * (ta + 0.5 * ds);
        let ha = length(pos + dir * ta) - clouds.r_ground;
        let hb = length(pos + dir * (ta + ds)) - clouds.r_ground;
        let d = segment_depth(mid.xy, ha, hb, ds);
        if (gap >= 0.0 && d <= gap * ds) {
            break;
        }
        tau = tau + d;
    }
    return tau;
}

// height_field.rs `HeightField::depth_to_light`.
fn depth_to_light(pos: vec3<f32>, l: vec3<f32>, n: u32) -> f32 {
    let r = length(pos);
    let o = inside_sphere(r, dot(pos, l) / r, clouds.r_ground + clouds.low_top_km);
    if (o.z == 0.0) {
        return 0.0;
    }
    return hf_ray_depth(pos, l, 0.0, max(o.y, 0.0), n, -1.0);
}

// height_field.rs `HeightField::depth_connected`.
fn depth_connected(pos: vec3<f32>, dir: vec3<f32>, n: u32, gap: f32) -> f32 {
    let r = length(pos);
    let s = slab_from(r, dot(pos, dir) / r, clouds.low_base_km, clouds.low_top_km);
    if (s.z == 0.0) {
        return 0.0;
    }
    return hf_ray_depth(pos, dir, s.x, s.y, n, gap);
}

// height_field.rs `probe_source` (the diffusion model when
// `diffusion_gain` > 0, else the octaves).
fn probe_source(lobes: vec4<f32>, cos_theta: f32, tau: f32, pos: vec3<f32>, l: vec3<f32>, mu0: f32) -> f32 {
    var f = 0.0;
    var ai = 1.0;
    var bi = 1.0;
    var k = 1.0;
    for (var o = 0u; o < clamp(clouds.octave_count, 1u, 8u); o = o + 1u) {
        f = f + bi * cloud_phase(cos_theta, k) * exp(-ai * tau);
        ai = ai * clouds.octave_a;
        bi = bi * clouds.octave_b;
        k = k * clouds.octave_c;
    }
    if (clouds.diffusion_gain > 0.0) {
        let gap = clouds.diffusion_shape.x * clouds.low_extinction_per_km;
        let tau_b = depth_connected(pos, -l, clouds.light_steps, gap);
        f = f + diffuse_source(tau, tau_b, mu0, cos_theta);
        f = f + forward_source(lobes, tau);
    }
    return f;
}

// height_field.rs `march_height_field`.
fn march_height_field(view: vec3<f32>, lights: CloudLights, ambient: vec3<f32>) -> CloudHit {
    let sl = slab(view, clouds.low_base_km, clouds.low_top_km);
    if (sl.z == 0.0) {
        return clear_hit();
    }
    let t0 = sl.x;
    let t1 = min(sl.y, t0 + clouds.max_march_km);
    let thickness = clouds.low_top_km - clouds.low_base_km;
    let probes = max(clouds.steps / u32(clouds.hf_map.x), 4u);
    let n = step_count(t1 - t0, thickness, probes);
    let dt = (t1 - t0) / f32(n);
    let origin = vec3<f32>(0.0, 0.0, clouds.r_observer);
    var ls = lights;
    var lobes: array<vec4<f32>, 2>;
    for (var j = 0u; j < ls.count; j = j + 1u) {
        if (clouds.diffusion_gain > 0.0) {
            lobes[j] = forward_lobes(dot(view, ls.dir[j]));
        }
    }
    var l = vec3<f32>(0.0);
    var tr = 1.0;
    var dist = 0.0;
    for (var s = 0u; s < n; s = s + 1u) {
        let ta = t0 + f32(s) * dt;
        let t = ta + 0.5 * dt;
        let pos = origin + view * t;
        let ha = length(origin + view * ta) - clouds.r_ground;
        let hb = length(origin + view * (ta + dt)) - clouds.r_ground;
        let tau_seg = segment_depth(pos.xy, ha, hb, dt);
        if (tau_seg <= 0.0) {
            continue;
        }
        var src = vec3<f32>(0.0);
        for (var j = 0u; j < ls.count; j = j + 1u) {
            let tau = depth_to_light(pos, ls.dir[j], clouds.light_steps);
            let mu0 = dot(pos, ls.dir[j]) / length(pos);
            src = src + probe_source(lobes[j], dot(view, ls.dir[j]), tau, pos, ls.dir[j], mu0) * ls.rgb[j];
        }
        let h = length(pos) - clouds.r_ground;
        let amb = 0.4 + 0.6 * clamp((h - clouds.low_base_km) / thickness, 0.0, 1.0);
        let seg = exp(-tau_seg);
        let w = tr * (1.0 - seg);
        l = l + w * (src + ambient * amb);
        dist = dist + w * t;
        tr = tr * seg;
        if (tr < 1e-4) {
            break;
        }
    }
    let ext = 1.0 - tr;
    var d = t0;
    if (ext > 0.0) {
        d = dist / ext;
    }
    return CloudHit(l, tr, d);
}
