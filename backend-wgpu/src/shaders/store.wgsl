// Himmel wgpu backend: the store pass (compiled after frame.wgsl): the
// accumulated radiance into the target texture. Its uniforms are `Frame`
// (Rust `FrameUniforms`).

// Writes the accumulated radiance into the target (cube maps: face =
// strip column / face size), alpha = 1 where the projection shows the scene.
@compute @workgroup_size(8, 8, 1)
fn store(@builtin(global_invocation_id) gid: vec3<u32>) {
    if (!inside(gid)) {
        return;
    }
    let py = gid.y + frame.band_first_row;
    let d = pixel_dir(f32(gid.x) + 0.5, f32(py) + 0.5);
    let i = gid.y * frame.width + gid.x;
    var layer = 0u;
    var x = gid.x;
    if (frame.projection == 3u) {
        layer = gid.x / frame.face_size;
        x = gid.x - layer * frame.face_size;
    }
    textureStore(target_tex, vec2<u32>(x, py), layer, vec4<f32>(accum[i].xyz, d.w));
}
