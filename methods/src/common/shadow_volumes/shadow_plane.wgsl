// The shadow-plane vertex stage shared by the methods that draw extruded shadow planes (both Biri
// methods; vertices as `common::shadow_volumes::stencil::PLANE_LAYOUT`), and the distance at which
// a fragment's
// pixel ray crosses its plane. Needs PRELUDE.

struct PlaneFrag {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
    // The unit normal of the quad's plane, computed on the CPU from its edge and extrusion.
    @location(1) @interpolate(flat) normal: vec3<f32>,
};

@vertex
fn vs_plane(@location(0) p: vec3<f32>, @location(1) normal: vec3<f32>) -> PlaneFrag {
    return PlaneFrag(camera.clip_from_world * vec4<f32>(p, 1.0), p, normal);
}

// Distance from the eye to where the ray through this fragment's pixel centre crosses its plane
// (`camera_plane_distance`: the same on every adapter, whatever its sub-pixel precision).
fn plane_distance(v: PlaneFrag) -> f32 {
    return camera_plane_distance(camera, v.clip.xy, v.world, v.normal);
}
