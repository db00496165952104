// Particle media: the surface AOV behind the cloud. The shared surface pass shaded the visible
// surfaces with the background medium only (its output is `surface`, a private texture here),
// and one pass per light removed that light's share shadowed by the cloud (particle_shadow.wgsl);
// this pass multiplies them by the particles' transmittance toward the eye (the froxel volume's
// alpha at the pixel's ray length, lookup.wgsl) and puts the sky, attenuated along the whole
// ray, where the ray hits nothing. Needs the resolve prelude, grid.wgsl, lookup.wgsl and
// extinction.wgsl.

@group(1) @binding(2) var<uniform> froxel: Froxel;
@group(1) @binding(3) var volume: texture_2d<f32>;
@group(1) @binding(4) var<uniform> particle_medium: ParticleMedium;
// Unread here; extinction.wgsl (composed for ParticleMedium) declares functions that read it.
@group(1) @binding(5) var<storage, read> optical_depth: array<f32>;
@group(1) @binding(6) var surface_out: texture_storage_2d<rgba32float, write>;

@compute @workgroup_size(8, 8, 1)
fn particle_surface(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = vec2<u32>(camera.viewport.xy);
    if (id.x >= size.x || id.y >= size.y) {
        return;
    }
    let px = vec2<i32>(id.xy);
    let frag = vec2<f32>(id.xy) + 0.5;
    let dir = camera_ray_dir(camera, frag);
    let hit = textureLoad(ray_distance, px, 0).r;
    let d = camera_ray_length(camera, dir, hit);
    let to_eye = volume_at(frag, dir, d).a;
    var out = particle_medium.sky.rgb * transmittance(medium, d);
    if (hit >= 0.0) {
        out = textureLoad(surface, px, 0).rgb;
    }
    textureStore(surface_out, px, vec4<f32>(out * to_eye, 1.0));
}
