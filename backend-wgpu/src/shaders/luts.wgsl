// The parameter-dependent atmosphere LUTs on the GPU: a port of lut.rs
// `AtmosphereLuts::transmittance_lut` (both the true and the δ-scaled
// transmittance, Bruneton 2017 parameterisation, midpoint rule) and
// `AtmosphereLuts::multiscatter_row` (Hillaire 2020 §5.5: second-order
// light and the f_ms transfer over a fixed set of directions, summed as a
// geometric series), same parametrisation, step counts and direction set.
//
// Spectra have 10 bands, held as three vec4 "band groups" (bands 4k..4k+3;
// the last two lanes of group 2 are zero); LUT texels store their three
// groups consecutively, the layout skyview.wgsl reads. The Rust mirror of
// `LutParams` is `luts::LutUniforms`. medium.wgsl is appended (its functions
// read the uniform as `atmo`).

struct LutParams {
    // Rayleigh scattering at sea level (km⁻¹)
    rayleigh: array<vec4<f32>, 3>,
    // aerosol scattering and extinction at sea level (km⁻¹)
    mie_scattering: array<vec4<f32>, 3>,
    mie_extinction: array<vec4<f32>, 3>,
    // ozone absorption at the peak (km⁻¹)
    ozone: array<vec4<f32>, 3>,
    // δ-scaled forward scattering f·σ_M (km⁻¹)
    forward: array<vec4<f32>, 3>,
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
    // cos of the forward peak's half angle; 1 when the forward peak is
    // flattened within it, 0 otherwise
    cos_forward_peak: f32,
    forward_peak: u32,
    // scattering orders of the multiple-scattering series (0: all)
    orders: u32,
    // transmittance LUT width and height, march steps per texel
    transmittance_width: u32,
    transmittance_height: u32,
    transmittance_steps: u32,
    // multiple-scattering LUT size n (n × n), directions (k², as
    // lut.rs `sphere_directions` returns them), march steps
    multiscatter_n: u32,
    multiscatter_dirs: u32,
    multiscatter_steps: u32,
    _pad0: u32, // padding
    _pad1: u32, // padding
}

@group(0) @binding(0) var<uniform> atmo: LutParams;
@group(0) @binding(1) var<storage, read_write> trans: array<vec4<f32>>;
@group(0) @binding(2) var<storage, read_write> trans_s: array<vec4<f32>>;
@group(0) @binding(3) var<storage, read_write> multi: array<vec4<f32>>;
// lut.rs `sphere_directions` (xyz; w unused), computed on the CPU
@group(0) @binding(4) var<storage, read> dirs: array<vec4<f32>>;

const PI: f32 = 3.14159265358979;

// Zero for the two padding lanes of band group 2.
const LANES: array<vec4<f32>, 3> = array<vec4<f32>, 3>(
    vec4<f32>(1.0),
    vec4<f32>(1.0),
    vec4<f32>(1.0, 1.0, 0.0, 0.0),
);

// medium.rs `Medium::densities`: Rayleigh, aerosol, ozone.
fn densities(r: f32) -> vec3<f32> {
    let h = max(r - atmo.bottom_radius, 0.0);
    return vec3<f32>(
        exp(-h * atmo.inv_h_rayleigh),
        exp(-h * atmo.inv_h_mie),
        max(1.0 - abs(h - atmo.ozone_peak) * atmo.inv_ozone_width, 0.0),
    );
}

// One transmittance texel (lut.rs `r_mu_from_transmittance_uv`,
// `column_densities`, `optical_depth`): T and the δ-scaled T_s, which
// share the column densities.
@compute @workgroup_size(8, 8, 1)
fn transmittance(@builtin(global_invocation_id) gid: vec3<u32>) {
    let w = atmo.transmittance_width;
    let h = atmo.transmittance_height;
    if (gid.x >= w || gid.y >= h) {
        return;
    }
    let u = (f32(gid.x) + 0.5) / f32(w);
    let v = (f32(gid.y) + 0.5) / f32(h);
    let x_mu = unit_from_tex(u, w);
    let x_r = unit_from_tex(v, h);
    let b = atmo.bottom_radius;
    let top = atmo.top_radius;
    let hh = safe_sqrt(top * top - b * b);
    let rho = hh * x_r;
    let r = safe_sqrt(rho * rho + b * b);
    let d_min = top - r;
    let d_max = rho + hh;
    let d = d_min + x_mu * (d_max - d_min);
    var mu = 1.0;
    if (d != 0.0) {
        mu = clamp((hh * hh - rho * rho - d * d) / (2.0 * r * d), -1.0, 1.0);
    }
    let len = distance_to_top(r, mu);
    let steps = atmo.transmittance_steps;
    let dt = len / f32(steps);
    var col = vec3<f32>(0.0);
    for (var i = 0u; i < steps; i = i + 1u) {
        let t = (f32(i) + 0.5) * dt;
        let ri = safe_sqrt(t * t + 2.0 * r * mu * t + r * r);
        col = col + densities(ri) * dt;
    }
    let idx = (gid.y * w + gid.x) * 3u;
    for (var k = 0u; k < 3u; k = k + 1u) {
        let od = atmo.rayleigh[k] * col.x + atmo.mie_extinction[k] * col.y + atmo.ozone[k] * col.z;
        trans[idx + k] = exp(-od) * LANES[k];
        trans_s[idx + k] = exp(-(od - atmo.forward[k] * col.y)) * LANES[k];
    }
}

// lut.rs `sun_transmittance` on the δ-scaled LUT, all three band groups
// (the texel coordinates computed once), with the Earth's-shadow
// visibility `vis` (> 0) already computed.
fn sun_transmittance_s(r: f32, mu_s: f32, vis: f32) -> array<vec4<f32>, 3> {
    let w = atmo.transmittance_width;
    let h = atmo.transmittance_height;
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
    let u = tex_from_unit(x_mu, w);
    let v = tex_from_unit(x_r, h);
    let bl = bilinear(u, v, w, h);
    let fx = bl.f.x;
    let fy = bl.f.y;
    let i00 = bl.i.x * 3u;
    let i01 = bl.i.y * 3u;
    let i10 = bl.i.z * 3u;
    let i11 = bl.i.w * 3u;
    var out: array<vec4<f32>, 3>;
    for (var k = 0u; k < 3u; k = k + 1u) {
        let a = trans_s[i00 + k] * (1.0 - fx) + trans_s[i01 + k] * fx;
        let c = trans_s[i10 + k] * (1.0 - fx) + trans_s[i11 + k] * fx;
        out[k] = (a * (1.0 - fy) + c * fy) * vis;
    }
    return out;
}

fn mu_s_from_unit(x: f32) -> f32 {
    let y = clamp(2.0 * clamp(x, 0.0, 1.0) - 1.0, -1.0, 1.0);
    return sign(y) * y * y;
}

const WG: u32 = 64u;
// Per invocation: second-order light L (3 band groups), then f_ms (3).
var<workgroup> partial: array<vec4<f32>, 384>;

// One multiple-scattering texel (lut.rs `multiscatter_row`) per workgroup
// (x: μ_s index i, y: altitude index j); its 64 invocations march the
// directions d, d + 64, … and invocation 0 sums them in invocation order.
@compute @workgroup_size(64, 1, 1)
fn multiscatter(
    @builtin(workgroup_id) wid: vec3<u32>,
    @builtin(local_invocation_index) lane: u32,
) {
    let n = atmo.multiscatter_n;
    let nd = atmo.multiscatter_dirs;
    let steps = atmo.multiscatter_steps;
    let b = atmo.bottom_radius;
    let top = atmo.top_radius;
    let v = (f32(wid.y) + 0.5) / f32(n);
    var r = b + clamp(unit_from_tex(v, n), 0.0, 1.0) * (top - b);
    r = clamp(r, b + 1e-3, top - 1e-3);
    let u = (f32(wid.x) + 0.5) / f32(n);
    let mu_s = mu_s_from_unit(unit_from_tex(u, n));
    let sun = vec3<f32>(safe_sqrt(1.0 - mu_s * mu_s), 0.0, mu_s);
    let pos = vec3<f32>(0.0, 0.0, r);
    let g = atmo.mie_g;
    let cone = atmo.cos_forward_peak;
    var l = array<vec4<f32>, 3>(vec4<f32>(0.0), vec4<f32>(0.0), vec4<f32>(0.0));
    var f = array<vec4<f32>, 3>(vec4<f32>(0.0), vec4<f32>(0.0), vec4<f32>(0.0));
    for (var di = lane; di < nd; di = di + WG) {
        let d = dirs[di].xyz;
        let mu = d.z;
        let cos_theta = dot(d, sun);
        let pr = rayleigh_phase(cos_theta);
        var pm: f32;
        if (atmo.forward_peak != 0u && cos_theta > cone) {
            pm = cornette_shanks_phase(g, cone);
        } else {
            pm = cornette_shanks_phase(g, cos_theta);
        }
        let ground = hits_ground(r, mu);
        var t_max: f32;
        if (ground) {
            t_max = distance_to_bottom(r, mu);
        } else {
            t_max = distance_to_top(r, mu);
        }
        let dt = t_max / f32(steps);
        var tv = array<vec4<f32>, 3>(vec4<f32>(1.0), vec4<f32>(1.0), vec4<f32>(1.0));
        var ld = array<vec4<f32>, 3>(vec4<f32>(0.0), vec4<f32>(0.0), vec4<f32>(0.0));
        var fd = array<vec4<f32>, 3>(vec4<f32>(0.0), vec4<f32>(0.0), vec4<f32>(0.0));
        for (var s = 0u; s < steps; s = s + 1u) {
            let t = (f32(s) + 0.5) * dt;
            let p = pos + d * t;
            let rp = length(p);
            let mus = dot(p, sun) / rp;
            let dens = densities(rp);
            let vis = sun_visibility(rp, mus);
            var tsun = array<vec4<f32>, 3>(vec4<f32>(0.0), vec4<f32>(0.0), vec4<f32>(0.0));
            if (vis > 0.0) {
                tsun = sun_transmittance_s(rp, mus, vis);
            }
            for (var k = 0u; k < 3u; k = k + 1u) {
                let sr = atmo.rayleigh[k] * dens.x;
                let sm = atmo.mie_scattering[k] * dens.y;
                let fwd = atmo.forward[k];
                let ss = sr + sm - fwd * dens.y;
                let ext = atmo.rayleigh[k] * dens.x + atmo.mie_extinction[k] * dens.y
                    + atmo.ozone[k] * dens.z - fwd * dens.y;
                let seg = exp(-ext * dt);
                let integ = integrate_segment(ext, seg, dt);
                ld[k] = ld[k] + tv[k] * (sr * pr + sm * pm) * tsun[k] * integ;
                fd[k] = fd[k] + tv[k] * ss * integ;
                tv[k] = tv[k] * seg;
            }
        }
        if (ground) {
            let pg = pos + d * t_max;
            let rg = length(pg);
            let mug = dot(pg, sun) / rg;
            let vis = sun_visibility(rg, mug);
            if (vis > 0.0) {
                let tsun = sun_transmittance_s(rg, mug, vis);
                for (var k = 0u; k < 3u; k = k + 1u) {
                    ld[k] = ld[k] + tv[k] * tsun[k] * (max(mug, 0.0) * atmo.ground_albedo / PI);
                }
            }
        }
        for (var k = 0u; k < 3u; k = k + 1u) {
            l[k] = l[k] + ld[k];
            f[k] = f[k] + fd[k];
        }
    }
    for (var k = 0u; k < 3u; k = k + 1u) {
        partial[lane * 6u + k] = l[k];
        partial[lane * 6u + 3u + k] = f[k];
    }
    workgroupBarrier();
    if (lane != 0u) {
        return;
    }
    let inv = 1.0 / f32(nd);
    let orders = atmo.orders;
    let idx = (wid.y * n + wid.x) * 3u;
    for (var k = 0u; k < 3u; k = k + 1u) {
        var l2 = vec4<f32>(0.0);
        var fms = vec4<f32>(0.0);
        for (var i = 0u; i < WG; i = i + 1u) {
            l2 = l2 + partial[i * 6u + k];
            fms = fms + partial[i * 6u + 3u + k];
        }
        l2 = l2 * inv;
        let fb = min(fms * inv, vec4<f32>(0.999));
        var series: vec4<f32>;
        if (orders == 0u) {
            series = vec4<f32>(1.0) / (vec4<f32>(1.0) - fb);
        } else {
            // Σ_{k < orders − 1} fb^k (0 for single scattering).
            series = vec4<f32>(0.0);
            var pw = vec4<f32>(1.0);
            for (var o = 1u; o < orders; o = o + 1u) {
                series = series + pw;
                pw = pw * fb;
            }
        }
        multi[idx + k] = l2 * series * LANES[k];
    }
}
