// The atmosphere's uniforms and LUT lookups shared by skyview.wgsl and
// clouds.wgsl (appended to each, with medium.wgsl and bilinear.wgsl; each
// declares the bindings `atmo: Atmo`, `trans`, `trans_s` and `multi` in
// its own group): ports of lut.rs and march.rs.
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

// The phase functions of one view ray (march.rs `ScatterPhases::new`):
// Rayleigh, aerosol, and the aerosol's flattened within the δ-scaled
// forward cone.
struct AirPhases {
    pr: f32,
    pm: f32,
    pm_flat: f32,
}

fn air_phases(cos_theta: f32) -> AirPhases {
    var ph: AirPhases;
    ph.pr = rayleigh_phase(cos_theta);
    ph.pm = cornette_shanks_phase(atmo.mie_g, cos_theta);
    ph.pm_flat = ph.pm;
    if (atmo.forward_peak != 0u && cos_theta > atmo.cos_forward_peak) {
        ph.pm_flat = cornette_shanks_phase(atmo.mie_g, atmo.cos_forward_peak);
    }
    return ph;
}

// The δ-scaled extinction and the in-scattering source of band group k at
// point p (planet-centred, km) lit from `sun` (march.rs
// `ScatterPhases::source`: `MediumAt::new`, then `lit`).
struct AirSource {
    ext: vec4<f32>,
    src: vec4<f32>,
}

fn air_source(ph: AirPhases, p: vec3<f32>, sun: vec3<f32>, k: u32) -> AirSource {
    let rp = length(p);
    let mus = dot(p, sun) / rp;
    let hgt = max(rp - atmo.bottom_radius, 0.0);
    let d_r = exp(-hgt * atmo.inv_h_rayleigh);
    let d_m = exp(-hgt * atmo.inv_h_mie);
    let d_o = max(1.0 - abs(hgt - atmo.ozone_peak) * atmo.inv_ozone_width, 0.0);
    let fwd = atmo.forward[k];
    let sr = atmo.rayleigh[k] * d_r;
    let sm = atmo.mie_scattering[k] * d_m;
    var a: AirSource;
    a.ext = atmo.rayleigh[k] * d_r + atmo.mie_extinction[k] * d_m + atmo.ozone[k] * d_o - fwd * d_m;
    let tsun = sun_transmittance(true, rp, mus, k);
    let psi = multiscatter_at(rp, mus, k);
    a.src = (sr * ph.pr + sm * ph.pm_flat) * tsun + (sr + sm - fwd * d_m) * psi;
    if (ph.pm > ph.pm_flat) {
        a.src = a.src + sm * (ph.pm - ph.pm_flat) * sun_transmittance(false, rp, mus, k);
    }
    return a;
}

// Band factors of the three groups to linear sRGB (spectrum.rs
// `BandWeights::to_rgb`).
fn to_rgb(f0: vec4<f32>, f1: vec4<f32>, f2: vec4<f32>) -> vec3<f32> {
    return vec3<f32>(
        dot(atmo.w_r[0], f0) + dot(atmo.w_r[1], f1) + dot(atmo.w_r[2], f2),
        dot(atmo.w_g[0], f0) + dot(atmo.w_g[1], f1) + dot(atmo.w_g[2], f2),
        dot(atmo.w_b[0], f0) + dot(atmo.w_b[1], f1) + dot(atmo.w_b[2], f2),
    );
}

