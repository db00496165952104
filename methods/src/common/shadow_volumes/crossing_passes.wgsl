// The method side of the crossing lists (after PRELUDE, shadow_plane.wgsl and
// crossing_lists.wgsl): the count and gather fragment entries of the shadow-plane draws
// (`vs_plane`), and the walk over a sorted list.
// The including module supplies `fn crossing_lit(px: vec2<u32>, a: f32, b: f32) -> vec3<f32>`:
// the method's in-scatter of the lit interval [a, b] (distances from the eye) on pixel px's ray,
// so each method keeps its own per-interval integral (biri-shadow-volumes: eq. 7 between two
// distances; biri-polynomial: Γ(b) − Γ(a)).

// Pass 1: one count per plane fragment in front of the visible surface. (The marker after
// @fragment becomes @early_depth_test(force) where the device has it: `passes_wgsl`.)
@fragment /* early depth test */
fn fs_crossing_count(v: PlaneFrag) {
    crossing_count_fragment(vec2<u32>(v.clip.xy));
}

// Pass 3: the fragment's distance along the view ray, + front-facing (entering a shadow volume),
// − back-facing (leaving one).
@fragment /* early depth test */
fn fs_crossing_gather(v: PlaneFrag, @builtin(front_facing) front: bool) {
    let d = plane_distance(v);
    crossing_append(vec2<u32>(v.clip.xy), select(-d, d, front));
}

// Pass 4: the sum of `crossing_lit(px, a, b)` over the lit intervals of the ray through pixel px
// from the eye to distance `end` (the visible surface), walking its sorted crossings from the
// eye's shadow count (crossing_cfg.eye_count). Count ≤ 0 is lit (a negative count only comes
// from a plane the rasteriser lost, and is treated as lit rather than trusted).
// Two loops, so that `crossing_lit` runs once per lit interval of the group's busiest pixel: a
// SIMD rasteriser (lavapipe) runs a branch for a group of pixels whenever one of them takes it,
// so calling it from inside the crossing loop cost one call per crossing of the group's longest
// list. The first loop writes the distances where the lit state toggles over the sorted list
// (in place: one write per crossing read at most), the second pairs them up. A method that needs
// the lit bounds before it integrates (biri-shadow-volumes' per-ray spot fit) calls the first
// half, `crossing_lit_bounds`, and pairs the bounds itself (`crossing_lit_bound`).
fn crossing_walk(px: vec2<u32>, end: f32) -> vec3<f32> {
    return crossing_lit_sum(px, crossing_lit_bounds(px, end), end);
}

// The lit intervals of a walked list: their bounds are [0 if the eye is lit] ++ the toggles
// (stored from pool index `base`) ++ [end if the ray ends lit], `bounds` of them (even).
struct CrossingLit {
    base: u32,
    eye_lit: u32,
    toggles: u32,
    bounds: u32,
};

// `crossing_walk`'s first loop: sorts pixel px's list and writes the toggles over it.
fn crossing_lit_bounds(px: vec2<u32>, end: f32) -> CrossingLit {
    let list = crossing_sorted(px);
    var count = i32(crossing_cfg.eye_count);
    var toggles = 0u;
    for (var a = 0u; a < list.y; a++) {
        let x = crossing_pool[list.x + a];
        let lit = count <= 0;
        count += select(-1, 1, x > 0.0);
        if (lit != (count <= 0)) {
            crossing_pool[list.x + toggles] = min(abs(x), end);
            toggles += 1u;
        }
    }
    let eye_lit = select(0u, 1u, crossing_cfg.eye_count == 0u);
    return CrossingLit(list.x, eye_lit, toggles, eye_lit + toggles + select(0u, 1u, count <= 0));
}

// `crossing_walk`'s second loop: `crossing_lit` over the lit intervals, the bounds in pairs.
fn crossing_lit_sum(px: vec2<u32>, lit: CrossingLit, end: f32) -> vec3<f32> {
    var sum = vec3<f32>(0.0);
    for (var j = 0u; j + 1u < lit.bounds; j += 2u) {
        let a = crossing_lit_bound(lit, j, end);
        let b = crossing_lit_bound(lit, j + 1u, end);
        sum += crossing_lit(px, a, b);
    }
    return sum;
}

// A compute walk's output for pixel px (index i): light `light`'s `walked` in-scatter added to
// the running sum over lights (light 0 starts it), stored into the sum and the target. The
// including module declares `crossing_sum` (array<vec4<f32>>, read_write) and `crossing_out`
// (texture_storage_2d<rgba32float, write>).
fn crossing_accumulate(px: vec2<u32>, i: u32, light: u32, walked: vec3<f32>) {
    var acc = vec4<f32>(walked, 0.0);
    if (light > 0u) {
        acc += crossing_sum[i];
    }
    crossing_sum[i] = acc;
    textureStore(crossing_out, vec2<i32>(px), acc);
}

// Bound j of the lit intervals: 0 (the eye, when lit), a toggle, or `end`.
fn crossing_lit_bound(lit: CrossingLit, j: u32, end: f32) -> f32 {
    if (j < lit.eye_lit) {
        return 0.0;
    }
    if (j - lit.eye_lit < lit.toggles) {
        return crossing_pool[lit.base + j - lit.eye_lit];
    }
    return end;
}
