// Light shafts, `toth` (Tóth & Umenhoffer 2009; passes/lighting/godrays.rs):
// each view ray is marched from the eye to the surface the G-buffer shows,
// through the part of it inside the fog (y ≤ top), and sums the fog's
// single scattering, in cd/m²:
//
//   L_s = σ_s Σ_i w_i [p(θ_sun) E_sun T_sun(y_i) V_sun(x_i)
//                      + p(θ_moon) E_moon T_moon(y_i) V_moon(x_i)
//                      + Σ_k p(θ_k) S_k T_k(y_i) V_k(x_i)]
//
// * w_i = ∫ over step i of exp(−σ_t s) ds: the view ray's transmittance
//   integrated exactly over each step (exact for light constant over it);
// * T_light(y) = exp(−σ_t (top − y) / sin h) (world.md), E the light's
//   transmitted illuminance (lux), p the fog's phase at cos θ = ray · l;
// * V: the light's cascaded shadow map at the sample (2 × 2 PCF by the
//   comparison sampler), 1 outside the maps;
// * the sky: its environment light's cells k above the horizon (env.rs;
//   the texel's interleaved set and the aureoles' cells), S_k = |∫L ω dΩ|
//   over the cell (≈ ∫L dΩ for a cell a few degrees wide) per channel,
//   T_k = exp(−σ_t (top − y) / sin h_k) along the cell's own direction,
//   V_k from the cell's visibility map at x_i. Cells below the horizon are
//   left out (their light crosses the fog's whole depth, or the ground).
//   Step i looks up the interleaved set (texel's set + i) mod N_sets, and
//   in it every `stride`-th cell (`sky_cells` per step), the next step the next ones,
//   weighted by `stride`, so that the march sees each cell ~steps/stride
//   times;
// * N × N interleaving: texel (x, y) starts its march at the fraction
//   ((x mod N) + N (y mod N) + ½) / N² of a step; shade.wgsl averages the
//   N × N block.
// The march runs on an image 1 / shaft_q.z of the frame's size, each texel
// for the frame pixel at its block's centre; on a reduced image `refine`
// then makes the full-resolution one the lighting pass reads. Sky pixels
// are not marched (the sky's own fog is left out, as its extinction is).
// common.wgsl (the uniforms, the view ray), shafts.wgsl (the phase, the
// lights' visibility) and shafts_sky.wgsl (the sky's cells) are prepended,
// shafts_gather.wgsl (the depth-aware gather, for `refine`) appended.

@group(0) @binding(1) var g_distance: texture_2d<f32>;
@group(0) @binding(2) var g_material: texture_2d<u32>;
@group(0) @binding(5) var shafts_out: texture_storage_2d<rgba32float, write>;
// The reduced image, for `refine` (a stand-in for `march`).
@group(0) @binding(9) var shafts_in: texture_2d<f32>;
// The pixels `refine` leaves to `march_list` (x | y << 16), their count
// first (cleared before each frame's refine).
struct Todo {
    count: atomic<u32>,
    px: array<u32>,
}
@group(0) @binding(10) var<storage, read_write> todo: Todo;
// The march of frame pixel px's view ray in `steps` steps, with the start
// offset jitter (a fraction of a step), the sky cells' interleaved set
// cell_set and sky_per_step of its cells looked up per step.
fn march_pixel(px: vec2<i32>, jitter: f32, cell_set: u32, steps: u32, sky_per_step: u32) -> vec3<f32> {
    let w = u32(u.right.w);
    let h = u32(u.up.w);
    let dist = textureLoad(g_distance, px, 0).x;
    let ray = pixel_ray(px, w, h);
    let eye = u.eye.xyz;
    let top = u.fog.y;
    let span = fog_interval(0.0, dist, ray);
    let t0 = span.x;
    let t1 = span.y;
    if t1 <= t0 {
        return vec3<f32>(0.0);
    }
    let dt = (t1 - t0) / f32(steps);
    let st = u.fog.x;
    // ∫_0^dt exp(−σ_t s) ds, and the transmittance across one step.
    var seg = dt;
    if st * dt > 1e-5 {
        seg = (1.0 - exp(-st * dt)) / st;
    }
    let step_t = exp(-st * dt);
    let fwd = dot(ray, u.forward.xyz);
    let sun_on = u.sun_dir.w > 0.5 && u.sun_dir.y > 0.0;
    let moon_on = u.moon_dir.w > 0.5 && u.moon_dir.y > 0.0;
    var sun_sum = 0.0;
    var moon_sum = 0.0;
    var sky_sum = vec3<f32>(0.0);
    let sky_on = u.flags.x == 1u && u.counts.x > 0u && sky_per_step > 0u;
    let side = max(u.flags.z, 1u);
    let stride = clamp((u.counts.x + u.flags.w + sky_per_step - 1u) / max(sky_per_step, 1u), 1u, steps);
    var tv = seg;
    for (var i = 0u; i < steps; i++) {
        let t = t0 + (f32(i) + jitter) * dt;
        let x = eye + ray * t;
        let depth = max(top - x.y, 0.0);
        if sun_on {
            let tl = exp(-st * depth / max(u.sun_dir.y, 1e-4));
            sun_sum += tl * light_visibility(0u, u.counts.y, x, t * fwd) * tv;
        }
        if moon_on {
            let tl = exp(-st * depth / max(u.moon_dir.y, 1e-4));
            moon_sum += tl * light_visibility(u.flags.y, u.counts.z, x, t * fwd) * tv;
        }
        if sky_on {
            // The sets take turns along the march (the texel's own first).
            let set_i = (cell_set + i) % (side * side);
            sky_sum += sky_light(x, depth, ray, set_i, i % stride, stride) * tv;
        }
        tv *= step_t;
    }
    let ss = u.shafts.x;
    var l = vec3<f32>(0.0);
    if sun_on {
        l += u.sun_rgb.rgb * (ss * phase(dot(ray, u.sun_dir.xyz)) * sun_sum);
    }
    if moon_on {
        l += u.moon_rgb.rgb * (ss * phase(dot(ray, u.moon_dir.xyz)) * moon_sum);
    }
    return l + ss * sky_sum;
}

// Texel (or pixel) q's start offset in the N × N pattern, a fraction of
// a step, and its sky cells' set.
fn interleaved(q: vec2<u32>) -> vec2<f32> {
    let n = max(u.shaft_q.y, 1u);
    let side = max(u.flags.z, 1u);
    let jitter = (f32((q.x % n) + (q.y % n) * n) + 0.5) / f32(n * n);
    return vec2<f32>(jitter, f32((q.x % side) + (q.y % side) * side));
}

@compute @workgroup_size(8, 8)
fn march(@builtin(global_invocation_id) gid: vec3<u32>) {
    let w = u32(u.right.w);
    let h = u32(u.up.w);
    let div = max(u.shaft_q.z, 1u);
    let lw = (w + div - 1u) / div;
    let lh = (h + div - 1u) / div;
    if gid.x >= lw || gid.y >= lh {
        return;
    }
    let q = vec2<i32>(gid.xy);
    let px = min(q * i32(div) + i32(div / 2u), vec2<i32>(i32(w) - 1, i32(h) - 1));
    if textureLoad(g_material, px, 0).x == 0u {
        textureStore(shafts_out, q, vec4<f32>(0.0));
        return;
    }
    let k = interleaved(gid.xy);
    textureStore(shafts_out, q, vec4<f32>(march_pixel(px, k.x, u32(k.y), max(u.shaft_q.x, 1u), u.shaft_q.w), 0.0));
}

// `refine` (reduced images only): the full-resolution image of the
// shafts. A pixel takes the depth-aware gather of the reduced image
// (shafts_gather.wgsl) unless one of the 2 × 2 texels nearest to it shows
// the sky or another surface (its distance off the pixel's by more than
// REFINE_DEPTH of it, plus 2 cm) — where the reduced image cannot say what
// the pixel's own ray sees. There the pixel's view ray is marched itself,
// in twice the steps (one start offset instead of the gather's N²), so
// that the edges stay sharp, with half the sky cells a step (the sky's
// light in the fog varies slowly; a texel's share of lookups).
const REFINE_DEPTH: f32 = 0.06;

@compute @workgroup_size(8, 8)
fn refine(@builtin(global_invocation_id) gid: vec3<u32>) {
    let w = u32(u.right.w);
    let h = u32(u.up.w);
    if gid.x >= w || gid.y >= h {
        return;
    }
    let px = vec2<i32>(gid.xy);
    if textureLoad(g_material, px, 0).x == 0u {
        textureStore(shafts_out, px, vec4<f32>(0.0));
        return;
    }
    let dist = textureLoad(g_distance, px, 0).x;
    let div = i32(max(u.shaft_q.z, 1u));
    let lsize = vec2<i32>(textureDimensions(shafts_in));
    let base = vec2<i32>(floor((vec2<f32>(px) + 0.5) / f32(div) - 0.5));
    var edge = false;
    for (var k = 0; k < 4; k++) {
        let q = clamp(base + vec2<i32>(k % 2, k / 2), vec2<i32>(0), lsize - 1);
        let rp = min(q * div + div / 2, vec2<i32>(i32(w) - 1, i32(h) - 1));
        edge = edge || textureLoad(g_material, rp, 0).x == 0u
            || abs(textureLoad(g_distance, rp, 0).x - dist) > REFINE_DEPTH * dist + 0.02;
    }
    if edge {
        // Marched by `march_list`, whose threads all march (in `refine`,
        // the threads beside a marching one would wait for it).
        let i = atomicAdd(&todo.count, 1u);
        todo.px[i] = gid.x | (gid.y << 16u);
    } else {
        textureStore(shafts_out, px, gather_shafts(px, dist, w, h));
    }
}

@compute @workgroup_size(64)
fn march_list(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let i = gid.x + gid.y * groups.x * 64u;
    if i >= atomicLoad(&todo.count) {
        return;
    }
    let c = todo.px[i];
    let q = vec2<u32>(c & 0xffffu, c >> 16u);
    let k = interleaved(q);
    let fine = max(u.shaft_q.x, 1u) * 2u;
    textureStore(shafts_out, vec2<i32>(q), vec4<f32>(march_pixel(vec2<i32>(q), k.x, u32(k.y), fine, (u.shaft_q.w + 1u) / 2u), 1.0));
}
