// The sky light's gather (passes/lighting/mod.rs `encode_sky`), part of
// the lighting module (common.wgsl, shade.wgsl, this, shafts_gather.wgsl):
// the `gather` entry point between the `sky` pass and `shade`, and the
// wider mean `shade` takes where the interleaved sets agree (`widen`).
// The gather pass reads the sky pass's outputs and writes, per pixel, the
// sets' irradiance averaged over the block and their spread; the aureoles'
// irradiance and the open fraction; the specular visibility — what the
// lighting pass reads as sky_e_in, sky_s_in and sky_v_in.
@group(1) @binding(11) var raw_e_in: texture_2d<f32>;
@group(1) @binding(12) var raw_s_in: texture_2d<f32>;
@group(2) @binding(0) var gather_e_out: texture_storage_2d<rgba32float, write>;
@group(2) @binding(1) var gather_a_out: texture_storage_2d<rgba32float, write>;
@group(2) @binding(2) var gather_v_out: texture_storage_2d<r32float, write>;

// Whether pixel q shows the surface through p with normal n (seen at
// distance dist): a similar normal and a point on the plane through p
// (within 2 % of the distance).
fn same_surface(q: vec2<i32>, p: vec3<f32>, n: vec3<f32>, dist: f32, w: u32, h: u32) -> bool {
    if any(q < vec2<i32>(0)) || q.x >= i32(w) || q.y >= i32(h) {
        return false;
    }
    if textureLoad(g_material, q, 0).x == 0u {
        return false;
    }
    let nq = textureLoad(g_normal, q, 0).xyz;
    let pq = u.eye.xyz + pixel_ray(q, w, h) * textureLoad(g_distance, q, 0).x;
    return dot(nq, n) >= 0.95 && abs(dot(pq - p, n)) <= 0.02 * dist;
}

const LUMA: vec3<f32> = vec3<f32>(0.2126, 0.7152, 0.0722);

// The gather pass: each pixel's sky light from its N × N block of
// interleaved sets (Keller & Heidrich 2001), where the surface continues.
// Each set counts once: the block's pixel of that set, or where the
// surface ends there (an edge, a corner), the nearest pixel of the same
// set beyond the centre (one block over) that lies on it. Written: the
// sets' mean irradiance and the spread of their luminances (each set is
// an estimate of the whole sky); the aureoles' irradiance, which every
// pixel sums whole, averaged only over the block's pixels that see about
// as much of it (within AUREOLE_TOLERANCE: never across the edge of the
// Sun's shadow, where the aureole goes with the Sun), and the open
// fraction of the sky; the specular visibility.
@compute @workgroup_size(8, 8)
fn gather(@builtin(global_invocation_id) gid: vec3<u32>) {
    let sp = surface_at(gid.xy);
    if !sp.covered {
        return;
    }
    let w = u32(u.right.w);
    let h = u32(u.up.w);
    let px = vec2<i32>(gid.xy);
    let dist = sp.dist;
    let n = sp.n;
    let p = sp.p;
    let side = i32(u.flags.z);
    let lo = -(side / 2);
    let own_a = dot(textureLoad(raw_s_in, px, 0).rgb, LUMA);
    var acc = vec4<f32>(0.0);
    var acc_y2 = 0.0;
    var acc_s = 0.0;
    var acc_a = vec3<f32>(0.0);
    var wsum_a = 0.0;
    var wsum = 0.0;
    for (var dy = lo; dy < lo + side; dy++) {
        for (var dx = lo; dx < lo + side; dx++) {
            let d = vec2<i32>(dx, dy);
            let over = select(vec2<i32>(-side), vec2<i32>(side), d < vec2<i32>(0));
            for (var c = 0; c < 4; c++) {
                let q = px + d + over * vec2<i32>(c & 1, c >> 1u);
                if !same_surface(q, p, n, dist, w, h) {
                    continue;
                }
                let eq = textureLoad(raw_e_in, q, 0);
                acc += eq;
                let yq = dot(eq.rgb, LUMA);
                acc_y2 += yq * yq;
                let sq = textureLoad(raw_s_in, q, 0);
                let ya = dot(sq.rgb, LUMA);
                if abs(ya - own_a) <= AUREOLE_TOLERANCE * max(max(ya, own_a), 1e-20) {
                    acc_a += sq.rgb;
                    wsum_a += 1.0;
                }
                acc_s += sq.w;
                wsum += 1.0;
                break;
            }
        }
    }
    let k = max(wsum, 1.0);
    let e = acc.rgb / k;
    let y = dot(e, LUMA);
    // The sets' spread (a sample standard deviation; none from one set).
    var spread = 0.0;
    if wsum > 1.5 {
        spread = sqrt(max(acc_y2 / wsum - y * y, 0.0) * wsum / (wsum - 1.0));
    }
    textureStore(gather_e_out, px, vec4<f32>(e, spread));
    textureStore(gather_a_out, px, vec4<f32>(acc_a / max(wsum_a, 1.0), acc.a / k));
    textureStore(gather_v_out, px, vec4<f32>(acc_s / k, 0.0, 0.0, 0.0));
}

// The block's mean of the sets' irradiance e (the gather pass's), averaged
// further over the 2 × 2, then 4 × 4 blocks around px (the gathered means
// at their centres, where the surface continues) while each wider mean
// agrees with the narrower one within the narrower one's standard error
// (the sets' `spread` in luminance over √sets): where the sets disagree
// only by their quadrature (a window seen through a handful of cells) the
// wider mean takes over; where the light really changes (a contact
// shadow) the narrower one stays.
fn widen(px: vec2<i32>, p: vec3<f32>, n: vec3<f32>, dist: f32, w: u32, h: u32, e: vec3<f32>, spread: f32) -> vec3<f32> {
    let side = i32(u.flags.z);
    var cur = e;
    var count = f32(side * side);
    for (var level = 1u; level <= WIDEN_LEVELS; level++) {
        let blocks = 1 << level;
        let lo = side / 2 - (blocks * side) / 2;
        var acc = vec3<f32>(0.0);
        var k = 0.0;
        for (var by = 0; by < blocks; by++) {
            for (var bx = 0; bx < blocks; bx++) {
                let q = px + vec2<i32>(lo + bx * side, lo + by * side);
                if same_surface(q, p, n, dist, w, h) {
                    acc += textureLoad(sky_e_in, q, 0).rgb;
                    k += 1.0;
                }
            }
        }
        if k < 0.75 * f32(blocks * blocks) {
            break;
        }
        let wide = acc / k;
        if abs(dot(wide - cur, LUMA)) > WIDEN_K * spread / sqrt(count) {
            break;
        }
        cur = wide;
        count = k * f32(side * side);
    }
    return cur;
}

// Standard errors a wider mean may differ by (`widen`).
const WIDEN_K: f32 = 1.0;
// Doublings of the block `widen` tries.
const WIDEN_LEVELS: u32 = 2u;
// Relative difference of two pixels' aureole light within which the
// gather averages it (`gather`).
const AUREOLE_TOLERANCE: f32 = 0.5;
