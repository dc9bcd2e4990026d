// The sky's cells seen from a surface point through their visibility
// maps (the sky pass in shade.wgsl sums them): a cell whole where its
// lookups find it open, not at all where they find it blocked, else part
// by part, each part's rays crossing the blocker on their way.
// Concatenated after common.wgsl and shade.wgsl (its bindings, `parts`,
// plane_gradient, disk).

// Lookups a part of a sky cell along the horizon takes over its extent
// (cell_light; other parts take one).
const PART_SAMPLES: u32 = 4u;
// A blocker lies on a ray's way within this fraction of its cell's radius.
const NEAR_RAY: f32 = 0.25;
// A cell in parts: the lift of p off its surface (texels) and the bias
// against the receiver's own slope (texels of its depth change).
const PARTS_LIFT: f32 = 0.5;
const SLOPE_BIAS: f32 = 1.0;

// The irradiance from part j of a cell on a surface of normal n, were it
// all visible.
fn part_light(j: u32, n: vec3<f32>) -> vec3<f32> {
    let q = parts[j];
    return max(vec3<f32>(dot(n, q.r.xyz), dot(n, q.g.xyz), dot(n, q.b.xyz)), vec3<f32>(0.0));
}

// Whether any of the four texels of map k that a bilinear lookup at
// texel position t reads shows nothing (the cleared depth, 1).
fn empty_near(k: u32, t: vec2<f32>, size: vec2<f32>) -> bool {
    let t0 = vec2<i32>(clamp(floor(t - 0.5), vec2<f32>(0.0), size - 2.0));
    var far = 0.0;
    for (var c = 0; c < 4; c++) {
        far = max(far, textureLoad(visibility, t0 + vec2<i32>(c & 1, c >> 1u), i32(k), 0));
    }
    return far >= 0.9999;
}

// The light of sky cell k at p with normal n were it all visible: n·M,
// or where the cell's cone crosses the surface's plane, its parts'
// (each clamped to the side the surface faces).
fn cell_whole(c: SkyCell, n: vec3<f32>) -> vec3<f32> {
    let sin_r = c.parts.z / sqrt(1.0 + c.parts.z * c.parts.z);
    if dot(n, c.dir.xyz) >= sin_r {
        return max(vec3<f32>(dot(n, c.r.xyz), dot(n, c.g.xyz), dot(n, c.b.xyz)), vec3<f32>(0.0));
    }
    var e = vec3<f32>(0.0);
    let first = u32(c.parts.x);
    for (var j = first; j < first + u32(c.parts.y); j++) {
        e += part_light(j, n);
    }
    return e;
}

// What a part's rays need of cell k's map: the cell, p's place in the map
// (uv, texels; depth z), the receiver plane's gradient g, the map's depth
// range (m) and texels per metre, the nearest blocker's depth, how far
// (step per metre) a blocker's direction may lie from a ray's to be on
// its way.
struct MapLookup {
    k: u32,
    uv: vec2<f32>,
    size: vec2<f32>,
    z: f32,
    g: vec2<f32>,
    depth_m: f32,
    per_m: f32,
    zb: f32,
    near: f32,
}

// The blockers among cell_light's lookups: offset (texels) and depth (0:
// open there).
var<private> tap_o: array<vec2<f32>, 20>;
var<private> tap_d: array<f32, 20>;
// Per blocker: its offset's direction across the map (unit) and its
// surface point's direction from p as a step per metre (blocker_on_way).
var<private> tap_u: array<vec2<f32>, 20>;
var<private> tap_s: array<vec2<f32>, 20>;

// The depth of the blocker on the way of a ray from p along dir (a step
// across the map per metre along the cell's direction): the nearest
// whose surface point, seen from p, lies within `near` of the ray's
// direction; else the nearest on the side of the map the ray leaves
// towards (within 60° of it); else the nearest of all. (A roof above p,
// or the side wall of a corner p stands in, must not set the parallax of
// a ray that leaves under a window's lintel.)
fn blocker_on_way(m: MapLookup, dir: vec2<f32>) -> f32 {
    var zn = 0.0;
    var zs = 0.0;
    let len_dir = length(dir);
    let beside = len_dir * (m.z - m.zb) * m.depth_m * m.per_m > 1.0;
    for (var t = 0u; t < 20u; t++) {
        if tap_d[t] > 0.0 {
            if length(tap_s[t] - dir) < m.near {
                zn = max(zn, tap_d[t]);
            }
            if beside && dot(tap_u[t], dir) > 0.5 * len_dir {
                zs = max(zs, tap_d[t]);
            }
        }
    }
    if zn > 0.0 {
        return zn;
    }
    return select(m.zb, zs, zs > 0.0);
}

// Whether the ray from p along dir is open: one bilinear depth comparison,
// against the receiver's plane, where it crosses depth zp (its blocker's).
fn ray_open(m: MapLookup, dir: vec2<f32>, zp: f32) -> f32 {
    let hp = max(m.z - zp, 0.0) * m.depth_m;
    let o = dir * (hp * m.per_m);
    var v = textureSampleCompareLevel(visibility, cmp_sampler, m.uv + o / m.size, i32(m.k), m.z + dot(o, m.g));
    if v > 0.0 && empty_near(m.k, m.uv * m.size + o, m.size) {
        // Past the edge of everything the map shows: the ray must not
        // have run beneath it on the way (out of a closed box through a
        // wall the map sees edge-on). Halfway, it lies deeper than what
        // the map shows there or it is blocked.
        for (var f = 0.25; f < 0.8; f += 0.25) {
            let th = vec2<i32>(clamp(m.uv * m.size + f * o, vec2<f32>(0.0), m.size - 1.0));
            if textureLoad(visibility, th, i32(m.k), 0) < m.z - f * hp / m.depth_m - 2e-4 {
                v = 0.0;
            }
        }
    }
    return v;
}

// The light of sky cell k at point p with normal n (rgb) and the visible
// fraction of its parts (a). Nine lookups first — along the cell's
// direction and over the disk its cone covers where it meets the top of
// the map: all open, the cell counts whole; all blocked, not at all.
// Otherwise each part's visibility is that of rays over its extent
// (ray_open), each a bilinear depth comparison where it crosses the
// blocker on its way (its parallax across the map), against the
// receiver's plane.
fn cell_light(k: u32, p: vec3<f32>, n: vec3<f32>, rot: f32) -> vec4<f32> {
    let c = cells[k];
    if u.occlusion.x == 1u {
        // No visibility maps: the ao pass occludes.
        return vec4<f32>(cell_whole(c, n), 1.0);
    }
    let m = cell_view[k];
    let texel = c.dir.w;
    // Off the surface along its normal against its own texels: less where
    // the cell is in parts (their lookups take a slope-scaled bias below),
    // since the lift moves the rays' origin.
    let lift = select(1.5, PARTS_LIFT, c.parts.y > 1.0);
    let q = p + n * (lift * texel);
    let s = m * vec4<f32>(q, 1.0);
    let uv = light_uv(s);
    if !inside(uv) || s.z < 0.0 {
        return vec4<f32>(cell_whole(c, n), 1.0);
    }
    var z = s.z - 1e-4;
    var open = textureSampleCompareLevel(visibility, cmp_sampler, uv, i32(k), z);
    if c.parts.y <= 1.0 {
        // One part: the cell's own direction, one bilinear lookup.
        return vec4<f32>(cell_whole(c, n) * open, open);
    }
    let size = vec2<f32>(textureDimensions(visibility));
    // The map's half side and depth range from its matrix's rows.
    let inv_half = length(vec3<f32>(m[0].x, m[1].x, m[2].x));
    let depth_m = 1.0 / length(vec3<f32>(m[0].z, m[1].z, m[2].z));
    let per_m = 0.5 * inv_half * size.x;
    // (A plane seen nearly edge-on would tilt through every blocker in
    // reach: its slope is capped.)
    let g = plane_gradient(m, n, c.dir.xyz, texel, depth_m, 0.3);
    z -= SLOPE_BIAS * (abs(g.x) + abs(g.y));
    // The cone's radius, texels, where it leaves the map's top.
    let search = clamp(s.z * depth_m * c.parts.z * per_m, 1.0, 64.0);
    let t0 = vec2<i32>(clamp(uv * size, vec2<f32>(0.0), size - 1.0));
    let d0 = textureLoad(visibility, t0, i32(k), 0);
    // The nearest blocker among the lookups (depth; 0: none yet).
    var zb = select(0.0, d0, d0 < z - 2e-4);
    for (var i = 0u; i < 8u; i++) {
        let o = disk(i, 8u, rot) * search;
        let t = vec2<i32>(clamp(uv * size + o, vec2<f32>(0.0), size - 1.0));
        let d = textureLoad(visibility, t, i32(k), 0);
        let below = z + dot(o, g);
        open += select(0.0, 1.0, d >= below);
        tap_o[i] = o;
        tap_d[i] = select(0.0, d, d < below - 2e-4);
        if d < below - 2e-4 {
            zb = max(zb, d);
        }
    }
    if open >= 9.0 {
        return vec4<f32>(cell_whole(c, n), 1.0);
    }
    if open <= 0.0 && c.parts.w == 0.0 {
        return vec4<f32>(0.0);
    }
    // The nearest blocker within the cone (a blocker much narrower than
    // the disk still counts through p's own texel above).
    let taps = 12u;
    for (var i = 0u; i < taps; i++) {
        let o = disk(i, taps, rot) * search;
        let t = vec2<i32>(clamp(uv * size + o, vec2<f32>(0.0), size - 1.0));
        let d = textureLoad(visibility, t, i32(k), 0);
        tap_o[8u + i] = o;
        tap_d[8u + i] = select(0.0, d, d < z + dot(o, g) - 2e-4);
        if d < z + dot(o, g) - 2e-4 {
            zb = max(zb, d);
        }
    }
    if zb <= 0.0 {
        // Only the bilinear lookup saw a blocker (an edge within a texel).
        return vec4<f32>(cell_whole(c, n) * open / 9.0, open / 9.0);
    }
    var e = vec3<f32>(0.0);
    var seen = 0.0;
    let first = u32(c.parts.x);
    let count = u32(c.parts.y);
    let seed = rot * 0.15915494;
    let look = MapLookup(k, uv, size, z, g, depth_m, per_m, zb, NEAR_RAY * c.parts.z);
    for (var t = 0u; t < 20u; t++) {
        let dist = max((z - tap_d[t]) * depth_m * per_m, 1e-6);
        tap_u[t] = tap_o[t] / max(length(tap_o[t]), 1e-6);
        tap_s[t] = tap_o[t] / dist;
    }
    for (var j = first; j < first + count; j++) {
        let part = parts[j];
        // Points spread over the part's extent, turned per pixel (so the
        // blocks' means see the part's open fraction, not only its
        // centre's): 2 × 2 strata in a cell along the horizon, where a
        // window's edge cuts the sky's steepest gradient; one elsewhere.
        let r = fract(vec2<f32>(seed, fract(seed * 1.6180339 + 0.31)) + f32(j - first) * vec2<f32>(0.7548777, 0.5698403));
        let zp = blocker_on_way(look, vec2<f32>(part.r.w, -part.g.w));
        var v = 0.0;
        let ns = select(1u, PART_SAMPLES, c.parts.w > 0.0);
        let side = select(1.0, 2.0, ns > 1u);
        for (var q = 0u; q < ns; q++) {
            let stratum = vec2<f32>(f32(q % 2u), f32(q / 2u));
            let jit = (stratum + r) / side - 0.5;
            let dir = vec2<f32>(part.r.w, -part.g.w) + jit * vec2<f32>(part.extent.x, -part.extent.y);
            v += ray_open(look, dir, zp);
        }
        v /= f32(ns);
        e += part_light(j, n) * v;
        seen += v;
    }
    return vec4<f32>(e, seen / max(f32(count), 1.0));
}
