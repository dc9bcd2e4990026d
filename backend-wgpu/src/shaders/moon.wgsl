// Himmel wgpu backend: the Moon pass and the solar-eclipse corona.
//
// Compiled after frame.wgsl in one module (it uses `frame`, `accum`,
// `pixel_dir`), with its own bind group 1: the per-frame `Moon` uniform
// (constants and tables of skymodel moon.rs `MoonShader`, tabulated on the
// CPU) and the lunar albedo and normal maps (uploaded once).
//
// The Rust mirror of `Moon` is `MoonUniforms` (src/uniforms.rs) followed by
// `MOON_TABLE_ROWS` vec4 table rows; a test checks the layout naga computes.

struct Moon {
    // the disk's centre (ENU, unit, refracted)
    centre: vec3<f32>,
    // the drawn radius (rad)
    radius: f32,
    // celestial east at the (airless) centre (sky frame, unit)
    east: vec3<f32>,
    // sine of the drawn radius
    sin_radius: f32,
    // celestial north at the (airless) centre (sky frame, unit)
    north: vec3<f32>,
    // 1 when pixel directions are un-refracted first, 0 otherwise
    refract: u32,
    // Moon → Sun unit vector (sky frame)
    sun: vec3<f32>,
    // B(g) S(g) p/π: the sunlit BRDF factor without μ0/(μ0 + μ) and the
    // albedo (moon.rs `MoonShader`)
    sun_factor: f32,
    // selenographic axes in the sky frame (unit; z: the north pole)
    axis_x: vec3<f32>,
    // the angle a pixel subtends at the disk (rad)
    pixel_angle: f32,
    axis_y: vec3<f32>,
    // cosine of the disk's radius with its limb margin: the disk test
    cos_bound: f32,
    axis_z: vec3<f32>,
    _pad0: f32, // padding
    // sunlight at the Moon (linear sRGB)
    sun_rgb: vec3<f32>,
    // first node of the extinction table (line-of-sight zenith cosine)
    extinction_z0: f32,
    // earthshine (linear sRGB)
    earth_rgb: vec3<f32>,
    // extinction table node spacing (zenith cosine)
    extinction_dz: f32,
    // geocentric sky east in the sky frame (unit)
    geo_east: vec3<f32>,
    // first node of the refraction table (apparent altitude, rad)
    refraction_alt0: f32,
    // geocentric sky north in the sky frame (unit)
    geo_north: vec3<f32>,
    // refraction table node spacing (rad)
    refraction_dalt: f32,
    // lunar eclipse: the centre's offset from the shadow axis, east and
    // north (rad)
    shadow_east: f32,
    shadow_north: f32,
    // geocentric semidiameter (rad)
    semidiameter: f32,
    // axis distance of the eclipse table's last node (rad)
    shadow_last: f32,
    // table nodes: extinction, eclipse (0: no eclipse shading), refraction
    extinction_nodes: u32,
    eclipse_nodes: u32,
    refraction_nodes: u32,
    // sub-samples per pixel axis (0: analytic limb)
    subsamples: u32,
    // albedo map width and height (texels)
    albedo_width: u32,
    albedo_height: u32,
    // normal map width and height (texels)
    normal_width: u32,
    normal_height: u32,
    // the disk's pixel rectangle [x0, x1) × [y0, y1)
    disk_x0: u32,
    disk_y0: u32,
    disk_x1: u32,
    disk_y1: u32,
    // the corona's pixel rectangle [x0, x1) × [y0, y1)
    corona_x0: u32,
    corona_y0: u32,
    corona_x1: u32,
    corona_y1: u32,
    // corona: cos of its outer radius (6 R☉)
    corona_cos_outer: f32,
    // the Sun's and the Moon's drawn radii (rad)
    corona_sun_radius: f32,
    corona_moon_radius: f32,
    // the camera's largest pixel angle (rad)
    max_pixel_angle: f32,
    // corona table: first node and node spacing (zenith cosine), nodes
    corona_z0: f32,
    corona_dz: f32,
    corona_nodes: u32,
    // the profile at 6 R☉ (subtracted)
    corona_floor: f32,
    // extinction at MOON_EXT, refraction at MOON_REFR, eclipse at
    // MOON_ECL, corona at MOON_COR
    tables: array<vec4<f32>, 304>,
}

const MOON_EXT: u32 = 0u;
const MOON_REFR: u32 = 16u;
const MOON_ECL: u32 = 80u;
const MOON_COR: u32 = 240u;

@group(1) @binding(0) var<uniform> moon: Moon;
// the albedo map (w × h), then the normal map's (east, north) pairs
@group(1) @binding(1) var<storage, read> moon_maps: array<f32>;

// atan2 with the degree-11 minimax polynomial of moon.rs `fast_atan2`.
fn fast_atan2(y: f32, x: f32) -> f32 {
    let ax = abs(x);
    let ay = abs(y);
    let swap = ay > ax;
    let num = select(ay, ax, swap);
    let den = select(ax, ay, swap);
    if (den == 0.0) {
        return 0.0;
    }
    let t = num / den;
    let t2 = t * t;
    var a = t * (0.99997726 + t2 * (-0.33262347 + t2 * (0.19354346
        + t2 * (-0.11643287 + t2 * (0.05265332 + t2 * -0.0117212)))));
    if (swap) {
        a = HALF_PI - a;
    }
    if (x < 0.0) {
        a = PI - a;
    }
    if (y < 0.0) {
        return -a;
    }
    return a;
}

// Texel coordinates of (lon, lat) on a w × h equirectangular map
// (moon.rs `AlbedoMap::sample`): columns i0, i1 (wrapping), rows j0, j1
// (clamped), and the bilinear fractions.
struct MapTexel {
    i: vec2<u32>,
    j: vec2<u32>,
    f: vec2<f32>,
}

fn map_texel(lon: f32, lat: f32, w: u32, h: u32) -> MapTexel {
    let u = (lon / TAU + 0.5) * f32(w) - 0.5;
    let v = clamp((0.5 - lat / PI) * f32(h) - 0.5, 0.0, f32(h - 1u));
    let i0f = floor(u);
    let j0f = floor(v);
    // i0f wrapped into [0, w) (rem_euclid) in float: exact for these
    // integers, and no integer division (scalarised on CPU adapters).
    let wf = f32(w);
    let i0 = u32(i0f - wf * floor(i0f / wf));
    let j0 = u32(j0f);
    var t: MapTexel;
    t.i = vec2<u32>(i0, select(i0 + 1u, 0u, i0 + 1u >= w));
    t.j = vec2<u32>(j0, min(j0 + 1u, h - 1u));
    t.f = vec2<f32>(u - i0f, v - j0f);
    return t;
}

fn moon_albedo(lon: f32, lat: f32) -> f32 {
    let w = moon.albedo_width;
    let t = map_texel(lon, lat, w, moon.albedo_height);
    let a = moon_maps[t.j.x * w + t.i.x] * (1.0 - t.f.x) + moon_maps[t.j.x * w + t.i.y] * t.f.x;
    let b = moon_maps[t.j.y * w + t.i.x] * (1.0 - t.f.x) + moon_maps[t.j.y * w + t.i.y] * t.f.x;
    return a * (1.0 - t.f.y) + b * t.f.y;
}

fn normal_texel(base: u32, w: u32, i: u32, j: u32) -> vec2<f32> {
    let k = base + 2u * (j * w + i);
    return vec2<f32>(moon_maps[k], moon_maps[k + 1u]);
}

// The normal map's (east, north) components (moon.rs `NormalMap::sample`).
fn moon_normal(lon: f32, lat: f32) -> vec2<f32> {
    let base = moon.albedo_width * moon.albedo_height;
    let w = moon.normal_width;
    let t = map_texel(lon, lat, w, moon.normal_height);
    let a = normal_texel(base, w, t.i.x, t.j.x) * (1.0 - t.f.x) + normal_texel(base, w, t.i.y, t.j.x) * t.f.x;
    let b = normal_texel(base, w, t.i.x, t.j.y) * (1.0 - t.f.x) + normal_texel(base, w, t.i.y, t.j.y) * t.f.x;
    return a * (1.0 - t.f.y) + b * t.f.y;
}

// moon.rs `unrefract`: the apparent altitude lowered by Bennett's
// refraction (tabulated on the CPU over the disk's altitudes), azimuth kept.
fn moon_unrefract(d: vec3<f32>) -> vec3<f32> {
    let alt = asin(clamp(d.z, -1.0, 1.0));
    let n = moon.refraction_nodes - 1u;
    let x = clamp((alt - moon.refraction_alt0) / moon.refraction_dalt, 0.0, f32(n));
    let i = min(u32(x), n - 1u);
    let r = mix(moon.tables[MOON_REFR + i].x, moon.tables[MOON_REFR + i + 1u].x, x - f32(i));
    let hz = sqrt(d.x * d.x + d.y * d.y);
    if (hz < 1e-9) {
        return d;
    }
    let s = sin(alt - r);
    let c = cos(alt - r);
    return vec3<f32>(d.x / hz * c, d.y / hz * c, s);
}

// moon.rs `MoonShader::sky_xy`: offsets east and north in disk radii.
fn moon_sky_xy(d0: vec3<f32>) -> vec2<f32> {
    var d = d0;
    if (moon.refract != 0u) {
        d = moon_unrefract(d0);
    }
    return vec2<f32>(dot(d, moon.east), dot(d, moon.north)) / moon.sin_radius;
}

// moon.rs `MoonShader::radiance`: linear sRGB (cd/m²) at sky-frame surface
// point p whose line of sight has ENU z component z.
fn moon_radiance(p: vec3<f32>, z: f32) -> vec3<f32> {
    let ax = moon.axis_x;
    let ay = moon.axis_y;
    let az = moon.axis_z;
    let sx = dot(p, ax);
    let sy = dot(p, ay);
    let sz = dot(p, az);
    let cl = sqrt(sx * sx + sy * sy);
    let lat = fast_atan2(sz, cl);
    let lon = fast_atan2(sy, sx);
    let alb = moon_albedo(lon, lat);
    let fade = min(p.z * 5.0, 1.0);
    var n = p;
    if (cl > 1e-4 && fade > 0.0) {
        let t = moon_normal(lon, lat) * fade;
        let east = cross(az, p) / cl;
        let north = (az - p * sz) / cl;
        let up = sqrt(max(1.0 - t.x * t.x - t.y * t.y, 0.0));
        n = east * t.x + north * t.y + p * up;
    }
    let mu = max(n.z, 0.0);
    let s = moon.sun;
    var mu0 = 0.0;
    if (dot(p, s) > 0.0) {
        mu0 = dot(n, s);
    }
    var ls = 0.0;
    if (mu0 > 0.0) {
        ls = mu0 / max(mu0 + mu, 1e-6);
    }
    let direct = moon.sun_factor * ls * alb;
    var sun = moon.sun_rgb;
    let ne = moon.eclipse_nodes;
    if (ne > 0u) {
        let de = moon.shadow_east + moon.semidiameter * dot(p, moon.geo_east);
        let dn = moon.shadow_north + moon.semidiameter * dot(p, moon.geo_north);
        let d = sqrt(de * de + dn * dn);
        let last = f32(ne - 1u);
        let x = min(d / moon.shadow_last * last, last);
        let i0 = u32(floor(x));
        let i1 = min(i0 + 1u, ne - 1u);
        let f = x - f32(i0);
        sun = sun * (moon.tables[MOON_ECL + i0].xyz * (1.0 - f) + moon.tables[MOON_ECL + i1].xyz * f);
    }
    let nz = moon.extinction_nodes;
    let zx = clamp((z - moon.extinction_z0) / moon.extinction_dz, 0.0, f32(nz - 1u));
    let j0 = u32(floor(zx));
    let j1 = min(j0 + 1u, nz - 1u);
    let fz = zx - f32(j0);
    let t = moon.tables[MOON_EXT + j0].xyz * (1.0 - fz) + moon.tables[MOON_EXT + j1].xyz * fz;
    return (sun * direct + moon.earth_rgb * alb) * t;
}

// Radiance (xyz) and coverage (w) of the disk's part of the pixel whose
// centre direction is d (moon.rs `MoonShader::shade`: analytic limb).
fn moon_shade(d: vec3<f32>) -> vec4<f32> {
    let xy = moon_sky_xy(d);
    let r = sqrt(xy.x * xy.x + xy.y * xy.y);
    let cov = clamp((1.0 - r) * moon.radius / moon.pixel_angle + 0.5, 0.0, 1.0);
    if (cov <= 0.0 || dot(d, moon.centre) <= 0.0) {
        return vec4<f32>(0.0);
    }
    var p: vec3<f32>;
    if (r >= 1.0) {
        p = vec3<f32>(xy.x / r, xy.y / r, 0.0);
    } else {
        p = vec3<f32>(xy.x, xy.y, sqrt(1.0 - r * r));
    }
    return vec4<f32>(moon_radiance(p, d.z), cov);
}

// moon_pass.rs `supersample`: n × n sub-samples of pixel (px, py); those
// below the horizon are hidden by the ground.
fn moon_supersample(px: u32, py: u32, n: u32) -> vec4<f32> {
    var acc = vec3<f32>(0.0);
    var hits = 0u;
    let inv = 1.0 / f32(n);
    for (var j = 0u; j < n; j = j + 1u) {
        for (var i = 0u; i < n; i = i + 1u) {
            let s4 = pixel_dir(f32(px) + (f32(i) + 0.5) * inv, f32(py) + (f32(j) + 0.5) * inv);
            if (s4.w == 0.0) {
                continue;
            }
            let sd = s4.xyz;
            if (sd.z < 0.0) {
                continue;
            }
            // moon.rs `covers_exact`, then `surface_point`.
            let xy = moon_sky_xy(sd);
            let r2 = xy.x * xy.x + xy.y * xy.y;
            if (dot(sd, moon.centre) <= 0.0 || r2 >= 1.0) {
                continue;
            }
            acc = acc + moon_radiance(vec3<f32>(xy.x, xy.y, sqrt(1.0 - r2)), sd.z);
            hits = hits + 1u;
        }
    }
    if (hits == 0u) {
        return vec4<f32>(0.0);
    }
    return vec4<f32>(acc / f32(hits), f32(hits) / f32(n * n));
}

// The pixel (x, y) of invocation `gid` of a dispatch over the pixel
// rectangle [x0, x1) × [y0, y1) ∩ this band, and z = 1 when it lies
// inside (0 for the workgroups' overhang).
fn rect_pixel(gid: vec3<u32>, x0: u32, y0: u32, x1: u32, y1: u32) -> vec3<u32> {
    let px = gid.x + x0;
    let py = gid.y + max(y0, frame.band_first_row);
    let inside = px < x1 && py < min(y1, frame.band_first_row + frame.band_rows);
    return vec3<u32>(px, py, select(0u, 1u, inside));
}

// Moon pass (moon_pass.rs `render`): the opaque disk replaces what the
// earlier passes (Milky Way, stars, planets) drew, by its coverage.
// Dispatched over the disk's rectangle ∩ this band.
@compute @workgroup_size(8, 8, 1)
fn moon_disk(@builtin(global_invocation_id) gid: vec3<u32>) {
    let p = rect_pixel(gid, moon.disk_x0, moon.disk_y0, moon.disk_x1, moon.disk_y1);
    let px = p.x;
    let py = p.y;
    if (p.z == 0u) {
        return;
    }
    let d4 = pixel_dir(f32(px) + 0.5, f32(py) + 0.5);
    let d = d4.xyz;
    if (d4.w == 0.0 || dot(d, moon.centre) < moon.cos_bound) {
        return;
    }
    var s: vec4<f32>;
    let n = moon.subsamples;
    if (n == 0u) {
        // The ground hides the Moon below the horizon.
        if (d.z < 0.0) {
            return;
        }
        s = moon_shade(d);
    } else {
        s = moon_supersample(px, py, n);
    }
    if (s.w <= 0.0) {
        return;
    }
    let i = (py - frame.band_first_row) * frame.width + px;
    let a = accum[i];
    accum[i] = vec4<f32>(a.xyz * (1.0 - s.w) + s.xyz * s.w, a.w);
}

// Baumbach's inner corona relative to the disk's mean radiance at r solar
// radii (sun.rs `corona_relative`).
fn corona_relative(r: f32) -> f32 {
    if (r < 1.0) {
        return 0.0;
    }
    let r2 = r * r;
    let r7 = r2 * r2 * r2 * r;
    let r17 = r7 * r7 * r2 * r;
    return 1e-6 * (0.0532 * pow(r, -2.5) + 1.425 / r7 + 2.565 / r17);
}

// The inner corona of an eclipsed Sun (moon_pass.rs `render_corona`), part
// of the Sun pass: the profile less its value at 6 R☉, times the disk's mean
// radiance and the transmittance (tabulated over the line of sight's
// zenith cosine), hidden by the Moon's anti-aliased disk.
@compute @workgroup_size(8, 8, 1)
fn corona(@builtin(global_invocation_id) gid: vec3<u32>) {
    let p = rect_pixel(gid, moon.corona_x0, moon.corona_y0, moon.corona_x1, moon.corona_y1);
    let px = p.x;
    let py = p.y;
    if (p.z == 0u) {
        return;
    }
    let d4 = pixel_dir(f32(px) + 0.5, f32(py) + 0.5);
    let d = d4.xyz;
    let sun = frame.sun;
    if (d4.w == 0.0 || d.z < 0.0 || dot(d, sun) < moon.corona_cos_outer) {
        return;
    }
    let r = atan2(length(cross(d, sun)), dot(d, sun)) / moon.corona_sun_radius;
    let rel = corona_relative(r) - moon.corona_floor;
    if (rel <= 0.0) {
        return;
    }
    let mc = frame.eclipse_moon;
    let gm = atan2(length(cross(d, mc)), dot(d, mc));
    let visible = 1.0 - clamp((moon.corona_moon_radius - gm) / moon.max_pixel_angle + 0.5, 0.0, 1.0);
    if (visible <= 0.0) {
        return;
    }
    let nc = moon.corona_nodes;
    let x = clamp((d.z - moon.corona_z0) / moon.corona_dz, 0.0, f32(nc - 1u));
    let k = min(u32(x), nc - 2u);
    let t = mix(moon.tables[MOON_COR + k].xyz, moon.tables[MOON_COR + k + 1u].xyz, x - f32(k));
    let i = (py - frame.band_first_row) * frame.width + px;
    accum[i] = accum[i] + vec4<f32>(t * (rel * visible), 0.0);
}
