// `resolve: per-pixel`: exact shadow in shadow without a CPU sort, on the shared crossing lists
// (common/shadow_volumes/crossing_lists.wgsl, crossing_passes.wgsl; group 2). For one light
// (cfg.light.x)
// the shadow planes, depth-tested against the scene, are drawn twice: `fs_crossing_count` sizes
// each pixel's list, `fs_crossing_gather` stores each fragment's crossing (distance along the
// view ray, signed: + front-facing = entering a volume, − leaving). `cs_walk` sorts each list,
// walks it from the eye's count and sums L_dss (eq. 7 between two distances) over the lit
// intervals up to the visible surface; the light's sum is added to the running total of earlier
// lights. Composed after planes.wgsl (group 1 bindings 0–2: Γ table, cfg, ray distance).

// The running sum over lights and the in-scatter target (`crossing_accumulate`).
@group(1) @binding(5) var<storage, read_write> crossing_sum: array<vec4<f32>>;
@group(1) @binding(6) var crossing_out: texture_storage_2d<rgba32float, write>;

// Eq. 7 on pixel px's ray between distances a and b (the walk's lit intervals).
fn crossing_lit(px: vec2<u32>, a: f32, b: f32) -> vec3<f32> {
    let dir = camera_ray_dir(camera, vec2<f32>(px) + 0.5);
    return lit_between(gamma_table, cfg.light.x, dir, a, b, cfg.light.w);
}

@compute @workgroup_size(8, 8)
fn cs_walk(@builtin(global_invocation_id) gid: vec3<u32>) {
    let dims = textureDimensions(ray_distance);
    if (gid.x >= dims.x || gid.y >= dims.y) {
        return;
    }
    let dir = camera_ray_dir(camera, vec2<f32>(gid.xy) + 0.5);
    let end = camera_ray_length(camera, dir, textureLoad(ray_distance, vec2<i32>(gid.xy), 0).r);
    let k = cfg.light.x;
    var walked = vec3<f32>(0.0);
    if (spot_fit_applies(k)) {
        // The fit needs the ray's lit span: the list is walked first, then fitted, then the lit
        // intervals summed from the fit (here, not through `crossing_lit`, so that the fit is a
        // local value rather than a private variable every invocation would zero-fill).
        let lit = crossing_lit_bounds(gid.xy, end);
        if (lit.bounds >= 2u) {
            let first = crossing_lit_bound(lit, 0u, end);
            let fit = spot_fit(k, dir, first, crossing_lit_bound(lit, lit.bounds - 1u, end));
            for (var j = 0u; j + 1u < lit.bounds; j += 2u) {
                let a = crossing_lit_bound(lit, j, end);
                walked += spot_fit_between(fit, a, crossing_lit_bound(lit, j + 1u, end));
            }
        }
    } else {
        walked = crossing_walk(gid.xy, end);
    }
    crossing_accumulate(gid.xy, gid.y * dims.x + gid.x, k, walked);
}
