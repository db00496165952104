// `resolve: per-pixel`: exact shadow in shadow without a CPU sort. For one light (cfg.light.x) a
// render pass over its shadow planes, depth-tested against the scene, appends each fragment's
// crossing (distance along the view ray, signed: + front-facing = entering a volume, − leaving)
// to its pixel's fixed-capacity list (cfg.light.z entries; an atomic count per pixel, overflow
// counted, never silent). A compute pass then sorts each list by distance, walks it from the eye
// with the eye's count (cfg.light.y) and sums L_dss over the lit intervals only (count ≤ 0), up
// to the visible surface; the light's sum is added to the running total of earlier lights.
// Composed after planes.wgsl (group 1 bindings 0–2: Γ table, cfg, ray distance).

@group(1) @binding(3) var<storage, read_write> crossing_count: array<atomic<u32>>;
@group(1) @binding(4) var<storage, read_write> crossing_list: array<f32>;
@group(1) @binding(5) var<storage, read_write> inscatter_sum: array<vec4<f32>>;
@group(1) @binding(6) var inscatter_out: texture_storage_2d<rgba32float, write>;
// [0]: pixel-lights whose list overflowed; [1]: the longest list seen (before truncation).
@group(1) @binding(7) var<storage, read_write> list_stats: array<atomic<u32>, 2>;

@fragment
fn fs_gather(v: PlaneOut, @builtin(front_facing) front: bool) {
    let width = textureDimensions(ray_distance).x;
    let px = vec2<u32>(v.clip.xy);
    let i = px.y * width + px.x;
    let d = length(v.world - camera.position.xyz);
    let slot = atomicAdd(&crossing_count[i], 1u);
    if (slot < cfg.light.z) {
        crossing_list[i * cfg.light.z + slot] = select(-d, d, front);
    }
}

@compute @workgroup_size(8, 8)
fn cs_walk(@builtin(global_invocation_id) gid: vec3<u32>) {
    let dims = textureDimensions(ray_distance);
    if (gid.x >= dims.x || gid.y >= dims.y) {
        return;
    }
    let i = gid.y * dims.x + gid.x;
    let cap = cfg.light.z;
    let total = atomicLoad(&crossing_count[i]);
    let n = min(total, cap);
    // Unconditional: lavapipe (Mesa 22.3) crashes on an atomicAdd under a branch here.
    atomicAdd(&list_stats[0], select(0u, 1u, total > cap));
    atomicMax(&list_stats[1], total);
    let base = i * cap;
    // Bubble sort by distance, flattened to one loop (n passes over the n − 1 neighbour pairs):
    // lavapipe's shader compiler crashes on nested dynamic loops. Lists are short.
    for (var it = 0u; it < n * n; it++) {
        let j = it % n;
        if (j + 1u < n) {
            let x = crossing_list[base + j];
            let y = crossing_list[base + j + 1u];
            if (abs(x) > abs(y)) {
                crossing_list[base + j] = y;
                crossing_list[base + j + 1u] = x;
            }
        }
    }
    let dir = camera_ray_dir(camera, vec2<f32>(gid.xy) + 0.5);
    let end = camera_ray_length(camera, dir, textureLoad(ray_distance, vec2<i32>(gid.xy), 0).r);
    let k = cfg.light.x;
    // Shadow count of the current point; ≤ 0 is lit (a negative count only comes from a plane
    // the rasteriser clipped, and is treated as lit rather than trusted).
    var count = i32(cfg.light.y);
    var start = 0.0;
    var sum = vec3<f32>(0.0);
    for (var a = 0u; a < n; a++) {
        let x = crossing_list[base + a];
        let d = min(abs(x), end);
        let lit = count <= 0;
        count += select(-1, 1, x > 0.0);
        if (lit && count > 0) {
            sum += lit_between(gamma_table, k, dir, start, d, cfg.light.w);
        } else if (!lit && count <= 0) {
            start = d;
        }
    }
    if (count <= 0) {
        sum += lit_between(gamma_table, k, dir, start, end, cfg.light.w);
    }
    var acc = vec4<f32>(sum, 0.0);
    if (k > 0u) {
        acc += inscatter_sum[i];
    }
    inscatter_sum[i] = acc;
    textureStore(inscatter_out, vec2<i32>(gid.xy), acc);
}
