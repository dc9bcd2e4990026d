// The temporal filter (passes/lighting/temporal.rs, `lighting.temporal`).
//
// Per pixel with a surface (sky pixels pass through as the sky passes
// drew them, and enter the history as they are):
// 1. where the surface was: x_prev = x + 0.5 − velocity (the G-buffer's
//    motion in pixels with this frame's jitter taken out, gbuffer.wgsl);
// 2. disocclusion: the surface point p (on this frame's jittered view ray)
//    lies at e = |p − previous eye| from the previous eye; the history
//    counts only where one of the 3 × 3 texels about x_prev kept a distance
//    within (depth_tolerance + 2 θ / |n·v|) · e of it, θ a pixel's angle
//    (the same surface: a plane seen at grazing incidence changes its
//    distance by e θ / |n·v| over a pixel, and the samples of two frames
//    lie up to a pixel or two apart; at an edge the jitter puts either
//    surface in a pixel, and its neighbours keep the other), and its frame
//    count n is the nearest texel's;
// 3. the history's colour: Catmull–Rom over the 4 × 4 texels about x_prev
//    (sharp under motion; exact at texel centres), clipped in YCoCg towards
//    the mean of the 3 × 3 neighbourhood of this frame into the box
//    mean ± γ (σ + σ_t) (variance clipping, Salvi 2016): what no longer
//    matches what the neighbourhood shows now (a ghost, changed light) is
//    pulled in. σ is the neighbourhood's spread in this frame, σ_t the
//    pixel's own spread of luma over its past frames (from the running
//    mean of luma², kept in the history): a pixel whose frames scatter
//    (SSR's few GGX samples) gets a box wide enough for its noise, so the
//    box does not drag its mean towards one frame's neighbourhood;
// 4. a history outside the box by a factor m counts n / m² frames (a
//    clipped history stood for other light, so the pixel moves on to the
//    new light rather than sitting at the box's edge);
//    n' = min(n + 1, max_frames), out = history + (current − history) / n':
//    the running mean of a still pixel's jittered frames.
// The history keeps (distance, n', mean luma²) beside the colour for the
// next frame.

struct Temporal {
    // xyz: eye; w: tan(fov / 2).
    eye: vec4<f32>,
    // xyz: forward; w: width / height.
    forward: vec4<f32>,
    // xyz: right; w: width, px.
    right: vec4<f32>,
    // xyz: up; w: height, px.
    up: vec4<f32>,
    // xyz: the previous frame's eye; w: 1 when a history exists.
    prev_eye: vec4<f32>,
    // xy: this frame's jitter (px); z: γ; w: depth tolerance.
    jitter: vec4<f32>,
    // max_frames, 0, 0, 0.
    q: vec4<u32>,
}

@group(0) @binding(0) var<uniform> u: Temporal;
@group(0) @binding(1) var g_distance: texture_2d<f32>;
@group(0) @binding(2) var g_material: texture_2d<u32>;
@group(0) @binding(3) var g_velocity: texture_2d<f32>;
@group(0) @binding(4) var current: texture_2d<f32>;
@group(0) @binding(5) var hist_colour: texture_2d<f32>;
// x: the distance kept (0: sky), y: the frames the pixel's history holds,
// z: the running mean of the pixel's luma (YCoCg Y) squared.
@group(0) @binding(6) var hist_aux: texture_2d<f32>;
@group(0) @binding(7) var out_tex: texture_storage_2d<rgba32float, write>;
@group(0) @binding(8) var out_colour: texture_storage_2d<rgba32float, write>;
@group(0) @binding(9) var out_aux: texture_storage_2d<rgba32float, write>;
@group(0) @binding(10) var g_normal: texture_2d<f32>;

fn size() -> vec2<i32> {
    return vec2<i32>(i32(u.right.w), i32(u.up.w));
}

fn clamped(q: vec2<i32>) -> vec2<i32> {
    return clamp(q, vec2<i32>(0), size() - 1);
}

// The view ray through the jittered sample of pixel q (as common.wgsl's).
fn pixel_ray(q: vec2<i32>) -> vec3<f32> {
    let h = u.up.w;
    let t = u.eye.w;
    let nx = (f32(q.x) + 0.5 - u.jitter.x - 0.5 * u.right.w) / (0.5 * h) * t;
    let ny = -(f32(q.y) + 0.5 - u.jitter.y - 0.5 * h) / (0.5 * h) * t;
    return normalize(u.forward.xyz + u.right.xyz * nx + u.up.xyz * ny);
}

fn ycocg(c: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(
        0.25 * c.r + 0.5 * c.g + 0.25 * c.b,
        0.5 * c.r - 0.5 * c.b,
        -0.25 * c.r + 0.5 * c.g - 0.25 * c.b,
    );
}

fn rgb(c: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(c.x + c.y - c.z, c.x + c.z, c.x - c.y - c.z);
}

// Catmull–Rom weights of the four texels about a sample at fraction f.
fn catmull_rom(f: f32) -> vec4<f32> {
    let f2 = f * f;
    let f3 = f2 * f;
    return vec4<f32>(
        -0.5 * f3 + f2 - 0.5 * f,
        1.5 * f3 - 2.5 * f2 + 1.0,
        -1.5 * f3 + 2.0 * f2 + 0.5 * f,
        0.5 * f3 - 0.5 * f2,
    );
}

// The history's colour at pixel position x (centres at +0.5).
fn history_at(x: vec2<f32>) -> vec3<f32> {
    let t = x - 0.5;
    let base = vec2<i32>(floor(t));
    let f = t - floor(t);
    let wx = catmull_rom(f.x);
    let wy = catmull_rom(f.y);
    var c = vec3<f32>(0.0);
    for (var j = 0; j < 4; j++) {
        for (var i = 0; i < 4; i++) {
            let q = clamped(base + vec2<i32>(i - 1, j - 1));
            c += wx[i] * wy[j] * textureLoad(hist_colour, q, 0).rgb;
        }
    }
    return max(c, vec3<f32>(0.0));
}

// How far h lies outside the box: the largest |h − centre| / half-width
// over the three axes (≤ 1 inside).
fn box_excess(h: vec3<f32>, lo: vec3<f32>, hi: vec3<f32>) -> f32 {
    let c = 0.5 * (lo + hi);
    let e = max(0.5 * (hi - lo), vec3<f32>(1e-7 * (abs(c.x) + 1e-20)));
    let a = abs((h - c) / e);
    return max(a.x, max(a.y, a.z));
}

// Pulls h along the line to the box's centre until it lies in the box
// (m: its box_excess).
fn clip_box(h: vec3<f32>, lo: vec3<f32>, hi: vec3<f32>, m: f32) -> vec3<f32> {
    let c = 0.5 * (lo + hi);
    if m > 1.0 {
        return c + (h - c) / m;
    }
    return h;
}

@compute @workgroup_size(8, 8)
fn resolve(@builtin(global_invocation_id) gid: vec3<u32>) {
    let s = size();
    let px = vec2<i32>(gid.xy);
    if px.x >= s.x || px.y >= s.y {
        return;
    }
    let cur = textureLoad(current, px, 0).rgb;
    if textureLoad(g_material, px, 0).x == 0u {
        textureStore(out_colour, px, vec4<f32>(cur, 1.0));
        textureStore(out_aux, px, vec4<f32>(0.0, 1.0, 0.0, 0.0));
        return;
    }
    let dist = textureLoad(g_distance, px, 0).x;
    // The neighbourhood's mean and standard deviation (YCoCg).
    var m1 = vec3<f32>(0.0);
    var m2 = vec3<f32>(0.0);
    for (var dy = -1; dy <= 1; dy++) {
        for (var dx = -1; dx <= 1; dx++) {
            let c = ycocg(textureLoad(current, clamped(px + vec2<i32>(dx, dy)), 0).rgb);
            m1 += c;
            m2 += c * c;
        }
    }
    m1 /= 9.0;
    let sigma = sqrt(max(m2 / 9.0 - m1 * m1, vec3<f32>(0.0)));
    // Where the surface was, and whether the history saw it there.
    let x_prev = vec2<f32>(px) + 0.5 - textureLoad(g_velocity, px, 0).xy;
    var n = 0.0;
    var y2 = 0.0;
    let inside = all(x_prev >= vec2<f32>(0.0)) && all(x_prev <= vec2<f32>(s));
    if u.prev_eye.w > 0.5 && inside {
        let ray = pixel_ray(px);
        let p = u.eye.xyz + ray * dist;
        let e = length(p - u.prev_eye.xyz);
        let t0 = vec2<i32>(floor(x_prev));
        let nv = abs(dot(normalize(textureLoad(g_normal, px, 0).xyz), ray));
        let theta = 2.0 * u.eye.w / u.up.w;
        let tol = (u.jitter.w + 2.0 * theta / max(nv, 0.02)) * e;
        var same = false;
        for (var k = 0; k < 9; k++) {
            let a = textureLoad(hist_aux, clamped(t0 + vec2<i32>(k % 3 - 1, k / 3 - 1)), 0);
            same = same || (a.x > 0.0 && abs(a.x - e) <= tol);
        }
        if same {
            let a = textureLoad(hist_aux, clamped(t0), 0);
            n = a.y;
            y2 = a.z;
        }
    }
    var out = cur;
    var frames = 1.0;
    let y_cur = ycocg(cur).x;
    var y2_out = y_cur * y_cur;
    if n > 0.0 {
        let h_raw = ycocg(history_at(x_prev));
        // The pixel's own noise: the spread of its frames' luma about the
        // history's mean (σ_t), widening the box of a pixel whose frames
        // scatter more than its neighbourhood shows in one frame.
        let sigma_t = sqrt(max(y2 - h_raw.x * h_raw.x, 0.0));
        let g = u.jitter.z * (sigma + vec3<f32>(sigma_t));
        let m = box_excess(h_raw, m1 - g, m1 + g);
        let h = rgb(clip_box(h_raw, m1 - g, m1 + g, m));
        // A clipped history stood for another light: it counts for fewer
        // frames, the fewer the farther outside the box it lay, so the
        // pixel moves on to what it shows now instead of sitting at the
        // box's edge for max_frames frames.
        frames = min(n / max(m * m, 1.0) + 1.0, f32(u.q.x));
        out = h + (cur - h) / frames;
        y2_out = y2 + (y_cur * y_cur - y2) / frames;
    }
    textureStore(out_tex, px, vec4<f32>(out, 1.0));
    textureStore(out_colour, px, vec4<f32>(out, 1.0));
    textureStore(out_aux, px, vec4<f32>(dist, frames, y2_out, 0.0));
}
