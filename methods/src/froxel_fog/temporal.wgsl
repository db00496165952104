// Temporal accumulation of the injected source (Wronski 2014's reprojection, blended as Godot 4's
// volumetric_fog_process): each froxel's centre is projected into the previous frame's grid
// (its camera in `froxel.prev_*`), the previous accumulated source is read there trilinearly
// (dropped outside the previous grid, as Godot and Unreal do), and this frame's jittered
// injection is blended in with weight `froxel.blend`. What is done with a history that is no
// longer true is the knob `history` (HISTORY): kept (none: Godot's and Unreal's volumetric fog);
// clamped to the range of this frame's source over the 3 × 3 × 3 froxels around it (clamp:
// Karis 2014's TAA neighbourhood clamp in 3-D); or dropped where the froxel's lighting changed
// (reject): `inject` also evaluates each froxel at its centre, a deterministic sample whose
// relative change since the history began beyond REJECT_CHANGE means the light, a shadow or the
// medium moved — the jitter alone never changes it (rejection by a change in lighting; Unreal
// drops history only outside the previous frustum or behind last frame's depth); or, tolerant of a
// moving camera (range), dropped where the centre source the history began with, reprojected, lies
// outside the range of this frame's centre sources over the 3 × 3 × 3 froxels around (Karis 2014's
// neighbourhood box, tested on the deterministic centre samples instead of clamping the noisy
// jittered ones): the froxel grid moves with the camera, so a froxel's centre is another world
// point every frame and `reject`'s exact comparison drops all history while the camera moves;
// or, exact under a moving camera (revisit), dropped where this frame's lighting at the previous
// grid's centres the history was trilinearly read from differs from that frame's centre sample
// there: `inject` also evaluates every froxel of the previous frame's grid (its camera), so the
// comparison is at one world point, and a light that moved with the camera (a flashlight) is
// rejected wherever it lights while a still light keeps its history. The rejecting modes (reject,
// range, revisit) keep in the history only the residual of the jittered samples over the centre
// sample, which `integrate` adds to this frame's centre sample: a reprojection then resamples
// only what the jitter adds, not the whole source (which blurred, README).
// Needs PRELUDE, grid.wgsl and the volume bindings (volume.wgsl).

// Accumulated source of the previous frame (read) and of this one (written): rgb the source (the
// rejecting modes: its residual over the centre sample), a (the rejecting modes) the centre
// source, summed over channels, its history began with (revisit with a moved camera: last frame's).
@group(1) @binding(3) var<storage, read> history: array<vec4<f32>>;
@group(1) @binding(4) var<storage, read_write> accumulated: array<vec4<f32>>;
// History reject, range, revisit: this frame's source at each froxel's centre (`inject`), rgb,
// and a its sum; ahead of them the froxels whose reprojected history was dropped (counts[0]) and
// that had one to drop (counts[1]) this frame (counters `history_rejected`,
// `history_reprojected`; in this buffer because the stage's storage buffers are all used).
struct CentreSources {
    counts: array<atomic<u32>, 4>,
    at: array<vec4<f32>>,
};
@group(1) @binding(8) var<storage, read_write> centre: CentreSources;

// Knob `history`: 0 none (every reprojected history kept), 1 clamp, 2 reject, 3 range, 4 revisit.
override HISTORY: u32 = 0u;

// Continuous coordinates of world point p in the previous frame's grid: column x, column y and
// slice, each cell spanning [i, i + 1).
fn previous_grid_coord(p: vec3<f32>) -> vec3<f32> {
    let c = froxel.prev_clip_from_world * vec4<f32>(p, 1.0);
    let ndc = c.xy / c.w;
    let px = vec2<f32>((ndc.x * 0.5 + 0.5) * camera.viewport.x, (0.5 - 0.5 * ndc.y) * camera.viewport.y);
    let w = p - froxel.prev_position.xyz;
    let t = length(w);
    let far_t = froxel.prev_position.w / dot(w / t, froxel.prev_forward.xyz);
    let s = slice_coordinate(froxel, t, far_t);
    return vec3<f32>(px / froxel.pixel_size, select(-1.0, s, c.w > 0.0 && t <= far_t));
}

// The previous frame's camera as a Camera (what grid_ray, froxel_point and the light evaluation
// read): its clip_from_world, eye and forward with the far plane in w; world_from_clip is not
// read, and holds this frame's.
fn previous_camera() -> Camera {
    let eye = vec4<f32>(froxel.prev_position.xyz, camera.position.w);
    return Camera(froxel.prev_clip_from_world, camera.world_from_clip, eye, froxel.prev_forward, camera.viewport);
}

// The history trilinearly at grid coordinates g (cell centres at i + 0.5), clamped to the grid.
fn history_at(g: vec3<f32>) -> vec4<f32> {
    let n = vec3<f32>(f32(froxel.grid_x), f32(froxel.grid_y), f32(froxel.slices));
    let c = clamp(g - 0.5, vec3<f32>(0.0), n - 1.0);
    let i0 = vec3<u32>(floor(c));
    let i1 = min(i0 + 1u, vec3<u32>(n - 1.0));
    let f = c - floor(c);
    var out = vec4<f32>(0.0);
    for (var corner = 0u; corner < 8u; corner++) {
        let b = vec3<bool>((corner & 1u) != 0u, (corner & 2u) != 0u, (corner & 4u) != 0u);
        let idx = select(i0, i1, b);
        let w = select(1.0 - f, f, b);
        out += w.x * w.y * w.z * history[froxel_index(idx.x, idx.y, idx.z)];
    }
    return out;
}

// The history of froxel id reprojected into this frame; None (valid false) on the first frame
// and outside the previous frame's grid.
struct History {
    value: vec4<f32>,
    valid: bool,
    // where it was read in the previous frame's grid (only with a moved camera)
    at: vec3<f32>,
};

fn reprojected(id: vec3<u32>, i: u32) -> History {
    if (froxel.history == 0u) {
        return History(vec4<f32>(0.0), false, vec3<f32>(0.0));
    }
    if (froxel.moved == 0u) {
        return History(history[i], true, vec3<f32>(0.0));
    }
    let g = previous_grid_coord(froxel_point(id, vec3<f32>(0.5)));
    let n = vec3<f32>(f32(froxel.grid_x), f32(froxel.grid_y), f32(froxel.slices));
    let inside = all(g >= vec3<f32>(0.0)) && all(g <= n);
    return History(history_at(g), inside, g);
}

// The range (per channel) of this frame's injected source over the 3 × 3 × 3 froxels around id
// (fewer at the grid's faces): min in [0], max in [1].
fn neighbourhood(id: vec3<u32>) -> array<vec3<f32>, 2> {
    let last = vec3<i32>(i32(froxel.grid_x), i32(froxel.grid_y), i32(froxel.slices)) - 1;
    var lo = vec3<f32>(3.4e38);
    var hi = vec3<f32>(-3.4e38);
    for (var o = 0; o < 27; o++) {
        let d = vec3<i32>(o % 3, (o / 3) % 3, o / 9) - 1;
        let q = vec3<u32>(clamp(vec3<i32>(id) + d, vec3<i32>(0), last));
        let s = source[froxel_index(q.x, q.y, q.z)].rgb;
        lo = min(lo, s);
        hi = max(hi, s);
    }
    return array<vec3<f32>, 2>(lo, hi);
}

// History `reject` (knob `reject_change`): the relative change of a froxel's centre source
// (summed over channels) since its history began beyond which the history is dropped. The
// centre sample is deterministic, so the jitter's own spread never trips it.
override REJECT_CHANGE: f32 = 0.001;

// The range of this frame's centre sources (summed over channels) over the 3 × 3 × 3 froxels
// around id (fewer at the grid's faces): min in x, max in y.
fn centre_range(id: vec3<u32>) -> vec2<f32> {
    let last = vec3<i32>(i32(froxel.grid_x), i32(froxel.grid_y), i32(froxel.slices)) - 1;
    var range = vec2<f32>(3.4e38, -3.4e38);
    for (var o = 0; o < 27; o++) {
        let d = vec3<i32>(o % 3, (o / 3) % 3, o / 9) - 1;
        let q = vec3<u32>(clamp(vec3<i32>(id) + d, vec3<i32>(0), last));
        let c = centre.at[froxel_index(q.x, q.y, q.z)].a;
        range = vec2<f32>(min(range.x, c), max(range.y, c));
    }
    return range;
}

// Whether froxel id's (index i) lighting changed since its history `h` began (h.a: the centre
// source then, carried while the history is kept, so slow drifts add up; this frame's in
// centre.at[i].a, written by `inject`). With the camera still (or history reject) the same froxel
// is the same world point: a relative change beyond REJECT_CHANGE. With history range and a
// moved camera h.a is the previous grid's centres interpolated at this froxel's centre: a change
// when it lies outside this frame's centre range around it, widened by REJECT_CHANGE.
fn lighting_changed(id: vec3<u32>, i: u32, h: History) -> bool {
    if (HISTORY == 3u && froxel.moved != 0u) {
        let range = centre_range(id);
        return h.value.a < range.x * (1.0 - REJECT_CHANGE) || h.value.a > range.y * (1.0 + REJECT_CHANGE);
    }
    if (HISTORY == 4u && froxel.moved != 0u) {
        return revisited_change(h.at);
    }
    return changed(centre.at[i].a, h.value.a);
}

// Whether a centre source changed from `then` to `now` by more than REJECT_CHANGE (relative).
fn changed(now: f32, then: f32) -> bool {
    return abs(now - then) > REJECT_CHANGE * max(now, then);
}

// History revisit: whether the lighting changed at any of the previous grid's froxel centres
// the history at grid coordinates g is interpolated from (weight > 0; as history_at): each
// history's centre source (a: the froxel's centre sample last frame) against this frame's
// lighting at the same world point (source[j].a, written by `inject`).
fn revisited_change(g: vec3<f32>) -> bool {
    let n = vec3<f32>(f32(froxel.grid_x), f32(froxel.grid_y), f32(froxel.slices));
    let c = clamp(g - 0.5, vec3<f32>(0.0), n - 1.0);
    let i0 = vec3<u32>(floor(c));
    let i1 = min(i0 + 1u, vec3<u32>(n - 1.0));
    let f = c - floor(c);
    var any_changed = false;
    for (var corner = 0u; corner < 8u; corner++) {
        let b = vec3<bool>((corner & 1u) != 0u, (corner & 2u) != 0u, (corner & 4u) != 0u);
        let idx = select(i0, i1, b);
        let w = select(1.0 - f, f, b);
        let j = froxel_index(idx.x, idx.y, idx.z);
        any_changed = any_changed || (w.x * w.y * w.z > 0.0 && changed(source[j].a, history[j].a));
    }
    return any_changed;
}

// This workgroup's share of `centre.counts`, added once per workgroup (not once per froxel).
var<workgroup> group_counts: array<atomic<u32>, 2>;

// Blends froxel id's reprojected history (none, clamped or rejected) with this frame's source
// into `accumulated`; whether it had a reprojected history (x) and whether that was dropped (y).
fn blend_froxel(id: vec3<u32>) -> vec2<bool> {
    let i = froxel_index(id.x, id.y, id.z);
    let current = source[i];
    let h = reprojected(id, i);
    var previous = h.value.rgb;
    if (HISTORY >= 2u) {
        // The history holds the residual: the mean of the jittered samples less the centre
        // sample (the froxel shows centre + residual, `injected` in volume.wgsl), so a kept
        // history carries only what the jitter adds, and reprojection resamples that, not the
        // whole source. Dropped (or none yet): the history restarts (below). a: the centre
        // source the kept history began with.
        let c = centre.at[i];
        let rejected = h.valid && lighting_changed(id, i, h);
        // History revisit under a moved camera compares frame to frame: the kept history's
        // centre source is this frame's (the history's own was at another world point).
        let then = select(h.value.a, c.a, HISTORY == 4u && froxel.moved != 0u);
        let residual = current.rgb - c.rgb;
        let kept = vec4<f32>(mix(previous, residual, froxel.blend), then);
        // Dropped because the lighting changed: with `jitter_pair` the history restarts from
        // this frame's pair (it has no first-order jitter error), so a froxel a moving light
        // drops every frame shows a jitter correction as its kept neighbours do, and the edge of
        // the dropped region does not flicker as the light moves (pen-orbit, README). No history
        // yet (the first frame, a froxel entering the view), or without pairs (a single jittered
        // sample would flicker): the centre sample alone, as without accumulation, and the
        // history grows from there — starting a moving camera's history from a full-weight pair
        // carries that frame's correction, blurred by each reprojection, into the next frames
        // (the trucking fence-spot test: 0.1070 against 0.1018 from the centre).
        let restart = select(vec3<f32>(0.0), residual, JITTER_PAIR && h.valid);
        accumulated[i] = select(vec4<f32>(restart, c.a), kept, h.valid && !rejected);
        return vec2<bool>(h.valid, rejected);
    }
    if (HISTORY == 1u) {
        let range = neighbourhood(id);
        previous = clamp(previous, range[0], range[1]);
    }
    let blended = mix(previous, current.rgb, select(1.0, froxel.blend, h.valid));
    accumulated[i] = vec4<f32>(blended, 0.0);
    return vec2<bool>(h.valid, false);
}

@compute @workgroup_size(4, 4, 4)
fn temporal(@builtin(global_invocation_id) id: vec3<u32>, @builtin(local_invocation_index) local: u32) {
    view = camera;
    var counted = vec2<bool>(false);
    if (id.x < froxel.grid_x && id.y < froxel.grid_y && id.z < froxel.slices) {
        counted = blend_froxel(id);
    }
    if (counted.y) {
        atomicAdd(&group_counts[0], 1u);
    }
    if (counted.x) {
        atomicAdd(&group_counts[1], 1u);
    }
    workgroupBarrier();
    if (HISTORY >= 2u && local == 0u) {
        atomicAdd(&centre.counts[0], atomicLoad(&group_counts[0]));
        atomicAdd(&centre.counts[1], atomicLoad(&group_counts[1]));
    }
}
