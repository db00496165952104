// The farthest visible point's view depth (where the planes end): a max-reduction of the
// surface pass's ray distances, far plane for rays that hit nothing. Positive f32 bits order
// like the floats, so an atomic max on u32 is a max on depth. Needs PRELUDE.

@group(1) @binding(0) var ray_distance: texture_2d<f32>;
@group(1) @binding(1) var<storage, read_write> far_bits: array<atomic<u32>>;

var<workgroup> group_max: atomic<u32>;

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) g: vec3<u32>, @builtin(local_invocation_index) li: u32) {
    let size = vec2<u32>(camera.viewport.xy);
    if (all(g.xy < size)) {
        let dir = camera_ray_dir(camera, vec2<f32>(g.xy) + 0.5);
        let d = camera_ray_length(camera, dir, textureLoad(ray_distance, vec2<i32>(g.xy), 0).r);
        atomicMax(&group_max, bitcast<u32>(max(d * dot(dir, camera.forward.xyz), 0.0)));
    }
    workgroupBarrier();
    if (li == 0u) {
        atomicMax(&far_bits[0], atomicLoad(&group_max));
    }
}
