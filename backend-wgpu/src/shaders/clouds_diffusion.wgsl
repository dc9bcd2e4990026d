// The diffusion model of the low layer's multiple scattering (march.rs
// `Diffusion`), concatenated after clouds.wgsl (`CLOUDS_WGSL`): the
// column's optical depths, the slab's orientation, its Eddington solution
// and the forward lobes. `clouds.diffusion_shape` carries gap_density,
// surface_step, surface_weight and forward_orders.

// march.rs `optical_depth_through`.
fn optical_depth_through(pos: vec3<f32>, dir: vec3<f32>, n: u32) -> f32 {
    let r = length(pos);
    let sl = slab_from(r, dot(pos, dir) / r, clouds.low_base_km, clouds.low_top_km);
    if (sl.z == 0.0) {
        return 0.0;
    }
    let ds = (sl.y - sl.x) / f32(n);
    var tau = 0.0;
    for (var k = 0u; k < n; k = k + 1u) {
        let p = pos + dir * (sl.x + (f32(k) + 0.5) * ds);
        tau = tau + low_extinction(p.xy, length(p) - clouds.r_ground) * ds;
    }
    return tau;
}

// march.rs `diffuse_source`: the Eddington solution of the column along
// the light (per unit irradiance, sr⁻¹).
fn diffuse_source(tau_l: f32, tau_b: f32, mu0_in: f32, cos_theta: f32) -> f32 {
    let mu0 = max(mu0_in, 0.05);
    let g = clouds.diffusion_g;
    let s = 1.0 - g;
    let mu1 = s * mu0;
    let x = s * mu0 * tau_l;
    let big_x = s * mu0 * (tau_l + tau_b);
    let beam = exp(-tau_l);
    let through = exp(-(tau_l + tau_b));
    let c = 3.0 * mu0 * mu1 + 2.0 * mu0;
    let a = -(c + through * (2.0 * mu0 - 3.0 * mu0 * mu1)) / (big_x + 4.0 / 3.0);
    let b = c + 2.0 / 3.0 * a;
    let u = max(-3.0 * mu0 * mu1 * beam + a * x + b, 0.0);
    let flux = -mu0 * beam - a / 3.0;
    return clouds.diffusion_gain * max(u + 3.0 * g * flux * cos_theta, 0.0) / (4.0 * PI);
}

// march.rs `extinction_at`: the extinction at a planet-centred point.
fn extinction_at(p: vec3<f32>) -> f32 {
    return low_extinction(p.xy, length(p) - clouds.r_ground);
}

// march.rs `optical_depth_connected`: `optical_depth_through` ending at
// the first sample at most `gap` km⁻¹ (a gap between clouds).
fn optical_depth_connected(pos: vec3<f32>, dir: vec3<f32>, n: u32, gap: f32) -> f32 {
    let r = length(pos);
    let sl = slab_from(r, dot(pos, dir) / r, clouds.low_base_km, clouds.low_top_km);
    if (sl.z == 0.0) {
        return 0.0;
    }
    let ds = (sl.y - sl.x) / f32(n);
    var tau = 0.0;
    for (var k = 0u; k < n; k = k + 1u) {
        let sigma = extinction_at(pos + dir * (sl.x + (f32(k) + 0.5) * ds));
        if (sigma <= gap) {
            break;
        }
        tau = tau + sigma * ds;
    }
    return tau;
}

// march.rs `slab_cosine`: the light's zenith cosine on the slab, turned
// towards a lit flank where the cloud is dense.
fn slab_cosine(pos: vec3<f32>, sigma: f32, l: vec3<f32>) -> f32 {
    let mu0 = dot(pos, l) / length(pos);
    let h = clouds.diffusion_shape.y / clouds.low_inv_scale;
    let grad = vec3<f32>(
        extinction_at(pos + vec3<f32>(h, 0.0, 0.0)) - sigma,
        extinction_at(pos + vec3<f32>(0.0, h, 0.0)) - sigma,
        extinction_at(pos + vec3<f32>(0.0, 0.0, h)) - sigma,
    );
    let len = length(grad);
    if (len <= 0.0 || clouds.low_extinction_per_km <= 0.0) {
        return mu0;
    }
    let facing = max(dot(-grad / len, l), mu0);
    let w = min(clouds.diffusion_shape.z * sigma / clouds.low_extinction_per_km, 1.0);
    return mu0 + w * (facing - mu0);
}

// march.rs `phase_power`: the m-fold convolution of the phase function.
fn phase_power(m: u32, cos_theta: f32) -> f32 {
    var sum = 0.0;
    var binom = 1.0;
    for (var j = 0u; j <= m; j = j + 1u) {
        let w = pow_i(clouds.phase_w_forward, j) * pow_i(1.0 - clouds.phase_w_forward, m - j);
        let g = pow_i(clouds.phase_g_forward, j) * pow_i(clouds.phase_g_back, m - j);
        sum = sum + binom * w * hg_phase(g, cos_theta);
        binom = binom * f32(m - j) / f32(j + 1u);
    }
    return sum;
}

// x^k by repeated multiplication (Rust's `powi` for the small k here;
// WGSL's `pow` is undefined for negative bases).
fn pow_i(x: f32, k: u32) -> f32 {
    var r = 1.0;
    for (var i = 0u; i < k; i = i + 1u) {
        r = r * x;
    }
    return r;
}

// march.rs `forward_lobes` (per ray, up to 4 orders).
fn forward_lobes(cos_theta: f32) -> vec4<f32> {
    var out = vec4<f32>(0.0);
    var gk = clouds.diffusion_g;
    let orders = min(u32(clouds.diffusion_shape.w), 4u);
    for (var k = 0u; k < orders; k = k + 1u) {
        gk = gk * clouds.diffusion_g;
        let diffuse = (1.0 + 3.0 * gk * cos_theta) / (4.0 * PI);
        out[k] = max(phase_power(k + 2u, cos_theta) - diffuse, 0.0);
    }
    return out;
}

// march.rs `forward_source`.
fn forward_source(lobes: vec4<f32>, tau_l: f32) -> f32 {
    var term = exp(-tau_l);
    var sum = 0.0;
    for (var k = 0u; k < 4u; k = k + 1u) {
        term = term * tau_l / f32(k + 1u);
        sum = sum + term * lobes[k];
    }
    return sum;
}
