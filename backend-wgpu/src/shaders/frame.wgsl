// Himmel wgpu backend: what every image pass shares (prepended to each
// pass's file: atmosphere.wgsl, sun.wgsl, milkyway.wgsl, points.wgsl,
// store.wgsl, moon.wgsl, and points.wgsl + quads.wgsl; src/uniforms.rs
// builds one module per pass; texture.wgsl and clouds.wgsl are built
// beside their passes, passes/texture.rs and passes/clouds.rs).
//
// Every pass adds its radiance (linear sRGB, cd/m²) into `accum`, one
// vec4 per pixel of the image (a cube map is the 6H×H strip of
// conventions.md), back to front; `store` then writes the sum into the
// rgba32float target texture (one layer, or six cube faces), alpha = 1
// where the projection shows the scene. All passes bind the same group 0
// (declared here), so one bind group serves every pass.
//
// The Rust mirrors (src/uniforms.rs): `Frame` is `FrameUniforms`, `Night`
// is `NightUniforms`, `Point` is `PointRecord`; tests check the layouts
// naga computes for these structs against them. A vec3<f32> has alignment
// 16 and size 12 (WGSL spec, "Alignment and Size"), so each is followed by a
// 4-byte scalar: a quantity of its own, or a `_pad` field that the Rust
// mirror spells out as well.

struct Frame {
    // image width and height (px; the 6H×H strip for a cube map)
    width: u32,
    height: u32,
    // projection: 0 fisheye, 1 equirect, 2 perspective, 3 cubemap
    // (Rust `projection_code`)
    projection: u32,
    // cube face size H (px)
    face_size: u32,
    // perspective camera: forward, right and up (ENU, unit)
    forward: vec3<f32>,
    // tan of half the vertical field of view
    tan_half_fov: f32,
    right: vec3<f32>,
    _pad0: f32, // padding
    up: vec3<f32>,
    _pad1: f32, // padding
    // the Sun's centre (ENU, unit)
    sun: vec3<f32>,
    // cos of the Sun pass's supersampling margin around the centre
    cos_sun_margin: f32,
    // the direction the moonlit sky view is lit from (the Moon's centre,
    // ENU, unit; zero when `moonlit` is 0)
    moonlight: vec3<f32>,
    // 1 when `sky` also holds the moonlit sky view after the Sun's (cpu
    // lib.rs `SkyLight`), 0 otherwise
    moonlit: u32,
    // solar eclipses: the Moon's centre (ENU, unit); the Sun pass skips
    // the sub-samples behind its disk
    eclipse_moon: vec3<f32>,
    // sine of the Moon's drawn radius
    sin_moon_radius: f32,
    // sine of the Sun's drawn radius
    sin_sun_radius: f32,
    // line-of-sight zenith cosines of the Sun table's first and last z node
    sun_z_min: f32,
    sun_z_max: f32,
    // Sun sub-samples per pixel axis
    sun_subsamples: u32,
    // Sun table nodes in ρ (normalised disk radius) and in z
    sun_rho_nodes: u32,
    sun_z_nodes: u32,
    // first pixel (x, y) of the Sun dispatch's rectangle in this band
    sun_x0: u32,
    sun_y0: u32,
    // sky-view LUT width and height (texels)
    sky_view_width: u32,
    sky_view_height: u32,
    // the band of rows this dispatch renders: first row, row count
    // (`accum` holds the band; frames beyond the buffer limits are banded)
    band_first_row: u32,
    band_rows: u32,
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
    // rows of the ENU → ICRS rotation
    enu_to_icrs_x: vec3<f32>,
    // sin ε (J2000 obliquity)
    sin_obliquity: f32,
    enu_to_icrs_y: vec3<f32>,
    // cos ε
    cos_obliquity: f32,
    enu_to_icrs_z: vec3<f32>,
    _pad0: f32, // padding
    // airglow at the zenith (linear sRGB, cd/m²)
    airglow: vec3<f32>,
    // (R / (R + h))² of the airglow layer (van Rhijn)
    van_rhijn_k2: f32,
    // zodiacal light per S10 (linear sRGB, cd/m²)
    zodiacal: vec3<f32>,
    _pad1: f32, // padding
    // faint-star floor (linear sRGB, cd/m²)
    floor: vec3<f32>,
    _pad2: f32, // padding
    // Milky Way map width and height (texels)
    map_width: u32,
    map_height: u32,
    // extinction table nodes
    extinction_nodes: u32,
    // point sources: tile size (px) and tiles per image row
    tile_size: u32,
    tiles_per_row: u32,
    // first word of the stars' and of the planets' tile list in `tiles`
    star_list: u32,
    planet_list: u32,
    // first word of the stars' and of the planets' non-empty tile indices
    // in `tiles`, and their numbers
    star_busy_first: u32,
    planet_busy_first: u32,
    star_busy_count: u32,
    planet_busy_count: u32,
    // core radius r (px; an integer)
    core_radius: f32,
    // 1 / (2σ²) of the Gaussian core (px⁻²)
    inv_two_sigma2: f32,
    // the quad target's scale (quads.wgsl; a power of two, 1 for
    // rgba32float)
    quad_scale: f32,
    _pad3: f32, // padding
    _pad4: f32, // padding
}

// One point source's footprint (stars.rs `SplatPlan`; equirect sources
// near the seam have one copy per wrap). The Rust mirror is `PointRecord`.
struct Point {
    // position (px, continuous image coordinates)
    x: f32,
    y: f32,
    // core scale (lux)
    core_scale: f32,
    // glare disk radius (px; 0: none)
    glare_radius: f32,
    // colour (linear sRGB, luminance 1)
    colour: vec3<f32>,
    // glare scale (lux)
    glare_scale: f32,
    // the pixel holding the position: ⌊x⌋, ⌊y⌋
    pixel_x: i32,
    pixel_y: i32,
    // cube face (0 for the other projections)
    face: i32,
    // 1 when the footprint is checked against the ground
    near_horizon: u32,
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
    let w = f32(frame.width);
    let h = f32(frame.height);
    let p = frame.projection;
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
        let t = frame.tan_half_fov;
        let nx = (px - w * 0.5) / (h * 0.5) * t;
        let ny = -(py - h * 0.5) / (h * 0.5) * t;
        let d = frame.forward + frame.right * nx + frame.up * ny;
        return vec4<f32>(normalize(d), 1.0);
    }
    // Cube map strip: OpenGL face table (major axis, sc, tc) in the scene
    // frame (x East, y Up, z South), faces +X −X +Y −Y +Z −Z.
    let fs = f32(frame.face_size);
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

// Whether invocation `gid` of a dispatch over this band's rows is a pixel
// of the image (the workgroups overhang it).
fn inside(gid: vec3<u32>) -> bool {
    return gid.x < frame.width && gid.y < frame.band_rows;
}

// The solid angle (sr) of the pixel centred at (px, py): projection.rs
// `Camera::pixel_solid_angle` in f32.
fn pixel_omega(px: f32, py: f32) -> f32 {
    let w = f32(frame.width);
    let h = f32(frame.height);
    let p = frame.projection;
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
        s = 2.0 * frame.tan_half_fov / h;
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
