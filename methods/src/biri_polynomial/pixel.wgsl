// `resolve: per-pixel` (modernised; the paper's whole-plane order is `resolve: planes`): the
// shadow planes of light poly.light go into the pixels' crossing lists (common/wgsl/
// crossing_lists.wgsl, crossing_passes.wgsl; group 2) — `fs_crossing_count` sizes them,
// `fs_crossing_gather` stores each fragment's signed distance (+ entering a shadow, − leaving) —
// and a full-screen pass sorts each list and walks it from the eye's count, adding eq. 12's terms
// over the lit intervals only: Γ(b) − Γ(a) for each lit [a, b] up to the visible point, with the
// very Γ the plane and surface fragments evaluate (`biri_gamma_frag`: eq. 6's kernel segment
// integral from the eye, or eq. 7 for spots). Per fragment whatever `eval` says (a per-pixel
// resolve has no vertices). Composed after passes.wgsl, spot.wgsl and spot_rays.wgsl.

// The lit interval [a, b] of pixel px's ray: eq. 12's +Γ(b) − Γ(a).
fn crossing_lit(px: vec2<u32>, a: f32, b: f32) -> vec3<f32> {
    let frag = vec2<f32>(px) + 0.5;
    return biri_gamma_frag(frag, b) - biri_gamma_frag(frag, a);
}

@fragment
fn fs_walk(@builtin(position) frag: vec4<f32>) -> @location(0) vec4<f32> {
    let dir = camera_ray_dir(camera, frag.xy);
    let end = camera_ray_length(camera, dir, textureLoad(ray_distance, vec2<i32>(frag.xy), 0).r);
    return vec4<f32>(crossing_walk(vec2<u32>(frag.xy), end), 0.0);
}
