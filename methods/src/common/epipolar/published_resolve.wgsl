// The resolve of a method whose compute passes publish the summed in-scatter to a texture
// (epipolar-minmax, prefiltered-single-scattering): that texture plus the surface and ambient
// terms. Needs the resolve prelude (common::resolve).

@group(1) @binding(3) var inscatter: texture_2d<f32>;

@fragment
fn fs(@builtin(position) frag: vec4<f32>) -> Out {
    let px = vec2<i32>(frag.xy);
    let l_in = textureLoad(inscatter, px, 0).rgb;
    let dir = camera_ray_dir(camera, frag.xy);
    let d = pixel_ray_length(px, dir);
    let surf = textureLoad(surface, px, 0).rgb;
    return Out(vec4<f32>(l_in, 1.0), vec4<f32>(surf + l_in + ambient_fog(dir, d), 1.0));
}
