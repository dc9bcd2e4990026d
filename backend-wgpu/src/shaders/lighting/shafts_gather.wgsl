// The depth-aware gather of the light shafts' reduced image `shafts_in`
// (shade.wgsl, and godrays.wgsl's `refine`, which declare it with the
// G-buffer's distance and material; after common.wgsl).

// The light shafts at pixel px (seen at distance dist): the marched
// image's texels around it, each at the depth of the pixel it marched.
// With N × N interleaving, the N × N block around it (a box, so that each
// of the N² start offsets counts once); else the bilinear 2 × 2. Texels
// on another surface (depth off by more than a few per cent) are left out;
// where all are, the nearest in depth stands in.
fn gather_shafts(px: vec2<i32>, dist: f32, w: u32, h: u32) -> vec4<f32> {
    let div = i32(u.shaft_q.z);
    let n = i32(u.shaft_q.y);
    let lsize = vec2<i32>(textureDimensions(shafts_in));
    let c = (vec2<f32>(px) + 0.5) / f32(div) - 0.5;
    let base = vec2<i32>(floor(c));
    let f = c - floor(c);
    var k = n;
    var lo = -(n / 2 - 1);
    if n <= 1 {
        k = 2;
        lo = 0;
    }
    var acc = vec4<f32>(0.0);
    var wsum = 0.0;
    var best = vec4<f32>(0.0);
    var best_d = 1e30;
    let sigma = 0.03 * dist + 0.02;
    for (var dy = lo; dy < lo + k; dy++) {
        for (var dx = lo; dx < lo + k; dx++) {
            let q = clamp(base + vec2<i32>(dx, dy), vec2<i32>(0), lsize - 1);
            let rp = min(q * div + div / 2, vec2<i32>(i32(w) - 1, i32(h) - 1));
            if textureLoad(g_material, rp, 0).x == 0u {
                continue;
            }
            let dq = abs(textureLoad(g_distance, rp, 0).x - dist);
            let v = textureLoad(shafts_in, q, 0);
            if dq < best_d {
                best_d = dq;
                best = v;
            }
            var wt = exp(-(dq * dq) / (sigma * sigma));
            if n <= 1 {
                let b = select(1.0 - f, f, vec2<i32>(dx, dy) == vec2<i32>(1));
                wt *= max(b.x * b.y, 1e-4);
            }
            acc += v * wt;
            wsum += wt;
        }
    }
    if wsum < 1e-3 {
        return best;
    }
    return acc / wsum;
}
