// Himmel wgpu backend: the clouds pass (compiled after frame.wgsl, followed
// by atmo.wgsl, medium.wgsl and bilinear.wgsl). A port of skymodel's
// clouds/{noise,field,march}.rs and frame/clouds.rs, function for function
// under the same names, so that each pixel sees the same numbers as the
// CPU's `PixelPass::Clouds` (`CloudFrame::composite`).
//
// Every model constant comes from Rust through `Clouds` (the mirror is
// `CloudUniforms`, passes/clouds.rs): the fields, the phase function
// `CLOUD_PHASE`, the octaves `OCTAVES`, the march settings, the noise's
// period, octave counts, contrast and octave shift, the lights and the
// ambient light. What stays here is the algorithm: the hash's constants,
// the fade polynomial, and inside `march_low` its own literals (the
// ambient's height gradient, the 8-octave cap, the early exit), which
// follow march.rs when `march_low` is re-synced (see the marked block).

struct Clouds {
    // low layer (field.rs `LowField`): the wind offset (km), 1 / cell size
    // (km⁻¹) and the coverage
    low_offset_km: vec2<f32>,
    low_inv_scale: f32,
    low_coverage: f32,
    // base and top altitude (km), extinction of the densest cloud (km⁻¹)
    // and the patch's half-width (km; f32::MAX when unbounded)
    low_base_km: f32,
    low_top_km: f32,
    low_extinction_per_km: f32,
    low_half_extent_km: f32,
    // the kind's height profile (field.rs `ProfileShape`) and the seed
    low_rise: f32,
    low_fall0: f32,
    low_fall1: f32,
    low_seed: u32,
    // high layer (field.rs `HighField`): wind offset (km), unit vector
    // along the wind
    high_offset_km: vec2<f32>,
    high_along: vec2<f32>,
    // 1 / cell size along and across the wind (km⁻¹), coverage, altitude (km)
    high_inv_scale_along: f32,
    high_inv_scale_across: f32,
    high_coverage: f32,
    high_altitude_km: f32,
    // vertical optical depth of the densest cloud, seed; 1 when the layer
    // exists
    high_optical_depth: f32,
    high_seed: u32,
    has_low: u32,
    has_high: u32,
    // noise.rs `OCTAVE_SHIFT`, field.rs `NOISE_CONTRAST`
    octave_shift: vec3<f32>,
    noise_contrast: f32,
    // field.rs `NOISE_PERIOD_CELLS`, `LOW_OCTAVES`, `HIGH_OCTAVES`;
    // march.rs `MarchSettings::steps`
    noise_period_cells: u32,
    low_octaves: u32,
    high_octaves: u32,
    steps: u32,
    // `MarchSettings::light_steps`, the octaves (march.rs `Octaves`: n, a, b, c)
    light_steps: u32,
    octave_count: u32,
    octave_a: f32,
    octave_b: f32,
    octave_c: f32,
    // march.rs `CLOUD_PHASE`
    phase_g_forward: f32,
    phase_g_back: f32,
    phase_w_forward: f32,
    // march.rs `Shell` (km), `MAX_MARCH_KM`, frame/clouds.rs `CLEAR`
    r_ground: f32,
    r_observer: f32,
    max_march_km: f32,
    clear: f32,
    // the sky's mean downward radiance (linear sRGB, cd/m²), light count
    ambient: vec3<f32>,
    light_count: u32,
    // the lights (`CloudFrame::light_sources`): unit ENU direction, band
    // factors outside the atmosphere, and their linear sRGB (lux) when the
    // atmosphere does not extinguish them; `air`: 1 when the atmosphere
    // pass runs (LUTs bound)
    light0_dir: vec3<f32>,
    air: u32,
    light0_spectrum: array<vec4<f32>, 3>,
    light0_rgb: vec3<f32>,
    // steps of the aerial perspective's march (lights.rs `AERIAL_STEPS`)
    air_steps: u32,
    light1_dir: vec3<f32>,
    // march.rs `Diffusion::gain` (0: the octaves model, `MultipleScattering`)
    diffusion_gain: f32,
    light1_spectrum: array<vec4<f32>, 3>,
    light1_rgb: vec3<f32>,
    // march.rs `Diffusion::g`
    diffusion_g: f32,
    // the aerial perspective's lights (sky_light.rs `SkyInputs`): the
    // Sun's direction and irradiance scale, the Moon's (scale 0: none)
    air_sun: vec3<f32>,
    air_sun_scale: f32,
    air_moon: vec3<f32>,
    air_moon_scale: f32,
    // field.rs `CLOSE_FROM`, `CLOSE_DECK` (the deck closing at high coverage)
    close_from: f32,
    close_deck: f32,
    // cloud_shadow.rs `CloudFrame::shade_ground`: the number of ground
    // lights (`CloudFrame::ground_direct`) and 1 when the observer stands
    // on the ground (every ground pixel then takes the transmittance at
    // the observer, `ground_at_observer`)
    ground_count: u32,
    ground_flat: u32,
    // per ground light: unit ENU direction (xyz) and the transmittance at
    // the observer (w); the direct part of the ground's luminance (cd/m²)
    ground0_dir: vec4<f32>,
    ground0_rgb: vec4<f32>,
    ground1_dir: vec4<f32>,
    ground1_rgb: vec4<f32>,
    // march.rs `Diffusion`: gap_density, surface_step, surface_weight,
    // forward_orders (clouds_diffusion.wgsl)
    diffusion_shape: vec4<f32>,
    // height_field.rs (clouds_heightfield.wgsl): `PROBE_DIVISOR` (0: the
    // volumetric tier), texels per side, half-width (km), texel (km); the
    // warp's distance (km, 0: a regular grid), the number of light maps
    hf_map: vec4<f32>,
    hf_warp: vec4<f32>,
    // diffusion_grid.rs `DiffusionGrid` (clouds_grid.wgsl): the grids'
    // corner (x, y, altitude km) and cell (km); cells along x, y, z and
    // the number of grids (0: the column model alone); weight, fade_km, g
    grid_origin: vec4<f32>,
    grid_dims: vec4<f32>,
    grid_weight: vec4<f32>,
    // amortised marching (clouds_amortise.wgsl, cloud_grid.rs
    // `LowCloudGrid`): the stride N (≤ 1: every pixel marched), the coarse
    // grid's nodes along x and y, 0
    march_grid: vec4<u32>,
    // temporal reprojection (clouds_history.wgsl, cloud_history.rs
    // `HistoryStep`): 1 when the last frame's nodes may serve, the phase of
    // the quarter marched, bit a set when the lights of a frames ago are
    // within `HISTORY_LIGHT_DEG`, `HISTORY_MAX_AGE`; the field's move since
    // the last frame (km), `HISTORY_AGREE` and the negligible weight
    history: vec4<u32>,
    history_shift: vec4<f32>,
}

@group(1) @binding(0) var<uniform> clouds: Clouds;
@group(1) @binding(1) var<uniform> atmo: Atmo;
@group(1) @binding(2) var<storage, read> trans: array<vec4<f32>>;
@group(1) @binding(3) var<storage, read> trans_s: array<vec4<f32>>;
@group(1) @binding(4) var<storage, read> multi: array<vec4<f32>>;

// ---------------------------------------------------------------------------
// noise.rs

// noise.rs `hash_u32` (lowbias32); u32 arithmetic wraps as in Rust.
fn hash_u32(x0: u32) -> u32 {
    var x = x0;
    x = x ^ (x >> 16u);
    x = x * 0x7feb352du;
    x = x ^ (x >> 15u);
    x = x * 0x846ca68bu;
    x = x ^ (x >> 16u);
    return x;
}

// noise.rs `lattice`: the value at lattice point (i, j, k), in [0, 1).
fn lattice(i: u32, j: u32, k: u32, seed: u32) -> f32 {
    let h = hash_u32((i * 0x8da6b343u) ^ (j * 0xd8163841u) ^ (k * 0xcb1ab31fu) ^ hash_u32(seed));
    return f32(h >> 8u) * (1.0 / 16777216.0);
}

// noise.rs `fade`: 6t⁵ − 15t⁴ + 10t³.
fn fade(t: f32) -> f32 {
    return t * t * t * (t * (t * 6.0 - 15.0) + 10.0);
}

// noise.rs `lerp` (not `mix`: the same rounding as the CPU).
fn lerp(a: f32, b: f32, t: f32) -> f32 {
    return a + (b - a) * t;
}

// noise.rs `value_noise`: periodic with `period` cells (a power of two).
fn value_noise(p: vec3<f32>, period: u32, seed: u32) -> f32 {
    let f = floor(p);
    let t = p - f;
    let mask = period - 1u;
    // Two's complement keeps floor(−0.5) = −1 ≡ period − 1 (mod period).
    let i0 = u32(i32(f.x)) & mask;
    let j0 = u32(i32(f.y)) & mask;
    let k0 = u32(i32(f.z)) & mask;
    let i1 = (i0 + 1u) & mask;
    let j1 = (j0 + 1u) & mask;
    let k1 = (k0 + 1u) & mask;
    let u = fade(t.x);
    let v = fade(t.y);
    let w = fade(t.z);
    let x00 = lerp(lattice(i0, j0, k0, seed), lattice(i1, j0, k0, seed), u);
    let x10 = lerp(lattice(i0, j1, k0, seed), lattice(i1, j1, k0, seed), u);
    let x01 = lerp(lattice(i0, j0, k1, seed), lattice(i1, j0, k1, seed), u);
    let x11 = lerp(lattice(i0, j1, k1, seed), lattice(i1, j1, k1, seed), u);
    return lerp(lerp(x00, x10, v), lerp(x01, x11, v), w);
}

// noise.rs `fbm`: octave k at frequency 2^k, amplitude 2^−k, seed + k.
fn fbm(p: vec3<f32>, octaves: u32, period: u32, seed: u32) -> f32 {
    var sum = 0.0;
    var norm = 0.0;
    var amp = 1.0;
    var freq = 1.0;
    for (var k = 0u; k < octaves; k = k + 1u) {
        let q = p * freq + clouds.octave_shift * f32(k);
        sum = sum + amp * value_noise(q, period << k, seed + k);
        norm = norm + amp;
        amp = amp * 0.5;
        freq = freq * 2.0;
    }
    if (norm > 0.0) {
        return sum / norm;
    }
    return 0.0;
}

// ---------------------------------------------------------------------------
// field.rs

// field.rs `profile` of the frame's kind (`ProfileShape` in the uniforms).
fn profile(hf: f32) -> f32 {
    return hermite(0.0, clouds.low_rise, hf) * (1.0 - hermite(clouds.low_fall0, clouds.low_fall1, hf));
}

// field.rs `contrast`.
fn contrast(n: f32) -> f32 {
    return clamp((n - 0.5) * clouds.noise_contrast + 0.5, 0.0, 1.0);
}

// field.rs `close`.
fn close(n: f32, coverage: f32) -> f32 {
    return n + (1.0 - n) * clouds.close_deck * hermite(clouds.close_from, 1.0, coverage);
}

// field.rs `cover`.
fn cover(v: f32, coverage: f32) -> f32 {
    return clamp((v - (1.0 - coverage)) / max(coverage, 1e-3), 0.0, 1.0);
}

// field.rs `LowField::density`.
fn low_density(xy: vec2<f32>, h_km: f32) -> f32 {
    let hf = (h_km - clouds.low_base_km) / (clouds.low_top_km - clouds.low_base_km);
    let e = clouds.low_half_extent_km;
    if (!(hf >= 0.0 && hf <= 1.0) || abs(xy.x) > e || abs(xy.y) > e) {
        return 0.0;
    }
    let prof = profile(hf);
    if (prof <= 0.0) {
        return 0.0;
    }
    let q = (xy - clouds.low_offset_km) * clouds.low_inv_scale;
    let p = vec3<f32>(q.x, q.y, h_km * clouds.low_inv_scale);
    let n = contrast(fbm(p, clouds.low_octaves, clouds.noise_period_cells, clouds.low_seed));
    return cover(close(n, clouds.low_coverage) * prof, clouds.low_coverage);
}

// field.rs `LowField::extinction`, km⁻¹.
fn low_extinction(xy: vec2<f32>, h_km: f32) -> f32 {
    return clouds.low_extinction_per_km * low_density(xy, h_km);
}

// field.rs `HighField::optical_depth`.
fn high_optical_depth(xy: vec2<f32>) -> f32 {
    let p = xy - clouds.high_offset_km;
    let al = clouds.high_along;
    let a = dot(p, al) * clouds.high_inv_scale_along;
    let b = (p.x * al.y - p.y * al.x) * clouds.high_inv_scale_across;
    let n = contrast(fbm(vec3<f32>(a, b, 0.5), clouds.high_octaves, clouds.noise_period_cells, clouds.high_seed));
    return clouds.high_optical_depth * cover(close(n, clouds.high_coverage), clouds.high_coverage);
}

// ---------------------------------------------------------------------------
// march.rs: geometry

// march.rs `CloudPhase::eval` of `CLOUD_PHASE`, sr⁻¹.
fn hg_phase(g: f32, cos_theta: f32) -> f32 {
    let d = max(1.0 + g * g - 2.0 * g * cos_theta, 1e-6);
    return (1.0 - g * g) / (4.0 * PI * d * sqrt(d));
}

fn cloud_phase(cos_theta: f32, k: f32) -> f32 {
    let w = clouds.phase_w_forward;
    return w * hg_phase(clouds.phase_g_forward * k, cos_theta)
        + (1.0 - w) * hg_phase(clouds.phase_g_back * k, cos_theta);
}

// An interval [x, y] of a ray; z = 1 when it exists (Rust `Option`).
// march.rs `inside_sphere`.
fn inside_sphere(r0: f32, mu: f32, r: f32) -> vec3<f32> {
    let disc = r0 * r0 * (mu * mu - 1.0) + r * r;
    if (disc >= 0.0) {
        let s = safe_sqrt(disc);
        return vec3<f32>(-r0 * mu - s, -r0 * mu + s, 1.0);
    }
    return vec3<f32>(0.0);
}

// march.rs `slab_interval`.
fn slab_interval(r0: f32, mu: f32, r_lo: f32, r_hi: f32) -> vec3<f32> {
    let o = inside_sphere(r0, mu, r_hi);
    if (o.z == 0.0) {
        return vec3<f32>(0.0);
    }
    var start = max(o.x, 0.0);
    var end = o.y;
    if (end <= start) {
        return vec3<f32>(0.0);
    }
    let i = inside_sphere(r0, mu, r_lo);
    if (i.z != 0.0) {
        if (i.x <= start && start < i.y) {
            start = i.y;
        } else if (i.x > start) {
            end = min(end, i.x);
        }
    }
    return vec3<f32>(start, end, select(0.0, 1.0, end > start));
}

// march.rs `Shell::slab_from`.
fn slab_from(r: f32, mu: f32, lo_km: f32, hi_km: f32) -> vec3<f32> {
    let s = slab_interval(r, mu, clouds.r_ground + lo_km, clouds.r_ground + hi_km);
    if (s.z == 0.0) {
        return s;
    }
    var end = s.y;
    let g = inside_sphere(r, mu, clouds.r_ground);
    if (g.z != 0.0 && mu < 0.0) {
        end = min(end, max(g.x, 0.0));
    }
    return vec3<f32>(s.x, end, select(0.0, 1.0, end > s.x));
}

// march.rs `Shell::slab`.
fn slab(view: vec3<f32>, lo_km: f32, hi_km: f32) -> vec3<f32> {
    return slab_from(clouds.r_observer, view.z, lo_km, hi_km);
}

// march.rs `step_count`.
fn step_count(len: f32, thickness: f32, steps: u32) -> u32 {
    let dt = thickness / f32(steps);
    return clamp(u32(ceil(len / dt)), 1u, 4u * steps);
}

// march.rs `optical_depth_to_light`.
fn optical_depth_to_light(pos: vec3<f32>, l: vec3<f32>, n: u32) -> f32 {
    let r = length(pos);
    let mu = dot(pos, l) / r;
    let o = inside_sphere(r, mu, clouds.r_ground + clouds.low_top_km);
    if (o.z == 0.0) {
        return 0.0;
    }
    let d = max(o.y, 0.0);
    let ds = d / f32(n);
    var tau = 0.0;
    for (var k = 0u; k < n; k = k + 1u) {
        let p = pos + l * ((f32(k) + 0.5) * ds);
        tau = tau + low_extinction(p.xy, length(p) - clouds.r_ground) * ds;
    }
    return tau;
}

// march.rs `CloudHit`.
struct CloudHit {
    radiance: vec3<f32>,
    transmittance: f32,
    distance_km: f32,
}

// march.rs `CloudHit::add`: a segment of optical depth tau at t km whose
// source is src + ambient (0.4 + 0.6 h); whether the ray's light is spent.
fn hit_add(hit: ptr<function, CloudHit>, tau: f32, t: f32, src: vec3<f32>, ambient: vec3<f32>, h: f32) -> bool {
    let seg = exp(-tau);
    let w = (*hit).transmittance * (1.0 - seg);
    (*hit).radiance = (*hit).radiance + w * (src + ambient * (0.4 + 0.6 * h));
    (*hit).distance_km = (*hit).distance_km + w * t;
    (*hit).transmittance = (*hit).transmittance * seg;
    return (*hit).transmittance < 1e-4;
}

// march.rs `CloudHit::finish`: the extinction-weighted mean distance.
fn hit_finish(hit: CloudHit, t0: f32) -> CloudHit {
    let ext = 1.0 - hit.transmittance;
    var d = t0;
    if (ext > 0.0) {
        d = hit.distance_km / ext;
    }
    return CloudHit(hit.radiance, hit.transmittance, d);
}

fn clear_hit() -> CloudHit {
    return CloudHit(vec3<f32>(0.0), 1.0, 0.0);
}

// march.rs `CloudLight`s at one point: directions and irradiance (linear
// sRGB, lux); `count` of them valid.
struct CloudLights {
    dir: array<vec3<f32>, 2>,
    rgb: array<vec3<f32>, 2>,
    count: u32,
}

// ======================= march.rs `march_low` — BEGIN =======================
// Mirrors the Rust function (`march_low_with_grids`: the diffusion
// grids of clouds_grid.wgsl) line for line; re-sync this block when
// march.rs changes. Field, shell and settings come from `clouds`.
fn march_low(view: vec3<f32>, lights: CloudLights, ambient: vec3<f32>) -> CloudHit {
    let n_oct = clamp(clouds.octave_count, 1u, 8u);
    let sl = slab(view, clouds.low_base_km, clouds.low_top_km);
    if (sl.z == 0.0) {
        return clear_hit();
    }
    let t0 = sl.x;
    let t1 = min(sl.y, t0 + clouds.max_march_km);
    let thickness = clouds.low_top_km - clouds.low_base_km;
    let n = step_count(t1 - t0, thickness, clouds.steps);
    let dt = (t1 - t0) / f32(n);
    let origin = vec3<f32>(0.0, 0.0, clouds.r_observer);
    var ls = lights;
    var phases: array<array<f32, 8>, 2>;
    for (var j = 0u; j < ls.count; j = j + 1u) {
        let cos_t = dot(view, ls.dir[j]);
        var k = 1.0;
        for (var o = 0u; o < n_oct; o = o + 1u) {
            phases[j][o] = cloud_phase(cos_t, k);
            k = k * clouds.octave_c;
        }
    }
    var lobes: array<vec4<f32>, 2>;
    for (var j = 0u; j < ls.count; j = j + 1u) {
        if (clouds.diffusion_gain > 0.0) {
            lobes[j] = forward_lobes(dot(view, ls.dir[j]));
        }
    }
    var hit = CloudHit(vec3<f32>(0.0), 1.0, 0.0);
    for (var s = 0u; s < n; s = s + 1u) {
        let t = t0 + (f32(s) + 0.5) * dt;
        let pos = origin + view * t;
        // `Shell::point`
        let xy = vec2<f32>(view.x * t, view.y * t);
        let h = length(pos) - clouds.r_ground;
        let sigma = low_extinction(xy, h);
        if (sigma <= 0.0) {
            continue;
        }
        var src = vec3<f32>(0.0);
        for (var j = 0u; j < ls.count; j = j + 1u) {
            let tau = optical_depth_to_light(pos, ls.dir[j], clouds.light_steps);
            var f = 0.0;
            var ai = 1.0;
            var bi = 1.0;
            for (var o = 0u; o < n_oct; o = o + 1u) {
                f = f + bi * phases[j][o] * exp(-ai * tau);
                ai = ai * clouds.octave_a;
                bi = bi * clouds.octave_b;
            }
            if (clouds.diffusion_gain > 0.0) {
                let gap = clouds.diffusion_shape.x * clouds.low_extinction_per_km;
                let tau_b = optical_depth_connected(pos, -ls.dir[j], clouds.light_steps, gap);
                let mu = slab_cosine(pos, sigma, ls.dir[j]);
                let column = diffuse_source(tau, tau_b, mu, dot(view, ls.dir[j]));
                f = f + grid_diffuse(j, column, xy, h, view);
                f = f + forward_source(lobes[j], tau);
            }
            src = src + f * ls.rgb[j];
        }
        let hf = clamp((h - clouds.low_base_km) / thickness, 0.0, 1.0);
        if (hit_add(&hit, sigma * dt, t, src, ambient, hf)) {
            break;
        }
    }
    return hit_finish(hit, t0);
}
// ======================= march.rs `march_low` — END =========================

// march.rs `shade_high`: single scattering of the thin sheet.
fn shade_high(view: vec3<f32>, lights: CloudLights, ambient: vec3<f32>) -> CloudHit {
    let r_layer = clouds.r_ground + clouds.high_altitude_km;
    if (clouds.r_observer >= r_layer) {
        return clear_hit();
    }
    let o = inside_sphere(clouds.r_observer, view.z, r_layer);
    if (o.z == 0.0) {
        return clear_hit();
    }
    let t = o.y;
    let p = vec3<f32>(0.0, 0.0, clouds.r_observer) + view * t;
    let up = p / length(p);
    let mu_v = max(dot(view, up), 1e-3);
    let tau = high_optical_depth(vec2<f32>(view.x * t, view.y * t));
    if (tau <= 0.0) {
        return clear_hit();
    }
    let tv = exp(-tau / mu_v);
    var ls = lights;
    var l = vec3<f32>(0.0);
    for (var j = 0u; j < ls.count; j = j + 1u) {
        let mu_l = dot(ls.dir[j], up);
        if (mu_l <= 1e-3) {
            continue;
        }
        let x = tau * (1.0 / mu_l - 1.0 / mu_v);
        // (1 − e^{−x}) / x, continuous through x = 0 (Rust: −expm1(−x)/x;
        // its series near 0).
        var g: f32;
        if (abs(x) < 1e-2) {
            g = 1.0 - x * (0.5 - x * (1.0 / 6.0 - x / 24.0));
        } else {
            g = (1.0 - exp(-x)) / x;
        }
        let f = cloud_phase(dot(view, ls.dir[j]), 1.0) * tau / mu_v * tv * g;
        l = l + f * ls.rgb[j];
    }
    l = l + ambient * (1.0 - tv);
    return CloudHit(l, tv, t);
}

// ---------------------------------------------------------------------------
// frame/clouds.rs

// `CloudFrame::lights_at`: the lights at the point t km along `view`, after
// the atmosphere's transmittance from there (none without the atmosphere).
fn lights_at(view: vec3<f32>, t: f32) -> CloudLights {
    var ls: CloudLights;
    ls.count = clouds.light_count;
    ls.dir[0] = clouds.light0_dir;
    ls.dir[1] = clouds.light1_dir;
    ls.rgb[0] = clouds.light0_rgb;
    ls.rgb[1] = clouds.light1_rgb;
    if (clouds.air == 0u) {
        return ls;
    }
    let p = vec3<f32>(0.0, 0.0, clouds.r_observer) + view * t;
    let r = length(p);
    for (var j = 0u; j < ls.count; j = j + 1u) {
        let mu = dot(p, ls.dir[j]) / r;
        var e: array<vec4<f32>, 3>;
        for (var k = 0u; k < 3u; k = k + 1u) {
            var s = clouds.light0_spectrum[k];
            if (j == 1u) {
                s = clouds.light1_spectrum[k];
            }
            e[k] = s * sun_transmittance(false, r, mu, k);
        }
        ls.rgb[j] = max(to_rgb(e[0], e[1], e[2]), vec3<f32>(0.0));
    }
    return ls;
}

fn no_lights() -> CloudLights {
    var ls: CloudLights;
    ls.count = 0u;
    return ls;
}

// `CloudFrame::low_hit`.
fn low_hit(view: vec3<f32>) -> CloudHit {
    if (clouds.has_low == 0u) {
        return clear_hit();
    }
    let sl = slab(view, clouds.low_base_km, clouds.low_top_km);
    if (sl.z == 0.0) {
        return clear_hit();
    }
    if (clouds.hf_map.x > 0.0) {
        return march_height_field(view, lights_at(view, sl.x), clouds.ambient);
    }
    return march_low(view, lights_at(view, sl.x), clouds.ambient);
}

// `CloudFrame::high_hit`.
fn high_hit(view: vec3<f32>) -> CloudHit {
    if (clouds.has_high == 0u) {
        return clear_hit();
    }
    let probe = shade_high(view, no_lights(), vec3<f32>(0.0));
    if (probe.transmittance >= 1.0 - clouds.clear) {
        return clear_hit();
    }
    return shade_high(view, lights_at(view, probe.distance_km), clouds.ambient);
}

// march.rs `aerial_perspective` to one distance `end` (km) for band group
// k: the in-scattered transfer (xyz of `l`) and the transmittance.
struct AirSegment {
    l: vec4<f32>,
    t: vec4<f32>,
}

fn aerial_perspective(r0: f32, view: vec3<f32>, sun: vec3<f32>, end: f32, n: u32, k: u32) -> AirSegment {
    let pos = vec3<f32>(0.0, 0.0, r0);
    var t_max: f32;
    if (hits_ground(r0, view.z)) {
        t_max = distance_to_bottom(r0, view.z);
    } else {
        t_max = distance_to_top(r0, view.z);
    }
    let phases = air_phases(dot(view, sun));
    var tv = vec4<f32>(1.0);
    var l = vec4<f32>(0.0);
    let t1 = clamp(end, 0.0, max(t_max, 0.0));
    let dt = t1 / f32(n);
    for (var s = 0u; s < n; s = s + 1u) {
        if (dt <= 0.0) {
            break;
        }
        let t = (f32(s) + 0.5) * dt;
        let a = air_source(phases, pos + view * t, sun, k);
        let seg = exp(-a.ext * dt);
        l = l + tv * a.src * integrate_segment(a.ext, seg, dt);
        tv = tv * seg;
    }
    return AirSegment(l, tv);
}

// `CloudFrame::air` (lights.rs `AerialPerspective::compute` for one
// direction and distance): in-scattered radiance (cd/m²) of the sunlit
// and the moonlit air, and the transmittance relative to white, from the
// observer to d_km along `view`.
struct Air {
    l: vec3<f32>,
    t: vec3<f32>,
}

fn air(view: vec3<f32>, d_km: f32) -> Air {
    var out = Air(vec3<f32>(0.0), vec3<f32>(1.0));
    if (clouds.air == 0u) {
        return out;
    }
    let end = d_km * 1000.0 / 1000.0;
    let white = to_rgb(vec4<f32>(1.0), vec4<f32>(1.0), vec4<f32>(1.0));
    let n = max(clouds.air_steps, 1u);
    var count = 1u;
    if (clouds.air_moon_scale > 0.0) {
        count = 2u;
    }
    for (var j = 0u; j < count; j = j + 1u) {
        var dir = clouds.air_sun;
        var scale = clouds.air_sun_scale;
        if (j == 1u) {
            dir = clouds.air_moon;
            scale = clouds.air_moon_scale;
        }
        let a0 = aerial_perspective(clouds.r_observer, view, dir, end, n, 0u);
        let a1 = aerial_perspective(clouds.r_observer, view, dir, end, n, 1u);
        let a2 = aerial_perspective(clouds.r_observer, view, dir, end, n, 2u);
        out.l = out.l + max(to_rgb(a0.l, a1.l, a2.l), vec3<f32>(0.0)) * scale;
        if (j == 0u) {
            out.t = clamp(to_rgb(a0.t, a1.t, a2.t) / white, vec3<f32>(0.0), vec3<f32>(1.0));
        }
    }
    return out;
}

// march.rs `optical_depth_ray`: the low layer from `pos` along `dir`.
fn optical_depth_ray(pos: vec3<f32>, dir: vec3<f32>) -> f32 {
    let r = length(pos);
    let sl = slab_from(r, dot(pos, dir) / r, clouds.low_base_km, clouds.low_top_km);
    if (sl.z == 0.0) {
        return 0.0;
    }
    let t1 = min(sl.y, sl.x + clouds.max_march_km);
    let n = step_count(t1 - sl.x, clouds.low_top_km - clouds.low_base_km, clouds.steps);
    let dt = (t1 - sl.x) / f32(n);
    var tau = 0.0;
    for (var s = 0u; s < n; s = s + 1u) {
        let p = pos + dir * (sl.x + (f32(s) + 0.5) * dt);
        tau = tau + low_extinction(p.xy, length(p) - clouds.r_ground) * dt;
    }
    return tau;
}

// cloud_shadow.rs `CloudFrame::transmittance_towards`.
fn transmittance_towards(pos: vec3<f32>, dir: vec3<f32>) -> f32 {
    var tau = 0.0;
    if (clouds.has_low != 0u) {
        tau = tau + optical_depth_ray(pos, dir);
    }
    if (clouds.has_high != 0u) {
        let r_layer = clouds.r_ground + clouds.high_altitude_km;
        let r = length(pos);
        let mu = dot(pos, dir) / r;
        let disc = r * r * (mu * mu - 1.0) + r_layer * r_layer;
        if (r < r_layer && disc >= 0.0) {
            let t = -r * mu + sqrt(disc);
            let p = pos + dir * t;
            let mu_l = max(dot(dir, p / length(p)), 1e-3);
            tau = tau + high_optical_depth(p.xy) / mu_l;
        }
    }
    return exp(-tau);
}

// cloud_shadow.rs `CloudFrame::ground_point`.
fn ground_point(view: vec3<f32>) -> vec3<f32> {
    let r = clouds.r_observer;
    let rg = clouds.r_ground;
    let eye = vec3<f32>(0.0, 0.0, r);
    if (r - rg < 1e-3) {
        return eye;
    }
    let mu = view.z;
    let disc = r * r * (mu * mu - 1.0) + rg * rg;
    if (disc >= 0.0 && mu < 0.0) {
        return eye + view * (-r * mu - sqrt(disc));
    }
    // The tangent ray: depressed by the dip, cos(dip) = rg / r.
    var h = vec3<f32>(1.0, 0.0, 0.0);
    let hl = length(view.xy);
    if (hl > 0.0) {
        h = vec3<f32>(view.xy / hl, 0.0);
    }
    let cos_dip = rg / r;
    let tangent = h * cos_dip - vec3<f32>(0.0, 0.0, sqrt(max(1.0 - cos_dip * cos_dip, 0.0)));
    return eye + tangent * sqrt(max(r * r - rg * rg, 0.0));
}

// cloud_shadow.rs `CloudFrame::shade_ground`: a ground pixel's direct
// light shadowed by the clouds.
fn shade_ground(view: vec3<f32>, px: vec3<f32>) -> vec3<f32> {
    if (view.z >= 0.0 || clouds.ground_count == 0u) {
        return px;
    }
    let r = clouds.r_observer;
    let rg = clouds.r_ground;
    if (clouds.ground_flat == 0u && r * r * (view.z * view.z - 1.0) + rg * rg < 0.0) {
        return px;
    }
    let p = ground_point(view);
    var out = px;
    for (var k = 0u; k < min(clouds.ground_count, 2u); k = k + 1u) {
        var g = clouds.ground0_dir;
        var rgb = clouds.ground0_rgb.xyz;
        if (k == 1u) {
            g = clouds.ground1_dir;
            rgb = clouds.ground1_rgb.xyz;
        }
        var t = g.w;
        if (clouds.ground_flat == 0u) {
            t = transmittance_towards(p, g.xyz);
        }
        out = max(out - rgb * (1.0 - t), vec3<f32>(0.0));
    }
    return out;
}
