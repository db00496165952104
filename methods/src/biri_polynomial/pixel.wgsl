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

// Light poly.light's in-scatter on pixel px: its list walked up to the visible surface.
fn walk_pixel(px: vec2<u32>) -> vec3<f32> {
    let dir = camera_ray_dir(camera, vec2<f32>(px) + 0.5);
    let end = camera_ray_length(camera, dir, textureLoad(ray_distance, vec2<i32>(px), 0).r);
    return crossing_walk(px, end);
}

// `walk = fragment`: full-screen, blended additively into the accumulation target.
@fragment
fn fs_walk(@builtin(position) frag: vec4<f32>) -> @location(0) vec4<f32> {
    return vec4<f32>(walk_pixel(vec2<u32>(frag.xy)), 0.0);
}

// `walk = compute` (pixel.rs): the running sum over lights and the target (`crossing_accumulate`).
@group(3) @binding(0) var<storage, read_write> crossing_sum: array<vec4<f32>>;
@group(3) @binding(1) var crossing_out: texture_storage_2d<rgba32float, write>;

@compute @workgroup_size(8, 8)
fn cs_walk(@builtin(global_invocation_id) gid: vec3<u32>) {
    let dims = textureDimensions(ray_distance);
    if (gid.x >= dims.x || gid.y >= dims.y) {
        return;
    }
    crossing_accumulate(gid.xy, gid.y * dims.x + gid.x, poly.light, walk_pixel(gid.xy));
}
