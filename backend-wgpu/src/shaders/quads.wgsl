// Himmel wgpu backend: the point sources as instanced quads
// (`PointMethod::Quads`; compiled after frame.wgsl and points.wgsl in one
// module, with the quad target in bind group 1). One instance per
// footprint record (`points`, the same records as the tiled passes), six
// vertices per instance (two triangles, no geometry shader) covering the
// record's pixel bounds — the core's (2r + 1)² pixels and the glare disk's
// — within the current band (and, in a cube map, within the record's
// face); the fragment shader evaluates `point_footprint` (points.wgsl) at
// the pixel and returns radiance, added by the blend state (One, One) into
// a float target of the band's size. `quad_resolve_*` then adds that
// target into `accum` at the pass's place in the pass order. Its uniforms
// are `Frame` and `Night`, its records `Point` (Rust `FrameUniforms`,
// `NightUniforms`, `PointRecord`).

// The quad target of the band, read by `quad_resolve`.
@group(1) @binding(0) var quad_src: texture_2d<f32>;

struct QuadOut {
    @builtin(position) pos: vec4<f32>,
    @location(0) @interpolate(flat) id: u32,
}

@vertex
fn quad_vs(@builtin(vertex_index) v: u32, @builtin(instance_index) id: u32) -> QuadOut {
    let s = points[id];
    var reach = i32(night.core_radius);
    if (s.glare_radius > 0.0) {
        reach = max(reach, i32(ceil(s.glare_radius)));
    }
    // Pixel edges: the pixels c − reach ..= c + reach.
    var x0 = f32(s.pixel_x - reach);
    var x1 = f32(s.pixel_x + reach + 1);
    if (frame.projection == 3u) {
        // A footprint stays on its face.
        let fs = f32(frame.face_size);
        x0 = max(x0, f32(s.face) * fs);
        x1 = min(x1, f32(s.face + 1) * fs);
    }
    let y0 = f32(s.pixel_y - reach) - f32(frame.band_first_row);
    let y1 = f32(s.pixel_y + reach + 1) - f32(frame.band_first_row);
    var out: QuadOut;
    out.pos = quad_corner(x0, y0, x1, y1, v);
    out.id = id;
    return out;
}

// Corner `v` (0..5) of the pixel rectangle [x0, x1] × [y0, y1] (band
// rows) in clip space, as two triangles: (0, 0) (1, 0) (0, 1), (0, 1)
// (1, 0) (1, 1).
fn quad_corner(x0: f32, y0: f32, x1: f32, y1: f32, v: u32) -> vec4<f32> {
    let cx = array<f32, 6>(0.0, 1.0, 0.0, 0.0, 1.0, 1.0);
    let cy = array<f32, 6>(0.0, 0.0, 1.0, 1.0, 0.0, 1.0);
    let x = mix(x0, x1, cx[v % 6u]);
    let y = mix(y0, y1, cy[v % 6u]);
    return vec4<f32>(
        2.0 * x / f32(frame.width) - 1.0,
        1.0 - 2.0 * y / f32(frame.band_rows),
        0.0,
        1.0,
    );
}

// Clears the list's non-empty 8 × 8 tiles of the target (drawn before the
// footprints with blending off; the resolve reads exactly these tiles):
// one instance per tile, `instance_index` = the word of `tiles` holding the
// tile's index, so that no full-target clear is needed.
@vertex
fn quad_clear_vs(@builtin(vertex_index) v: u32, @builtin(instance_index) word: u32) -> QuadOut {
    let t = tiles[word];
    let ts = night.tile_size;
    let x0 = f32((t % night.tiles_per_row) * ts);
    let y0 = f32((t / night.tiles_per_row) * ts) - f32(frame.band_first_row);
    var out: QuadOut;
    out.pos = quad_corner(x0, y0, x0 + f32(ts), y0 + f32(ts), v);
    out.id = t;
    return out;
}

@fragment
fn quad_clear_fs(q: QuadOut) -> @location(0) vec4<f32> {
    return vec4<f32>(0.0);
}

@fragment
fn quad_fs(q: QuadOut) -> @location(0) vec4<f32> {
    // The fragment position is the pixel centre (band rows).
    let px = u32(q.pos.x);
    let py = u32(q.pos.y) + frame.band_first_row;
    let fx = f32(px) + 0.5;
    let fy = f32(py) + 0.5;
    let omega = pixel_omega(fx, fy);
    if (omega <= 0.0) {
        discard;
    }
    let s = points[q.id];
    var below = false;
    if (s.near_horizon != 0u) {
        let d = pixel_dir(fx, fy);
        below = d.w == 0.0 || d.z < 0.0;
    }
    // × the target's scale (rgba16float: the brightest footprint near
    // 2¹³, far from its overflow at 65504 and its subnormals below 6e-5).
    let l = point_footprint(s, px, py, fx, fy, below, point_face(px)) / omega;
    return vec4<f32>(l * night.quad_scale, 0.0);
}

// Adds the band's quad target into `accum` over the list's non-empty
// 8 × 8 tiles (every quad lies within the tiles its record is listed in):
// one workgroup per tile, as the tiled passes (points.wgsl `point_sources`).
fn quad_resolve(wg: vec3<u32>, nwg: vec3<u32>, lid: vec3<u32>, first: u32, n: u32) {
    let tp = busy_tile_pixel(wg, nwg, lid, first, n);
    if (!tp.ok) {
        return;
    }
    let px = tp.x;
    let y = tp.y - frame.band_first_row;
    let i = y * frame.width + px;
    let l = textureLoad(quad_src, vec2<u32>(px, y), 0);
    accum[i] = accum[i] + vec4<f32>(l.xyz / night.quad_scale, 0.0);
}

@compute @workgroup_size(8, 8, 1)
fn quad_resolve_stars(
    @builtin(workgroup_id) wg: vec3<u32>,
    @builtin(num_workgroups) nwg: vec3<u32>,
    @builtin(local_invocation_id) lid: vec3<u32>,
) {
    quad_resolve(wg, nwg, lid, night.star_busy_first, night.star_busy_count);
}

@compute @workgroup_size(8, 8, 1)
fn quad_resolve_planets(
    @builtin(workgroup_id) wg: vec3<u32>,
    @builtin(num_workgroups) nwg: vec3<u32>,
    @builtin(local_invocation_id) lid: vec3<u32>,
) {
    quad_resolve(wg, nwg, lid, night.planet_busy_first, night.planet_busy_count);
}
