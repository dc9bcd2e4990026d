// Himmel wgpu backend: the atmosphere pass (compiled after frame.wgsl,
// followed by bilinear.wgsl): the sky-view LUT looked up per pixel, the
// Sun's sky view and, on a moonlit night, the Moon's. Its uniforms are
// `Frame` (Rust `FrameUniforms`).

// Bruneton (2017) GetTextureCoordFromUnitRange (lut.rs `tex_from_unit`).
fn tex_from_unit(x: f32, n: u32) -> f32 {
    let nf = f32(n);
    return 0.5 / nf + x * (1.0 - 1.0 / nf);
}

// Bilinear lookup of the sky-view LUT starting at texel `base` at
// (u, v) ∈ [0, 1]² with texel centres at (i + 0.5)/n, clamped
// (lut.rs `Lut2::sample_rgb`).
fn sky_sample(base: u32, u: f32, v: f32) -> vec3<f32> {
    let w = frame.sky_view_width;
    let h = frame.sky_view_height;
    let bl = bilinear(u, v, w, h);
    let i = bl.i + vec4<u32>(base);
    let a = mix(sky[i.x].xyz, sky[i.y].xyz, bl.f.x);
    let b = mix(sky[i.z].xyz, sky[i.w].xyz, bl.f.x);
    return mix(a, b, bl.f.y);
}

// One sky view's radiance for an ENU direction (lut.rs `SkyView::radiance`):
// azimuth from its light (0–180°, linear) × √(elevation / 90°); the ground
// below the horizon. The view starts at texel `base`.
fn view_radiance(dir: vec3<f32>, light: vec3<f32>, base: u32) -> vec3<f32> {
    if (dir.z < 0.0) {
        return sky[base + frame.sky_view_width * frame.sky_view_height].xyz;
    }
    let e = asin(min(dir.z, 1.0));
    let cr = dir.x * light.y - dir.y * light.x;
    let dt = dir.x * light.x + dir.y * light.y;
    var az = 0.0;
    if (cr != 0.0 || dt != 0.0) {
        az = atan2(abs(cr), dt);
    }
    let u = tex_from_unit(az / PI, frame.sky_view_width);
    let v = tex_from_unit(sqrt(e / HALF_PI), frame.sky_view_height);
    return sky_sample(base, u, v);
}

// Sky radiance for an ENU direction (cpu lib.rs `SkyLight::radiance`): the
// Sun's sky view plus, on a moonlit night, the Moon's.
fn sky_radiance(dir: vec3<f32>) -> vec3<f32> {
    var l = view_radiance(dir, frame.sun, 0u);
    if (frame.moonlit != 0u) {
        l = l + view_radiance(dir, frame.moonlight, frame.sky_view_width * frame.sky_view_height + 1u);
    }
    return l;
}

// Atmosphere pass: one sky-view lookup per pixel centre.
@compute @workgroup_size(8, 8, 1)
fn atmosphere(@builtin(global_invocation_id) gid: vec3<u32>) {
    if (!inside(gid)) {
        return;
    }
    let d = pixel_dir(f32(gid.x) + 0.5, f32(gid.y + frame.band_first_row) + 0.5);
    if (d.w == 0.0) {
        return;
    }
    let i = gid.y * frame.width + gid.x;
    accum[i] = accum[i] + vec4<f32>(sky_radiance(d.xyz), 0.0);
}
