// Near-field indirect light (`lighting.ao.bounce`, passes/lighting/bounce.rs):
// one diffuse bounce of the lit image from the surfaces on screen
// (SSDO-style, Ritschel et al. 2009, with rays instead of point samples).
//
// Per pixel p of the G-buffer with diffuse albedo ρ = base (1 − metallic)
// and normal n, the light that other surfaces send it is
//
//   L_b = (ρ/π) ∫_Ω L_o(x(ω), −ω) (n·ω) dω,
//
// x(ω) the first surface along ω. With N directions ω_i distributed as
// (n·ω)/π the estimator is L_b ≈ ρ (1/N) Σ L_o(x(ω_i)). The directions are
// stratified (a Fibonacci spiral over the unit disk, lifted to the
// hemisphere) and turned about n per pixel by interleaved gradient noise,
// moved every frame of a temporal run. Each ray is followed on screen by
// `steps` points at distances R ((k + j)/S)² (j: per-pixel jitter); the
// first point that lies behind the surface the G-buffer shows there, by
// less than the thickness or having crossed it since the last point, is
// the hit x (one on p's own plane, seen at a grazing angle, is passed
// over). L_o(x) is the lit radiance the
// lighting pass wrote at x's pixel (a Lambertian surface sends the same
// radiance every way); a hit surface that faces away from p, a ray that
// leaves the image or goes beyond R adds nothing (screen space: what the
// camera does not see does not bounce). `gather` writes (1/N) Σ L_o per
// pixel; `blur` averages it over a depth-aware box of (2 blur_px + 1)²
// pixels on the same surface (normals within 25°, on the centre's plane
// within 2 % of the distance, as ao.wgsl's blur) and writes lit + ρ × that,
// cd/m² (the albedo applied after the blur keeps the texture sharp).

struct Bounce {
    // xyz: eye; w: tan(fov / 2).
    eye: vec4<f32>,
    // xyz: forward; w: width / height.
    forward: vec4<f32>,
    // xyz: right; w: width, px.
    right: vec4<f32>,
    // xyz: up; w: height, px.
    up: vec4<f32>,
    // R (m), 0, the frame's jitter (px, x right, y down; temporal.rs).
    params: vec4<f32>,
    // Directions, steps per direction, the frame's index, blur half side.
    q: vec4<u32>,
}

@group(0) @binding(0) var<uniform> u: Bounce;
@group(0) @binding(1) var g_distance: texture_2d<f32>;
@group(0) @binding(2) var g_normal: texture_2d<f32>;
@group(0) @binding(3) var g_base: texture_2d<f32>;
@group(0) @binding(4) var g_material: texture_2d<u32>;
// The lit image (a copy of the target after the lighting pass).
@group(0) @binding(5) var lit: texture_2d<f32>;
// gather: the raw bounce; blur: the target.
@group(0) @binding(6) var out_tex: texture_storage_2d<rgba32float, write>;
// blur: the raw bounce (gather: unused, the lit copy).
@group(0) @binding(7) var raw: texture_2d<f32>;

const PI: f32 = 3.14159265358979;
// The golden angle as a fraction of a turn, (3 − √5) / 2.
const GOLDEN: f32 = 0.38196601125;

// The image's size, view rays and projection (`size`, `ray_at`, `project`):
// screen.wgsl, concatenated before this.

// Interleaved gradient noise (Jimenez 2014) in [0, 1), at an offset `o`
// and moved by 5.588238 px per frame of a temporal run.
fn ign(q: vec2<u32>, o: f32) -> f32 {
    let f = vec2<f32>(q) + 5.588238 * f32(u.q.z) + o;
    return fract(52.9829189 * fract(0.06711056 * f.x + 0.00583715 * f.y));
}

// The radiance that the first surface along ω from p sends back, or 0.
fn trace(p: vec3<f32>, n: vec3<f32>, w: vec3<f32>, me: vec2<i32>, j: f32) -> vec3<f32> {
    let steps = max(u.q.y, 1u);
    let r = u.params.x;
    // Whether the last point looked at lay in front of the surface there.
    var front = true;
    for (var k = 0u; k < steps; k++) {
        let f = (f32(k) + j) / f32(steps);
        let t = r * f * f;
        let s = project(p + w * t);
        if s.z <= 1e-4 {
            return vec3<f32>(0.0);
        }
        let q = vec2<i32>(floor(s.xy));
        if any(q < vec2<i32>(0)) || any(q >= size()) {
            return vec3<f32>(0.0);
        }
        if all(q == me) || textureLoad(g_material, q, 0).x == 0u {
            continue;
        }
        let zq = textureLoad(g_distance, q, 0).x * dot(ray_at(vec2<f32>(q) + 0.5), u.forward.xyz);
        // Behind the surface seen there, by less than the thickness: the
        // larger of two step lengths and 2 % of its depth (5 % let rays
        // passing behind a box at a distance pick up its sunlit face).
        let thick = max(2.0 * r * (2.0 * f * f32(steps) + 1.0) / f32(steps * steps), 0.02 * zq);
        let behind = s.z - zq;
        // A hit: behind by less than the thickness, or by less than twice it
        // when the ray crossed the surface between this point and the last
        // (steep rays onto a floor seen at grazing angles pass far behind it
        // within one step).
        let crossed = front && behind < 2.0 * thick;
        if behind > 1e-3 * zq && (behind < thick || crossed) {
            let nq = textureLoad(g_normal, q, 0).xyz;
            let pq = u.eye.xyz + ray_at(vec2<f32>(q) + 0.5) * textureLoad(g_distance, q, 0).x;
            if dot(nq, n) > 0.95 && abs(dot(pq - p, n)) < 0.02 * zq {
                // p's own plane, seen at a grazing angle: a point just above
                // it can lie behind the depth of the pixel's centre.
                front = false;
                continue;
            }
            if dot(nq, w) >= 0.0 {
                // Its back: the ray is blocked, nothing comes this way.
                return vec3<f32>(0.0);
            }
            return textureLoad(lit, q, 0).rgb;
        }
        front = behind <= 1e-3 * zq;
    }
    return vec3<f32>(0.0);
}

@compute @workgroup_size(8, 8)
fn gather(@builtin(global_invocation_id) gid: vec3<u32>) {
    let me = vec2<i32>(gid.xy);
    if any(me >= size()) {
        return;
    }
    if !diffuse(me) {
        textureStore(out_tex, me, vec4<f32>(0.0));
        return;
    }
    let n = normalize(textureLoad(g_normal, me, 0).xyz);
    let dist = textureLoad(g_distance, me, 0).x;
    // Off the surface by 0.1 % of the distance.
    let p = u.eye.xyz + ray_at(vec2<f32>(me) + 0.5) * dist + n * (1e-3 * dist);
    // A tangent frame (Duff et al. 2017).
    let sg = select(-1.0, 1.0, n.z >= 0.0);
    let a0 = -1.0 / (sg + n.z);
    let c0 = n.x * n.y * a0;
    let t1 = vec3<f32>(1.0 + sg * n.x * n.x * a0, sg * c0, -sg * n.x);
    let t2 = vec3<f32>(c0, sg + n.y * n.y * a0, -n.y);
    let turn = ign(gid.xy, 0.0);
    let j = ign(gid.xy, 17.0);
    let count = max(u.q.x, 1u);
    var sum = vec3<f32>(0.0);
    for (var i = 0u; i < count; i++) {
        let u = (f32(i) + 0.5) / f32(count);
        let rad = sqrt(u);
        let phi = 2.0 * PI * fract(f32(i) * GOLDEN + turn);
        let w = t1 * (rad * cos(phi)) + t2 * (rad * sin(phi)) + n * sqrt(max(1.0 - u, 0.0));
        sum += trace(p, n, w, me, fract(j + f32(i) * 0.618034));
    }
    textureStore(out_tex, me, vec4<f32>(sum / f32(count), 1.0));
}

// The diffuse albedo at pixel q.
fn albedo(q: vec2<i32>) -> vec3<f32> {
    let base = textureLoad(g_base, q, 0);
    return base.rgb * (1.0 - base.a);
}

// Whether pixel q shows a surface with some diffuse albedo.
fn diffuse(q: vec2<i32>) -> bool {
    let rho = albedo(q);
    return textureLoad(g_material, q, 0).x != 0u && max(rho.r, max(rho.g, rho.b)) > 0.0;
}

@compute @workgroup_size(8, 8)
fn blur(@builtin(global_invocation_id) gid: vec3<u32>) {
    let me = vec2<i32>(gid.xy);
    if any(me >= size()) {
        return;
    }
    let here = textureLoad(lit, me, 0);
    if !diffuse(me) {
        textureStore(out_tex, me, here);
        return;
    }
    let n = normalize(textureLoad(g_normal, me, 0).xyz);
    let dist = textureLoad(g_distance, me, 0).x;
    let p = u.eye.xyz + ray_at(vec2<f32>(me) + 0.5) * dist;
    let r = i32(u.q.w);
    var sum = vec3<f32>(0.0);
    var weight = 0.0;
    for (var dy = -r; dy <= r; dy++) {
        for (var dx = -r; dx <= r; dx++) {
            let q = me + vec2<i32>(dx, dy);
            if any(q < vec2<i32>(0)) || any(q >= size()) || !diffuse(q) {
                continue;
            }
            let nq = textureLoad(g_normal, q, 0).xyz;
            let pq = u.eye.xyz + ray_at(vec2<f32>(q) + 0.5) * textureLoad(g_distance, q, 0).x;
            if dot(nq, n) < 0.906 || abs(dot(pq - p, n)) > 0.02 * dist {
                continue;
            }
            sum += textureLoad(raw, q, 0).rgb;
            weight += 1.0;
        }
    }
    let mean = sum / max(weight, 1.0);
    textureStore(out_tex, me, vec4<f32>(here.rgb + albedo(me) * mean, here.a));
}
