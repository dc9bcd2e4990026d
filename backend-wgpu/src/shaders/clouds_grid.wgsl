// Himmel wgpu backend: the volumetric tier's 3D diffusion grids
// (skymodel clouds/diffusion_grid.rs), concatenated after
// clouds_heightfield.wgsl. The grids are solved once per frame in
// skymodel (`DiffusionGrid::build`) and bound as `hf_columns` (the
// height-field tier's buffer, free in the volumetric tier): per light,
// its nx·ny·nz cells (x fastest) of (U, F_x, F_y, F_z), U < 0 in a clear
// cell. `clouds.grid_origin`, `grid_dims`, `grid_weight` describe them.

// diffusion_grid.rs `DiffusionGrid::sample`: U and F trilinear over the
// cloudy cells around the point (w: the weights' sum, 0 when none).
fn grid_sample(k: u32, xy: vec2<f32>, h_km: f32) -> vec4<f32> {
    let q = (vec3<f32>(xy.x, xy.y, h_km) - clouds.grid_origin.xyz) / clouds.grid_origin.w
        - vec3<f32>(0.5);
    let nx = i32(clouds.grid_dims.x);
    let ny = i32(clouds.grid_dims.y);
    let nz = i32(clouds.grid_dims.z);
    let base = floor(q);
    let fr = q - base;
    let offset = k * u32(nx * ny * nz);
    var acc = vec4<f32>(0.0);
    var wsum = 0.0;
    for (var corner = 0; corner < 8; corner = corner + 1) {
        let d = vec3<i32>(corner & 1, (corner >> 1u) & 1, (corner >> 2u) & 1);
        let c = vec3<i32>(base) + d;
        if (c.x < 0 || c.y < 0 || c.z < 0 || c.x >= nx || c.y >= ny || c.z >= nz) {
            continue;
        }
        let cell = hf_columns[offset + u32(c.x + nx * (c.y + ny * c.z))];
        if (cell.x < 0.0) {
            continue;
        }
        let wv = select(vec3<f32>(1.0) - fr, fr, d == vec3<i32>(1));
        let w = wv.x * wv.y * wv.z;
        acc = acc + w * cell;
        wsum = wsum + w;
    }
    if (wsum <= 1e-6) {
        return vec4<f32>(-1.0, 0.0, 0.0, 0.0);
    }
    return acc / wsum;
}

// diffusion_grid.rs `DiffusionGrid::weight_at`.
fn grid_weight_at(xy: vec2<f32>) -> f32 {
    let fade = clouds.grid_weight.y;
    if (fade <= 0.0) {
        return clouds.grid_weight.x;
    }
    let half = -clouds.grid_origin.x;
    let inside = half - max(abs(xy.x), abs(xy.y));
    return clouds.grid_weight.x * clamp(inside / fade, 0.0, 1.0);
}

// diffusion_grid.rs `DiffusionGrid::diffuse`: the grid's source
// (U − 3 g F · v)/4π blended with the column model's `column` (the
// column alone where light `k` has no grid or the grid no cloud).
fn grid_diffuse(k: u32, column: f32, xy: vec2<f32>, h_km: f32, view: vec3<f32>) -> f32 {
    if (f32(k) >= clouds.grid_dims.w) {
        return column;
    }
    let w = grid_weight_at(xy);
    if (w <= 0.0) {
        return column;
    }
    let s = grid_sample(k, xy, h_km);
    if (s.x < 0.0) {
        return column;
    }
    let g = clouds.grid_weight.z;
    let grid = max(s.x - 3.0 * g * dot(s.yzw, view), 0.0) / (4.0 * 3.14159265);
    return w * grid + (1.0 - w) * column;
}
