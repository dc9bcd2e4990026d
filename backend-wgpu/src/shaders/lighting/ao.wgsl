// Ambient occlusion (`lighting.ao`, passes/lighting/ao.rs): per pixel of
// the G-buffer, the cosine-weighted visibility within the radius R,
//
//   A = (1/π) ∫_Ω V_R(ω) (n·ω) dω,
//
// V_R(ω) = 0 where geometry lies closer than R along ω, and the bent normal
// (the cosine-weighted mean unblocked direction, ∫ ω V_R (n·ω) dω
// normalised), from the G-buffer's distance and normal
// alone (screen space: what the camera does not see does not occlude).
//
// * `gtao` (Jimenez et al. 2016, "Practical real-time strategies for
//   accurate indirect occlusion"): slices through the view vector v, each
//   at a screen angle φ; in a slice, angles θ are measured from v towards
//   the slice's screen direction. The normal projected into the slice (n_p,
//   length |n_p|, angle γ) bounds the hemisphere to [γ − π/2, γ + π/2];
//   the horizons h₀ ≤ 0 ≤ h₁ are the highest G-buffer points closer than R
//   on each side (a sample's elevation fades to the hemisphere's edge over
//   the last `FALLOFF` of R), and
//     â(h) = (cos γ + 2h sin γ − cos(2h − γ)) / 4,
//     A_slice = |n_p| (â(h₀) + â(h₁)),
//   the exact integral of cos(θ − γ)|sin θ| between them. A is Σ A_slice
//   over Σ |n_p| (cos γ + γ sin γ) (the same sum unoccluded), so that an
//   open plane gives 1 for any number of slices. The slices' angles are
//   offset over a 4 × 4 pixel pattern, the samples' distances by
//   interleaved gradient noise; the blur gathers them.
// * `ssao` (Mittring 2007; the normal-oriented hemisphere kernel): N points
//   x_i = p + r_i ω_i, ω_i cosine-distributed about n (stratified, rotated
//   about n per pixel by interleaved gradient noise), r_i from 0.1 R to R
//   (denser near p); x_i is blocked when the surface the G-buffer shows
//   through x_i lies in front of it, by less than R (farther: another
//   object, in front of p rather than above it). A = the unblocked
//   fraction: a point test, not a ray test, so it misses blockers beyond
//   each point along its direction and reads lighter than the reference.
// * `blur` (both): a depth-aware box of (2 blur_px + 1)² pixels over the
//   neighbours on the same surface (normal within 25°, on the centre's
//   plane within 2 % of the distance).
// * `gtao` with `thickness_m`: the visibility bitmask (below, before gtao).
// * `hbao` (Bavoil et al. 2008): ao_hbao.wgsl, concatenated after this.
// * S3HO (`gtao` with `lighting.ao.sh`): the same slices also project the
//   blocked part of the cosine-weighted visibility onto the real spherical
//   harmonics of l ≤ 2 (world frame),
//     B_lm = ∫_Ω (1 − V_R(ω)) max(0, n·ω) Y_lm(ω) dω
//          = A_l Y_lm(n) − T_lm  (A_l = π, 2π/3, π/4; T the transfer),
//   each slice's blocked arcs [γ − π/2, h₀] and [h₁, γ + π/2] by the
//   midpoint rule (8 points each), scaled like A: π Σ_slices / Σ |n_p|
//   (cos γ + γ sin γ) — an open pixel gives exactly 0, however few the
//   slices. B_00 = Y_00 π (1 − A) follows from A; the other eight go out
//   as f16 pairs (rgba32uint), and the lighting pass takes Σ L_lm B_lm,
//   with the sky's radiance coefficients L_lm, from the open sky's light.
//   That is S3HO's `sh_sky` `sh2`. With `radiance` (the default) the
//   blocked arcs are weighted by the sky's radiance itself instead of its
//   nine coefficients (directional occlusion): the light the blockers hide,
//     E_b = ∫_Ω (1 − V_R(ω)) max(0, n·ω) L(ω) dω,
//   per slice and side the arc's exact cosine-weighted measure (gtao's
//   â differences) × the arc's mean radiance under the same weight (the
//   midpoint rule, 8 points, each a bilinear read of the sky's radiance
//   map: the environment's narrowest prefiltered level, 64 × 32
//   equirect), normalised like A. Under a uniform sky L it is exactly
//   π L (1 − A), scalar AO's; under a low Sun it takes the aureole where
//   the blockers stand, which order 2 spreads over the whole side of the
//   sky. E_b goes out as three f32 (rgba32uint), and the lighting pass
//   takes it from the open sky's light. The bitmask's set sectors do the
//   same with one point each.
// Output: rgba32float, xyz the bent normal (world frame), w = A; sky pixels
// (0, 0, 0, 1); with S3HO, B_1m..B_2m packed (or E_b).

struct Ao {
    // xyz: eye; w: tan(fov / 2).
    eye: vec4<f32>,
    // xyz: forward; w: width / height.
    forward: vec4<f32>,
    // xyz: right; w: width, px.
    right: vec4<f32>,
    // xyz: up; w: height, px.
    up: vec4<f32>,
    // R (m), the bitmask's thickness (m; 0: off), the frame's jitter (px,
    // x right, y down; temporal.rs).
    params: vec4<f32>,
    // Method (0 ssao, 1 gtao, 2 hbao: ao_hbao.wgsl), slices, steps, samples.
    q: vec4<u32>,
    // Blur half side (px), the frame's index in a temporal run, S3HO (0
    // off, 1 `sh2`, 2 `radiance`), 0.
    q2: vec4<u32>,
}

@group(0) @binding(0) var<uniform> u: Ao;
@group(0) @binding(1) var g_distance: texture_2d<f32>;
@group(0) @binding(2) var g_normal: texture_2d<f32>;
@group(0) @binding(3) var g_material: texture_2d<u32>;
@group(0) @binding(4) var ao_out: texture_storage_2d<rgba32float, write>;
@group(0) @binding(5) var ao_in: texture_2d<f32>;
// S3HO: B_1,-1 … B_2,2 as f16 pairs (1 × 1 stand-ins without it).
@group(0) @binding(6) var sh_out: texture_storage_2d<rgba32uint, write>;
@group(0) @binding(7) var sh_in: texture_2d<u32>;
// S3HO `radiance`: the sky's radiance, equirect (column: azimuth from
// North through East; row 0 the zenith), cd/m²; 1 × 1 without it.
@group(0) @binding(8) var sky_map: texture_2d<f32>;

// The slices' sum of B_1,-1 … B_2,2 (unnormalised), gtao's by-product; with
// S3HO `radiance`, E_b (rgb) in the first three.
var<private> sh_sum: array<f32, 8>;

const PI: f32 = 3.14159265358979;
const HALF_PI: f32 = 1.57079632679490;
// The fraction of R over which a sample's weight fades to 0.
const FALLOFF: f32 = 0.1;
// Quadrature points of the bent normal's integral over a slice's arc.
const BENT_POINTS: u32 = 16u;

// The image's size, view rays and projection (`size`, `ray_at`, `project`):
// screen.wgsl, concatenated before this.

fn on_screen(q: vec2<i32>) -> bool {
    return all(q >= vec2<i32>(0)) && all(q < size());
}

// The surface point pixel q shows.
fn position(q: vec2<i32>) -> vec3<f32> {
    return u.eye.xyz + ray_at(vec2<f32>(q) + 0.5) * textureLoad(g_distance, q, 0).x;
}

// Interleaved gradient noise (Jimenez 2014), in [0, 1); moved by 5.588238
// px per frame of a temporal run (his animated form).
fn ign(q: vec2<u32>) -> f32 {
    let f = vec2<f32>(q) + 5.588238 * f32(u.q2.y);
    return fract(52.9829189 * fract(0.06711056 * f.x + 0.00583715 * f.y));
}

// The 4 × 4 Bayer (ordered-dither) rank of pixel q, in [0, 16).
fn bayer4(q: vec2<u32>) -> u32 {
    var m = array<u32, 16>(0u, 8u, 2u, 10u, 12u, 4u, 14u, 6u, 3u, 11u, 1u, 9u, 15u, 7u, 13u, 5u);
    return m[(q.x & 3u) + 4u * (q.y & 3u)];
}

// The real SH basis of l = 1, 2 at unit d (the order of env.rs
// `sh9_basis`, without Y_00).
fn sh8(d: vec3<f32>) -> array<f32, 8> {
    return array<f32, 8>(
        0.488603 * d.y, 0.488603 * d.z, 0.488603 * d.x,
        1.092548 * d.x * d.y, 1.092548 * d.y * d.z, 0.315392 * (3.0 * d.z * d.z - 1.0),
        1.092548 * d.x * d.z, 0.546274 * (d.x * d.x - d.y * d.y));
}

fn sh_on() -> bool {
    return u.q2.z != 0u;
}

// S3HO weights the blocked arcs by the sky's radiance (`sh_sky` `radiance`).
fn radiance_on() -> bool {
    return u.q2.z == 2u;
}

// B_1,-1 … B_2,2 packed as f16 pairs, or E_b as three f32.
fn pack_sh(t: array<f32, 8>) -> vec4<u32> {
    if radiance_on() {
        return vec4<u32>(bitcast<u32>(t[0]), bitcast<u32>(t[1]), bitcast<u32>(t[2]), 0u);
    }
    return vec4<u32>(pack2x16float(vec2<f32>(t[0], t[1])), pack2x16float(vec2<f32>(t[2], t[3])),
        pack2x16float(vec2<f32>(t[4], t[5])), pack2x16float(vec2<f32>(t[6], t[7])));
}

// Adds what pack_sh packed into sh_sum.
fn add_packed(t: vec4<u32>) {
    if radiance_on() {
        for (var i = 0u; i < 3u; i++) {
            sh_sum[i] += bitcast<f32>(t[i]);
        }
        return;
    }
    for (var i = 0u; i < 4u; i++) {
        let h = unpack2x16float(t[i]);
        sh_sum[2u * i] += h.x;
        sh_sum[2u * i + 1u] += h.y;
    }
}

// The sky's radiance towards unit d (world frame): bilinear in the
// equirect map, wrapping in azimuth.
fn sky_radiance(d: vec3<f32>) -> vec3<f32> {
    let dims = vec2<i32>(textureDimensions(sky_map));
    let az = atan2(d.x, -d.z) / (2.0 * PI);
    let uv = vec2<f32>(az - floor(az), acos(clamp(d.y, -1.0, 1.0)) / PI);
    let t = uv * vec2<f32>(dims) - 0.5;
    let t0 = floor(t);
    let f = t - t0;
    var out = vec3<f32>(0.0);
    for (var c = 0; c < 4; c++) {
        let o = vec2<i32>(c & 1, c >> 1u);
        let x = (i32(t0.x) + o.x + dims.x) % dims.x;
        let y = clamp(i32(t0.y) + o.y, 0, dims.y - 1);
        let w = mix(1.0 - f.x, f.x, f32(o.x)) * mix(1.0 - f.y, f.y, f32(o.y));
        out += textureLoad(sky_map, vec2<i32>(x, y), 0).rgb * w;
    }
    return out;
}

// S3HO `radiance`: adds a blocked arc [lo, hi] of a slice to E_b — its
// exact cosine-weighted measure `meas` (× |n_p|) times its mean radiance
// under the same weight (midpoint rule).
fn add_radiance_arc(lo: f32, hi: f32, meas: f32, v: vec3<f32>, sl: Slice) {
    if meas <= 0.0 || hi <= lo {
        return;
    }
    let n = BENT_POINTS / 2u;
    let ds = (hi - lo) / f32(n);
    var acc = vec3<f32>(0.0);
    var wsum = 0.0;
    for (var i = 0u; i < n; i++) {
        let th = lo + (f32(i) + 0.5) * ds;
        let w = max(cos(th - sl.g), 0.0) * abs(sin(th));
        acc += sky_radiance(v * cos(th) + sl.ortho * sin(th)) * w;
        wsum += w;
    }
    if wsum <= 0.0 {
        return;
    }
    let e = acc * (meas / wsum);
    sh_sum[0] += e.x;
    sh_sum[1] += e.y;
    sh_sum[2] += e.z;
}

// The cosine-weighted integral of one side of a slice up to horizon h.
fn arc(h: f32, g: f32) -> f32 {
    return 0.25 * (cos(g) + 2.0 * h * sin(g) - cos(2.0 * h - g));
}

// One slice of `gtao`/`hbao` through the view vector v at screen angle
// (s + rot) / slices × π: its screen direction, the unit vector in the
// slice orthogonal to v, the normal projected into the slice (unit, with
// its length) and that projection's angle γ from v. ok: false where the
// slice is degenerate (along v, or n normal to it).
struct Slice {
    dir2: vec2<f32>,
    ortho: vec3<f32>,
    np_hat: vec3<f32>,
    nlen: f32,
    g: f32,
    ok: bool,
}

fn slice_at(s: u32, slices: u32, rot: f32, v: vec3<f32>, n: vec3<f32>) -> Slice {
    var out: Slice;
    out.ok = false;
    let phi = (f32(s) + rot) / f32(slices) * PI;
    out.dir2 = vec2<f32>(cos(phi), sin(phi));
    let dir3 = u.right.xyz * out.dir2.x - u.up.xyz * out.dir2.y;
    let o = dir3 - v * dot(dir3, v);
    if dot(o, o) < 1e-12 {
        return out;
    }
    out.ortho = normalize(o);
    let axis = cross(v, out.ortho);
    let np = n - axis * dot(n, axis);
    out.nlen = length(np);
    if out.nlen < 1e-4 {
        return out;
    }
    out.np_hat = np / out.nlen;
    out.g = atan2(dot(np, out.ortho), dot(np, v));
    out.ok = true;
    return out;
}

// Sample k of `steps` along a slice's side (sgn ±1): its offset from p,
// whether the walk leaves the screen there (stop), and whether it shows
// a surface at all (ok: not the sky, not p itself).
struct SliceSample {
    delta: vec3<f32>,
    stop: bool,
    ok: bool,
}

fn slice_sample(p: vec3<f32>, px: vec2<i32>, sl: Slice, sgn: f32, t: f32, r_px: f32) -> SliceSample {
    var out: SliceSample;
    out.stop = false;
    out.ok = false;
    let d_px = 1.0 + (r_px - 1.0) * t * t;
    let q = vec2<i32>(floor(vec2<f32>(px) + 0.5 + sl.dir2 * (sgn * d_px)));
    if !on_screen(q) {
        out.stop = true;
        return out;
    }
    if textureLoad(g_material, q, 0).x == 0u {
        return out;
    }
    out.delta = position(q) - p;
    out.ok = length(out.delta) >= 1e-6;
    return out;
}

// The offset `delta` of a sample from p, put into the slice: the sample's
// pixel centre lies up to half a pixel off it, so keep its height above
// the tangent plane and its distance along it (an off-slice point of the
// plane itself would rise above the slice's tangent line and occlude).
// `tangent`: the slice's line in the tangent plane on the sample's side.
fn into_slice(delta: vec3<f32>, n: vec3<f32>, tangent: vec3<f32>, sl: Slice) -> vec3<f32> {
    let len = length(delta);
    let z = dot(delta, n);
    let rho = sqrt(max(len * len - z * z, 0.0));
    return tangent * rho + sl.np_hat * (z / sl.nlen);
}

// The slice's share of ∫ ω (n·ω) dω over its open arc [h0, h1] (midpoint
// rule; the slice's measure is |sin θ| dθ): the bent normal's sum.
fn open_moment(h0: f32, h1: f32, v: vec3<f32>, sl: Slice) -> vec3<f32> {
    var m = vec2<f32>(0.0);
    let dh = (h1 - h0) / f32(BENT_POINTS);
    for (var i = 0u; i < BENT_POINTS; i++) {
        let th = h0 + (f32(i) + 0.5) * dh;
        m += vec2<f32>(cos(th), sin(th)) * (cos(th - sl.g) * abs(sin(th)));
    }
    return (v * m.x + sl.ortho * m.y) * (sl.nlen * dh);
}

// The visibility bitmask (Therrien, Levesque & Gilet 2023): with a
// thickness T (`lighting.ao.thickness_m`, uniform params.y > 0), a slice's
// half-disk [γ − π/2, γ + π/2] is cut into 32 sectors, and each sample
// blocks the sectors between its front (the G-buffer point) and its back
// (that point T farther along its view ray) instead of everything below
// its horizon: a thin pole occludes its own width, not the sky behind it.

// The cosine-weighted measure of the slice from 0 to θ (signed), the
// integral gtao's arc() takes on each side.
fn cum(th: f32, g: f32) -> f32 {
    return select(-arc(th, g), arc(th, g), th >= 0.0);
}

// The sectors [i0, i1) of 32 as bits.
fn sector_bits(u0: f32, u1: f32) -> u32 {
    let i0 = u32(clamp(floor(min(u0, u1) * 32.0 + 0.5), 0.0, 32.0));
    let i1 = u32(clamp(floor(max(u0, u1) * 32.0 + 0.5), 0.0, 32.0));
    if i1 <= i0 {
        return 0u;
    }
    let ones = select((1u << (i1 - i0)) - 1u, 0xffffffffu, i1 - i0 == 32u);
    return ones << i0;
}

// The angle from v towards the slice's ortho of an offset's projection on
// the slice's plane.
fn plane_angle(d: vec3<f32>, v: vec3<f32>, sl: Slice) -> f32 {
    return atan2(dot(d, sl.ortho), dot(d, v));
}

// Where a point put into the slice lies across its half-disk, 0 … 1.
fn sector_of(ds: vec3<f32>, v: vec3<f32>, sl: Slice) -> f32 {
    return (plane_angle(ds, v, sl) - (sl.g - HALF_PI)) / PI;
}

// A slice's open measure (× |n_p|) and the bent normal's sum over its
// unset sectors; S3HO's sum over the set ones.
fn bitmask_slice(bits: u32, v: vec3<f32>, sl: Slice) -> vec4<f32> {
    var open = 0.0;
    var m = vec3<f32>(0.0);
    let d = PI / 32.0;
    for (var k = 0u; k < 32u; k++) {
        let lo = sl.g - HALF_PI + f32(k) * d;
        let th = lo + 0.5 * d;
        let dir = v * cos(th) + sl.ortho * sin(th);
        if (bits & (1u << k)) == 0u {
            open += cum(lo + d, sl.g) - cum(lo, sl.g);
            m += dir * (cos(th - sl.g) * abs(sin(th)) * d);
        } else if radiance_on() {
            let e = sky_radiance(dir) * ((cum(lo + d, sl.g) - cum(lo, sl.g)) * sl.nlen);
            sh_sum[0] += e.x;
            sh_sum[1] += e.y;
            sh_sum[2] += e.z;
        } else if sh_on() {
            let y = sh8(dir);
            let wt = cos(th - sl.g) * abs(sin(th)) * sl.nlen * d;
            for (var c = 0u; c < 8u; c++) {
                sh_sum[c] += y[c] * wt;
            }
        }
    }
    return vec4<f32>(m * sl.nlen, open * sl.nlen);
}

// How gtao and hbao walk a pixel's slices: their number, the samples per
// side, the slices' angular offset (over a 4 × 4 pixel pattern, turned by
// the golden ratio per frame of a run) and the samples' jitter.
struct SliceWalk {
    slices: u32,
    steps: u32,
    rot: f32,
    jit: f32,
}

fn slice_walk(px: vec2<i32>) -> SliceWalk {
    let rot = fract((f32(bayer4(vec2<u32>(px))) + 0.5) / 16.0 + 0.618034 * f32(u.q2.y));
    return SliceWalk(max(u.q.y, 1u), max(u.q.z, 1u), rot, ign(vec2<u32>(px)));
}

fn gtao(px: vec2<i32>, p: vec3<f32>, n: vec3<f32>, r_px: f32) -> vec4<f32> {
    let radius = u.params.x;
    let v = normalize(u.eye.xyz - p);
    let walk = slice_walk(px);
    let thickness = u.params.y;
    var vis = 0.0;
    var norm = 0.0;
    var bent = vec3<f32>(0.0);
    for (var s = 0u; s < walk.slices; s++) {
        let sl = slice_at(s, walk.slices, walk.rot, v, n);
        if !sl.ok {
            continue;
        }
        let ortho = sl.ortho;
        let nlen = sl.nlen;
        let g = sl.g;
        var h = array<f32, 2>(g - HALF_PI, g + HALF_PI);
        var bits = 0u;
        for (var side = 0; side < 2; side++) {
            let sgn = f32(2 * side - 1);
            let low = cos(h[side]);
            // The slice's line in the tangent plane on this side.
            let tangent = v * low + ortho * sin(h[side]);
            var best = low;
            for (var k = 0u; k < walk.steps; k++) {
                let smp = slice_sample(p, px, sl, sgn, (f32(k) + walk.jit) / f32(walk.steps), r_px);
                if smp.stop {
                    break;
                }
                if !smp.ok {
                    continue;
                }
                let delta = smp.delta;
                let len = length(delta);
                let ds = into_slice(delta, n, tangent, sl);
                if thickness > 0.0 {
                    if len < radius {
                        // The back's angle: the front's (put into the
                        // slice) moved by what T along the view ray turns
                        // the point as the slice's plane sees it.
                        let back = delta + normalize(p + delta - u.eye.xyz) * thickness;
                        let turn = plane_angle(back, v, sl) - plane_angle(delta, v, sl);
                        let uf = sector_of(ds, v, sl);
                        bits |= sector_bits(uf, uf + turn / PI);
                    }
                    continue;
                }
                let wgt = clamp((radius - len) / (FALLOFF * radius), 0.0, 1.0);
                best = max(best, mix(low, dot(ds, v) / max(length(ds), 1e-9), wgt));
            }
            let ang = acos(clamp(best, -1.0, 1.0));
            if side == 0 {
                h[0] = max(-ang, g - HALF_PI);
            } else {
                h[1] = min(ang, g + HALF_PI);
            }
        }
        norm += nlen * (cos(g) + g * sin(g));
        if thickness > 0.0 {
            let b = bitmask_slice(bits, v, sl);
            vis += b.w;
            bent += b.xyz;
            continue;
        }
        vis += nlen * (arc(h[0], g) + arc(h[1], g));
        if radiance_on() {
            add_radiance_arc(g - HALF_PI, h[0], nlen * (arc(g - HALF_PI, g) - arc(h[0], g)), v, sl);
            add_radiance_arc(h[1], g + HALF_PI, nlen * (arc(g + HALF_PI, g) - arc(h[1], g)), v, sl);
        } else if sh_on() {
            // S3HO's share of the slice: its blocked arcs, [γ − π/2, h₀]
            // and [h₁, γ + π/2] (each on one side of the view vector,
            // where |sin θ| is smooth), so that an open slice adds nothing
            // however few the slices.
            for (var side = 0; side < 2; side++) {
                let lo = select(g - HALF_PI, h[1], side == 1);
                let hi = select(h[0], g + HALF_PI, side == 1);
                let ds = (hi - lo) / f32(BENT_POINTS / 2u);
                for (var i = 0u; i < BENT_POINTS / 2u; i++) {
                    let th = lo + (f32(i) + 0.5) * ds;
                    let y = sh8(v * cos(th) + ortho * sin(th));
                    let wt = cos(th - g) * abs(sin(th)) * nlen * ds;
                    for (var c = 0u; c < 8u; c++) {
                        sh_sum[c] += y[c] * wt;
                    }
                }
            }
        }
        bent += open_moment(h[0], h[1], v, sl);
    }
    var ao = 1.0;
    if norm > 1e-6 {
        ao = clamp(vis / norm, 0.0, 1.0);
        for (var i = 0u; i < 8u; i++) {
            sh_sum[i] *= PI / norm;
        }
    }
    var b = n;
    if dot(bent, bent) > 1e-12 {
        b = normalize(bent);
    }
    return vec4<f32>(b, ao);
}

fn ssao(px: vec2<i32>, p: vec3<f32>, n: vec3<f32>, dist: f32) -> vec4<f32> {
    let radius = u.params.x;
    let count = max(u.q.w, 1u);
    // A tangent frame about n, rotated per pixel.
    let up = select(vec3<f32>(0.0, 1.0, 0.0), vec3<f32>(1.0, 0.0, 0.0), abs(n.y) > 0.9);
    let t0 = normalize(cross(up, n));
    let b0 = cross(n, t0);
    let rot = 2.0 * PI * ign(vec2<u32>(px));
    let t = t0 * cos(rot) + b0 * sin(rot);
    let b = cross(n, t);
    let start = p + n * (1e-3 * radius);
    let eye_dist = dist;
    // Stratified over a golden-angle spiral: sample i at cos²θ = 1 − u_i.
    var open = 0.0;
    var bent = vec3<f32>(0.0);
    for (var i = 0u; i < count; i++) {
        let u1 = (f32(i) + 0.5) / f32(count);
        let r = sqrt(u1);
        let phi = f32(i) * 2.39996323;
        let d = t * (r * cos(phi)) + b * (r * sin(phi)) + n * sqrt(max(1.0 - u1, 0.0));
        // Lengths from 0.1 R to R, denser near p; the order decorrelated
        // from the direction's by a second sequence.
        let s = fract(f32(i) * 0.618034 + 0.5 * ign(vec2<u32>(px) + vec2<u32>(7u, 13u)));
        let x = start + d * (radius * mix(0.1, 1.0, s * s));
        let c = project(x);
        let q = vec2<i32>(floor(c.xy));
        var blocked = false;
        if on_screen(q) && c.z > 0.0 && textureLoad(g_material, q, 0).x != 0u {
            let surf = textureLoad(g_distance, q, 0).x;
            let xd = length(x - u.eye.xyz);
            blocked = surf < xd - 1e-3 * radius && abs(eye_dist - surf) < radius;
        }
        if !blocked {
            open += 1.0;
            bent += d;
        }
    }
    var bn = n;
    if dot(bent, bent) > 1e-12 {
        bn = normalize(bent);
    }
    return vec4<f32>(bn, open / f32(count));
}

@compute @workgroup_size(8, 8)
fn occlude(@builtin(global_invocation_id) gid: vec3<u32>) {
    let px = vec2<i32>(gid.xy);
    if !on_screen(px) {
        return;
    }
    if textureLoad(g_material, px, 0).x == 0u {
        textureStore(ao_out, px, vec4<f32>(0.0, 0.0, 0.0, 1.0));
        if sh_on() {
            textureStore(sh_out, px, vec4<u32>(0u));
        }
        return;
    }
    let dist = textureLoad(g_distance, px, 0).x;
    let n = normalize(textureLoad(g_normal, px, 0).xyz);
    let ray = ray_at(vec2<f32>(px) + 0.5);
    let p = u.eye.xyz + ray * dist;
    // R in pixels at this depth.
    let z = max(dist * dot(ray, u.forward.xyz), 1e-6);
    let r_px = u.params.x * 0.5 * u.up.w / (u.eye.w * z);
    if r_px < 1.0 {
        // The radius is below a pixel: nothing the G-buffer resolves.
        textureStore(ao_out, px, vec4<f32>(n, 1.0));
        if sh_on() {
            textureStore(sh_out, px, vec4<u32>(0u));
        }
        return;
    }
    if u.q.x == 1u {
        textureStore(ao_out, px, gtao(px, p, n, r_px));
        if sh_on() {
            textureStore(sh_out, px, pack_sh(sh_sum));
        }
    } else if u.q.x == 2u {
        textureStore(ao_out, px, hbao(px, p, n, r_px));
    } else {
        textureStore(ao_out, px, ssao(px, p, n, dist));
    }
}

@compute @workgroup_size(8, 8)
fn blur(@builtin(global_invocation_id) gid: vec3<u32>) {
    let px = vec2<i32>(gid.xy);
    if !on_screen(px) {
        return;
    }
    let c = textureLoad(ao_in, px, 0);
    if textureLoad(g_material, px, 0).x == 0u {
        textureStore(ao_out, px, c);
        if sh_on() {
            textureStore(sh_out, px, textureLoad(sh_in, px, 0));
        }
        return;
    }
    let dist = textureLoad(g_distance, px, 0).x;
    let n = normalize(textureLoad(g_normal, px, 0).xyz);
    let p = position(px);
    let r = i32(u.q2.x);
    var acc = vec4<f32>(0.0);
    var wsum = 0.0;
    for (var dy = -r; dy <= r; dy++) {
        for (var dx = -r; dx <= r; dx++) {
            let q = px + vec2<i32>(dx, dy);
            if !on_screen(q) || textureLoad(g_material, q, 0).x == 0u {
                continue;
            }
            let nq = textureLoad(g_normal, q, 0).xyz;
            if dot(nq, n) < 0.9 || abs(dot(position(q) - p, n)) > 0.02 * dist {
                continue;
            }
            acc += textureLoad(ao_in, q, 0);
            wsum += 1.0;
            if sh_on() {
                add_packed(textureLoad(sh_in, q, 0));
            }
        }
    }
    if wsum < 0.5 {
        textureStore(ao_out, px, c);
        if sh_on() {
            textureStore(sh_out, px, textureLoad(sh_in, px, 0));
        }
        return;
    }
    if sh_on() {
        for (var i = 0u; i < 8u; i++) {
            sh_sum[i] /= wsum;
        }
        textureStore(sh_out, px, pack_sh(sh_sum));
    }
    let m = acc / wsum;
    var b = n;
    if dot(m.xyz, m.xyz) > 1e-12 {
        b = normalize(m.xyz);
    }
    textureStore(ao_out, px, vec4<f32>(b, m.w));
}
