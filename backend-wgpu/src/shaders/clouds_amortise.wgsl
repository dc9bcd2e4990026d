// Himmel wgpu backend: the clouds pass's composition and the amortised
// march of the low layer (`clouds.low.march_stride`), concatenated after
// clouds_grid.wgsl. A port of skymodel's frame/cloud_grid.rs
// (`LowCloudGrid`) and of `CloudFrame::{low_seen, composite_with}`
// (frame/clouds.rs).
//
// With a stride N ≥ 2 (`clouds.march_grid`: N, the coarse nodes nx and ny,
// the agreement threshold `AGREE_TRANSMITTANCE` as bits), the low layer is
// marched in two dispatches before the per-pixel pass:
//
// 1. `clouds_grid_coarse`: every N-th pixel of every N-th row and the last
//    column and row (nx × ny nodes);
// 2. `clouds_grid_refine`: the midpoints of the edges and the centre of
//    each coarse cell whose corners disagree (a corner outside the
//    projection, or transmittances spread by more than the threshold).
//
// Both write a lattice of (2 nx − 1) × (2 ny − 1) entries, `low_grid`:
// lattice point (2i, 2j) is node (i, j), odd coordinates the midpoints
// between nodes. `clouds_pass` then takes each pixel's low layer from its
// coarse cell, or its half-size cell, where their corners agree
// (bilinear), and queues the others (`edges`), which `clouds_edges`
// marches side by side — the same choices as the CPU's, without a
// marching pixel holding up the interpolated ones beside it.

// A layer's hit with the air in front of it (frame/clouds.rs `SeenHit`).
struct Seen {
    hit: CloudHit,
    air_l: vec3<f32>,
    air_t: vec3<f32>,
}

// `CloudFrame::seen`: `hit` along `view` with the air in front (none when
// clear).
fn seen(view: vec3<f32>, hit: CloudHit) -> Seen {
    if (hit.transmittance >= 1.0 - clouds.clear) {
        return Seen(hit, vec3<f32>(0.0), vec3<f32>(1.0));
    }
    let a = air(view, hit.distance_km);
    return Seen(hit, a.l, a.t);
}

// `CloudFrame::low_seen`.
fn low_seen(view: vec3<f32>) -> Seen {
    return seen(view, low_hit(view));
}

// One layer of `CloudFrame::composite_with` over `px`.
fn over(px: vec3<f32>, s: Seen) -> vec3<f32> {
    let t = s.hit.transmittance;
    if (t >= 1.0 - clouds.clear) {
        return px;
    }
    return t * px + (1.0 - t) * s.air_l + s.air_t * s.hit.radiance;
}

// `CloudFrame::composite_with`: `behind` seen through the high layer, then
// the low one `low`, a ground pixel's direct light shadowed first.
fn composite_with(view: vec3<f32>, behind: vec3<f32>, low: Seen) -> vec3<f32> {
    let px = shade_ground(view, behind);
    return over(over(px, seen(view, high_hit(view))), low);
}

// ---------------------------------------------------------------------------
// cloud_grid.rs `LowCloudGrid`

@group(1) @binding(6) var<storage, read_write> low_grid: array<vec4<f32>>;

// A lattice entry: (radiance, T), (air radiance, distance), (air
// transmittance, 1 when the pixel shows the scene).
struct GridEntry {
    s: Seen,
    valid: bool,
}

fn lattice_width() -> u32 {
    return 2u * clouds.march_grid.y - 1u;
}

// cloud_grid.rs `nodes`: node i's pixel along an axis of n pixels.
fn node_px(i: u32, n: u32) -> u32 {
    return min(i * clouds.march_grid.x, n - 1u);
}

// The pixel of lattice coordinate l: a node, or the midpoint (rounded
// down) between two.
fn lattice_px(l: u32, n: u32) -> u32 {
    if ((l & 1u) == 0u) {
        return node_px(l / 2u, n);
    }
    return (node_px(l / 2u, n) + node_px(l / 2u + 1u, n)) / 2u;
}

fn grid_store(lx: u32, ly: u32, s: Seen, valid: bool) {
    let k = 3u * (ly * lattice_width() + lx);
    low_grid[k] = vec4<f32>(s.hit.radiance, s.hit.transmittance);
    low_grid[k + 1u] = vec4<f32>(s.air_l, s.hit.distance_km);
    low_grid[k + 2u] = vec4<f32>(s.air_t, select(0.0, 1.0, valid));
}

fn grid_load(lx: u32, ly: u32) -> GridEntry {
    let k = 3u * (ly * lattice_width() + lx);
    let a = low_grid[k];
    let b = low_grid[k + 1u];
    let c = low_grid[k + 2u];
    return GridEntry(Seen(CloudHit(a.xyz, a.w, b.w), b.xyz, c.xyz), c.w > 0.5);
}

// Marches the pixel of lattice point (lx, ly) into the lattice.
fn grid_march(lx: u32, ly: u32) {
    let x = lattice_px(lx, frame.width);
    let y = lattice_px(ly, frame.height);
    let d = pixel_dir(f32(x) + 0.5, f32(y) + 0.5);
    if (d.w == 0.0) {
        grid_store(lx, ly, Seen(clear_hit(), vec3<f32>(0.0), vec3<f32>(1.0)), false);
        return;
    }
    grid_store(lx, ly, low_seen(d.xyz), true);
}

// cloud_grid.rs `agree`: all four show the scene and their
// transmittances spread by at most `AGREE_TRANSMITTANCE`.
fn agree(q0: array<GridEntry, 4>) -> bool {
    var q = q0;
    var lo = 2.0;
    var hi = -1.0;
    for (var k = 0u; k < 4u; k = k + 1u) {
        if (!q[k].valid) {
            return false;
        }
        lo = min(lo, q[k].s.hit.transmittance);
        hi = max(hi, q[k].s.hit.transmittance);
    }
    return hi - lo <= bitcast<f32>(clouds.march_grid.w);
}

// The four lattice entries (x0 y0, x1 y0, x0 y1, x1 y1) of the rectangle
// [ax, bx] × [ay, by] of lattice coordinates.
fn grid_quad(ax: u32, bx: u32, ay: u32, by: u32) -> array<GridEntry, 4> {
    return array<GridEntry, 4>(grid_load(ax, ay), grid_load(bx, ay), grid_load(ax, by), grid_load(bx, by));
}

// Whether coarse cell (i, j)'s corners agree.
fn cell_agrees(i: u32, j: u32) -> bool {
    return agree(grid_quad(2u * i, 2u * i + 2u, 2u * j, 2u * j + 2u));
}

// cloud_grid.rs `bilinear`: clear when all four corners are; the air in
// front weighted by the corners' extinction (1 − T).
fn grid_bilinear(q0: array<GridEntry, 4>, fx: f32, fy: f32) -> Seen {
    var q = q0;
    var all_clear = true;
    for (var k = 0u; k < 4u; k = k + 1u) {
        all_clear = all_clear && q[k].s.hit.transmittance >= 1.0 - clouds.clear;
    }
    if (all_clear) {
        return Seen(clear_hit(), vec3<f32>(0.0), vec3<f32>(1.0));
    }
    var w = array<f32, 4>((1.0 - fx) * (1.0 - fy), fx * (1.0 - fy), (1.0 - fx) * fy, fx * fy);
    var out = Seen(CloudHit(vec3<f32>(0.0), 0.0, 0.0), vec3<f32>(0.0), vec3<f32>(0.0));
    var ext = 0.0;
    for (var k = 0u; k < 4u; k = k + 1u) {
        let h = q[k].s;
        out.hit.radiance = out.hit.radiance + w[k] * h.hit.radiance;
        out.hit.transmittance = out.hit.transmittance + w[k] * h.hit.transmittance;
        out.hit.distance_km = out.hit.distance_km + w[k] * h.hit.distance_km;
        let we = w[k] * (1.0 - h.hit.transmittance);
        out.air_l = out.air_l + we * h.air_l;
        out.air_t = out.air_t + we * h.air_t;
        ext = ext + we;
    }
    if (ext > 0.0) {
        out.air_l = out.air_l / ext;
        out.air_t = out.air_t / ext;
    } else {
        out.air_l = vec3<f32>(0.0);
        out.air_t = vec3<f32>(1.0);
    }
    return out;
}

// cloud_grid.rs `frac`: where x lies in [a, b].
fn grid_frac(x: u32, a: u32, b: u32) -> f32 {
    return f32(x - min(x, a)) / f32(max(b - a, 1u));
}

// Level 1: the coarse nodes, one invocation each.
@compute @workgroup_size(8, 8, 1)
fn clouds_grid_coarse(@builtin(global_invocation_id) gid: vec3<u32>) {
    if (gid.x >= clouds.march_grid.y || gid.y >= clouds.march_grid.z) {
        return;
    }
    grid_march(2u * gid.x, 2u * gid.y);
}

// Level 2: one invocation per lattice point between the nodes, marched
// when a coarse cell it belongs to disagrees (an edge midpoint belongs to
// the two cells beside it, a centre to its own).
@compute @workgroup_size(8, 8, 1)
fn clouds_grid_refine(@builtin(global_invocation_id) gid: vec3<u32>) {
    let nx = clouds.march_grid.y;
    let ny = clouds.march_grid.z;
    let lx = gid.x;
    let ly = gid.y;
    if (lx >= 2u * nx - 1u || ly >= 2u * ny - 1u) {
        return;
    }
    let ox = (lx & 1u) == 1u;
    let oy = (ly & 1u) == 1u;
    var need = false;
    if (ox && oy) {
        need = !cell_agrees(lx / 2u, ly / 2u);
    } else if (ox) {
        let j = ly / 2u;
        need = (j >= 1u && !cell_agrees(lx / 2u, j - 1u)) || (j + 1u < ny && !cell_agrees(lx / 2u, j));
    } else if (oy) {
        let i = lx / 2u;
        need = (i >= 1u && !cell_agrees(i - 1u, ly / 2u)) || (i + 1u < nx && !cell_agrees(i, ly / 2u));
    }
    if (need) {
        grid_march(lx, ly);
    }
}

// cloud_grid.rs `LowCloudGrid::interpolate`: the low layer at pixel
// (x, y) from the lattice where the corners of its cell, or of its
// half-size cell, agree, or where the grid marched the pixel itself;
// `found` false when the pixel needs a march of its own.
struct FromGrid {
    s: Seen,
    found: bool,
}

fn not_found() -> FromGrid {
    return FromGrid(Seen(clear_hit(), vec3<f32>(0.0), vec3<f32>(1.0)), false);
}

fn from_grid(x: u32, y: u32) -> FromGrid {
    let n = clouds.march_grid.x;
    let nx = clouds.march_grid.y;
    let ny = clouds.march_grid.z;
    let i = min(x / n, nx - 2u);
    let j = min(y / n, ny - 2u);
    let x0 = node_px(i, frame.width);
    let x1 = node_px(i + 1u, frame.width);
    let y0 = node_px(j, frame.height);
    let y1 = node_px(j + 1u, frame.height);
    var q = grid_quad(2u * i, 2u * i + 2u, 2u * j, 2u * j + 2u);
    if (agree(q)) {
        return FromGrid(grid_bilinear(q, grid_frac(x, x0, x1), grid_frac(y, y0, y1)), true);
    }
    for (var k = 0u; k < 4u; k = k + 1u) {
        if (!q[k].valid) {
            return not_found();
        }
    }
    // The half-size cell: lattice [la, la + 1] along each axis.
    let xm = (x0 + x1) / 2u;
    let ym = (y0 + y1) / 2u;
    var xa = x0;
    var xb = xm;
    var lxa = 2u * i;
    if (x > xm) {
        xa = xm;
        xb = x1;
        lxa = 2u * i + 1u;
    }
    var ya = y0;
    var yb = ym;
    var lya = 2u * j;
    if (y > ym) {
        ya = ym;
        yb = y1;
        lya = 2u * j + 1u;
    }
    var f = grid_quad(lxa, lxa + 1u, lya, lya + 1u);
    if (agree(f)) {
        return FromGrid(grid_bilinear(f, grid_frac(x, xa, xb), grid_frac(y, ya, yb)), true);
    }
    for (var k = 0u; k < 4u; k = k + 1u) {
        if (!f[k].valid) {
            return not_found();
        }
    }
    // A pixel the grid marched is not marched again.
    var px = array<vec2<u32>, 4>(vec2<u32>(xa, ya), vec2<u32>(xb, ya), vec2<u32>(xa, yb), vec2<u32>(xb, yb));
    for (var k = 0u; k < 4u; k = k + 1u) {
        if (px[k].x == x && px[k].y == y) {
            return FromGrid(f[k].s, true);
        }
    }
    return not_found();
}

// The pixels of the band whose low layer the grid cannot give: their
// number, then their indices in the band (`clouds_edges` marches them
// side by side, rather than each beside interpolated neighbours that
// wait for it).
struct EdgeQueue {
    count: atomic<u32>,
    pixels: array<u32>,
}

@group(1) @binding(7) var<storage, read_write> edges: EdgeQueue;

// Empties the queue before a band's `clouds_pass`.
@compute @workgroup_size(1, 1, 1)
fn clouds_edges_reset() {
    atomicStore(&edges.count, 0u);
}

// The view direction of the band's pixel gid (w = 0: outside the band or
// the projection, nothing to compose).
fn band_pixel_dir(gid: vec3<u32>) -> vec4<f32> {
    if (!inside(gid)) {
        return vec4<f32>(0.0);
    }
    let y = gid.y + frame.band_first_row;
    return pixel_dir(f32(gid.x) + 0.5, f32(y) + 0.5);
}

// The clouds pass: each pixel's radiance so far composed behind the
// layers, the low layer marched at every pixel.
@compute @workgroup_size(8, 8, 1)
fn clouds_pass(@builtin(global_invocation_id) gid: vec3<u32>) {
    let d = band_pixel_dir(gid);
    if (d.w == 0.0) {
        return;
    }
    let i = gid.y * frame.width + gid.x;
    let p = accum[i];
    accum[i] = vec4<f32>(composite_with(d.xyz, p.xyz, low_seen(d.xyz)), p.w);
}

// The clouds pass with the amortised march: the low layer from the grid,
// a pixel the grid cannot give queued for `clouds_edges` (no march here:
// the shader holds none of its code).
@compute @workgroup_size(8, 8, 1)
fn clouds_grid_pixels(@builtin(global_invocation_id) gid: vec3<u32>) {
    let d = band_pixel_dir(gid);
    if (d.w == 0.0) {
        return;
    }
    let i = gid.y * frame.width + gid.x;
    let y = gid.y + frame.band_first_row;
    let g = from_grid(gid.x, y);
    if (!g.found) {
        edges.pixels[atomicAdd(&edges.count, 1u)] = i;
        return;
    }
    let p = accum[i];
    accum[i] = vec4<f32>(composite_with(d.xyz, p.xyz, g.s), p.w);
}

// The queued pixels of the band, marched (one invocation each, over as
// many invocations as the band has pixels).
@compute @workgroup_size(8, 8, 1)
fn clouds_edges(@builtin(global_invocation_id) gid: vec3<u32>) {
    if (!inside(gid)) {
        return;
    }
    let k = gid.y * frame.width + gid.x;
    if (k >= atomicLoad(&edges.count)) {
        return;
    }
    let i = edges.pixels[k];
    let x = i % frame.width;
    let y = i / frame.width + frame.band_first_row;
    let d = pixel_dir(f32(x) + 0.5, f32(y) + 0.5);
    let p = accum[i];
    accum[i] = vec4<f32>(composite_with(d.xyz, p.xyz, low_seen(d.xyz)), p.w);
}
