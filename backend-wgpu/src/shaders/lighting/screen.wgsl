// The screen helpers of the screen-space passes whose uniforms `u` begin
// with the camera block (view.rs `CameraBlock`) and a `params` vec4 whose
// zw are the frame's jitter (px, x right, y down; temporal.rs): ao.wgsl
// and bounce.wgsl, each concatenated after this.
//
//   u.eye: xyz the eye, w tan(fov / 2); u.forward: xyz forward, w the
//   aspect; u.right: xyz right, w the width (px); u.up: xyz up, w the
//   height (px).

// The image's size, px.
fn size() -> vec2<i32> {
    return vec2<i32>(i32(u.right.w), i32(u.up.w));
}

// The view ray through the pixel position c (pixel centres at k + ½) of
// the jittered image.
fn ray_at(c: vec2<f32>) -> vec3<f32> {
    let h = u.up.w;
    let t = u.eye.w;
    let nx = (c.x - u.params.z - 0.5 * u.right.w) / (0.5 * h) * t;
    let ny = -(c.y - u.params.w - 0.5 * h) / (0.5 * h) * t;
    return normalize(u.forward.xyz + u.right.xyz * nx + u.up.xyz * ny);
}

// The pixel position of world point x (and its view depth in z).
fn project(x: vec3<f32>) -> vec3<f32> {
    let d = x - u.eye.xyz;
    let z = dot(d, u.forward.xyz);
    let h = u.up.w;
    let k = 0.5 * h / (u.eye.w * max(z, 1e-6));
    return vec3<f32>(dot(d, u.right.xyz) * k + 0.5 * u.right.w + u.params.z, -dot(d, u.up.xyz) * k + 0.5 * h + u.params.w, z);
}
