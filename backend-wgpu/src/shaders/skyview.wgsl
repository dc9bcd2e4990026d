// The per-frame sky-view LUT on the GPU: a port of lut.rs
// `SkyView::row`/`SkyView::transfer` and `SkyView::from_rows` (Hillaire
// 2020 §5: a ray march per texel lit through the transmittance and
// multiple-scattering LUTs, computed by luts.wgsl or uploaded from the CPU
// precompute).
//
// Spectra have 10 bands, held as three vec4 "band groups" (bands 4k..4k+3;
// the last two lanes of group 2 are zero); LUT texels store their three
// groups consecutively. The Rust mirror of `Atmo` is `AtmosphereUniforms`.

struct Atmo {
    // Rayleigh scattering at sea level (km⁻¹)
    rayleigh: array<vec4<f32>, 3>,
    // aerosol scattering and extinction at sea level (km⁻¹)
    mie_scattering: array<vec4<f32>, 3>,
    mie_extinction: array<vec4<f32>, 3>,
    // ozone absorption at the peak (km⁻¹)
    ozone: array<vec4<f32>, 3>,
    // δ-scaled forward scattering f·σ_M (km⁻¹)
    forward: array<vec4<f32>, 3>,
    // band → linear sRGB weights (lux), per channel and band group
    w_r: array<vec4<f32>, 3>,
    w_g: array<vec4<f32>, 3>,
    w_b: array<vec4<f32>, 3>,
    // local Sun direction (x, 0, z; unit)
    sun: vec3<f32>,
    // the light's irradiance scale (lut.rs `SkyViewInput`: (1 AU /
    // distance)² for the Sun, the moonlight's scale for the Moon)
    irradiance_scale: f32,
    // medium.wgsl: ground and top-of-atmosphere radii (km), inverse scale
    // heights of the Rayleigh and aerosol densities (km⁻¹)
    bottom_radius: f32,
    top_radius: f32,
    inv_h_rayleigh: f32,
    inv_h_mie: f32,
    // ozone peak altitude (km), inverse ozone half width (km⁻¹)
    ozone_peak: f32,
    inv_ozone_width: f32,
    // aerosol asymmetry g, ground albedo
    mie_g: f32,
    ground_albedo: f32,
    // the Sun's angular radius (rad; medium.wgsl)
    sun_angular_radius: f32,
    // the observer's radius r0 (km)
    observer_radius: f32,
    // cos of the forward peak's half angle; 1 when the forward peak is
    // flattened within it, 0 otherwise
    cos_forward_peak: f32,
    forward_peak: u32,
    // transmittance LUT width and height, multiple-scattering LUT size n
    // (n × n), ray-march steps per sky-view texel
    transmittance_width: u32,
    transmittance_height: u32,
    multiscatter_n: u32,
    sky_view_steps: u32,
    // sky-view LUT width and height (texels)
    sky_view_width: u32,
    sky_view_height: u32,
    _pad0: u32, // padding
    _pad1: u32, // padding
}

@group(0) @binding(0) var<uniform> atmo: Atmo;
@group(0) @binding(1) var<storage, read> trans: array<vec4<f32>>;
@group(0) @binding(2) var<storage, read> trans_s: array<vec4<f32>>;
@group(0) @binding(3) var<storage, read> multi: array<vec4<f32>>;
// w × h sky-view texels, then the ground luminance
@group(0) @binding(4) var<storage, read_write> sky: array<vec4<f32>>;

const HALF_PI: f32 = 1.57079632679490;

// Bilinear lookup of band group k of a transmittance LUT (bilinear.wgsl).
fn trans_sample(scattering: bool, u: f32, v: f32, k: u32) -> vec4<f32> {
    let bl = bilinear(u, v, atmo.transmittance_width, atmo.transmittance_height);
    let i = bl.i * 3u + vec4<u32>(k);
    var t00: vec4<f32>;
    var t01: vec4<f32>;
    var t10: vec4<f32>;
    var t11: vec4<f32>;
    if (scattering) {
        t00 = trans_s[i.x];
        t01 = trans_s[i.y];
        t10 = trans_s[i.z];
        t11 = trans_s[i.w];
    } else {
        t00 = trans[i.x];
        t01 = trans[i.y];
        t10 = trans[i.z];
        t11 = trans[i.w];
    }
    let a = t00 * (1.0 - bl.f.x) + t01 * bl.f.x;
    let b = t10 * (1.0 - bl.f.x) + t11 * bl.f.x;
    return a * (1.0 - bl.f.y) + b * bl.f.y;
}

// lut.rs `sun_transmittance`: the transmittance LUT (Bruneton 2017
// parameterisation) times the Earth's-shadow visibility.
fn sun_transmittance(scattering: bool, r: f32, mu_s: f32, k: u32) -> vec4<f32> {
    let vis = sun_visibility(r, mu_s);
    if (vis <= 0.0) {
        return vec4<f32>(0.0);
    }
    let b = atmo.bottom_radius;
    let top = atmo.top_radius;
    let hh = safe_sqrt(top * top - b * b);
    let rho = safe_sqrt(r * r - b * b);
    let d = distance_to_top(r, mu_s);
    let d_min = top - r;
    let d_max = rho + hh;
    var x_mu = 0.0;
    if (d_max > d_min) {
        x_mu = clamp((d - d_min) / (d_max - d_min), 0.0, 1.0);
    }
    let x_r = clamp(rho / hh, 0.0, 1.0);
    let u = tex_from_unit(x_mu, atmo.transmittance_width);
    let v = tex_from_unit(x_r, atmo.transmittance_height);
    return trans_sample(scattering, u, v, k) * vis;
}

fn unit_from_mu_s(mu_s: f32) -> f32 {
    let m = clamp(mu_s, -1.0, 1.0);
    return 0.5 + 0.5 * sign(m) * sqrt(abs(m));
}

fn multiscatter_at(r: f32, mu_s: f32, k: u32) -> vec4<f32> {
    let n = atmo.multiscatter_n;
    let u = tex_from_unit(unit_from_mu_s(mu_s), n);
    let v = tex_from_unit(clamp((r - atmo.bottom_radius) / (atmo.top_radius - atmo.bottom_radius), 0.0, 1.0), n);
    let bl = bilinear(u, v, n, n);
    let i = bl.i * 3u + vec4<u32>(k);
    let a = multi[i.x] * (1.0 - bl.f.x) + multi[i.y] * bl.f.x;
    let b = multi[i.z] * (1.0 - bl.f.x) + multi[i.w] * bl.f.x;
    return a * (1.0 - bl.f.y) + b * bl.f.y;
}

// lut.rs `SkyView::transfer` for band group k.
fn transfer(r0: f32, view: vec3<f32>, sun: vec3<f32>, steps: u32, k: u32) -> vec4<f32> {
    let pos = vec3<f32>(0.0, 0.0, r0);
    let mu = view.z;
    let ground = hits_ground(r0, mu);
    var t_max: f32;
    if (ground) {
        t_max = distance_to_bottom(r0, mu);
    } else {
        t_max = distance_to_top(r0, mu);
    }
    let cos_theta = dot(view, sun);
    let g = atmo.mie_g;
    let pr = rayleigh_phase(cos_theta);
    let pm = cornette_shanks_phase(g, cos_theta);
    let fwd = atmo.forward[k];
    let cone = atmo.cos_forward_peak;
    var pm_flat = pm;
    if (atmo.forward_peak != 0u && cos_theta > cone) {
        pm_flat = cornette_shanks_phase(g, cone);
    }
    let t_h = max(distance_to_top(r0, 0.0), 1e-3);
    let n = clamp(u32(ceil(f32(steps) * sqrt(t_max / t_h))), min(steps, 20u), steps);
    var tv = vec4<f32>(1.0);
    var l = vec4<f32>(0.0);
    var t_prev = 0.0;
    let ray = atmo.rayleigh[k];
    let mie_s = atmo.mie_scattering[k];
    let mie_e = atmo.mie_extinction[k];
    let oz = atmo.ozone[k];
    for (var s = 0u; s < n; s = s + 1u) {
        let x = (f32(s) + 1.0) / f32(n);
        let t_next = t_max * x * x;
        let dt = t_next - t_prev;
        let t = 0.5 * (t_prev + t_next);
        t_prev = t_next;
        let p = pos + view * t;
        let rp = length(p);
        let mus = dot(p, sun) / rp;
        let hgt = max(rp - atmo.bottom_radius, 0.0);
        let d_r = exp(-hgt * atmo.inv_h_rayleigh);
        let d_m = exp(-hgt * atmo.inv_h_mie);
        let d_o = max(1.0 - abs(hgt - atmo.ozone_peak) * atmo.inv_ozone_width, 0.0);
        let sr = ray * d_r;
        let sm = mie_s * d_m;
        let ext = ray * d_r + mie_e * d_m + oz * d_o - fwd * d_m;
        let tsun = sun_transmittance(true, rp, mus, k);
        let psi = multiscatter_at(rp, mus, k);
        var src = (sr * pr + sm * pm_flat) * tsun + (sr + sm - fwd * d_m) * psi;
        if (pm > pm_flat) {
            src = src + sm * (pm - pm_flat) * sun_transmittance(false, rp, mus, k);
        }
        let seg = exp(-ext * dt);
        l = l + tv * src * integrate_segment(ext, seg, dt);
        tv = tv * seg;
    }
    if (ground) {
        let pg = pos + view * t_max;
        let rg = length(pg);
        let mug = dot(pg, sun) / rg;
        let tsun = sun_transmittance(true, rg, mug, k);
        l = l + tv * tsun * (max(mug, 0.0) * atmo.ground_albedo / PI);
    }
    return l;
}

fn luminance(c: vec3<f32>) -> f32 {
    return 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z;
}

// spectrum.rs `clip_to_gamut`.
fn clip_to_gamut(c: vec3<f32>) -> vec3<f32> {
    let m = min(c.x, min(c.y, c.z));
    if (m >= 0.0) {
        return c;
    }
    let y = luminance(c);
    if (y <= 0.0) {
        return vec3<f32>(0.0);
    }
    let t = y / (y - m);
    return max(vec3<f32>(y) + t * (c - vec3<f32>(y)), vec3<f32>(0.0));
}

fn to_rgb(f0: vec4<f32>, f1: vec4<f32>, f2: vec4<f32>) -> vec3<f32> {
    return vec3<f32>(
        dot(atmo.w_r[0], f0) + dot(atmo.w_r[1], f1) + dot(atmo.w_r[2], f2),
        dot(atmo.w_g[0], f0) + dot(atmo.w_g[1], f1) + dot(atmo.w_g[2], f2),
        dot(atmo.w_b[0], f0) + dot(atmo.w_b[1], f1) + dot(atmo.w_b[2], f2),
    );
}

// One sky-view texel (lut.rs `SkyView::row`).
@compute @workgroup_size(8, 8, 1)
fn sky_view(@builtin(global_invocation_id) gid: vec3<u32>) {
    let w = atmo.sky_view_width;
    let h = atmo.sky_view_height;
    if (gid.x >= w || gid.y >= h) {
        return;
    }
    let u = (f32(gid.x) + 0.5) / f32(w);
    let v = (f32(gid.y) + 0.5) / f32(h);
    let az = clamp(unit_from_tex(u, w), 0.0, 1.0) * PI;
    let xe = clamp(unit_from_tex(v, h), 0.0, 1.0);
    let e = xe * xe * HALF_PI;
    let d = vec3<f32>(cos(e) * cos(az), cos(e) * sin(az), sin(e));
    let sun = atmo.sun;
    let r0 = atmo.observer_radius;
    let steps = atmo.sky_view_steps;
    let f0 = transfer(r0, d, sun, steps, 0u);
    let f1 = transfer(r0, d, sun, steps, 1u);
    let f2 = transfer(r0, d, sun, steps, 2u);
    let rgb = clip_to_gamut(to_rgb(f0, f1, f2)) * atmo.irradiance_scale;
    sky[gid.y * w + gid.x] = vec4<f32>(rgb, 0.0);
}

fn sky_sample(u: f32, v: f32) -> vec3<f32> {
    let w = atmo.sky_view_width;
    let h = atmo.sky_view_height;
    let bl = bilinear(u, v, w, h);
    let a = mix(sky[bl.i.x].xyz, sky[bl.i.y].xyz, bl.f.x);
    let b = mix(sky[bl.i.z].xyz, sky[bl.i.w].xyz, bl.f.x);
    return mix(a, b, bl.f.y);
}

var<workgroup> rings: array<vec3<f32>, 64>;

// The ground luminance below the horizon (lut.rs `SkyView::from_rows`):
// albedo/π × (direct + diffuse horizontal illuminance), the diffuse part
// integrated over the new sky view in 64 elevation rings × 64 azimuths;
// one workgroup, one ring per invocation, summed in ring order.
@compute @workgroup_size(64, 1, 1)
fn ground(@builtin(local_invocation_index) a: u32) {
    let w = atmo.sky_view_width;
    let h = atmo.sky_view_height;
    let ne = 64.0;
    let na = 64u;
    let e0 = f32(a) / ne * HALF_PI;
    let e1 = f32(a + 1u) / ne * HALF_PI;
    let e = 0.5 * (e0 + e1);
    let ring = (sin(e1) - sin(e0)) * sin(e);
    let v = tex_from_unit(sqrt(e / HALF_PI), h);
    var acc = vec3<f32>(0.0);
    for (var b = 0u; b < na; b = b + 1u) {
        let u = tex_from_unit((f32(b) + 0.5) / f32(na), w);
        let dw = ring * PI / f32(na) * 2.0;
        acc = acc + sky_sample(u, v) * dw;
    }
    rings[a] = acc;
    workgroupBarrier();
    if (a == 0u) {
        var diffuse = vec3<f32>(0.0);
        for (var i = 0u; i < 64u; i = i + 1u) {
            diffuse = diffuse + rings[i];
        }
        let r0 = atmo.observer_radius;
        let mu = clamp(atmo.sun.z, -1.0, 1.0);
        let t0 = sun_transmittance(false, r0, mu, 0u);
        let t1 = sun_transmittance(false, r0, mu, 1u);
        let t2 = sun_transmittance(false, r0, mu, 2u);
        let direct = to_rgb(t0, t1, t2);
        let mu_s = max(atmo.sun.z, 0.0);
        let albedo = atmo.ground_albedo / PI;
        sky[w * h] = vec4<f32>(albedo * (direct * mu_s * atmo.irradiance_scale + diffuse), 0.0);
    }
}
