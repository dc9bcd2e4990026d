// The per-frame sky-view LUT on the GPU: a port of lut.rs
// `SkyView::row`/`SkyView::transfer` and `SkyView::from_rows` (Hillaire
// 2020 §5: a ray march per texel lit through the transmittance and
// multiple-scattering LUTs, computed by luts.wgsl or uploaded from the CPU
// precompute).
//
// The uniforms `Atmo` and the LUT lookups are atmo.wgsl's (appended with
// medium.wgsl and bilinear.wgsl).

@group(0) @binding(0) var<uniform> atmo: Atmo;
@group(0) @binding(1) var<storage, read> trans: array<vec4<f32>>;
@group(0) @binding(2) var<storage, read> trans_s: array<vec4<f32>>;
@group(0) @binding(3) var<storage, read> multi: array<vec4<f32>>;
// w × h sky-view texels, then the ground luminance
@group(0) @binding(4) var<storage, read_write> sky: array<vec4<f32>>;

const PI: f32 = 3.14159265358979;
const HALF_PI: f32 = 1.57079632679490;

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
    let phases = air_phases(dot(view, sun));
    let t_h = max(distance_to_top(r0, 0.0), 1e-3);
    let n = clamp(u32(ceil(f32(steps) * sqrt(t_max / t_h))), min(steps, 20u), steps);
    var tv = vec4<f32>(1.0);
    var l = vec4<f32>(0.0);
    var t_prev = 0.0;
    for (var s = 0u; s < n; s = s + 1u) {
        let x = (f32(s) + 1.0) / f32(n);
        let t_next = t_max * x * x;
        let dt = t_next - t_prev;
        let t = 0.5 * (t_prev + t_next);
        t_prev = t_next;
        let a = air_source(phases, pos + view * t, sun, k);
        let seg = exp(-a.ext * dt);
        l = l + tv * a.src * integrate_segment(a.ext, seg, dt);
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
