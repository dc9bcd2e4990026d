// Medium geometry and phase functions shared by luts.wgsl, skyview.wgsl and
// clouds.wgsl (appended to each; each declares its uniform as `atmo` with the
// fields `bottom_radius`, `top_radius` and `sun_angular_radius`, and the
// constant PI): ports of medium.rs and lut.rs, as the CPU computes them.

fn safe_sqrt(x: f32) -> f32 {
    return sqrt(max(x, 0.0));
}

fn tex_from_unit(x: f32, n: u32) -> f32 {
    let nf = f32(n);
    return 0.5 / nf + x * (1.0 - 1.0 / nf);
}

fn unit_from_tex(u: f32, n: u32) -> f32 {
    let nf = f32(n);
    return (u - 0.5 / nf) / (1.0 - 1.0 / nf);
}

fn hermite(e0: f32, e1: f32, x: f32) -> f32 {
    let t = clamp((x - e0) / (e1 - e0), 0.0, 1.0);
    return t * t * (3.0 - 2.0 * t);
}

fn distance_to_top(r: f32, mu: f32) -> f32 {
    let top = atmo.top_radius;
    return max(-r * mu + safe_sqrt(r * r * (mu * mu - 1.0) + top * top), 0.0);
}

fn distance_to_bottom(r: f32, mu: f32) -> f32 {
    let b = atmo.bottom_radius;
    return max(-r * mu - safe_sqrt(r * r * (mu * mu - 1.0) + b * b), 0.0);
}

fn hits_ground(r: f32, mu: f32) -> bool {
    let b = atmo.bottom_radius;
    return mu < 0.0 && r * r * (mu * mu - 1.0) + b * b >= 0.0;
}

// medium.rs `Medium::sun_visibility`.
fn sun_visibility(r: f32, mu_s: f32) -> f32 {
    let sin_h = min(atmo.bottom_radius / r, 1.0);
    let cos_h = -safe_sqrt(1.0 - sin_h * sin_h);
    let a = atmo.sun_angular_radius * sin_h;
    return hermite(-a, a, mu_s - cos_h);
}

fn rayleigh_phase(c: f32) -> f32 {
    return 3.0 / (16.0 * PI) * (1.0 + c * c);
}

fn cornette_shanks_phase(g: f32, c: f32) -> f32 {
    let k = 3.0 / (8.0 * PI) * (1.0 - g * g) / (2.0 + g * g);
    let d = max(1.0 + g * g - 2.0 * g * c, 1e-6);
    return k * (1.0 + c * c) / (d * sqrt(d));
}

// ∫₀^dt e^{−σt} dt per band (lut.rs `integrate_segment`).
fn integrate_segment(ext: vec4<f32>, seg: vec4<f32>, dt: f32) -> vec4<f32> {
    let big = (vec4<f32>(1.0) - seg) / max(ext, vec4<f32>(1e-30));
    let small = dt * (vec4<f32>(1.0) - 0.5 * ext * dt);
    return select(small, big, ext * dt > vec4<f32>(1e-4));
}
