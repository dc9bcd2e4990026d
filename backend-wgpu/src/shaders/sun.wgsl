// Himmel wgpu backend: the Sun pass (compiled after frame.wgsl): the
// limb-darkened, extinguished disk from the Sun table, supersampled near
// the disk. Its uniforms are `Frame` (Rust `FrameUniforms`).

// The Sun table: linear sRGB radiance (cd/m²) of the disk at normalised
// disk radius ρ = sin γ / sin R (nodes sin(π/2 · i/(n−1)): uniform in
// asin ρ, dense at the limb where μ^α falls steeply) and line-of-sight zenith
// cosine z (nodes from z_min to z_max), limb darkening × transmittance.
fn sun_sample(rho: f32, z: f32) -> vec3<f32> {
    let nr = frame.sun_rho_nodes;
    let nz = frame.sun_z_nodes;
    let x = asin(clamp(rho, 0.0, 1.0)) / HALF_PI * f32(nr - 1u);
    let span = max(frame.sun_z_max - frame.sun_z_min, 1e-12);
    let y = clamp((z - frame.sun_z_min) / span, 0.0, 1.0) * f32(nz - 1u);
    let x0 = min(u32(x), nr - 1u);
    let y0 = min(u32(y), nz - 1u);
    let x1 = min(x0 + 1u, nr - 1u);
    let y1 = min(y0 + 1u, nz - 1u);
    let fx = x - f32(x0);
    let fy = y - f32(y0);
    let a = mix(sun_table[y0 * nr + x0].xyz, sun_table[y0 * nr + x1].xyz, fx);
    let b = mix(sun_table[y1 * nr + x0].xyz, sun_table[y1 * nr + x1].xyz, fx);
    return mix(a, b, fy);
}

// Sun pass: pixels within the margin of the disk are supersampled
// (n × n sub-pixel directions), as the CPU backend does. Dispatched over the
// pixel rectangle that holds the margin, from (sun_x0, sun_y0).
@compute @workgroup_size(8, 8, 1)
fn sun(@builtin(global_invocation_id) gid: vec3<u32>) {
    let px = gid.x + frame.sun_x0;
    let py = gid.y + frame.sun_y0;
    if (px >= frame.width || py >= frame.band_first_row + frame.band_rows) {
        return;
    }
    let d = pixel_dir(f32(px) + 0.5, f32(py) + 0.5);
    let c = frame.sun;
    if (d.w == 0.0 || dot(d.xyz, c) < frame.cos_sun_margin) {
        return;
    }
    let n = frame.sun_subsamples;
    let inv = 1.0 / f32(n);
    var acc = vec3<f32>(0.0);
    for (var sj = 0u; sj < n; sj = sj + 1u) {
        for (var si = 0u; si < n; si = si + 1u) {
            let sx = f32(px) + (f32(si) + 0.5) * inv;
            let sy = f32(py) + (f32(sj) + 0.5) * inv;
            let s4 = pixel_dir(sx, sy);
            if (s4.w == 0.0) {
                continue;
            }
            let sd = s4.xyz;
            // The ground hides the disk below the horizon; in a solar
            // eclipse the Moon hides it.
            let mc = frame.eclipse_moon;
            let behind_moon = dot(sd, mc) > 0.0 && length(cross(sd, mc)) < frame.sin_moon_radius;
            // The disk test by the sine of the angle from the centre
            // (sun.rs `SunDisk::covers`: a cosine test near 1 is not
            // accurate in f32).
            let sc = length(cross(sd, c));
            if (sd.z < 0.0 || dot(sd, c) <= 0.0 || sc >= frame.sin_sun_radius || behind_moon) {
                continue;
            }
            let rho = min(sc / frame.sin_sun_radius, 1.0);
            acc = acc + sun_sample(rho, sd.z);
        }
    }
    let i = (py - frame.band_first_row) * frame.width + px;
    accum[i] = accum[i] + vec4<f32>(acc * (inv * inv), 0.0);
}
