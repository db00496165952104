// Froxel apply pass: each pixel reads the integrated volume at its ray length (the visible
// surface or the far plane, lookup.wgsl) and writes in-scatter and total. Needs the resolve
// prelude, grid.wgsl and lookup.wgsl.

@group(1) @binding(2) var<uniform> froxel: Froxel;
@group(1) @binding(3) var volume: texture_2d<f32>;

@fragment
fn fs(@builtin(position) frag: vec4<f32>) -> Out {
    let px = vec2<i32>(frag.xy);
    let dir = camera_ray_dir(camera, frag.xy);
    let d = pixel_ray_length(px, dir);
    let l_in = volume_at(frag.xy, dir, d).rgb;
    let surf = textureLoad(surface, px, 0).rgb;
    return Out(vec4<f32>(l_in, 1.0), vec4<f32>(surf + l_in + ambient_fog(dir, d), 1.0));
}
