// Light shafts in screen space, `mitchell` and `sousa` (passes/lighting/
// radial.rs): the fog's single scattering of the light L (the Sun when it
// is above the horizon, else the Moon), in cd/m², on an image 1 / shaft_q.z
// of the frame's size, each texel for the frame pixel at its block's centre.
//
// `source` — per texel, the unoccluded fog column of its view ray (the
// eye to the surface, the part of it with y ≤ top: t ∈ [t0, t1]) and the
// light's mask:
//
//   S = E σ_s p(θ) ∫_{t0}^{t1} exp(−σ_t (top − y(t)) / sin h) exp(−σ_t t) dt
//     = E σ_s p(θ) [e^{ε(t0)} − e^{ε(t1)}] / κ,
//   ε(t) = −σ_t (top − y(t)) / sin h − σ_t t,  κ = σ_t (1 − r_y / sin h)
//
// (y(t) = eye_y + r_y t, cos θ = r · l: the light's transmittance to a
// point of the column times the view ray's, exactly integrated); the mask
// M = 1 on sky texels (the light comes from there), else the light's
// shadow-map visibility (2 × 2 PCF) at the fog just in front of the
// surface (1 % of its distance, ≥ 5 cm): 1 where no shadows are drawn.
//
// `blur` — radial blur of M toward the light's image s (the vanishing
// point of the light's rays): taps at the fractions f_j = stride · j /
// n_eff of the way from the texel to s, weighted and normalised:
//
//   B = Σ_j w_j M(f_j) / Σ_j w_j,  w_j = exp(κ (t1 − t0) f_j)
//
// The weights come from the medium: an occluder seen at the fraction f of
// the way to s, at about the texel's own distance, lies on the light's
// path to the column's point t ≈ t1 − f (t1 − t0) (at f = 0 the surface,
// at f = 1 the eye: a point's path to the light projects onto the screen
// from the pixel to s), and that point's in-scattering reaches the eye
// with weight ∝ exp(−κ t). So Mitchell's decay per tap is exp(κ (t1 − t0)
// / n_eff), his weight the normalisation 1 / Σ w_j, his density 1 (the taps
// reach s: the whole column), his exposure S; with no occluder B = 1 and
// the pixel gets S, the closed form. Taps outside the frame are left out
// (the normalisation is over the taps inside).
//
// `mitchell`: one pass, `samples` taps, stride 1, n_eff = samples.
// `sousa`: three passes of n = samples / 3 taps, strides 1, n, n², n_eff
// = n³: each blurs the previous pass's B (the first, M), so that the
// three compose to n³ taps of the same weights. The last pass writes
// S · B (rgb, cd/m²) for shade.wgsl, which gathers it by depth (2 × 2
// bilinear) and adds it after the view ray's extinction, as `toth`'s.
// The sky's own light in the fog is left out (`toth` marches it).
// common.wgsl and shafts.wgsl (the phase, the lights' visibility) are
// prepended.

struct Radial {
    // Taps of this pass, their stride (in the finest steps), the finest
    // steps from the texel to the light's image (n_eff), 1 on the last
    // pass.
    q: vec4<u32>,
}

@group(0) @binding(1) var g_distance: texture_2d<f32>;
@group(0) @binding(2) var g_material: texture_2d<u32>;
@group(0) @binding(5) var radial_in: texture_2d<f32>;
@group(0) @binding(6) var radial_out: texture_storage_2d<rgba32float, write>;
@group(0) @binding(7) var<uniform> pass_q: Radial;

// The light the blur converges on: xyz towards it, w its first cascade;
// its illuminance (rgb) and cascades (w); none: w of the first < 0.
fn shaft_light() -> array<vec4<f32>, 2> {
    if u.sun_dir.w > 0.5 && u.sun_dir.y > 0.0 {
        return array<vec4<f32>, 2>(vec4<f32>(u.sun_dir.xyz, 0.0), vec4<f32>(u.sun_rgb.rgb, f32(u.counts.y)));
    }
    if u.moon_dir.w > 0.5 && u.moon_dir.y > 0.0 {
        return array<vec4<f32>, 2>(vec4<f32>(u.moon_dir.xyz, f32(u.flags.y)), vec4<f32>(u.moon_rgb.rgb, f32(u.counts.z)));
    }
    return array<vec4<f32>, 2>(vec4<f32>(0.0, 1.0, 0.0, -1.0), vec4<f32>(0.0));
}

// The frame pixel whose surface a texel takes (the G-buffer's).
fn texel_pixel(q: vec2<i32>) -> vec2<i32> {
    let div = i32(max(u.shaft_q.z, 1u));
    return min(q * div + div / 2, vec2<i32>(i32(u.right.w) - 1, i32(u.up.w) - 1));
}

// Where texel q stands on the frame (pixel coordinates): its block's
// centre, where shade.wgsl's bilinear gather puts it.
fn texel_centre(q: vec2<i32>) -> vec2<f32> {
    return (vec2<f32>(q) + 0.5) * f32(max(u.shaft_q.z, 1u));
}

// The view ray through the frame point c (pixel coordinates).
fn ray_at(c: vec2<f32>) -> vec3<f32> {
    let t = u.eye.w;
    let hh = 0.5 * u.up.w;
    let nx = (c.x - 0.5 * u.right.w) / hh * t;
    let ny = -(c.y - hh) / hh * t;
    return normalize(u.forward.xyz + u.right.xyz * nx + u.up.xyz * ny);
}

// The view ray's fog column at pixel px (a surface at distance dist):
// t0, t1, κ (1/m), ε(t0); t1 ≤ t0 when it has none.
fn column(ray: vec3<f32>, dist: f32, l: vec3<f32>) -> vec4<f32> {
    let eye = u.eye.xyz;
    let top = u.fog.y;
    let span = fog_interval(0.0, dist, ray);
    let t0 = span.x;
    let t1 = span.y;
    let st = u.fog.x;
    let sh = max(l.y, 1e-4);
    let kappa = st * (1.0 - ray.y / sh);
    let e0 = -st * max(top - (eye.y + ray.y * t0), 0.0) / sh - st * t0;
    return vec4<f32>(t0, t1, kappa, e0);
}

// The light's image on the frame (pixel coordinates, the frame's pixel q
// covering [q, q + 1)).
fn light_image(l: vec3<f32>) -> vec2<f32> {
    let w = u.right.w;
    let h = u.up.w;
    let t = u.eye.w;
    let fl = max(dot(l, u.forward.xyz), 1e-6);
    let nx = dot(l, u.right.xyz) / fl;
    let ny = dot(l, u.up.xyz) / fl;
    return vec2<f32>(nx / t * 0.5 * h + 0.5 * w, 0.5 * h - ny / t * 0.5 * h);
}

@compute @workgroup_size(8, 8)
fn source(@builtin(global_invocation_id) gid: vec3<u32>) {
    let lsize = vec2<u32>(textureDimensions(radial_out));
    if gid.x >= lsize.x || gid.y >= lsize.y {
        return;
    }
    let q = vec2<i32>(gid.xy);
    let px = texel_pixel(q);
    let light = shaft_light();
    if textureLoad(g_material, px, 0).x == 0u || light[0].w < 0.0 {
        textureStore(radial_out, q, vec4<f32>(0.0, 0.0, 0.0, 1.0));
        return;
    }
    let l = light[0].xyz;
    let dist = textureLoad(g_distance, px, 0).x;
    let ray = ray_at(texel_centre(q));
    let c = column(ray, dist, l);
    var s = vec3<f32>(0.0);
    if c.y > c.x {
        // ∫ exp(ε(t)) dt over [t0, t1], ε(t) = ε(t0) − κ (t − t0).
        let span = c.y - c.x;
        var integral = span * exp(c.w - 0.5 * c.z * span);
        if abs(c.z * span) > 1e-4 {
            integral = (exp(c.w) - exp(c.w - c.z * span)) / c.z;
        }
        s = light[1].rgb * (u.shafts.x * phase(dot(ray, l)) * integral);
    }
    let back = max(0.01 * dist, 0.05);
    let x = u.eye.xyz + ray * max(dist - back, 0.0);
    let view_depth = max(dist - back, 0.0) * dot(ray, u.forward.xyz);
    let m = light_visibility(u32(light[0].w), u32(light[1].w), x, view_depth);
    textureStore(radial_out, q, vec4<f32>(s, m));
}

@compute @workgroup_size(8, 8)
fn blur(@builtin(global_invocation_id) gid: vec3<u32>) {
    let lsize = vec2<i32>(textureDimensions(radial_out));
    if i32(gid.x) >= lsize.x || i32(gid.y) >= lsize.y {
        return;
    }
    let q = vec2<i32>(gid.xy);
    let px = texel_pixel(q);
    let own = textureLoad(radial_in, q, 0);
    let light = shaft_light();
    let last = pass_q.q.w == 1u;
    if light[0].w < 0.0 {
        textureStore(radial_out, q, vec4<f32>(0.0, 0.0, 0.0, 1.0));
        return;
    }
    let l = light[0].xyz;
    // κ (t1 − t0): the log of the weights' growth from the texel to s
    // (0 on sky texels: their blur, read by the next pass, is even).
    var kl = 0.0;
    if textureLoad(g_material, px, 0).x != 0u {
        let c = column(ray_at(texel_centre(q)), textureLoad(g_distance, px, 0).x, l);
        kl = c.z * max(c.y - c.x, 0.0);
    }
    let taps = max(pass_q.q.x, 1u);
    let stride = f32(max(pass_q.q.y, 1u));
    let n_eff = f32(max(pass_q.q.z, 1u));
    let frame = vec2<f32>(u.right.w, u.up.w);
    let div = f32(max(u.shaft_q.z, 1u));
    let p = texel_centre(q);
    let toward = light_image(l) - p;
    let f_max = stride * f32(taps - 1u) / n_eff;
    let m = max(0.0, kl * f_max);
    var acc = 0.0;
    var wsum = 0.0;
    // w_j = exp(κ (t1 − t0) f_j − m), by its constant ratio from tap to tap.
    let ratio = exp(kl * stride / n_eff);
    var wt = exp(-m);
    for (var j = 0u; j < taps; j++) {
        let w_j = wt;
        wt *= ratio;
        let at = p + toward * (stride * f32(j) / n_eff);
        if any(at < vec2<f32>(0.0)) || any(at >= frame) {
            continue;
        }
        let t = min(vec2<i32>(at / div), lsize - 1);
        acc += w_j * textureLoad(radial_in, t, 0).a;
        wsum += w_j;
    }
    let b = acc / max(wsum, 1e-30);
    if last {
        textureStore(radial_out, q, vec4<f32>(own.rgb * b, b));
    } else {
        textureStore(radial_out, q, vec4<f32>(own.rgb, b));
    }
}
