// Himmel wgpu backend: temporal reprojection of the low layer's coarse
// nodes over a frame sequence, concatenated after clouds_amortise.wgsl. A
// port of skymodel's frame/cloud_history.rs (`CloudHistory::reproject`,
// `Kept::fetch`); the per-frame decisions (whether the last frame may
// serve, the quarter marched, the field's move, which ages' lights still
// hold) are the Rust `HistoryClock`'s, in `clouds.history` and
// `clouds.history_shift`.
//
// `clouds_grid_coarse_history` takes the place of `clouds_grid_coarse`:
// the node (i, j) is marched when it is in this frame's quarter
// ((i mod 2) + 2 (j mod 2) = phase) or the last frame cannot give it;
// otherwise it takes the last frame's lattice (`low_prev`, bilinear over
// its coarse nodes) at the direction where the cloud it sees now lay then.
// A lattice entry's validity word holds 1 + the frames since its value was
// marched (0: no scene).

@group(1) @binding(8) var<storage, read> low_prev: array<vec4<f32>>;
// Nodes reused, marched, and marched because a light moved (`HistoryUse`).
@group(1) @binding(9) var<storage, read_write> history_count: array<atomic<u32>, 4>;

// A node of the last frame's lattice and its age.
struct PrevNode {
    e: GridEntry,
    age: u32,
}

fn prev_load(i: u32, j: u32) -> PrevNode {
    let k = 3u * ((2u * j) * lattice_width() + 2u * i);
    let a = low_prev[k];
    let b = low_prev[k + 1u];
    let c = low_prev[k + 2u];
    let s = Seen(CloudHit(a.xyz, a.w, b.w), b.xyz, c.xyz);
    return PrevNode(GridEntry(s, c.w > 0.5), u32(max(round(c.w) - 1.0, 0.0)));
}

// grid_store with the value's age.
fn grid_store_aged(lx: u32, ly: u32, s: Seen, age: u32) {
    grid_store(lx, ly, s, true);
    low_grid[3u * (ly * lattice_width() + lx) + 2u].w = 1.0 + f32(age);
}

// projection.rs `Camera::dir_to_pixel` in f32: the continuous image
// position of unit ENU direction `d`; z = 0 where the projection does
// not show it.
fn dir_to_pixel(d: vec3<f32>) -> vec3<f32> {
    let w = f32(frame.width);
    let h = f32(frame.height);
    let p = frame.projection;
    // The angles from atan2 of both sides (acos and asin lose f32
    // precision near the poles: 3e-4 rad at the zenith, a hundredth of a
    // pixel at 128²).
    let flat = length(d.xy);
    if (p == 0u) {
        let zen = atan2(flat, d.z);
        let rho = zen / HALF_PI * min(w, h) * 0.5;
        if (rho <= 0.0) {
            return vec3<f32>(w * 0.5, h * 0.5, 1.0);
        }
        let az = atan2(d.x, d.y);
        return vec3<f32>(w * 0.5 - rho * sin(az), h * 0.5 - rho * cos(az), 1.0);
    } else if (p == 1u) {
        let alt = atan2(d.z, flat);
        var az = atan2(d.x, d.y);
        if (az < 0.0) {
            az = az + TAU;
        }
        return vec3<f32>(az / TAU * w, (HALF_PI - alt) / PI * h, 1.0);
    } else if (p == 2u) {
        let z = dot(d, frame.forward);
        if (z <= 1e-12) {
            return vec3<f32>(0.0);
        }
        let t = frame.tan_half_fov;
        let nx = dot(d, frame.right) / z / t;
        let ny = dot(d, frame.up) / z / t;
        return vec3<f32>(w * 0.5 + nx * h * 0.5, h * 0.5 - ny * h * 0.5, 1.0);
    }
    // projection.rs `cube_face_coords` in the scene frame (x East, y Up,
    // z South).
    let v = vec3<f32>(d.x, d.z, -d.y);
    let a = abs(v);
    var face = 0u;
    var sc = 0.0;
    var tc = 0.0;
    if (a.x >= a.y && a.x >= a.z) {
        if (v.x > 0.0) {
            face = 0u;
            sc = -v.z / a.x;
        } else {
            face = 1u;
            sc = v.z / a.x;
        }
        tc = -v.y / a.x;
    } else if (a.y >= a.z) {
        sc = v.x / a.y;
        if (v.y > 0.0) {
            face = 2u;
            tc = v.z / a.y;
        } else {
            face = 3u;
            tc = -v.z / a.y;
        }
    } else {
        tc = -v.y / a.z;
        if (v.z > 0.0) {
            face = 4u;
            sc = v.x / a.z;
        } else {
            face = 5u;
            sc = -v.x / a.z;
        }
    }
    let fs = f32(frame.face_size);
    return vec3<f32>(f32(face) * fs + (sc + 1.0) * 0.5 * fs, (tc + 1.0) * 0.5 * fs, 1.0);
}

// What the last frame gives a node: its value and age, `ok` false when it
// gives nothing.
struct Fetched {
    s: Seen,
    age: u32,
    ok: bool,
}

fn not_fetched() -> Fetched {
    return Fetched(Seen(clear_hit(), vec3<f32>(0.0), vec3<f32>(1.0)), 0u, false);
}

// cloud_history.rs `Kept::fetch`: the value that node (i, j), looking
// along `v`, takes from the last frame when the field has moved by
// `clouds.history_shift.xy` km since; nothing when the nodes it would
// come from disagree, show no scene or are too old.
fn history_fetch(v: vec3<f32>, i: u32, j: u32) -> Fetched {
    let last = prev_load(i, j);
    if (!last.e.valid || clouds.has_low == 0u) {
        return not_fetched();
    }
    let sl = slab(v, clouds.low_base_km, clouds.low_top_km);
    if (sl.z == 0.0) {
        // A ray that never meets the layer is clear at any time.
        return Fetched(Seen(clear_hit(), vec3<f32>(0.0), vec3<f32>(1.0)), 0u, true);
    }
    var d = 0.5 * (sl.x + sl.y);
    if (last.e.s.hit.transmittance < 1.0 - clouds.clear) {
        d = last.e.s.hit.distance_km;
    }
    let moved = v * d - vec3<f32>(clouds.history_shift.xy, 0.0);
    if (dot(moved, moved) <= 0.0) {
        return not_fetched();
    }
    let p = dir_to_pixel(normalize(moved));
    let fx = p.x - 0.5;
    let fy = p.y - 0.5;
    let w = f32(frame.width);
    let h = f32(frame.height);
    if (p.z == 0.0 || !(fx >= 0.0 && fy >= 0.0 && fx <= w - 1.0 && fy <= h - 1.0)) {
        return not_fetched();
    }
    let n = clouds.march_grid.x;
    let ci = min(u32(fx) / n, clouds.march_grid.y - 2u);
    let cj = min(u32(fy) / n, clouds.march_grid.z - 2u);
    let x0 = f32(node_px(ci, frame.width));
    let x1 = f32(node_px(ci + 1u, frame.width));
    let y0 = f32(node_px(cj, frame.height));
    let y1 = f32(node_px(cj + 1u, frame.height));
    let ax = clamp((fx - x0) / max(x1 - x0, 1.0), 0.0, 1.0);
    let ay = clamp((fy - y0) / max(y1 - y0, 1.0), 0.0, 1.0);
    var q = array<PrevNode, 4>(prev_load(ci, cj), prev_load(ci + 1u, cj), prev_load(ci, cj + 1u), prev_load(ci + 1u, cj + 1u));
    var wts = array<f32, 4>((1.0 - ax) * (1.0 - ay), ax * (1.0 - ay), (1.0 - ax) * ay, ax * ay);
    var lo = 2.0;
    var hi = -1.0;
    var age = 0u;
    for (var k = 0u; k < 4u; k = k + 1u) {
        if (!q[k].e.valid) {
            return not_fetched();
        }
        if (wts[k] > clouds.history_shift.w) {
            age = max(age, q[k].age + 1u);
            lo = min(lo, q[k].e.s.hit.transmittance);
            hi = max(hi, q[k].e.s.hit.transmittance);
        }
    }
    if (hi - lo > clouds.history_shift.z || age > clouds.history.w) {
        return not_fetched();
    }
    let e = array<GridEntry, 4>(q[0].e, q[1].e, q[2].e, q[3].e);
    return Fetched(grid_bilinear(e, ax, ay), age, true);
}

// Level 1 with the history: the coarse nodes, one invocation each, the
// quarter of this frame's phase and whatever the last frame cannot give
// marched, the others reprojected; counted as `HistoryUse` counts them.
@compute @workgroup_size(8, 8, 1)
fn clouds_grid_coarse_history(@builtin(global_invocation_id) gid: vec3<u32>) {
    if (gid.x >= clouds.march_grid.y || gid.y >= clouds.march_grid.z) {
        return;
    }
    let i = gid.x;
    let j = gid.y;
    let x = node_px(i, frame.width);
    let y = node_px(j, frame.height);
    let d = pixel_dir(f32(x) + 0.5, f32(y) + 0.5);
    if (d.w == 0.0) {
        grid_store(2u * i, 2u * j, Seen(clear_hit(), vec3<f32>(0.0), vec3<f32>(1.0)), false);
        return;
    }
    let fresh = clouds.history.x == 0u || (i % 2u) + 2u * (j % 2u) == clouds.history.y;
    if (!fresh) {
        let f = history_fetch(d.xyz, i, j);
        if (f.ok) {
            if ((clouds.history.z & (1u << f.age)) != 0u) {
                grid_store_aged(2u * i, 2u * j, f.s, f.age);
                atomicAdd(&history_count[0], 1u);
                return;
            }
            atomicAdd(&history_count[2], 1u);
        }
    }
    grid_store(2u * i, 2u * j, low_seen(d.xyz), true);
    atomicAdd(&history_count[1], 1u);
}
