// Light shafts, `froxel` (Wronski 2014; Hillaire 2015;
// passes/lighting/froxel.rs): a fog volume aligned with the view frustum.
//
// * grid: froxel (i, j) covers the frame's pixels [i d, (i + 1) d) ×
//   [j d, (j + 1) d) (d = resolution_divisor), its column the view ray
//   through the block's centre; slice k covers the distances along that
//   ray [t_k, t_k+1), t_k = D (k / N)², D the frame's farthest surface
//   (`extent`), N the slices;
// * `inject`: per froxel the fog's in-scattering per metre (cd/m²/m),
//   the Sun's and Moon's at n points stratified over the slice's part
//   inside the fog (y ≤ top; n = `interleave`), the sky's at the first,
//   their places jittered per frame:
//     S = σ_s [p(θ_sun) E_sun T_sun(y) V_sun(x) + (Moon) + Σ_k p(θ_k) S_k
//         T_k(y) V_k(x)]
//   with godrays.wgsl's terms (the sky's cells as its march takes them,
//   the slices taking turns), then blended with the
//   previous frame's volume at the froxel centre's reprojected place
//   (weight `temporal`; history outside the previous frustum or volume is
//   rejected);
// * `integrate`: front to back along each column, slice k adding
//   T_k S_k (1 − e^{−σ_t L_k}) / σ_t (L_k: the slice's length inside the
//   fog; exact for S constant over the slice, Hillaire 2015) and
//   T_{k+1} = T_k e^{−σ_t L_k}; written per slice as (the integral to the
//   slice's far end, T there);
// * `apply`: per frame pixel with a surface, the integral at its distance
//   (the slice's own part in closed form from its S), bilinear over the
//   four nearest columns, into the shafts' image at full resolution.
// Sky pixels get none (as `toth`). common.wgsl, shafts.wgsl and
// shafts_sky.wgsl are prepended.

struct Froxel {
    // The previous frame's view-projection.
    prev_view_proj: mat4x4<f32>,
    // xyz: the previous eye; w: 1 when the history holds.
    prev_eye: vec4<f32>,
    // Columns x, y, slices; w: the frame's number (low 16 bits) and the
    // samples per froxel (high 16 bits).
    grid: vec4<u32>,
    // x: the history's weight; y: this frame's jitter in [0, 1); z: the
    // froxel's side in pixels; w: 0.
    params: vec4<f32>,
}

@group(0) @binding(1) var g_distance: texture_2d<f32>;
@group(0) @binding(2) var g_material: texture_2d<u32>;
@group(0) @binding(5) var shafts_out: texture_storage_2d<rgba32float, write>;
@group(0) @binding(9) var<uniform> fx: Froxel;
// The farthest surface's distance (f32 bits): this frame's, the previous.
@group(0) @binding(10) var<storage, read_write> extent: array<atomic<u32>, 2>;
@group(0) @binding(11) var src: texture_3d<f32>;
@group(0) @binding(12) var dst: texture_storage_3d<rgba32float, write>;

// The view ray through the frame point p (pixels, continuous).
fn ray_at(p: vec2<f32>) -> vec3<f32> {
    let t = u.eye.w;
    let h = u.up.w;
    let nx = (p.x - 0.5 * u.right.w) / (0.5 * h) * t;
    let ny = -(p.y - 0.5 * h) / (0.5 * h) * t;
    return normalize(u.forward.xyz + u.right.xyz * nx + u.up.xyz * ny);
}

fn column_ray(c: vec2<u32>) -> vec3<f32> {
    return ray_at((vec2<f32>(c) + 0.5) * fx.params.z);
}

// The distance of slice boundary s (0..N) for a volume reaching d.
fn slice_t(s: f32, d: f32) -> f32 {
    let f = s / f32(fx.grid.z);
    return d * f * f;
}

fn far_m() -> f32 {
    return bitcast<f32>(atomicLoad(&extent[0]));
}

// The previous volume at continuous froxel coordinates q (texel centres
// at + 0.5), trilinear, clamped to the volume.
fn history(q: vec3<f32>) -> vec3<f32> {
    let size = vec3<i32>(fx.grid.xyz);
    let c = q - 0.5;
    let b = vec3<i32>(floor(c));
    let f = c - floor(c);
    var acc = vec3<f32>(0.0);
    for (var k = 0; k < 8; k++) {
        let o = vec3<i32>(k & 1, (k >> 1) & 1, (k >> 2) & 1);
        let w = select(1.0 - f, f, o == vec3<i32>(1));
        let t = clamp(b + o, vec3<i32>(0), size - 1);
        acc += textureLoad(src, t, 0).rgb * (w.x * w.y * w.z);
    }
    return acc;
}

@compute @workgroup_size(8, 8)
fn extent_max(@builtin(global_invocation_id) gid: vec3<u32>) {
    let w = u32(u.right.w);
    let h = u32(u.up.w);
    if gid.x >= w || gid.y >= h {
        return;
    }
    let px = vec2<i32>(gid.xy);
    if textureLoad(g_material, px, 0).x == 0u {
        return;
    }
    let d = textureLoad(g_distance, px, 0).x;
    atomicMax(&extent[0], bitcast<u32>(max(d, 0.0)));
}

@compute @workgroup_size(4, 4, 4)
fn inject(@builtin(global_invocation_id) gid: vec3<u32>) {
    if any(gid >= fx.grid.xyz) {
        return;
    }
    let ray = column_ray(gid.xy);
    let d = far_m();
    let k = f32(gid.z);
    let seg = fog_interval(slice_t(k, d), slice_t(k + 1.0, d), ray);
    if seg.y <= seg.x {
        textureStore(dst, gid, vec4<f32>(0.0));
        return;
    }
    // The jitter: this frame's offset, shifted over each 2 × 2 block of
    // columns.
    let cell = f32((gid.x & 1u) + 2u * (gid.y & 1u)) * 0.25;
    let jit = fract(fx.params.y + cell);
    let eye = u.eye.xyz;
    let top = u.fog.y;
    let st = u.fog.x;
    let fwd = dot(ray, u.forward.xyz);
    // The Sun and the Moon at n points stratified over the slice's part
    // in the fog (the jitter shifting them all), the sky's cells at the
    // first.
    let n = max(fx.grid.w >> 16u, 1u);
    var l = vec3<f32>(0.0);
    for (var m = 0u; m < n; m++) {
        let t = mix(seg.x, seg.y, (f32(m) + jit) / f32(n));
        let x = eye + ray * t;
        let depth = max(top - x.y, 0.0);
        if u.sun_dir.w > 0.5 && u.sun_dir.y > 0.0 {
            let tl = exp(-st * depth / max(u.sun_dir.y, 1e-4));
            let v = light_visibility(0u, u.counts.y, x, t * fwd);
            l += u.sun_rgb.rgb * (phase(dot(ray, u.sun_dir.xyz)) * tl * v / f32(n));
        }
        if u.moon_dir.w > 0.5 && u.moon_dir.y > 0.0 {
            let tl = exp(-st * depth / max(u.moon_dir.y, 1e-4));
            let v = light_visibility(u.flags.y, u.counts.z, x, t * fwd);
            l += u.moon_rgb.rgb * (phase(dot(ray, u.moon_dir.xyz)) * tl * v / f32(n));
        }
    }
    let t = mix(seg.x, seg.y, jit / f32(n));
    let x = eye + ray * t;
    let depth = max(top - x.y, 0.0);
    let sky_per = u.shaft_q.w;
    if u.flags.x == 1u && u.counts.x > 0u && sky_per > 0u {
        // As the march: the column's interleaved set, the slices taking
        // turns over the sets and over the cells in them (the same ones
        // every frame: turning them over the frames flickers).
        let side = max(u.flags.z, 1u);
        let turn = gid.z;
        let set_i = ((gid.x % side) + (gid.y % side) * side + turn) % (side * side);
        let stride = clamp((u.counts.x + u.flags.w + sky_per - 1u) / sky_per, 1u, fx.grid.z);
        l += sky_light(x, depth, ray, set_i, turn % stride, stride);
    }
    var s = u.shafts.x * l;
    if fx.prev_eye.w > 0.5 {
        // The froxel's centre in the previous frame's volume.
        let tc = slice_t(k + 0.5, d);
        let c = eye + ray * tc;
        let clip = fx.prev_view_proj * vec4<f32>(c, 1.0);
        let prev_d = bitcast<f32>(atomicLoad(&extent[1]));
        if clip.w > 1e-4 && prev_d > 0.0 {
            let ndc = clip.xy / clip.w;
            let p = vec2<f32>(ndc.x * 0.5 + 0.5, 0.5 - ndc.y * 0.5) * vec2<f32>(u.right.w, u.up.w);
            let ps = f32(fx.grid.z) * sqrt(length(c - fx.prev_eye.xyz) / prev_d);
            let q = vec3<f32>(p / fx.params.z, ps);
            if all(abs(ndc) <= vec2<f32>(1.0)) && ps <= f32(fx.grid.z) {
                s = mix(s, history(q), fx.params.x);
            }
        }
    }
    textureStore(dst, gid, vec4<f32>(s, 0.0));
}

@compute @workgroup_size(8, 8)
fn integrate(@builtin(global_invocation_id) gid: vec3<u32>) {
    if gid.x >= fx.grid.x || gid.y >= fx.grid.y {
        return;
    }
    let ray = column_ray(gid.xy);
    let d = far_m();
    let st = u.fog.x;
    var acc = vec3<f32>(0.0);
    var tr = 1.0;
    for (var k = 0u; k < fx.grid.z; k++) {
        let fk = f32(k);
        let seg = fog_interval(slice_t(fk, d), slice_t(fk + 1.0, d), ray);
        let len = seg.y - seg.x;
        let s = textureLoad(src, vec3<u32>(gid.xy, k), 0).rgb;
        let w = weight(len, st);
        acc += s * (tr * w);
        tr *= exp(-st * len);
        textureStore(dst, vec3<u32>(gid.xy, k), vec4<f32>(acc, tr));
    }
}

// The integral of column c (clamped to the grid) to distance dist along
// the column's ray.
fn column_at(c: vec2<i32>, dist: f32, d: f32) -> vec3<f32> {
    let n = i32(fx.grid.z);
    let cc = clamp(c, vec2<i32>(0), vec2<i32>(fx.grid.xy) - 1);
    let s = f32(n) * sqrt(clamp(dist / max(d, 1e-6), 0.0, 1.0));
    let k = clamp(i32(floor(s)), 0, n - 1);
    var before = vec3<f32>(0.0);
    if k > 0 {
        before = textureLoad(src, vec3<i32>(cc, k - 1), 0).rgb;
    }
    // The slice's own part, from its start to dist: its whole
    // contribution (the integral to its far end minus the one before)
    // times the part's share of its weight.
    let here = textureLoad(src, vec3<i32>(cc, k), 0);
    let ray = column_ray(vec2<u32>(cc));
    let st = u.fog.x;
    let full = fog_interval(slice_t(f32(k), d), slice_t(f32(k) + 1.0, d), ray);
    let part = fog_interval(slice_t(f32(k), d), min(dist, slice_t(f32(k) + 1.0, d)), ray);
    let wf = weight(full.y - full.x, st);
    let wp = weight(part.y - part.x, st);
    if wf <= 0.0 {
        return before;
    }
    return before + (here.rgb - before) * (wp / wf);
}

// ∫_0^len e^{−σ_t s} ds.
fn weight(len: f32, st: f32) -> f32 {
    if st * len > 1e-5 {
        return (1.0 - exp(-st * len)) / st;
    }
    return len;
}

@compute @workgroup_size(8, 8)
fn apply(@builtin(global_invocation_id) gid: vec3<u32>) {
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
    let d = far_m();
    let c = (vec2<f32>(px) + 0.5) / fx.params.z - 0.5;
    let b = vec2<i32>(floor(c));
    let f = c - floor(c);
    var l = vec3<f32>(0.0);
    for (var k = 0; k < 4; k++) {
        let o = vec2<i32>(k & 1, k >> 1);
        let wt = select(1.0 - f, f, o == vec2<i32>(1));
        l += column_at(b + o, dist, d) * (wt.x * wt.y);
    }
    textureStore(shafts_out, px, vec4<f32>(l, 0.0));
}
