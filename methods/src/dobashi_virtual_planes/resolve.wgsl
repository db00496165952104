// total = surface + L_in + ambient, with L_in read back from the accumulation target (divided by
// its scale: 1 for float, the documented factor for unorm8). Composed by common::resolve after
// dobashi.wgsl (the Planes uniform is the ResolvePass uniform, binding 2; the accumulation binding 3).

@group(1) @binding(0) var ray_distance: texture_2d<f32>;
@group(1) @binding(1) var surface: texture_2d<f32>;
@group(1) @binding(2) var<uniform> planes: Planes;
@group(1) @binding(3) var accum: texture_2d<f32>;

struct Out {
    @location(0) inscatter: vec4<f32>,
    @location(1) total: vec4<f32>,
};

@fragment
fn fs(@builtin(position) frag: vec4<f32>) -> Out {
    let px = vec2<i32>(frag.xy);
    let dir = camera_ray_dir(camera, frag.xy);
    let d = camera_ray_length(camera, dir, textureLoad(ray_distance, px, 0).r);
    let l_in = textureLoad(accum, px, 0).rgb / planes.scale.x;
    let ambient = medium.ambient.rgb * (vec3<f32>(1.0) - transmittance(medium, d));
    return Out(vec4<f32>(l_in, 1.0), vec4<f32>(textureLoad(surface, px, 0).rgb + l_in + ambient, 1.0));
}
