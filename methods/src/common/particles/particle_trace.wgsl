// Exact particle optical depth through a uniform grid over the spheres (common::particles::trace,
// built on the CPU): a 3-D DDA walks the cells a segment crosses, front to back, and each listed
// sphere's chord is clipped to the current cell's t-range, so every chord is counted exactly
// once without deduplication (ARCHITECTURE §1: τ = Σ τ_j · chord_j). Group 2. Needs PRELUDE.

// Mirrors common::particles::trace::GridInfo.
struct GridInfo {
    // xyz: the grid's low corner (m)
    lo: vec4<f32>,
    // xyz: one cell's size (m)
    cell: vec4<f32>,
    // xyz: cells per axis; w: number of spheres
    dims: vec4<u32>,
    // rgb: the sky radiance behind the cloud (W/(m² sr))
    sky: vec4<f32>,
};

// Mirrors common::particles::trace::GpuSphere.
struct Sphere {
    // xyz: centre (m); w: radius (m)
    center_radius: vec4<f32>,
    // rgb: single-scattering albedo; w: extinction τ (1/m)
    albedo_tau: vec4<f32>,
};

@group(2) @binding(0) var<uniform> grid: GridInfo;
@group(2) @binding(1) var<storage, read> spheres: array<Sphere>;
// Cell c lists cell_items[cell_start[c] .. cell_start[c + 1]].
@group(2) @binding(2) var<storage, read> cell_start: array<u32>;
@group(2) @binding(3) var<storage, read> cell_items: array<u32>;

// A segment's walk through the cells (Amanatides & Woo). After each `grid_walk_step`, [enter, exit] is the segment's part in cell `index`; the parts partition the
// segment's part inside the grid.
// Use: `var w = grid_walk(…); while (grid_walk_more(w)) { w = grid_walk_step(w); … }`.
struct GridWalk {
    cell: vec3<i32>,
    step: vec3<i32>,
    // t where the ray crosses the current cell's next face, per axis
    t_next: vec3<f32>,
    // t between faces, per axis
    t_delta: vec3<f32>,
    // start of the part not yet walked; the walk ends at t_end
    t: f32,
    t_end: f32,
    enter: f32,
    exit: f32,
    index: u32,
};

// The walk of o + d t, t in [t0, t1] (d a unit vector).
fn grid_walk(o: vec3<f32>, d: vec3<f32>, t0: f32, t1: f32) -> GridWalk {
    var w: GridWalk;
    let dims = vec3<i32>(grid.dims.xyz);
    let size = grid.cell.xyz;
    let lo = grid.lo.xyz;
    let hi = lo + size * vec3<f32>(dims);
    // Axis-parallel rays: a tiny component instead of 0 (no division by zero; the faces along
    // that axis are then never reached).
    let safe = select(d, vec3<f32>(1e-20), abs(d) < vec3<f32>(1e-20));
    let inv = 1.0 / safe;
    let a = (lo - o) * inv;
    let b = (hi - o) * inv;
    let near = min(a, b);
    let far = max(a, b);
    w.t = max(max(max(near.x, near.y), near.z), t0);
    w.t_end = min(min(min(far.x, far.y), far.z), t1);
    if (grid.dims.w == 0u) { w.t_end = w.t; }
    let p = o + d * (0.5 * (w.t + min(w.t_end, w.t + 1e-3 * min(min(size.x, size.y), size.z))));
    w.cell = clamp(vec3<i32>(floor((p - lo) / size)), vec3<i32>(0), dims - 1);
    w.step = select(vec3<i32>(-1), vec3<i32>(1), safe > vec3<f32>(0.0));
    let face = lo + size * vec3<f32>(w.cell + select(vec3<i32>(0), vec3<i32>(1), w.step > vec3<i32>(0)));
    w.t_next = (face - o) * inv;
    w.t_delta = abs(size * inv);
    return w;
}

// Whether the walk has cells left.
fn grid_walk_more(w: GridWalk) -> bool {
    return w.t < w.t_end;
}

// The walk moved to its next cell: [enter, exit] in cell `index`. Call while grid_walk_more.
// (By value, no pointer argument: lavapipe (Mesa 22.3) lost lanes in a loop whose condition
// advanced the walk through a pointer.)
fn grid_walk_step(w_in: GridWalk) -> GridWalk {
    var w = w_in;
    let dims = vec3<i32>(grid.dims.xyz);
    let c = w.cell;
    w.index = u32(c.x + dims.x * (c.y + dims.y * c.z));
    w.enter = w.t;
    let tn = w.t_next;
    // The axis whose face comes first, as a mask (no dynamic vector indexing).
    let x_first = tn.x <= tn.y && tn.x <= tn.z;
    let y_first = !x_first && tn.y <= tn.z;
    let axis = vec3<bool>(x_first, y_first, !x_first && !y_first);
    var exit = min(min(min(tn.x, tn.y), tn.z), w.t_end);
    w.cell += select(vec3<i32>(0), w.step, axis);
    w.t_next += select(vec3<f32>(0.0), w.t_delta, axis);
    // Leaving the grid (or rounding put the last face short of t_end): this cell takes the rest.
    if (any(w.cell < vec3<i32>(0)) || any(w.cell >= dims)) { exit = w.t_end; }
    w.exit = max(exit, w.enter);
    w.t = w.exit;
    return w;
}

// Sphere j's chord along o + d t clipped to [a, b]: (entry, exit), exit ≤ entry when empty.
fn sphere_piece(j: u32, o: vec3<f32>, d: vec3<f32>, a: f32, b: f32) -> vec2<f32> {
    let s = spheres[j].center_radius;
    let oc = s.xyz - o;
    let tc = dot(oc, d);
    // Half-chord from the perpendicular offset (no cancellation far from the sphere).
    let q = oc - d * tc;
    let h2 = s.w * s.w - dot(q, q);
    let h = sqrt(max(h2, 0.0));
    return select(vec2<f32>(a, a), vec2<f32>(max(tc - h, a), min(tc + h, b)), h2 > 0.0);
}

// The particles' extinction τ (1/m) of sphere j times its chord's length inside [a, b].
fn piece_depth(j: u32, o: vec3<f32>, d: vec3<f32>, a: f32, b: f32) -> f32 {
    let p = sphere_piece(j, o, d, a, b);
    return spheres[j].albedo_tau.w * max(p.y - p.x, 0.0);
}

// Σ τ_j |chord_j ∩ [a, b]| over the spheres listed in `cell`, four per loop iteration:
// lavapipe (Mesa 22.3, gallivm's LP_MAX_TGSI_LOOP_ITERATIONS) ends every loop of an invocation
// once 65 535 loop iterations have run in it in total, so the hot loops take few iterations.
fn cell_depth(cell: u32, o: vec3<f32>, d: vec3<f32>, a: f32, b: f32) -> f32 {
    let end = cell_start[cell + 1u];
    var tau = 0.0;
    for (var i = cell_start[cell]; i < end; i += 4u) {
        let last = end - 1u;
        tau += piece_depth(cell_items[i], o, d, a, b)
            + select(0.0, piece_depth(cell_items[min(i + 1u, last)], o, d, a, b), i + 1u < end)
            + select(0.0, piece_depth(cell_items[min(i + 2u, last)], o, d, a, b), i + 2u < end)
            + select(0.0, piece_depth(cell_items[min(i + 3u, last)], o, d, a, b), i + 3u < end);
    }
    return tau;
}

// The particles' optical depth along o + d t, t in [t0, t1]: Σ τ_j · chord_j, exactly.
fn optical_depth(o: vec3<f32>, d: vec3<f32>, t0: f32, t1: f32) -> f32 {
    var w = grid_walk(o, d, t0, t1);
    var tau = 0.0;
    while (grid_walk_more(w)) {
        w = grid_walk_step(w);
        tau += cell_depth(w.index, o, d, w.enter, w.exit);
    }
    return tau;
}

// The particles' optical depth from x toward light k: to the light for a local light, out of
// the grid (along −direction) for a directional one.
fn light_leg_depth(k: u32, x: vec3<f32>) -> f32 {
    let w = lights.lights[k].position.xyz - x;
    let r = length(w);
    var d = w / max(r, 1e-30);
    var t1 = r;
    if (light_kind(k) == LIGHT_DIRECTIONAL) {
        d = -lights.lights[k].direction.xyz;
        t1 = 3.0e38;
    }
    return optical_depth(x, d, 0.0, t1);
}
