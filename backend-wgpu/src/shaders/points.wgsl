// Himmel wgpu backend: the point sources (compiled after frame.wgsl): the
// stars' and the planets' footprints, tiled (`stars`, `planets`), and the
// footprint and tile helpers that quads.wgsl (compiled after this file)
// shares. Its uniforms are `Frame` and `Night`, its records `Point` (Rust
// `FrameUniforms`, `NightUniforms`, `PointRecord`).

// One point source's footprint at pixel (px, py) (centre fx, fy), as
// radiance × solid angle (divide by the pixel's solid angle): stars.rs
// `splat_at` — the Gaussian core (weights normalised on the CPU) and the
// glare disk. `below`: the pixel shows the ground or nothing; `face`: the
// pixel's cube face. Both point-source methods call it: the tiles
// (`point_sources`) and the instanced quads (quads.wgsl `quad_fs`).
fn point_footprint(s: Point, px: u32, py: u32, fx: f32, fy: f32, below: bool, face: i32) -> vec3<f32> {
    if ((s.near_horizon != 0u && below) || (frame.projection == 3u && s.face != face)) {
        return vec3<f32>(0.0);
    }
    let r = i32(night.core_radius);
    let rr = night.core_radius * night.core_radius + 0.5;
    let inv2s2 = night.inv_two_sigma2;
    let di = i32(px) - s.pixel_x;
    let dj = i32(py) - s.pixel_y;
    let dx = fx - s.x;
    let dy = fy - s.y;
    let d2 = dx * dx + dy * dy;
    var v = 0.0;
    if (abs(di) <= r && abs(dj) <= r && d2 <= rr) {
        v = s.core_scale * exp(-(dx * dx) * inv2s2) * exp(-(dy * dy) * inv2s2);
    }
    let rg = s.glare_radius;
    if (rg > 0.0) {
        let dd = sqrt(d2);
        let rgi = i32(ceil(rg));
        if (abs(di) <= rgi && abs(dj) <= rgi && dd < rg) {
            let x = 1.0 - dd / rg;
            v = v + s.glare_scale * x * x;
        }
    }
    return v * s.colour;
}

// The cube face of strip column px (0 for the other projections).
fn point_face(px: u32) -> i32 {
    if (frame.projection == 3u) {
        return i32(px / frame.face_size);
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
    let ts = night.tile_size;
    p.x = (p.t % night.tiles_per_row) * ts + lid.x;
    p.y = (p.t / night.tiles_per_row) * ts + lid.y;
    p.ok = p.x < frame.width && p.y >= frame.band_first_row && p.y < frame.band_first_row + frame.band_rows;
    return p;
}

// Point sources, tiled: each pixel sums the footprints of the sources
// listed for its 8 × 8 tile (no atomics) over the pixel's solid angle. One
// workgroup per non-empty tile (listed from word `first` on).
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
    let i = (py - frame.band_first_row) * frame.width + px;
    accum[i] = accum[i] + vec4<f32>(acc / omega, 0.0);
}

// Stars pass: the catalogue stars' footprints.
@compute @workgroup_size(8, 8, 1)
fn stars(
    @builtin(workgroup_id) wg: vec3<u32>,
    @builtin(num_workgroups) nwg: vec3<u32>,
    @builtin(local_invocation_id) lid: vec3<u32>,
) {
    point_sources(wg, nwg, lid, night.star_list, night.star_busy_first, night.star_busy_count);
}

// Planets pass: Mercury–Saturn's footprints.
@compute @workgroup_size(8, 8, 1)
fn planets(
    @builtin(workgroup_id) wg: vec3<u32>,
    @builtin(num_workgroups) nwg: vec3<u32>,
    @builtin(local_invocation_id) lid: vec3<u32>,
) {
    point_sources(wg, nwg, lid, night.planet_list, night.planet_busy_first, night.planet_busy_count);
}
