// Screen-space reflections (passes/lighting/ssr.rs, `lighting.ssr`).
//
// 1. `hiz_first` / `hiz_down`: the hierarchical depth chain: level 0 holds
//    per pixel d = 1 / view depth (0 on sky pixels: infinitely far), each
//    further level the largest d — the nearest surface — of the 2 × 2
//    texels below it. d is linear along a ray's image in screen space.
// 2. `resolve`: per pixel with roughness ≤ max_roughness, `samples` GGX
//    half vectors (Heitz 2018's sampling of the visible normals, α =
//    roughness², Hammersley points rotated per pixel), each reflected ray
//    traced through the chain (min–max traversal: a cell the ray crosses
//    wholly in front of its nearest surface is skipped and the next is
//    one level coarser; else one level finer; at level 0 the ray hits the
//    pixel when it lies behind the surface by less than the thickness).
//    A hit reads the lit radiance there (the previous frame reprojected,
//    or the current frame before reflections), with a confidence c: the
//    edge fade at the hit and whether the hit surface faces the ray. With
//    the samples weighted by Smith's G1(l), C = Σ g c / Σ g and
//    S = Σ g c L / Σ g; the shade pass's prefiltered specular term E
//    (spec_env, as it reaches the camera) and its split-sum weight W
//    (spec_w: (F0·A + B) × the transmittances to the camera) give
//        L_out = L_lit + W·S − C·E,
//    the sky's specular replaced by the reflection for the share C.

struct Ssr {
    // xyz: eye; w: tan(fov / 2).
    eye: vec4<f32>,
    // xyz: forward; w: width / height.
    forward: vec4<f32>,
    // xyz: right; w: width, px.
    right: vec4<f32>,
    // xyz: up; w: height, px.
    up: vec4<f32>,
    // The history's view-projection (world → clip).
    prev_view_proj: mat4x4<f32>,
    // max roughness, thickness (m), edge fade, the frame's index in a
    // temporal run (turns the noise).
    params: vec4<f32>,
    // samples, max steps, Hi-Z levels, 1 when the history is read.
    q: vec4<u32>,
    // xy: the frame's jitter (px, x right, y down; temporal.rs), 0, 0.
    jitter: vec4<f32>,
}

@group(0) @binding(0) var<uniform> u: Ssr;
@group(0) @binding(1) var g_distance: texture_2d<f32>;
@group(0) @binding(2) var g_normal: texture_2d<f32>;
@group(0) @binding(3) var g_material: texture_2d<u32>;
// hiz_first / hiz_down: the level written; resolve: the lit target.
@group(0) @binding(4) var hiz_out: texture_storage_2d<r32float, write>;
// hiz_down: the level below.
@group(0) @binding(5) var hiz_in: texture_2d<f32>;

@group(1) @binding(0) var hiz: texture_2d<f32>;
@group(1) @binding(1) var lit: texture_2d<f32>;
@group(1) @binding(2) var history: texture_2d<f32>;
@group(1) @binding(3) var spec_env: texture_2d<f32>;
@group(1) @binding(4) var spec_w: texture_2d<f32>;
@group(1) @binding(5) var out_tex: texture_storage_2d<rgba32float, write>;
@group(1) @binding(6) var conf_out: texture_storage_2d<r32float, write>;

const PI: f32 = 3.14159265358979;

fn size() -> vec2<f32> {
    return vec2<f32>(u.right.w, u.up.w);
}

// The view ray through pixel q's jittered sample (as common.wgsl's).
fn pixel_ray(q: vec2<i32>) -> vec3<f32> {
    let s = size();
    let t = u.eye.w;
    let nx = (f32(q.x) + 0.5 - u.jitter.x - 0.5 * s.x) / (0.5 * s.y) * t;
    let ny = -(f32(q.y) + 0.5 - u.jitter.y - 0.5 * s.y) / (0.5 * s.y) * t;
    return normalize(u.forward.xyz + u.right.xyz * nx + u.up.xyz * ny);
}

// World point p on screen: pixel coordinates of the jittered image
// (centres at +0.5) and d = 1 / view depth.
fn to_screen(p: vec3<f32>) -> vec3<f32> {
    let v = p - u.eye.xyz;
    let z = dot(v, u.forward.xyz);
    let k = 0.5 * u.up.w / (z * u.eye.w);
    return vec3<f32>(
        dot(v, u.right.xyz) * k + 0.5 * u.right.w + u.jitter.x,
        -dot(v, u.up.xyz) * k + 0.5 * u.up.w + u.jitter.y,
        1.0 / z,
    );
}

@compute @workgroup_size(8, 8)
fn hiz_first(@builtin(global_invocation_id) gid: vec3<u32>) {
    if f32(gid.x) >= u.right.w || f32(gid.y) >= u.up.w {
        return;
    }
    let px = vec2<i32>(gid.xy);
    var d = 0.0;
    if textureLoad(g_material, px, 0).x != 0u {
        let z = textureLoad(g_distance, px, 0).x * dot(pixel_ray(px), u.forward.xyz);
        d = 1.0 / max(z, 1e-6);
    }
    textureStore(hiz_out, px, vec4<f32>(d, 0.0, 0.0, 0.0));
}

@compute @workgroup_size(8, 8)
fn hiz_down(@builtin(global_invocation_id) gid: vec3<u32>) {
    let dst = vec2<i32>(textureDimensions(hiz_out));
    let px = vec2<i32>(gid.xy);
    if px.x >= dst.x || px.y >= dst.y {
        return;
    }
    let src = vec2<i32>(textureDimensions(hiz_in)) - 1;
    // Levels are rounded down: the last texel of a row (column) also
    // covers the odd texel left over below it.
    let last = select(vec2<i32>(1), vec2<i32>(2), px == dst - 1);
    var d = 0.0;
    for (var y = 0; y <= last.y; y++) {
        for (var x = 0; x <= last.x; x++) {
            let q = min(px * 2 + vec2<i32>(x, y), src);
            d = max(d, textureLoad(hiz_in, q, 0).x);
        }
    }
    textureStore(hiz_out, px, vec4<f32>(d, 0.0, 0.0, 0.0));
}

// Heitz 2018: a normal of the GGX distribution (α = a) visible from ve
// (local frame, z the surface normal), from the uniform point xi.
fn sample_vndf(ve: vec3<f32>, a: f32, xi: vec2<f32>) -> vec3<f32> {
    let vh = normalize(vec3<f32>(a * ve.x, a * ve.y, ve.z));
    let len2 = vh.x * vh.x + vh.y * vh.y;
    var t1 = vec3<f32>(1.0, 0.0, 0.0);
    if len2 > 0.0 {
        t1 = vec3<f32>(-vh.y, vh.x, 0.0) / sqrt(len2);
    }
    let t2 = cross(vh, t1);
    let r = sqrt(xi.x);
    let phi = 2.0 * PI * xi.y;
    let p1 = r * cos(phi);
    let s = 0.5 * (1.0 + vh.z);
    let p2 = (1.0 - s) * sqrt(max(1.0 - p1 * p1, 0.0)) + s * r * sin(phi);
    let nh = p1 * t1 + p2 * t2 + sqrt(max(0.0, 1.0 - p1 * p1 - p2 * p2)) * vh;
    return normalize(vec3<f32>(a * nh.x, a * nh.y, max(nh.z, 0.0)));
}

fn radical_inverse(i: u32) -> f32 {
    return f32(reverseBits(i)) * 2.3283064365386963e-10;
}

// Interleaved gradient noise (Jimenez 2014), moved 5.588238 px per frame
// of a temporal run.
fn ign(q: vec2<f32>) -> f32 {
    let p = q + 5.588238 * u.params.w;
    return fract(52.9829189 * fract(0.06711056 * p.x + 0.00583715 * p.y));
}

// Smith's masking term of GGX for a direction at cos θ = c.
fn smith_g1(c: f32, a: f32) -> f32 {
    let a2 = a * a;
    return 2.0 * c / (c + sqrt(a2 + (1.0 - a2) * c * c));
}

struct Hit {
    found: bool,
    px: vec2<i32>,
}

// The first surface on screen the ray from p along r meets (Hi-Z
// traversal), or none (it leaves the image, passes behind every surface
// thicker than the thickness, or the steps run out).
fn trace(p: vec3<f32>, r: vec3<f32>) -> Hit {
    var out: Hit;
    out.found = false;
    let z0 = dot(p - u.eye.xyz, u.forward.xyz);
    let rz = dot(r, u.forward.xyz);
    // The far end: 1 km along the ray, or short of the near plane.
    var len = 1000.0;
    let near = 0.05;
    if rz < 0.0 {
        len = min(len, (z0 - near) / -rz);
    }
    if len <= 0.0 {
        return out;
    }
    let s0 = to_screen(p);
    let s1 = to_screen(p + r * len);
    let delta = s1 - s0;
    let span = max(abs(delta.x), abs(delta.y));
    if span < 1e-3 {
        return out;
    }
    let sz = size();
    // Where the ray's image leaves the screen.
    var t_max = 1.0;
    if delta.x > 0.0 {
        t_max = min(t_max, (sz.x - s0.x) / delta.x);
    } else if delta.x < 0.0 {
        t_max = min(t_max, -s0.x / delta.x);
    }
    if delta.y > 0.0 {
        t_max = min(t_max, (sz.y - s0.y) / delta.y);
    } else if delta.y < 0.0 {
        t_max = min(t_max, -s0.y / delta.y);
    }
    var t = 1.5 / span;
    var level = 0u;
    let top = u.q.z - 1u;
    let thickness = u.params.y;
    for (var step = 0u; step < u.q.y; step++) {
        if t >= t_max {
            break;
        }
        let pos = s0 + delta * t;
        let cs = f32(1u << level);
        // The last cell of a row (column) reaches the image's edge.
        // (From the image's size: textureDimensions with a varying level
        // reads wrong sizes on lavapipe.)
        let last = max(floor(size() / cs), vec2<f32>(1.0)) - 1.0;
        // Nudged along the ray: a position on a cell's edge (where the
        // last cell was left) lies in the next cell.
        let cell = clamp(floor((pos.xy + sign(delta.xy) * 0.005) / cs), vec2<f32>(0.0), last);
        // The ray's exit from this cell (the image's edge: t_max).
        var t_exit = t_max;
        if delta.x < 0.0 || (delta.x > 0.0 && cell.x < last.x) {
            let bx = select(cell.x * cs, (cell.x + 1.0) * cs, delta.x > 0.0);
            t_exit = min(t_exit, (bx - s0.x) / delta.x);
        }
        if delta.y < 0.0 || (delta.y > 0.0 && cell.y < last.y) {
            let by = select(cell.y * cs, (cell.y + 1.0) * cs, delta.y > 0.0);
            t_exit = min(t_exit, (by - s0.y) / delta.y);
        }
        t_exit = max(t_exit, t);
        let zc = textureLoad(hiz, vec2<i32>(cell), i32(level)).x;
        let da = pos.z;
        let db = s0.z + delta.z * t_exit;
        if min(da, db) > zc {
            // Wholly in front of the cell's nearest surface.
            t = t_exit;
            level = min(level + 1u, top);
            continue;
        }
        if da > zc && delta.z < 0.0 {
            // It reaches that depth inside the cell: move there.
            t = max(t, (zc - s0.z) / delta.z);
        }
        if level > 0u {
            level -= 1u;
            continue;
        }
        let dr = s0.z + delta.z * t;
        // Only a surface that faces the ray can stop it (not the ray's own
        // plane, which a pixel's depth quantised at its centre may put in
        // front of a ray leaving it at a grazing angle).
        let faces = dot(textureLoad(g_normal, vec2<i32>(cell), 0).xyz, r) < 0.0;
        if faces && zc > 0.0 && 1.0 / max(dr, 1e-9) - 1.0 / zc <= thickness {
            out.found = true;
            out.px = vec2<i32>(cell);
            return out;
        }
        // Behind a thin surface: on past it.
        t = t_exit;
    }
    return out;
}

// The radiance at the hit pixel q: the previous frame's final image where
// the point lies in it, else this frame's before reflections.
fn hit_radiance(q: vec2<i32>) -> vec3<f32> {
    if u.q.w == 1u {
        let pw = u.eye.xyz + pixel_ray(q) * textureLoad(g_distance, q, 0).x;
        let c = u.prev_view_proj * vec4<f32>(pw, 1.0);
        if c.w > 0.0 {
            let ndc = c.xy / c.w;
            let pp = vec2<f32>((ndc.x * 0.5 + 0.5) * u.right.w, (0.5 - ndc.y * 0.5) * u.up.w);
            if all(pp >= vec2<f32>(0.0)) && all(pp < size()) {
                return textureLoad(history, vec2<i32>(pp), 0).rgb;
            }
        }
    }
    return textureLoad(lit, q, 0).rgb;
}

// The edge fade at pixel q.
fn edge_fade(q: vec2<i32>) -> f32 {
    let f = u.params.z;
    if f <= 0.0 {
        return 1.0;
    }
    let s = size();
    let c = vec2<f32>(q) + 0.5;
    let e = min(c, s - c) / (f * 0.5 * s);
    return clamp(min(e.x, e.y), 0.0, 1.0);
}

@compute @workgroup_size(8, 8)
fn resolve(@builtin(global_invocation_id) gid: vec3<u32>) {
    if f32(gid.x) >= u.right.w || f32(gid.y) >= u.up.w {
        return;
    }
    let px = vec2<i32>(gid.xy);
    textureStore(conf_out, px, vec4<f32>(0.0));
    if textureLoad(g_material, px, 0).x == 0u {
        return;
    }
    let nr = textureLoad(g_normal, px, 0);
    let rough = nr.w;
    let w_spec = textureLoad(spec_w, px, 0).rgb;
    if rough > u.params.x || all(w_spec <= vec3<f32>(0.0)) {
        return;
    }
    let n = normalize(nr.xyz);
    let ray = pixel_ray(px);
    let v = -ray;
    let dist = textureLoad(g_distance, px, 0).x;
    let z = dist * dot(ray, u.forward.xyz);
    // Off the surface by a little of the view depth (depth precision).
    let p = u.eye.xyz + ray * dist + n * (2e-3 * z);
    let a = max(rough * rough, 1e-3);
    // The surface's frame.
    let sgn = select(-1.0, 1.0, n.z >= 0.0);
    let ba = -1.0 / (sgn + n.z);
    let bb = n.x * n.y * ba;
    let tx = vec3<f32>(1.0 + sgn * n.x * n.x * ba, sgn * bb, -sgn * n.x);
    let ty = vec3<f32>(bb, sgn + n.y * n.y * ba, -n.y);
    let ve = vec3<f32>(dot(v, tx), dot(v, ty), dot(v, n));
    var count = u.q.x;
    if rough < 0.02 {
        count = 1u;
    }
    let rot = vec2<f32>(ign(vec2<f32>(px)), ign(vec2<f32>(px) + vec2<f32>(47.0, 17.0)));
    var g_sum = 0.0;
    var c_sum = 0.0;
    var l_sum = vec3<f32>(0.0);
    for (var i = 0u; i < count; i++) {
        var h = n;
        if count > 1u {
            let xi = fract(vec2<f32>((f32(i) + 0.5) / f32(count), radical_inverse(i)) + rot);
            let hl = sample_vndf(ve, a, xi);
            h = normalize(hl.x * tx + hl.y * ty + hl.z * n);
        }
        let r = reflect(ray, h);
        let nl = dot(r, n);
        if nl <= 0.0 {
            continue;
        }
        let g = smith_g1(nl, a);
        g_sum += g;
        let hit = trace(p, r);
        if !hit.found {
            continue;
        }
        let nq = textureLoad(g_normal, hit.px, 0).xyz;
        let c = edge_fade(hit.px) * clamp(-10.0 * dot(nq, r), 0.0, 1.0);
        c_sum += g * c;
        l_sum += g * c * hit_radiance(hit.px);
    }
    if g_sum <= 0.0 || c_sum <= 0.0 {
        return;
    }
    let conf = c_sum / g_sum;
    let s = l_sum / g_sum;
    let base = textureLoad(lit, px, 0);
    let e = textureLoad(spec_env, px, 0).rgb;
    let l = max(base.rgb + w_spec * s - conf * e, vec3<f32>(0.0));
    textureStore(out_tex, px, vec4<f32>(l, base.a));
    textureStore(conf_out, px, vec4<f32>(conf, 0.0, 0.0, 0.0));
}
