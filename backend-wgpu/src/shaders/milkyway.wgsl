// Himmel wgpu backend: the Milky Way pass (compiled after frame.wgsl): the
// diffuse night sky. Its uniforms are `Frame` and `Night` (Rust
// `FrameUniforms`, `NightUniforms`).

// The Milky Way map towards the ICRS unit vector `u`: bilinear, wrapping in
// right ascension (milkyway.rs `MilkyWayMap::radiance`).
fn milkyway_map(u: vec3<f32>) -> vec3<f32> {
    let w = night.map_width;
    let h = night.map_height;
    let ra = atan2(u.y, u.x);
    let dec = asin(clamp(u.z, -1.0, 1.0));
    var fu = 0.25 - ra * (0.5 / PI);
    if (fu < 0.0) {
        fu = fu + 1.0;
    }
    let fv = 0.5 - dec * (1.0 / PI);
    let x = fu * f32(w) - 0.5;
    let y = clamp(fv * f32(h) - 0.5, 0.0, f32(h - 1u));
    let x0 = floor(x);
    let y0 = floor(y);
    let tx = x - x0;
    let ty = y - y0;
    var xi0 = w - 1u;
    if (x0 >= 0.0) {
        xi0 = min(u32(x0), w - 1u);
    }
    let xi1 = select(xi0 + 1u, 0u, xi0 + 1u == w);
    let yi0 = u32(y0);
    let yi1 = min(yi0 + 1u, h - 1u);
    let top = mix(mw_map[yi0 * w + xi0].xyz, mw_map[yi0 * w + xi1].xyz, tx);
    let bot = mix(mw_map[yi1 * w + xi0].xyz, mw_map[yi1 * w + xi1].xyz, tx);
    return mix(top, bot, ty);
}

// The extinction table at zenith cosine μ (linear; w: refraction, rad).
fn extinction_at(mu: f32) -> vec4<f32> {
    let n = night.extinction_nodes - 1u;
    let x = clamp(mu, 0.0, 1.0) * f32(n);
    let i = min(u32(x), n - 1u);
    return mix(extinction[i], extinction[i + 1u], x - f32(i));
}

// Milky Way pass: the diffuse night sky (map + faint-star floor + zodiacal
// light + airglow) × extinction above the horizon (milkyway.rs
// `NightBackground::radiance`, night_pass.rs `NightFrame::milkyway`).
@compute @workgroup_size(8, 8, 1)
fn milkyway(@builtin(global_invocation_id) gid: vec3<u32>) {
    if (!inside(gid)) {
        return;
    }
    let d4 = pixel_dir(f32(gid.x) + 0.5, f32(gid.y + frame.band_first_row) + 0.5);
    let d = d4.xyz;
    if (d4.w == 0.0 || d.z < 0.0) {
        return;
    }
    let t = extinction_at(d.z);
    // Low down, the sky refraction lifts into view (milkyway.rs `unrefracted`).
    var dt = d;
    if (d.z < 0.18) {
        let hz = length(d.xy);
        if (hz >= 1e-9) {
            let alt = atan2(d.z, hz) - t.w;
            dt = vec3<f32>(d.x / hz * cos(alt), d.y / hz * cos(alt), sin(alt));
        }
    }
    let u = vec3<f32>(
        dot(night.enu_to_icrs_x, dt),
        dot(night.enu_to_icrs_y, dt),
        dot(night.enu_to_icrs_z, dt),
    );
    let se = night.sin_obliquity;
    let ce = night.cos_obliquity;
    let sb = clamp(-se * u.y + ce * u.z, -1.0, 1.0);
    let c2 = max(1.0 - sb * sb, 0.0);
    let zl = 60.0 + 140.0 * c2 * c2;
    let k2 = night.van_rhijn_k2;
    let ag = 1.0 / sqrt(max(1.0 - k2 * max(1.0 - d.z * d.z, 0.0), 1e-6));
    let l = milkyway_map(u) + night.floor + night.zodiacal * zl + night.airglow * ag;
    let i = gid.y * frame.width + gid.x;
    accum[i] = accum[i] + vec4<f32>(l * t.xyz, 0.0);
}
