// Depth-only rasterisation of the world into one layer of a light's map
// (passes/lighting/shadow.rs): the Sun's and Moon's cascades and the sky's
// visibility maps. Orthographic light views, depth linear in metres.

struct LightMatrix {
    m: mat4x4<f32>,
}

@group(0) @binding(0) var<uniform> light: LightMatrix;

@vertex
fn vs(@location(0) pos: vec3<f32>) -> @builtin(position) vec4<f32> {
    return light.m * vec4<f32>(pos, 1.0);
}
