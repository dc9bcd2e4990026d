// `hbao` (Bavoil, Sainz & Dimitrov 2008, "Image-space horizon-based
// ambient occlusion"), concatenated after ao.wgsl (its uniforms and
// helpers). Per pixel, 2 × `slices` screen directions (the two sides of
// each slice, the slices' angles interleaved as gtao's), `steps` samples
// along each within R. Angles are elevations above the plane through p
// normal to the view vector v (sin α = d̂·v). Along a direction the
// horizon starts at the surface's tangent (the tangent plane's line in the
// slice, elevation t); each sample that rises above the horizon so far
// raises it, and adds its rise in sin α, weighted by the attenuation
// W(r) = 1 − r²/R² of its distance r (a sample is put into the slice
// first, keeping its height above the tangent plane, as gtao does):
//
//   A = 1 − (1 / N_dir) Σ_dir Σ_rises W(r_i) (sin h_i − sin h_{i−1}).
//
// This is the published estimator: the occluded share of the hemisphere
// about v, with each elevation band weighted by cos α (not the cosine
// about n of gtao's and the reference's AO), softened by W. The bent
// normal is gtao's: the cosine-weighted mean direction of each slice's
// open arc between its two horizons. The slices (`slice_at`), the samples
// along them (`slice_sample`) put into them (`into_slice`) and the bent
// normal (`open_moment`) are ao.wgsl's, shared with gtao.

fn hbao(px: vec2<i32>, p: vec3<f32>, n: vec3<f32>, r_px: f32) -> vec4<f32> {
    let radius = u.params.x;
    let v = normalize(u.eye.xyz - p);
    let walk = slice_walk(px);
    var occluded = 0.0;
    var dirs = 0.0;
    var bent = vec3<f32>(0.0);
    for (var s = 0u; s < walk.slices; s++) {
        let sl = slice_at(s, walk.slices, walk.rot, v, n);
        if !sl.ok {
            continue;
        }
        let g = sl.g;
        var h = array<f32, 2>(g - HALF_PI, g + HALF_PI);
        for (var side = 0; side < 2; side++) {
            let sgn = f32(2 * side - 1);
            // The tangent's elevation on this side: the slice's line in the
            // tangent plane, at angle g ± π/2 from v.
            var sin_h = cos(h[side]);
            let tangent = v * sin_h + sl.ortho * sin(h[side]);
            var ao = 0.0;
            for (var k = 0u; k < walk.steps; k++) {
                let smp = slice_sample(p, px, sl, sgn, (f32(k) + walk.jit) / f32(walk.steps), r_px);
                if smp.stop {
                    break;
                }
                let delta = smp.delta;
                let len = length(delta);
                if !smp.ok || len >= radius {
                    continue;
                }
                let ds = into_slice(delta, n, tangent, sl);
                let sin_s = dot(ds, v) / max(length(ds), 1e-9);
                if sin_s > sin_h {
                    let r = len / radius;
                    ao += (1.0 - r * r) * (sin_s - sin_h);
                    sin_h = sin_s;
                }
            }
            occluded += ao;
            dirs += 1.0;
            let ang = acos(clamp(sin_h, -1.0, 1.0));
            if side == 0 {
                h[0] = max(-ang, g - HALF_PI);
            } else {
                h[1] = min(ang, g + HALF_PI);
            }
        }
        bent += open_moment(h[0], h[1], v, sl);
    }
    var ao = 1.0;
    if dirs > 0.0 {
        ao = clamp(1.0 - occluded / dirs, 0.0, 1.0);
    }
    var b = n;
    if dot(bent, bent) > 1e-12 {
        b = normalize(bent);
    }
    return vec4<f32>(b, ao);
}
