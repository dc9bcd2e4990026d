// Himmel wgpu backend: the texture pass (compiled after frame.wgsl): the
// frame plan's TextureFrame (skymodel frame/texture.rs `TextureFrame::over`)
// per pixel: the textures' bilinear lookups through the rotation (their
// bordered tiles, skymodel texture_sky/prepare.rs `SkyTexture::sample`),
// the cross-fade gains, the horizon band and the blend over what the
// earlier passes drew. Its own bind group 1: `Tex` (Rust `TextureUniforms`)
// and the texels, three floats each.

struct TexLayer {
    mapping: u32,
    width: u32,
    height: u32,
    tiles: u32,
    tile_w: u32,
    tile_h: u32,
    offset: u32,
    gain: f32,
}

struct Tex {
    rot_x: vec3<f32>,
    blend: f32,
    rot_y: vec3<f32>,
    layers: u32,
    rot_z: vec3<f32>,
    band_on: u32,
    band_color: vec3<f32>,
    band_height_deg: f32,
    band_softness_deg: f32,
    pad0: f32,
    pad1: f32,
    pad2: f32,
    layer: array<TexLayer, 2>,
}

@group(1) @binding(0) var<uniform> tex: Tex;
@group(1) @binding(1) var<storage, read> texels: array<f32>;

// The tile (z) that shows unit direction d in a w × h image of mapping m
// and the continuous position in it (xy) (texture_sky/mod.rs
// `Mapping::locate`): 0 polar, 1 sphere, 2 paraboloid, 3 cube, 4
// cube-uniform.
fn tex_locate(m: u32, w: f32, h: f32, d: vec3<f32>) -> vec3<f32> {
    if (m == 0u) {
        // Fisheye of the direction mirrored into the upper hemisphere.
        let zen = acos(clamp(abs(d.z), -1.0, 1.0));
        let az = atan2(d.x, d.y);
        let rho = zen / HALF_PI * min(w, h) * 0.5;
        return vec3<f32>(w * 0.5 - rho * sin(az), h * 0.5 - rho * cos(az), 0.0);
    }
    if (m == 1u) {
        let alt = asin(clamp(d.z, -1.0, 1.0));
        var az = atan2(d.x, d.y);
        if (az < 0.0) {
            az = az + TAU;
        }
        return vec3<f32>(az / TAU * w, (HALF_PI - alt) / PI * h, 0.0);
    }
    if (m == 2u) {
        if (d.z >= 0.0) {
            let a = -d.x / (1.0 + d.z);
            let b = d.y / (1.0 + d.z);
            return vec3<f32>((1.0 + a) * 0.5 * h, (1.0 - b) * 0.5 * h, 0.0);
        }
        let a = d.x / (1.0 - d.z);
        let b = d.y / (1.0 - d.z);
        return vec3<f32>((1.0 + a) * 0.5 * h, (1.0 - b) * 0.5 * h, 1.0);
    }
    // Cube faces (projection.rs `cube_face_coords`), scene frame.
    let v = vec3<f32>(d.x, d.z, -d.y);
    let a = abs(v);
    var face = 0.0;
    var sc = 0.0;
    var tc = 0.0;
    if (a.x >= a.y && a.x >= a.z) {
        if (v.x > 0.0) {
            face = 0.0;
            sc = -v.z / a.x;
        } else {
            face = 1.0;
            sc = v.z / a.x;
        }
        tc = -v.y / a.x;
    } else if (a.y >= a.z) {
        sc = v.x / a.y;
        if (v.y > 0.0) {
            face = 2.0;
            tc = v.z / a.y;
        } else {
            face = 3.0;
            tc = -v.z / a.y;
        }
    } else if (v.z > 0.0) {
        face = 4.0;
        sc = v.x / a.z;
        tc = -v.y / a.z;
    } else {
        face = 5.0;
        sc = -v.x / a.z;
        tc = -v.y / a.z;
    }
    if (m == 4u) {
        // The uniform-density cube's warp (texture_sky `unwarp`).
        sc = atan(sc) / (0.25 * PI);
        tc = atan(tc) / (0.25 * PI);
    }
    return vec3<f32>((sc + 1.0) * 0.5 * h, (tc + 1.0) * 0.5 * h, face);
}

fn tex_texel(base: u32, i: u32) -> vec3<f32> {
    let k = 3u * (base + i);
    return vec3<f32>(texels[k], texels[k + 1u], texels[k + 2u]);
}

// Layer k's bilinear lookup towards d (its bordered tiles).
fn tex_sample(k: u32, d: vec3<f32>) -> vec3<f32> {
    let l = tex.layer[k];
    let p = tex_locate(l.mapping, f32(l.width), f32(l.height), d);
    let t = min(u32(p.z), l.tiles - 1u);
    let x = clamp(p.x + 0.5, 0.0, f32(l.tile_w - 1u));
    let y = clamp(p.y + 0.5, 0.0, f32(l.tile_h - 1u));
    let x0 = min(u32(floor(x)), l.tile_w - 2u);
    let y0 = min(u32(floor(y)), l.tile_h - 2u);
    let tx = x - f32(x0);
    let ty = y - f32(y0);
    let base = l.offset + t * l.tile_w * l.tile_h;
    let r0 = base + y0 * l.tile_w + x0;
    let r1 = r0 + l.tile_w;
    let top = mix(tex_texel(r0, 0u), tex_texel(r0, 1u), tx);
    let bot = mix(tex_texel(r1, 0u), tex_texel(r1, 1u), tx);
    return mix(top, bot, ty);
}

// The horizon band's weight at altitude h (degrees): frame/texture.rs
// `HorizonBand::weight`.
fn band_weight(h: f32) -> f32 {
    if (tex.band_softness_deg <= 0.0) {
        return select(0.0, 1.0, h < tex.band_height_deg);
    }
    let t = clamp((h - tex.band_height_deg) / tex.band_softness_deg, 0.0, 1.0);
    return 1.0 - t * t * (3.0 - 2.0 * t);
}

@compute @workgroup_size(8, 8, 1)
fn sky_texture(@builtin(global_invocation_id) gid: vec3<u32>) {
    if (!inside(gid)) {
        return;
    }
    let d4 = pixel_dir(f32(gid.x) + 0.5, f32(gid.y + frame.band_first_row) + 0.5);
    if (d4.w == 0.0) {
        return;
    }
    let d = d4.xyz;
    let td = vec3<f32>(dot(tex.rot_x, d), dot(tex.rot_y, d), dot(tex.rot_z, d));
    var c = vec3<f32>(0.0);
    for (var k = 0u; k < tex.layers; k = k + 1u) {
        c = c + tex.layer[k].gain * tex_sample(k, td);
    }
    if (tex.band_on != 0u) {
        let w = band_weight(degrees(asin(clamp(d.z, -1.0, 1.0))));
        c = mix(c, tex.band_color, w);
    }
    let i = gid.y * frame.width + gid.x;
    let behind = accum[i];
    accum[i] = vec4<f32>(mix(behind.xyz, c, tex.blend), behind.w);
}
