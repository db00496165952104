// total = surface + L_in + ambient, with L_in read back from the accumulation target (divided by
// its scale: 1 for float, the documented factor for unorm8). Composed by common::resolve after
// dobashi.wgsl (the Planes uniform is the ResolvePass uniform, binding 2; the accumulation binding 3).

@group(1) @binding(2) var<uniform> planes: Planes;
@group(1) @binding(3) var accum: texture_2d<f32>;

@fragment
fn fs(@builtin(position) frag: vec4<f32>) -> Out {
    let px = vec2<i32>(frag.xy);
    let dir = camera_ray_dir(camera, frag.xy);
    let d = pixel_ray_length(px, dir);
    let l_in = textureLoad(accum, px, 0).rgb / planes.scale;
    let ambient = ambient_fog(dir, d);
    return Out(vec4<f32>(l_in, 1.0), vec4<f32>(textureLoad(surface, px, 0).rgb + l_in + ambient, 1.0));
}
