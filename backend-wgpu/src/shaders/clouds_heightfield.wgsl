// Himmel wgpu backend: the low layer's height-field tier
// (`clouds.low.tier = "heightfield"`), concatenated after clouds.wgsl and
// clouds_diffusion.wgsl. A port of skymodel's clouds/height_field.rs
// function by function under the same names. The maps themselves
// (`HeightField::build`: per column bottom, top, mean extinction, vertical
// optical depth) are built once per frame in skymodel and bound as
// `hf_columns`: the n² columns, then 2 n² entries per light of
// `HeightField::light_columns` (per column τ_l, then τ_b, at the
// `LIGHT_LEVELS` = 4 altitudes from its bottom to its top). `clouds.hf_map` holds (`PROBE_DIVISOR`, 0
// when the tier is off; texels per side n; a regular grid's half-width km;
// its texel km), `clouds.hf_warp` (the warp's distance km, 0 for a regular
// grid; the number of lights with maps).

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

// height_field.rs `HeightField::texel_coordinate`.
fn texel_coordinate(x: f32) -> f32 {
    let n = clouds.hf_map.y;
    if (clouds.hf_warp.x > 0.0) {
        let w = x / (abs(x) + clouds.hf_warp.x);
        return (w + 1.0) * 0.5 * n - 0.5;
    }
    return (x + clouds.hf_map.z) / clouds.hf_map.w - 0.5;
}

// height_field.rs `HeightField::corners`: the lower corner's texel (xy)
// and the bilinear fractions (zw).
fn hf_corner(xy: vec2<f32>) -> vec4<f32> {
    let u = vec2<f32>(texel_coordinate(xy.x), texel_coordinate(xy.y));
    let f = floor(u);
    return vec4<f32>(f, u - f);
}

// The bilinear weight of corner (di, dj) of `c` (`hf_corner`).
fn hf_weight(c: vec4<f32>, di: i32, dj: i32) -> f32 {
    let wx = select(1.0 - c.z, c.z, di == 1);
    let wy = select(1.0 - c.w, c.w, dj == 1);
    return wx * wy;
}

// height_field.rs `HeightField::segment_depth`.
fn segment_depth(xy: vec2<f32>, h0: f32, h1: f32, len: f32) -> f32 {
    let c = hf_corner(xy);
    var d = 0.0;
    for (var k = 0; k < 4; k = k + 1) {
        let di = k % 2;
        let dj = k / 2;
        let col = hf_texel(i32(c.x) + di, i32(c.y) + dj);
        d = d + hf_weight(c, di, dj) * column_depth(col, h0, h1, len);
    }
    return d;
}

// height_field.rs `HeightField::light_depths`: (τ_l, τ_b) of light `k`.
fn light_depths(k: u32, xy: vec2<f32>, h: f32) -> vec2<f32> {
    let n = i32(clouds.hf_map.y);
    let c = hf_corner(xy);
    var t = vec2<f32>(0.0);
    var wsum = 0.0;
    for (var m = 0; m < 4; m = m + 1) {
        let i = i32(c.x) + m % 2;
        let j = i32(c.y) + m / 2;
        let col = hf_texel(i, j);
        let w = hf_weight(c, m % 2, m / 2);
        if (col.z <= 0.0 || w <= 0.0) {
            continue;
        }
        let at = n * n + 2 * (i32(k) * n * n + j * n + i);
        let f = clamp((h - col.x) / (col.y - col.x), 0.0, 1.0) * 3.0;
        let m = min(u32(floor(f)), 2u);
        let r = f - f32(m);
        let dl = hf_columns[at];
        let db = hf_columns[at + 1];
        t = t + w * vec2<f32>(dl[m] + r * (dl[m + 1u] - dl[m]), db[m] + r * (db[m + 1u] - db[m]));
        wsum = wsum + w;
    }
    if (wsum > 0.0) {
        return t / wsum;
    }
    return vec2<f32>(0.0);
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
fn probe_source(lobes: vec4<f32>, cos_theta: f32, tau: f32, tau_b: f32, mu0: f32) -> f32 {
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
    var hit = CloudHit(vec3<f32>(0.0), 1.0, 0.0);
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
            var taus: vec2<f32>;
            if (f32(j) < clouds.hf_warp.y) {
                taus = light_depths(j, pos.xy, length(pos) - clouds.r_ground);
            } else {
                let gap = clouds.diffusion_shape.x * clouds.low_extinction_per_km;
                taus = vec2<f32>(
                    depth_to_light(pos, ls.dir[j], clouds.light_steps),
                    depth_connected(pos, -ls.dir[j], clouds.light_steps, gap),
                );
            }
            let mu0 = dot(pos, ls.dir[j]) / length(pos);
            let cos_t = dot(view, ls.dir[j]);
            src = src + probe_source(lobes[j], cos_t, taus.x, taus.y, mu0) * ls.rgb[j];
        }
        let h = length(pos) - clouds.r_ground;
        let hf = clamp((h - clouds.low_base_km) / thickness, 0.0, 1.0);
        if (hit_add(&hit, tau_seg, t, src, ambient, hf)) {
            break;
        }
    }
    return hit_finish(hit, t0);
}
