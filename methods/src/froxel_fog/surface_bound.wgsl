// Depth-aware jitter (knob `jitter_bound` = surface, with temporal accumulation): a froxel's
// jittered samples stay in front of its column's nearest visible surface. A pixel reads the
// volume at its surface (lookup.wgsl: linear in slice coordinate between the slice's bounds), so
// of the slice its surface cuts it takes only the front part, at the slice's mean source. One
// centre sample lights that slice wholly or not at all; jittered over the whole slice its mean
// lights it at the lit share b, and a surface in the slice reads b (1 − b) of a lit slice behind
// it: light behind a thin wall leaks through (corridor-walk, README). Bounded to the front part,
// the mean is the source the surface's pixels integrate. Unreal's volumetric fog uses the same
// per-column depth (`ConservativeDepthTexture` in VolumetricFog.usf, UE 5: no lighting behind
// a column's conservative depth, history dropped where last frame's depth hid the froxel); read,
// none copied. Needs PRELUDE, grid.wgsl and volume.wgsl's `froxel` and `view`.

// Per froxel column (x fastest): the slice coordinate (slices · (d / far)^(1 / exponent), as
// lookup.wgsl reads it) of the nearest visible surface over the column's pixels, written by
// `nearest_surface` each frame (a 4-byte stub when the bound is off).
@group(1) @binding(9) var<storage, read_write> nearest_slice: array<f32>;
// The surface pass's ray distance per pixel (−1 where the ray hits nothing: the far plane).
@group(1) @binding(10) var surface_distance: texture_2d<f32>;

// Knob `jitter_bound` = surface (with temporal accumulation): bound the jitter in depth.
override SURFACE_BOUND: bool = false;

// The share of slice k of column (x, y) in front of the column's nearest surface: 1 where the
// surface lies behind the slice — or in front of it (the slice then only reaches pixels that
// see past the nearest one, which read all of it).
fn front_share(x: u32, y: u32, k: u32) -> f32 {
    if (!SURFACE_BOUND) {
        return 1.0;
    }
    let s = nearest_slice[y * froxel.grid_x + x] - f32(k);
    return select(1.0, s, s > 0.0 && s < 1.0);
}

@compute @workgroup_size(8, 8, 1)
fn nearest_surface(@builtin(global_invocation_id) id: vec3<u32>) {
    view = camera;
    if (id.x >= froxel.grid_x || id.y >= froxel.grid_y) {
        return;
    }
    let size = vec2<i32>(textureDimensions(surface_distance));
    let ps = froxel.pixel_size;
    // The pixels whose centres lie in the column: [x · ps, (x + 1) · ps) across and down.
    let lo = min(vec2<i32>(ceil(vec2<f32>(id.xy) * ps - 0.5)), size - 1);
    let hi = max(min(vec2<i32>(ceil((vec2<f32>(id.xy) + 1.0) * ps - 0.5)), size), lo + 1);
    var nearest = f32(froxel.slices);
    for (var py = lo.y; py < hi.y; py++) {
        for (var px = lo.x; px < hi.x; px++) {
            let dir = camera_ray_dir(camera, vec2<f32>(f32(px), f32(py)) + 0.5);
            let far_t = camera_far_distance(camera, dir);
            let d = camera_ray_length(camera, dir, textureLoad(surface_distance, vec2<i32>(px, py), 0).r);
            let s = slice_coordinate(froxel, d, far_t);
            nearest = min(nearest, s);
        }
    }
    nearest_slice[id.y * froxel.grid_x + id.x] = nearest;
}
