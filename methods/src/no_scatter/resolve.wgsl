// The classic fog model: no in-scattering; total = attenuated surface + ambient.
// Needs PRELUDE and FULLSCREEN.
@group(1) @binding(0) var ray_distance: texture_2d<f32>;
@group(1) @binding(1) var surface: texture_2d<f32>;

struct Out {
    @location(0) inscatter: vec4<f32>,
    @location(1) total: vec4<f32>,
};

@fragment
fn fs(@builtin(position) frag: vec4<f32>) -> Out {
    let px = vec2<i32>(frag.xy);
    let dir = camera_ray_dir(camera, frag.xy);
    let d = camera_ray_length(camera, dir, textureLoad(ray_distance, px, 0).r);
    let ambient = medium.ambient.rgb * (vec3<f32>(1.0) - transmittance(medium, d));
    return Out(vec4<f32>(0.0, 0.0, 0.0, 1.0), vec4<f32>(textureLoad(surface, px, 0).rgb + ambient, 1.0));
}
