// Himmel wgpu backend: the sky passes as compute shaders.
//
// Every pass adds its radiance (linear sRGB, cd/m²) into `accum`, one
// vec4 per pixel of the image (a cube map is the 6H×H strip of
// conventions.md), back to front; `store` then writes the sum into the
// rgba32float target texture (one layer, or six cube faces), alpha = 1
// where the projection shows the scene. The Moon pass and the corona are
// entry points of the same shape in moon.wgsl (compiled after this file).
//
// The Rust mirror of `Frame` is `FrameUniforms` (src/uniforms.rs); a test
// checks the layout naga computes for this struct against it.

struct Frame {
    // image width, height (the strip for a cube map), projection
    // (0 fisheye, 1 equirect, 2 perspective, 3 cubemap), cube face size
    size: vec4<u32>,
    // perspective basis (ENU): forward (w: tan(fov/2)), right, up
    persp_f: vec4<f32>,
    persp_r: vec4<f32>,
    persp_u: vec4<f32>,
    // Sun centre (ENU unit), w: cos of the supersampling margin
    sun: vec4<f32>,
    // disk: cos(radius), sin(radius), z_min, z_max of the Sun table
    disk: vec4<f32>,
    // sky-view LUT width, height; Sun table ρ nodes, z nodes
    tables: vec4<u32>,
    // Sun sub-samples per axis; first pixel (x, y) of the Sun dispatch; 0
    opts: vec4<u32>,
    // the band of rows this dispatch renders: first row, row count
    // (`accum` holds the band; frames beyond the buffer limits are banded)
    band: vec4<u32>,
    // the Moon's centre (ENU unit); w: 1 when `sky` also holds the moonlit
    // sky view (cpu lib.rs `SkyLight`), 0 otherwise
    moon: vec4<f32>,
    // solar eclipses: the Moon's centre (ENU unit) and the sine of its
    // drawn radius; the Sun pass skips sub-samples behind its disk
    eclipse: vec4<f32>,
}

@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(1) var<storage, read_write> accum: array<vec4<f32>>;
// the sky-view LUT (w × h texels), then the ground luminance below the
// horizon; on a moonlit night the same again for the sky lit by the Moon
@group(0) @binding(2) var<storage, read> sky: array<vec4<f32>>;
@group(0) @binding(3) var<storage, read> sun_table: array<vec4<f32>>;
@group(0) @binding(4) var target_tex: texture_storage_2d_array<rgba32float, write>;

// The diffuse night sky (skymodel milkyway.rs `NightBackground`). The Rust
// mirror is `NightUniforms` (src/uniforms.rs).
struct Night {
    // rows of the ENU → ICRS rotation; w: sin ε, cos ε (J2000 obliquity),
    // (R / (R + h))² of the airglow layer (van Rhijn)
    enu_to_icrs_x: vec4<f32>,
    enu_to_icrs_y: vec4<f32>,
    enu_to_icrs_z: vec4<f32>,
    // linear sRGB, cd/m²: airglow at the zenith, zodiacal light per S10,
    // faint-star floor
    airglow: vec4<f32>,
    zodiacal: vec4<f32>,
    floor: vec4<f32>,
    // Milky Way map width, height; extinction table nodes; reserved
    dims: vec4<u32>,
    // point sources: tile size (px), tiles per row, first word of the
    // stars' and of the planets' tile lists in `tiles`
    tiles: vec4<u32>,
    // point sources: core radius r (px), reserved; 1 / (2σ²) (px⁻²), the
    // quad target's scale (quads.wgsl; a power of two, 1 for rgba32float)
    psf: vec4<f32>,
    // point sources: first word of the stars' and of the planets' non-empty
    // tile indices in `tiles`, and their numbers
    busy: vec4<u32>,
}

// One point source's footprint (stars.rs `SplatPlan`; equirect sources
// near the seam have one copy per wrap): position (px), core scale, glare
// radius (px); colour (luminance 1), glare scale; ⌊cx⌋, ⌊cy⌋, cube face,
// 1 when checked against the ground.
struct Point {
    a: vec4<f32>,
    b: vec4<f32>,
    c: vec4<i32>,
}

@group(0) @binding(5) var<uniform> night: Night;
// the Milky Way map (plate carrée in ICRS, linear sRGB cd/m², row-major
// from δ = +90°, α = 90°)
@group(0) @binding(6) var<storage, read> mw_map: array<vec4<f32>>;
// extinction at μ = i / (n − 1): linear sRGB factors; w: the refraction
// (rad) to take off the apparent altitude asin μ
@group(0) @binding(7) var<storage, read> extinction: array<vec4<f32>>;
@group(0) @binding(8) var<storage, read> points: array<Point>;
// per list: the first index of each tile (tiles + 1 words, absolute), then
// the point indices of every tile, then the indices of the non-empty tiles
@group(0) @binding(9) var<storage, read> tiles: array<u32>;

const PI: f32 = 3.14159265358979;
const HALF_PI: f32 = 1.57079632679490;
const TAU: f32 = 6.28318530717959;

fn enu_from_alt_az(alt: f32, az: f32) -> vec3<f32> {
    let ca = cos(alt);
    return vec3<f32>(ca * sin(az), ca * cos(az), sin(alt));
}

// The ENU direction at continuous image position (px, py), projection.rs
// `Camera::pixel_to_dir` in f32; w = 1 where the projection shows the
// scene, 0 outside (fisheye beyond 180° from the zenith).
fn pixel_dir(px: f32, py: f32) -> vec4<f32> {
    let w = f32(frame.size.x);
    let h = f32(frame.size.y);
    let p = frame.size.z;
    if (p == 0u) {
        let dx = px - w * 0.5;
        let dy = py - h * 0.5;
        let r = min(w, h) * 0.5;
        let rho = sqrt(dx * dx + dy * dy);
        let zen = HALF_PI * rho / r;
        if (zen > PI) {
            return vec4<f32>(0.0);
        }
        if (rho <= 0.0) {
            return vec4<f32>(0.0, 0.0, 1.0, 1.0);
        }
        let s = sin(zen);
        return vec4<f32>(-dx / rho * s, -dy / rho * s, cos(zen), 1.0);
    } else if (p == 1u) {
        let az = TAU * px / w;
        let alt = clamp(HALF_PI - PI * py / h, -HALF_PI, HALF_PI);
        return vec4<f32>(enu_from_alt_az(alt, az), 1.0);
    } else if (p == 2u) {
        let t = frame.persp_f.w;
        let nx = (px - w * 0.5) / (h * 0.5) * t;
        let ny = -(py - h * 0.5) / (h * 0.5) * t;
        let d = frame.persp_f.xyz + frame.persp_r.xyz * nx + frame.persp_u.xyz * ny;
        return vec4<f32>(normalize(d), 1.0);
    }
    // Cube map strip: OpenGL face table (major axis, sc, tc) in the scene
    // frame (x East, y Up, z South), faces +X −X +Y −Y +Z −Z.
    let fs = f32(frame.size.w);
    let face = clamp(i32(floor(px / fs)), 0, 5);
    let s = (px - f32(face) * fs) / fs;
    let t = py / fs;
    let sc = 2.0 * s - 1.0;
    let tc = 2.0 * t - 1.0;
    var v: vec3<f32>;
    switch face {
        case 0: { v = vec3<f32>(1.0, -tc, -sc); }
        case 1: { v = vec3<f32>(-1.0, -tc, sc); }
        case 2: { v = vec3<f32>(sc, 1.0, tc); }
        case 3: { v = vec3<f32>(sc, -1.0, -tc); }
        case 4: { v = vec3<f32>(sc, -tc, 1.0); }
        default: { v = vec3<f32>(-sc, -tc, -1.0); }
    }
    v = normalize(v);
    // Scene frame → ENU.
    return vec4<f32>(v.x, -v.z, v.y, 1.0);
}

// Bruneton (2017) GetTextureCoordFromUnitRange (lut.rs `tex_from_unit`).
fn tex_from_unit(x: f32, n: u32) -> f32 {
    let nf = f32(n);
    return 0.5 / nf + x * (1.0 - 1.0 / nf);
}

// Bilinear lookup of the sky-view LUT starting at texel `base` at
// (u, v) ∈ [0, 1]² with texel centres at (i + 0.5)/n, clamped
// (lut.rs `Lut2::sample_rgb`).
fn sky_sample(base: u32, u: f32, v: f32) -> vec3<f32> {
    let w = frame.tables.x;
    let h = frame.tables.y;
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
        return sky[base + frame.tables.x * frame.tables.y].xyz;
    }
    let e = asin(min(dir.z, 1.0));
    let cr = dir.x * light.y - dir.y * light.x;
    let dt = dir.x * light.x + dir.y * light.y;
    var az = 0.0;
    if (cr != 0.0 || dt != 0.0) {
        az = atan2(abs(cr), dt);
    }
    let u = tex_from_unit(az / PI, frame.tables.x);
    let v = tex_from_unit(sqrt(e / HALF_PI), frame.tables.y);
    return sky_sample(base, u, v);
}

// Sky radiance for an ENU direction (cpu lib.rs `SkyLight::radiance`): the
// Sun's sky view plus, on a moonlit night, the Moon's.
fn sky_radiance(dir: vec3<f32>) -> vec3<f32> {
    var l = view_radiance(dir, frame.sun.xyz, 0u);
    if (frame.moon.w != 0.0) {
        l = l + view_radiance(dir, frame.moon.xyz, frame.tables.x * frame.tables.y + 1u);
    }
    return l;
}

// The Sun table: linear sRGB radiance (cd/m²) of the disk at normalised
// disk radius ρ = sin γ / sin R (nodes sin(π/2 · i/(n−1)): uniform in
// asin ρ, dense at the limb where μ^α falls steeply) and line-of-sight zenith
// cosine z (nodes from z_min to z_max), limb darkening × transmittance.
fn sun_sample(rho: f32, z: f32) -> vec3<f32> {
    let nr = frame.tables.z;
    let nz = frame.tables.w;
    let x = asin(clamp(rho, 0.0, 1.0)) / HALF_PI * f32(nr - 1u);
    let span = max(frame.disk.w - frame.disk.z, 1e-12);
    let y = clamp((z - frame.disk.z) / span, 0.0, 1.0) * f32(nz - 1u);
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

fn inside(gid: vec3<u32>) -> bool {
    return gid.x < frame.size.x && gid.y < frame.band.y;
}

// Atmosphere pass: one sky-view lookup per pixel centre.
@compute @workgroup_size(8, 8, 1)
fn atmosphere(@builtin(global_invocation_id) gid: vec3<u32>) {
    if (!inside(gid)) {
        return;
    }
    let d = pixel_dir(f32(gid.x) + 0.5, f32(gid.y + frame.band.x) + 0.5);
    if (d.w == 0.0) {
        return;
    }
    let i = gid.y * frame.size.x + gid.x;
    accum[i] = accum[i] + vec4<f32>(sky_radiance(d.xyz), 0.0);
}

// Sun pass: pixels within the margin of the disk are supersampled
// (n × n sub-pixel directions), as the CPU backend does. Dispatched over the
// pixel rectangle that holds the margin, from (opts.y, opts.z).
@compute @workgroup_size(8, 8, 1)
fn sun(@builtin(global_invocation_id) gid: vec3<u32>) {
    let px = gid.x + frame.opts.y;
    let py = gid.y + frame.opts.z;
    if (px >= frame.size.x || py >= frame.band.x + frame.band.y) {
        return;
    }
    let d = pixel_dir(f32(px) + 0.5, f32(py) + 0.5);
    let c = frame.sun.xyz;
    if (d.w == 0.0 || dot(d.xyz, c) < frame.sun.w) {
        return;
    }
    let n = frame.opts.x;
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
            let mc = frame.eclipse.xyz;
            let behind_moon = dot(sd, mc) > 0.0 && length(cross(sd, mc)) < frame.eclipse.w;
            // The disk test by the sine of the angle from the centre
            // (sun.rs `SunDisk::covers`: a cosine test near 1 is not
            // accurate in f32).
            let sc = length(cross(sd, c));
            if (sd.z < 0.0 || dot(sd, c) <= 0.0 || sc >= frame.disk.y || behind_moon) {
                continue;
            }
            let rho = min(sc / frame.disk.y, 1.0);
            acc = acc + sun_sample(rho, sd.z);
        }
    }
    let i = (py - frame.band.x) * frame.size.x + px;
    accum[i] = accum[i] + vec4<f32>(acc * (inv * inv), 0.0);
}

// The Milky Way map towards the ICRS unit vector `u`: bilinear, wrapping in
// right ascension (milkyway.rs `MilkyWayMap::radiance`).
fn milkyway_map(u: vec3<f32>) -> vec3<f32> {
    let w = night.dims.x;
    let h = night.dims.y;
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
    let n = night.dims.z - 1u;
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
    let d4 = pixel_dir(f32(gid.x) + 0.5, f32(gid.y + frame.band.x) + 0.5);
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
        dot(night.enu_to_icrs_x.xyz, dt),
        dot(night.enu_to_icrs_y.xyz, dt),
        dot(night.enu_to_icrs_z.xyz, dt),
    );
    let se = night.enu_to_icrs_x.w;
    let ce = night.enu_to_icrs_y.w;
    let sb = clamp(-se * u.y + ce * u.z, -1.0, 1.0);
    let c2 = max(1.0 - sb * sb, 0.0);
    let zl = 60.0 + 140.0 * c2 * c2;
    let k2 = night.enu_to_icrs_z.w;
    let ag = 1.0 / sqrt(max(1.0 - k2 * max(1.0 - d.z * d.z, 0.0), 1e-6));
    let l = milkyway_map(u) + night.floor.xyz + night.zodiacal.xyz * zl + night.airglow.xyz * ag;
    let i = gid.y * frame.size.x + gid.x;
    accum[i] = accum[i] + vec4<f32>(l * t.xyz, 0.0);
}

// The solid angle (sr) of the pixel centred at (px, py): projection.rs
// `Camera::pixel_solid_angle` in f32.
fn pixel_omega(px: f32, py: f32) -> f32 {
    let w = f32(frame.size.x);
    let h = f32(frame.size.y);
    let p = frame.size.z;
    if (p == 0u) {
        let a = HALF_PI / (min(w, h) * 0.5);
        let dx = px - w * 0.5;
        let dy = py - h * 0.5;
        let z = a * sqrt(dx * dx + dy * dy);
        if (z > PI) {
            return 0.0;
        }
        if (z < 1e-9) {
            return a * a;
        }
        return a * a * sin(z) / z;
    } else if (p == 1u) {
        let row = floor(py);
        let h0 = HALF_PI - PI * (row + 1.0) / h;
        let h1 = HALF_PI - PI * row / h;
        return TAU / w * abs(sin(h1) - sin(h0));
    }
    var s = 2.0 / h;
    var x = 0.0;
    if (p == 2u) {
        s = 2.0 * frame.persp_f.w / h;
        x = (px - w * 0.5) * s;
    } else {
        let face = clamp(floor(px / h), 0.0, 5.0);
        x = (px - face * h) * s - 1.0;
    }
    var y = (py - h * 0.5) * s;
    if (p == 3u) {
        y = py * s - 1.0;
    }
    let q = 1.0 + x * x + y * y;
    return s * s / (q * sqrt(q));
}

// One point source's footprint at pixel (px, py) (centre fx, fy), as
// radiance × solid angle (divide by the pixel's solid angle): stars.rs
// `splat_at` — the Gaussian core (weights normalised on the CPU) and the
// glare disk. `below`: the pixel shows the ground or nothing; `face`: the
// pixel's cube face. Both point-source methods call it: the tiles
// (`point_sources`) and the instanced quads (quads.wgsl `quad_fs`).
fn point_footprint(s: Point, px: u32, py: u32, fx: f32, fy: f32, below: bool, face: i32) -> vec3<f32> {
    if ((s.c.w != 0 && below) || (frame.size.z == 3u && s.c.z != face)) {
        return vec3<f32>(0.0);
    }
    let r = i32(night.psf.x);
    let rr = night.psf.x * night.psf.x + 0.5;
    let inv2s2 = night.psf.z;
    let di = i32(px) - s.c.x;
    let dj = i32(py) - s.c.y;
    let dx = fx - s.a.x;
    let dy = fy - s.a.y;
    let d2 = dx * dx + dy * dy;
    var v = 0.0;
    if (abs(di) <= r && abs(dj) <= r && d2 <= rr) {
        v = s.a.z * exp(-(dx * dx) * inv2s2) * exp(-(dy * dy) * inv2s2);
    }
    let rg = s.a.w;
    if (rg > 0.0) {
        let dd = sqrt(d2);
        let rgi = i32(ceil(rg));
        if (abs(di) <= rgi && abs(dj) <= rgi && dd < rg) {
            let x = 1.0 - dd / rg;
            v = v + s.b.w * x * x;
        }
    }
    return v * s.b.xyz;
}

// The cube face of strip column px (0 for the other projections).
fn point_face(px: u32) -> i32 {
    if (frame.size.z == 3u) {
        return i32(px / frame.size.w);
    }
    return 0;
}

// The pixel of invocation `lid` in the busy tile of workgroup `wg` (one
// workgroup per non-empty 8 × 8 tile, listed from word `first` of `tiles`,
// `n` of them): the tile's index `t`, the pixel (x, y), and whether the
// pixel is in this band's image.
struct TilePixel {
    t: u32,
    x: u32,
    y: u32,
    ok: bool,
}

fn busy_tile_pixel(wg: vec3<u32>, nwg: vec3<u32>, lid: vec3<u32>, first: u32, n: u32) -> TilePixel {
    var p: TilePixel;
    let k = wg.y * nwg.x + wg.x;
    p.ok = k < n;
    if (!p.ok) {
        return p;
    }
    p.t = tiles[first + k];
    let ts = night.tiles.x;
    p.x = (p.t % night.tiles.y) * ts + lid.x;
    p.y = (p.t / night.tiles.y) * ts + lid.y;
    p.ok = p.x < frame.size.x && p.y >= frame.band.x && p.y < frame.band.x + frame.band.y;
    return p;
}

// Point sources, tiled: each pixel sums the footprints of the sources
// listed for its 8 × 8 tile (no atomics) over the pixel's solid angle. One
// workgroup per non-empty tile (`busy` words on).
fn point_sources(wg: vec3<u32>, nwg: vec3<u32>, lid: vec3<u32>, base: u32, first: u32, n: u32) {
    let tp = busy_tile_pixel(wg, nwg, lid, first, n);
    if (!tp.ok) {
        return;
    }
    let t = tp.t;
    let px = tp.x;
    let py = tp.y;
    let s0 = tiles[base + t];
    let s1 = tiles[base + t + 1u];
    if (s0 == s1) {
        return;
    }
    let fx = f32(px) + 0.5;
    let fy = f32(py) + 0.5;
    let omega = pixel_omega(fx, fy);
    if (omega <= 0.0) {
        return;
    }
    let d = pixel_dir(fx, fy);
    let below = d.w == 0.0 || d.z < 0.0;
    let face = point_face(px);
    var acc = vec3<f32>(0.0);
    for (var k = s0; k < s1; k = k + 1u) {
        acc = acc + point_footprint(points[tiles[k]], px, py, fx, fy, below, face);
    }
    let i = (py - frame.band.x) * frame.size.x + px;
    accum[i] = accum[i] + vec4<f32>(acc / omega, 0.0);
}

// Stars pass: the catalogue stars' footprints.
@compute @workgroup_size(8, 8, 1)
fn stars(
    @builtin(workgroup_id) wg: vec3<u32>,
    @builtin(num_workgroups) nwg: vec3<u32>,
    @builtin(local_invocation_id) lid: vec3<u32>,
) {
    point_sources(wg, nwg, lid, night.tiles.z, night.busy.x, night.busy.z);
}

// Planets pass: Mercury–Saturn's footprints.
@compute @workgroup_size(8, 8, 1)
fn planets(
    @builtin(workgroup_id) wg: vec3<u32>,
    @builtin(num_workgroups) nwg: vec3<u32>,
    @builtin(local_invocation_id) lid: vec3<u32>,
) {
    point_sources(wg, nwg, lid, night.tiles.w, night.busy.y, night.busy.w);
}

// Writes the accumulated radiance into the target (cube maps: face =
// strip column / face size), alpha = 1 where the projection shows the scene.
@compute @workgroup_size(8, 8, 1)
fn store(@builtin(global_invocation_id) gid: vec3<u32>) {
    if (!inside(gid)) {
        return;
    }
    let py = gid.y + frame.band.x;
    let d = pixel_dir(f32(gid.x) + 0.5, f32(py) + 0.5);
    let i = gid.y * frame.size.x + gid.x;
    var layer = 0u;
    var x = gid.x;
    if (frame.size.z == 3u) {
        layer = gid.x / frame.size.w;
        x = gid.x - layer * frame.size.w;
    }
    textureStore(target_tex, vec2<u32>(x, py), layer, vec4<f32>(accum[i].xyz, d.w));
}
