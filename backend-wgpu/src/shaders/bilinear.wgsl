
// Bilinear lookup in a row-major w × h table with texel centres at
// (i + 0.5)/n, clamped at the edges (lut.rs `Lut2::sample`): the indices of
// texels (x0, y0), (x1, y0), (x0, y1), (x1, y1) and the weights (fx, fy).
// Appended to atmosphere.wgsl, skyview.wgsl and luts.wgsl.
struct Bilinear {
    i: vec4<u32>,
    f: vec2<f32>,
}

fn bilinear(u: f32, v: f32, w: u32, h: u32) -> Bilinear {
    let x = clamp(u * f32(w) - 0.5, 0.0, f32(w - 1u));
    let y = clamp(v * f32(h) - 0.5, 0.0, f32(h - 1u));
    let x0 = u32(x);
    let y0 = u32(y);
    let x1 = min(x0 + 1u, w - 1u);
    let y1 = min(y0 + 1u, h - 1u);
    var b: Bilinear;
    b.i = vec4<u32>(y0 * w + x0, y0 * w + x1, y1 * w + x0, y1 * w + x1);
    b.f = vec2<f32>(x - f32(x0), y - f32(y0));
    return b;
}
