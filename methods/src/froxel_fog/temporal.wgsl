// Temporal accumulation of the injected source (Wronski 2014's reprojection, blended as Godot 4's
// volumetric_fog_process): each froxel's centre is projected into the previous frame's grid
// (its camera in `froxel.prev_*`), the previous accumulated source is read there trilinearly,
// and this frame's jittered injection is blended in with weight `froxel.blend`. Needs PRELUDE,
// grid.wgsl and the volume bindings (volume.wgsl).

// Accumulated source of the previous frame (read) and of this one (written).
@group(1) @binding(3) var<storage, read> history: array<vec4<f32>>;
@group(1) @binding(4) var<storage, read_write> accumulated: array<vec4<f32>>;

// Continuous coordinates of world point p in the previous frame's grid: column x, column y and
// slice, each cell spanning [i, i + 1).
fn previous_grid_coord(p: vec3<f32>) -> vec3<f32> {
    let c = froxel.prev_clip_from_world * vec4<f32>(p, 1.0);
    let ndc = c.xy / c.w;
    let px = vec2<f32>((ndc.x * 0.5 + 0.5) * camera.viewport.x, (0.5 - 0.5 * ndc.y) * camera.viewport.y);
    let w = p - froxel.prev_position.xyz;
    let t = length(w);
    let far_t = froxel.prev_position.w / dot(w / t, froxel.prev_forward.xyz);
    let s = f32(froxel.slices) * pow(clamp(t / far_t, 0.0, 1.0), 1.0 / froxel.depth_exponent);
    return vec3<f32>(px / froxel.pixel_size, select(-1.0, s, c.w > 0.0 && t <= far_t));
}

// The history trilinearly at grid coordinates g (cell centres at i + 0.5), clamped to the grid.
fn history_at(g: vec3<f32>) -> vec3<f32> {
    let n = vec3<f32>(f32(froxel.grid_x), f32(froxel.grid_y), f32(froxel.slices));
    let c = clamp(g - 0.5, vec3<f32>(0.0), n - 1.0);
    let i0 = vec3<u32>(floor(c));
    let i1 = min(i0 + 1u, vec3<u32>(n - 1.0));
    let f = c - floor(c);
    var out = vec3<f32>(0.0);
    for (var corner = 0u; corner < 8u; corner++) {
        let b = vec3<bool>((corner & 1u) != 0u, (corner & 2u) != 0u, (corner & 4u) != 0u);
        let idx = select(i0, i1, b);
        let w = select(1.0 - f, f, b);
        out += w.x * w.y * w.z * history[froxel_index(idx.x, idx.y, idx.z)].rgb;
    }
    return out;
}

@compute @workgroup_size(4, 4, 4)
fn temporal(@builtin(global_invocation_id) id: vec3<u32>) {
    if (id.x >= froxel.grid_x || id.y >= froxel.grid_y || id.z >= froxel.slices) {
        return;
    }
    let i = froxel_index(id.x, id.y, id.z);
    let current = source[i].rgb;
    var previous = current;
    if (froxel.history != 0u) {
        if (froxel.moved == 0u) {
            previous = history[i].rgb;
        } else {
            let p = froxel_point(id, vec3<f32>(0.5));
            let g = previous_grid_coord(p);
            let n = vec3<f32>(f32(froxel.grid_x), f32(froxel.grid_y), f32(froxel.slices));
            let inside = all(g >= vec3<f32>(0.0)) && all(g <= n);
            previous = select(current, history_at(g), inside);
        }
    }
    accumulated[i] = vec4<f32>(mix(previous, current, froxel.blend), 0.0);
}
