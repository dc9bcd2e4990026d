// The lighting of a world frame (passes/lighting/shade.rs): every pixel the
// G-buffer covers gets the radiance it sends to the camera, in cd/m²:
//
//   L = [Σ_lights f·E·(n·l)·shadow·T_fog,light + diffuse sky + specular sky
//        + emission] · T_fog,view · T_air + L_air
//
// * the Sun and the Moon: directional lights of the frame's transmitted
//   illuminance E (lux), Lambert + GGX (height-correlated Smith, Schlick
//   Fresnel); fully rough dielectrics are Lambertian. Shadows from the
//   cascaded maps: `off` (one texel), `pcf` (3×3 bilinear comparisons) or
//   `soft` (a blocker search, then a disk filter as wide as the light's
//   angular diameter × the blocker–receiver distance);
// * the sky: Σ_cells max(0, n·M_k) · V_k(p) (env.rs), V_k from the k-th
//   visibility map — the world hides the sky it covers; specular from the
//   prefiltered equirect maps × the split-sum BRDF × the visibility of the
//   cell nearest the reflected ray. Three passes: `sky` (each pixel's
//   interleaved set of cells and the aureoles' cells), `gather`
//   (sky_gather.wgsl: the N × N block's sets, the aureoles' light from the
//   pixels that see as much of it), then `shade`, which widens the block's
//   mean (`widen`, sky_gather.wgsl) where the sets disagree only by their
//   quadrature;
// * fog (world.md): light reaching height y: exp(−σt (top − y) / sin h);
//   sky light: exp(−σt (top − y)) (the vertical path, an approximation);
//   the view ray: exp(−σt × its length inside the fog);
// * aerial perspective: in-scattering L_air and transmittance T_air of the
//   air between the eye and the point, from a froxel table the sky model
//   computes (frame/lights.rs).
// * cloud shadows: the Sun's and the Moon's light × the clouds'
//   transmittance towards them (`cloud_transmittance`);
// * light shafts (godrays.wgsl, when the pass runs): the fog's
//   in-scattering along the view ray, marched at a reduced resolution, is
//   gathered here by depth over the interleaved N × N block and added
//   after the view ray's fog extinction.
// * ambient occlusion (ao.wgsl, when the pass ran): the sky's diffuse
//   irradiance E × min(1, AO / (Y(E) / Y(E_open))), E_open the cells'
//   irradiance with nothing in the way — the smaller of the visibility
//   maps' visibility and AO (passes/lighting/ao.rs); never the Sun or Moon.
//   With `lighting.sky.occlusion` `ao` the cells are open (no maps) and
//   E = E_open × AO, or with S3HO (`lighting.ao.sh`, only then) E_open
//   less the light the pixel's blockers take (`s3ho_blocked`): the ao
//   pass's integral of the sky's radiance over the blocked directions
//   (`sh_sky` `radiance`), or Σ L_lm B_lm, the sky's radiance
//   coefficients weighted by the blocked part of the pixel's
//   cosine-weighted visibility (`sh2`).
// Sky pixels are not written: they stay what the sky passes rendered.
// common.wgsl (the uniforms, the view ray) is prepended.

struct MaterialGpu {
    base_color: vec4<f32>,
    emissive_texture: vec4<f32>,
    metallic_roughness: vec4<f32>,
}

struct CellPart {
    // xyz: ∫ L ω dω of the red channel over the part; w: the step of its
    // rays across the cell's map (right) per metre along the cell's
    // direction.
    r: vec4<f32>,
    // w: the step (up).
    g: vec4<f32>,
    b: vec4<f32>,
    // xy: the part's extent (right, up) in the same units (0, 0: one part
    // a cell).
    extent: vec4<f32>,
}

@group(0) @binding(1) var g_distance: texture_2d<f32>;
@group(0) @binding(2) var g_normal: texture_2d<f32>;
@group(0) @binding(3) var g_base: texture_2d<f32>;
@group(0) @binding(4) var g_material: texture_2d<u32>;
@group(0) @binding(5) var out_tex: texture_storage_2d<rgba32float, write>;
@group(0) @binding(6) var<storage, read> materials: array<MaterialGpu>;
@group(0) @binding(7) var<storage, read> cells: array<SkyCell>;
@group(0) @binding(8) var<storage, read> cell_view: array<mat4x4<f32>>;
@group(0) @binding(9) var visibility: texture_depth_2d_array;
@group(0) @binding(10) var shadows: texture_depth_2d_array;
@group(0) @binding(11) var cmp_sampler: sampler_comparison;
@group(0) @binding(12) var specular: texture_2d_array<f32>;
@group(0) @binding(13) var brdf: texture_2d<f32>;
@group(0) @binding(14) var lin: sampler;
@group(0) @binding(15) var air_in: texture_3d<f32>;
@group(0) @binding(16) var air_t: texture_3d<f32>;
@group(0) @binding(17) var<storage, read> parts: array<CellPart>;
// The sky pass writes, the shade pass reads: per pixel the sky's diffuse
// irradiance (rgb) and the open fraction of the sky (a), and the
// visibility of the cell nearest the reflected ray.
@group(1) @binding(0) var sky_e_out: texture_storage_2d<rgba32float, write>;
@group(1) @binding(1) var sky_s_out: texture_storage_2d<rgba32float, write>;
@group(1) @binding(2) var sky_e_in: texture_2d<f32>;
@group(1) @binding(3) var sky_s_in: texture_2d<f32>;
@group(1) @binding(10) var sky_v_in: texture_2d<f32>;
// The godrays pass's in-scattering (rgb, cd/m²), at 1 / shaft_q.z of the
// resolution.
@group(1) @binding(4) var shafts_in: texture_2d<f32>;
// The clouds' transmittance towards the Sun (r) and the Moon (g) over the
// ground plane (cloud_shadow.rs).
@group(1) @binding(8) var cloud_t: texture_2d<f32>;
// The ao pass's bent normal (xyz) and AO (w); a 1 × 1 stand-in when it
// did not run.
@group(1) @binding(5) var ao_in: texture_2d<f32>;
// Its S3HO image: B_1,-1 … B_2,2 (the blocked transfer) as f16 pairs
// (ao.wgsl); a 1 × 1 stand-in without it.
@group(1) @binding(9) var sh_in: texture_2d<u32>;
// For the ssr pass (ssr.wgsl), when it runs (else 1 × 1 stand-ins, not
// written): the sky's prefiltered specular term as it reaches the camera
// (rgb, cd/m²) and its split-sum weight (F0·A + B) × the transmittances
// to the camera (rgb).
@group(1) @binding(6) var spec_env_out: texture_storage_2d<rgba32float, write>;
@group(1) @binding(7) var spec_w_out: texture_storage_2d<rgba32float, write>;

const SPECULAR_LEVELS: f32 = 5.0;

// The receiver's own plane in a light map: its depth (map units) changes
// by dot(o, g) at an offset of o texels from the receiver, so that a
// lookup there compares against the plane and never finds the receiver as
// its own blocker (receiver-plane depth bias). m: the map's matrix (rows:
// right / half, up / half), ld: towards the light.
fn plane_gradient(m: mat4x4<f32>, n: vec3<f32>, ld: vec3<f32>, texel: f32, depth_m: f32, min_nl: f32) -> vec2<f32> {
    let right = normalize(vec3<f32>(m[0].x, m[1].x, m[2].x));
    let up = normalize(vec3<f32>(m[0].y, m[1].y, m[2].y));
    let nl = max(dot(n, ld), min_nl);
    // Texel offsets run along +right and −up (image rows go down).
    return vec2<f32>(dot(n, right), -dot(n, up)) * texel / (nl * depth_m);
}

// A per-pixel rotation for the disk samples (interleaved gradient noise,
// Jimenez 2014).
fn rotation(px: vec2<u32>) -> f32 {
    // Turned per frame of a temporal run (5.588238 px: Jimenez's step).
    let f = vec2<f32>(px) + 5.588238 * u.jitter.z;
    return 2.0 * PI * fract(52.9829189 * fract(0.06711056 * f.x + 0.00583715 * f.y));
}

// The i-th of n points spread evenly over the unit disk (Vogel's spiral).
fn disk(i: u32, n: u32, rot: f32) -> vec2<f32> {
    let r = sqrt((f32(i) + 0.5) / f32(n));
    let a = f32(i) * 2.39996323 + rot;
    return r * vec2<f32>(cos(a), sin(a));
}

// Shadow of a directional light (cascades first..first+count) at p.
fn shadow(first: u32, count: u32, p: vec3<f32>, n: vec3<f32>, ld: vec3<f32>, view_depth: f32, tan_r: f32, px: vec2<u32>) -> f32 {
    let layer = cascade_layer(first, count, view_depth);
    let info = u.cascade_info[layer];
    let texel = info.x;
    let depth_m = info.y;
    let q = p + n * (1.5 * texel);
    let s = u.cascade[layer] * vec4<f32>(q, 1.0);
    let uv = light_uv(s);
    if !inside(uv) {
        return 1.0;
    }
    let size = vec2<f32>(textureDimensions(shadows));
    let z = s.z - (1.0 * texel) / depth_m;
    // The receiver's own plane tilts away in the map: at a distance x (m)
    // across the map it lies x·tan(n, l) deeper or shallower. Lookups x
    // away are biased by that much, so a wide filter does not find the
    // receiver itself as its blocker.
    let g = plane_gradient(u.cascade[layer], n, ld, texel, depth_m, 0.05);
    let mode = u.counts.w;
    if mode == 0u {
        let t = vec2<i32>(clamp(uv * size, vec2<f32>(0.0), size - 1.0));
        return select(0.0, 1.0, z <= textureLoad(shadows, t, i32(layer), 0));
    }
    if mode == 1u {
        var sum = 0.0;
        for (var dy = -1; dy <= 1; dy++) {
            for (var dx = -1; dx <= 1; dx++) {
                let q2 = vec2<f32>(f32(dx), f32(dy));
                let o = q2 / size;
                sum += textureSampleCompareLevel(shadows, cmp_sampler, uv + o, i32(layer), z + dot(q2, g));
            }
        }
        return sum / 9.0;
    }
    // Soft: the blocker search over the largest penumbra this receiver can
    // have (its depth below the map's top × tan r), then the disk filter.
    let rot = rotation(px);
    let search_m = max(s.z * depth_m * tan_r, texel);
    let search = min(search_m / texel, 64.0);
    var blockers = 0.0;
    var zb = 0.0;
    for (var i = 0u; i < 16u; i++) {
        let q2 = disk(i, 16u, rot) * search;
        let o = q2 / size;
        let t = vec2<i32>(clamp((uv + o) * size, vec2<f32>(0.0), size - 1.0));
        let d = textureLoad(shadows, t, i32(layer), 0);
        if d < z + dot(q2, g) - 2e-4 {
            blockers += 1.0;
            zb += d;
        }
    }
    if blockers == 0.0 {
        return 1.0;
    }
    zb = zb / blockers;
    // Penumbra half-width, texels: (receiver − blocker distance) × tan r.
    let radius = max((z - zb) * depth_m * tan_r / texel, 0.5);
    var sum = 0.0;
    let taps = 32u;
    for (var i = 0u; i < taps; i++) {
        let q2 = disk(i, taps, rot) * radius;
        let o = q2 / size;
        sum += textureSampleCompareLevel(shadows, cmp_sampler, uv + o, i32(layer), z + dot(q2, g));
    }
    return sum / f32(taps);
}

struct Surface {
    n: vec3<f32>,
    v: vec3<f32>,
    base: vec3<f32>,
    metallic: f32,
    roughness: f32,
}

fn lambertian(s: Surface) -> bool {
    return s.metallic <= 0.0 && s.roughness >= 1.0;
}

fn f0_of(s: Surface) -> vec3<f32> {
    return mix(vec3<f32>(0.04), s.base, s.metallic);
}

// BRDF × cos for a directional light from l.
fn direct(s: Surface, l: vec3<f32>) -> vec3<f32> {
    let nl = dot(s.n, l);
    if nl <= 0.0 {
        return vec3<f32>(0.0);
    }
    let diffuse = s.base * (1.0 - s.metallic) / PI;
    if lambertian(s) {
        return diffuse * nl;
    }
    let h = normalize(s.v + l);
    let nv = max(dot(s.n, s.v), 1e-4);
    let nh = max(dot(s.n, h), 0.0);
    let vh = max(dot(s.v, h), 0.0);
    let a = max(s.roughness * s.roughness, 2e-3);
    let a2 = a * a;
    let dd = nh * nh * (a2 - 1.0) + 1.0;
    let d = a2 / (PI * dd * dd);
    let vis = 0.5 / (nl * sqrt(nv * nv * (1.0 - a2) + a2) + nv * sqrt(nl * nl * (1.0 - a2) + a2));
    let f = f0_of(s) + (1.0 - f0_of(s)) * pow(1.0 - vh, 5.0);
    return ((1.0 - f) * diffuse + d * vis * f) * nl;
}

// A directional light (towards ld; rgb: illuminance, w: tan of its
// angular radius) through the fog to the surface, with its shadow from
// the cascades first..first+count (none when count is 0).
fn directional(s: Surface, p: vec3<f32>, ld: vec3<f32>, rgb: vec4<f32>, first: u32, count: u32, view_depth: f32, depth_in_fog: f32, px: vec2<u32>) -> vec3<f32> {
    var e = rgb.rgb;
    if u.fog.z > 0.5 {
        e = e * select(0.0, exp(-u.fog.x * depth_in_fog / max(ld.y, 1e-4)), ld.y > 0.0 || depth_in_fog == 0.0);
    }
    let f = direct(s, ld);
    if all(f <= vec3<f32>(0.0)) {
        return vec3<f32>(0.0);
    }
    var vis = 1.0;
    if count > 0u {
        vis = shadow(first, count, p, s.n, ld, view_depth, rgb.w, px);
    }
    return f * e * vis;
}

// The clouds' transmittance towards the light `ld` of channel k (0 the
// Sun, 1 the Moon) from p: the cloud-shadow map, bilinear, where p's ray
// towards the light crosses y = 0 (the clouds lie far above any world);
// beyond the map, its mean (the texture's extra row n).
fn cloud_transmittance(p: vec3<f32>, ld: vec3<f32>, k: u32) -> f32 {
    let n = u.clouds.w;
    if n < 0.5 {
        return 1.0;
    }
    let q = p.xz - ld.xz * (p.y / max(ld.y, 0.02));
    let uv = (q - u.clouds.xy) * u.clouds.z;
    if any(uv < vec2<f32>(0.0)) || any(uv > vec2<f32>(1.0)) {
        return textureLoad(cloud_t, vec2<i32>(0, i32(n)), 0)[k];
    }
    let st = uv * n - 0.5;
    let i0 = floor(st);
    let f = clamp(st - i0, vec2<f32>(0.0), vec2<f32>(1.0));
    let top = vec2<f32>(n - 1.0);
    let a = vec2<i32>(clamp(i0, vec2<f32>(0.0), top));
    let b = vec2<i32>(clamp(i0 + 1.0, vec2<f32>(0.0), top));
    let t00 = textureLoad(cloud_t, vec2<i32>(a.x, a.y), 0)[k];
    let t10 = textureLoad(cloud_t, vec2<i32>(b.x, a.y), 0)[k];
    let t01 = textureLoad(cloud_t, vec2<i32>(a.x, b.y), 0)[k];
    let t11 = textureLoad(cloud_t, vec2<i32>(b.x, b.y), 0)[k];
    return mix(mix(t00, t10, f.x), mix(t01, t11, f.x), f.y);
}

fn equirect_uv(d: vec3<f32>) -> vec2<f32> {
    let az = atan2(d.x, -d.z);
    let u0 = az / (2.0 * PI);
    return vec2<f32>(u0 - floor(u0), acos(clamp(d.y, -1.0, 1.0)) / PI);
}

fn prefiltered(r: vec3<f32>, roughness: f32) -> vec3<f32> {
    let level = clamp(roughness, 0.0, 1.0) * (SPECULAR_LEVELS - 1.0);
    let l0 = floor(level);
    let l1 = min(l0 + 1.0, SPECULAR_LEVELS - 1.0);
    let uv = equirect_uv(r);
    let a = textureSampleLevel(specular, lin, uv, i32(l0), 0.0).rgb;
    let b = textureSampleLevel(specular, lin, uv, i32(l1), 0.0).rgb;
    return mix(a, b, level - l0) * u.scales.x;
}

// Length of the segment from the eye to p inside the fog (y ≤ top).
fn fog_length(p: vec3<f32>) -> f32 {
    let top = u.fog.y;
    let e = u.eye.xyz;
    let len = length(p - e);
    let lo = min(e.y, p.y);
    let hi = max(e.y, p.y);
    if lo >= top {
        return 0.0;
    }
    if hi <= top || hi - lo < 1e-6 {
        return len;
    }
    return len * (top - lo) / (hi - lo);
}

// The sky's irradiance on normal n were nothing in the way: the pixel's
// set of cells and the aureoles' (as the sky pass sums them).
fn open_irradiance(n: vec3<f32>, g: vec2<u32>) -> vec3<f32> {
    let side = u.flags.z;
    let cell_set = (g.x % side) + (g.y % side) * side;
    let per = u.counts.x;
    let aureole_first = side * side * per;
    var e = vec3<f32>(0.0);
    for (var j = 0u; j < per + u.flags.w; j++) {
        var k = cell_set * per + j;
        if j >= per {
            k = aureole_first + j - per;
        }
        e += cell_whole(cells[k], n);
    }
    return e;
}

// S3HO: the sky's irradiance that the pixel's blockers take, per channel:
// with `sh_sky` `radiance` (u.occlusion.y 2) the ao pass's own integral of
// the sky's radiance over the blocked directions, E_b (three f32), else
// Σ L_lm B_lm, B the blocked part of the cosine-weighted visibility
// (ao.wgsl), B_00 = Y_00 π (1 − AO).
fn s3ho_blocked(px: vec2<i32>, ao: f32) -> vec3<f32> {
    let packed = textureLoad(sh_in, px, 0);
    if u.occlusion.y == 2u {
        return vec3<f32>(bitcast<f32>(packed.x), bitcast<f32>(packed.y), bitcast<f32>(packed.z));
    }
    var blocked = u.sky_sh[0].rgb * (0.282095 * PI * (1.0 - ao));
    for (var i = 0u; i < 4u; i++) {
        let b = unpack2x16float(packed[i]);
        blocked += u.sky_sh[1u + 2u * i].rgb * b.x + u.sky_sh[2u + 2u * i].rgb * b.y;
    }
    return blocked;
}

// What the G-buffer holds at a pixel: whether a surface covers it (inside
// the image), its distance, unit normal, view ray and point.
struct SurfaceAt {
    covered: bool,
    dist: f32,
    n: vec3<f32>,
    ray: vec3<f32>,
    p: vec3<f32>,
}

fn surface_at(g: vec2<u32>) -> SurfaceAt {
    let w = u32(u.right.w);
    let h = u32(u.up.w);
    var sp: SurfaceAt;
    sp.covered = false;
    if g.x >= w || g.y >= h {
        return sp;
    }
    let px = vec2<i32>(g);
    if textureLoad(g_material, px, 0).x == 0u {
        return sp;
    }
    sp.covered = true;
    sp.dist = textureLoad(g_distance, px, 0).x;
    sp.n = normalize(textureLoad(g_normal, px, 0).xyz);
    sp.ray = pixel_ray(px, w, h);
    sp.p = u.eye.xyz + sp.ray * sp.dist;
    return sp;
}

// The sky pass: this pixel's set of cells (its place in the N × N block),
// each cell's first moment seen through its visibility map.
@compute @workgroup_size(8, 8)
fn sky(@builtin(global_invocation_id) gid: vec3<u32>) {
    let sp = surface_at(gid.xy);
    if !sp.covered {
        return;
    }
    let px = vec2<i32>(gid.xy);
    let p = sp.p;
    let n = sp.n;
    let r = reflect(sp.ray, n);
    let side = u.flags.z;
    let cell_set = (gid.x % side) + (gid.y % side) * side;
    let per = u.counts.x;
    // The aureoles' cells follow the sets' (env.rs); every pixel sums them.
    let aureole_first = side * side * per;
    let rot = rotation(gid.xy);
    var e = vec3<f32>(0.0);
    // The aureoles' light, which every pixel sums whole: kept apart so that
    // the gather over the block (`gather`) does not carry it across the
    // edge of the Sun's shadow, nor `widen` at all.
    var e_aureole = vec3<f32>(0.0);
    var best = -2.0;
    var spec_vis = 1.0;
    var open_sum = 0.0;
    var open_all = 0.0;
    for (var j = 0u; j < per + u.flags.w; j++) {
        var k = cell_set * per + j;
        if j >= per {
            k = aureole_first + j - per;
        }
        let c = cells[k];
        let upper = c.dir.y > 0.0;
        let near_r = dot(r, c.dir.xyz);
        // A cell wholly behind the surface gives no light (its cone lies
        // beyond the surface's horizon).
        let behind = dot(n, c.dir.xyz) < -c.parts.z / sqrt(1.0 + c.parts.z * c.parts.z);
        if behind && !upper && near_r <= best {
            continue;
        }
        let cl = cell_light(k, p, n, rot);
        let vis = cl.a;
        if j >= per {
            e_aureole += cl.rgb;
        } else {
            e += cl.rgb;
        }
        if near_r > best {
            best = near_r;
            spec_vis = vis;
        }
        if upper {
            open_sum += vis * c.r.w;
            open_all += c.r.w;
        }
    }
    var open = 1.0;
    if open_all > 0.0 {
        open = open_sum / open_all;
    }
    textureStore(sky_e_out, px, vec4<f32>(e, open));
    textureStore(sky_s_out, px, vec4<f32>(e_aureole, spec_vis));
}


@compute @workgroup_size(8, 8)
fn shade(@builtin(global_invocation_id) gid: vec3<u32>) {
    let w = u32(u.right.w);
    let h = u32(u.up.w);
    if gid.x >= w || gid.y >= h {
        return;
    }
    let px = vec2<i32>(gid.xy);
    let id = textureLoad(g_material, px, 0).x;
    if id == 0u {
        return;
    }
    let m = materials[id - 1u];
    let dist = textureLoad(g_distance, px, 0).x;
    let nr = textureLoad(g_normal, px, 0);
    let bm = textureLoad(g_base, px, 0);
    let ray = pixel_ray(px, w, h);
    let p = u.eye.xyz + ray * dist;
    var s: Surface;
    s.n = normalize(nr.xyz);
    s.v = -ray;
    s.roughness = nr.w;
    s.base = bm.rgb;
    s.metallic = bm.a;
    let view_depth = dist * dot(ray, u.forward.xyz);
    let fog_on = u.fog.z > 0.5;
    let depth_in_fog = max(u.fog.y - p.y, 0.0);
    var l = vec3<f32>(0.0);
    // The Sun and the Moon.
    if u.sun_dir.w > 0.5 {
        l += directional(s, p, u.sun_dir.xyz, u.sun_rgb, 0u, u.counts.y, view_depth, depth_in_fog, gid.xy)
            * cloud_transmittance(p, u.sun_dir.xyz, 0u);
    }
    if u.moon_dir.w > 0.5 {
        l += directional(s, p, u.moon_dir.xyz, u.moon_rgb, u.flags.y, u.counts.z, view_depth, depth_in_fog, gid.xy)
            * cloud_transmittance(p, u.moon_dir.xyz, 1u);
    }
    // The sky: the irradiance of the interleaved sets, averaged over the
    // N × N block around the pixel where the surface continues.
    var open = 1.0;
    var spec_env = vec3<f32>(0.0);
    var spec_w = vec3<f32>(0.0);
    if u.flags.x == 1u {
        let g = textureLoad(sky_e_in, px, 0);
        let ga = textureLoad(sky_s_in, px, 0);
        var e = widen(px, p, s.n, dist, w, h, g.rgb, g.a) + ga.rgb;
        open = ga.a;
        if all(textureDimensions(ao_in) == vec2<u32>(w, h)) {
            let ao = textureLoad(ao_in, px, 0).w;
            if u.occlusion.x == 1u {
                // The cells are open: the ao pass alone occludes — AO, or
                // with S3HO (only here) the light it finds blocked (never
                // less than none: the lobes' ringing must not add light).
                if u.occlusion.y != 0u {
                    e = clamp(e - s3ho_blocked(px, ao), vec3<f32>(0.0), e);
                } else {
                    e *= ao;
                }
            } else {
                // The maps' own cosine-weighted visibility (luminance): AO
                // darkens only where it finds less.
                let y = vec3<f32>(0.2126, 0.7152, 0.0722);
                let seen = dot(e, y) / max(dot(open_irradiance(s.n, gid.xy), y), 1e-20);
                e *= min(1.0, ao / max(seen, 1e-3));
            }
        }
        let spec_vis = textureLoad(sky_v_in, px, 0).x;
        let r = reflect(ray, s.n);
        var sky_t = 1.0;
        if fog_on {
            sky_t = exp(-u.fog.x * depth_in_fog);
        }
        let diffuse = s.base * (1.0 - s.metallic) / PI;
        if lambertian(s) {
            l += diffuse * e * sky_t;
        } else {
            let nv = max(dot(s.n, s.v), 1e-4);
            let ab = textureSampleLevel(brdf, lin, vec2<f32>(nv, s.roughness), 0.0).rg;
            let f0 = f0_of(s);
            let fr = f0 + (max(vec3<f32>(1.0 - s.roughness), f0) - f0) * pow(1.0 - nv, 5.0);
            let spec = prefiltered(r, s.roughness) * (f0 * ab.x + ab.y) * spec_vis;
            l += ((1.0 - fr) * diffuse * e + spec) * sky_t;
            spec_env = spec * sky_t;
            spec_w = (f0 * ab.x + ab.y) * sky_t;
        }
    }
    l += m.emissive_texture.xyz;
    // The view ray: fog, then the air.
    var through = vec3<f32>(1.0);
    if fog_on {
        through = vec3<f32>(exp(-u.fog.x * fog_length(p)));
        l = l * through;
    }
    if u.shafts.w > 0.5 {
        // The refined image (godrays.wgsl `refine`) is the frame's own.
        var sh = textureLoad(shafts_in, px, 0);
        if u.shafts.w < 1.5 {
            sh = gather_shafts(px, dist, w, h);
        }
        l += sh.rgb;
    }
    if u.scales.z > 0.0 {
        let uvw = vec3<f32>(
            (f32(gid.x) + 0.5) / f32(w),
            (f32(gid.y) + 0.5) / f32(h),
            (sqrt(clamp(dist / u.scales.z, 0.0, 1.0)) * (u.scales.w - 1.0) + 0.5) / u.scales.w,
        );
        // The air between the eye and a surface the world closes off from
        // the sky (a room) is not lit by it: its in-scattering is scaled by
        // the surface's open fraction of the sky (an approximation).
        let ins = textureSampleLevel(air_in, lin, uvw, 0.0).rgb * u.scales.y * open;
        let tr = textureSampleLevel(air_t, lin, uvw, 0.0).rgb;
        l = l * tr + ins;
        through *= tr;
    }
    if all(textureDimensions(spec_w_out) == vec2<u32>(w, h)) {
        textureStore(spec_env_out, px, vec4<f32>(spec_env * through, 1.0));
        textureStore(spec_w_out, px, vec4<f32>(spec_w * through, 1.0));
    }
    textureStore(out_tex, px, vec4<f32>(l, 1.0));
}
