// Steps 3 and 5 of Biri et al. with stencil shadow planes, one light at a time (cfg.light.x):
// a depth-only scene pass, a z-pass count of the planes in front of each surface (stencil = the
// number of shadow volumes around the visible point, seeded with the eye's count), the lit
// surfaces' term +C Γ(w(d)) where the stencil is 0, then the planes back to front, each crossing
// adding (front-facing: entering a shadow) or subtracting (back-facing: leaving one) its term
// C Γ(w(distance)) under the paper's stencil rules (other light kinds: `crossing_term`). Signed float accumulation replaces the
// paper's reverse-subtract blending on 8-bit targets. Needs PRELUDE, FULLSCREEN and ldss.wgsl.

struct PlaneCfg {
    // x: light index; y: the eye's shadow count; z: per-pixel list capacity; w: `spot_panels`
    light: vec4<u32>,
};
@group(1) @binding(0) var gamma_table: texture_2d<f32>;
@group(1) @binding(1) var<uniform> cfg: PlaneCfg;
@group(1) @binding(2) var ray_distance: texture_2d<f32>;

// Invariant: `common::shadow_volumes::stencil_surfaces` redraws the scene over this depth with
// depth test Equal.
@vertex
fn vs_scene(v: VertexIn) -> @builtin(position) @invariant vec4<f32> {
    return camera.clip_from_world * (objects[v.object].world_from_local * vec4<f32>(v.position, 1.0));
}

@fragment
fn fs_plane(v: PlaneFrag, @builtin(front_facing) front: bool) -> @location(0) vec4<f32> {
    let dir = camera_ray_dir(camera, v.clip.xy);
    let term = crossing_term(gamma_table, cfg.light.x, dir, plane_distance(v), cfg.light.w);
    return vec4<f32>(select(-term, term, front), 0.0);
}

@fragment
fn fs_surface(@builtin(position) frag: vec4<f32>) -> @location(0) vec4<f32> {
    let dir = camera_ray_dir(camera, frag.xy);
    let d = camera_ray_length(camera, dir, textureLoad(ray_distance, vec2<i32>(frag.xy), 0).r);
    return vec4<f32>(crossing_term(gamma_table, cfg.light.x, dir, d, cfg.light.w), 0.0);
}

// `accumulate: unorm8` (the paper's 8-bit target): every crossing writes the whole L_dss from the
// eye to it, front faces added and back faces reverse-subtracted by the blend state, so the
// eye's term cancels and each value is ≥ 0 as the paper's Fig. 7 shader outputs.
@fragment
fn fs_plane_full(v: PlaneFrag) -> @location(0) vec4<f32> {
    let dir = camera_ray_dir(camera, v.clip.xy);
    let d = plane_distance(v);
    return vec4<f32>(lit_between(gamma_table, cfg.light.x, dir, 0.0, d, cfg.light.w), 0.0);
}

@fragment
fn fs_surface_full(@builtin(position) frag: vec4<f32>) -> @location(0) vec4<f32> {
    let dir = camera_ray_dir(camera, frag.xy);
    let d = camera_ray_length(camera, dir, textureLoad(ray_distance, vec2<i32>(frag.xy), 0).r);
    return vec4<f32>(lit_between(gamma_table, cfg.light.x, dir, 0.0, d, cfg.light.w), 0.0);
}
