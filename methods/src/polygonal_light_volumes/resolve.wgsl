// The resolve, one additive pipeline per light (common::resolve per-light mode): light LIGHT's
// unshadowed in-scatter to the visible surface where it has no volume this frame (no caster in
// its frustum) or where its volume is a shadow volume (directional light: the volume pass
// subtracts the shadowed stretches); the pipeline of light 0 also adds the accumulated volume
// terms of every light, the surface AOV and the ambient fog. Needs PRELUDE, FULLSCREEN,
// resolve_io.wgsl, ldss.wgsl and integral.wgsl.

struct Config {
    // bit k (light_bit) set when light k's unshadowed integral is added here
    direct: vec4<u32>,
};
@group(1) @binding(2) var<uniform> config: Config;
@group(1) @binding(4) var volumes: texture_2d<f32>;

override LIGHT: u32 = 0u;

@fragment
fn fs(@builtin(position) frag: vec4<f32>) -> Out {
    let px = vec2<i32>(frag.xy);
    let dir = camera_ray_dir(camera, frag.xy);
    let d = pixel_ray_length(px, dir);
    var l_in = vec3<f32>(0.0);
    if (light_bit(config.direct, LIGHT)) {
        l_in = inscatter_between(LIGHT, dir, 0.0, d);
    }
    var base = vec3<f32>(0.0);
    if (LIGHT == 0u) {
        // Rounding of the signed sums can leave a hair below zero where no light arrives.
        l_in = max(l_in + textureLoad(volumes, px, 0).rgb, vec3<f32>(0.0));
        base = textureLoad(surface, px, 0).rgb + ambient_fog(dir, d);
    }
    return Out(vec4<f32>(l_in, 1.0), vec4<f32>(base + l_in, 1.0));
}
