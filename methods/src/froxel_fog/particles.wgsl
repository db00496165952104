// Particle media into froxels (Hillaire 2015's unified volumes). `voxelise`: each froxel column
// spreads, for every particle binned to it and along 2 × 2 sub-rays over the column's pixels,
// the sphere's exact chord over the slices it crosses: each froxel's mean σ_s and τ along those
// rays (exact in depth, supersampled across). `extinction`: each column of a light's
// extinction grid sums the chords of its ray through the particles per slab and prefix-sums
// them: the optical depth from the grid's start to every slab end (the cloud's self-shadowing).
// Needs PRELUDE, grid.wgsl and extinction.wgsl.

struct Particle {
    center: vec3<f32>,
    radius: f32,
    sigma_s: vec3<f32>,
    tau: f32,
};

@group(1) @binding(0) var<uniform> froxel: Froxel;
@group(1) @binding(1) var<uniform> particle_medium: ParticleMedium;
@group(1) @binding(2) var<storage, read> particles: array<Particle>;
// Camera bins (offsets per froxel column, then particle indices) from 0, each light grid's from
// its `bins_at`; offsets are absolute positions in this array.
@group(1) @binding(3) var<storage, read> bins: array<u32>;
@group(1) @binding(4) var<storage, read_write> density: array<Voxel>;
@group(1) @binding(5) var<storage, read_write> optical_depth: array<f32>;

// The chord (t_in, t_out) of the ray o + t d (d unit) through particle p; t_out ≤ t_in if none.
fn chord(p: Particle, o: vec3<f32>, d: vec3<f32>) -> vec2<f32> {
    let q = p.center - o;
    let tc = dot(q, d);
    // The centre's squared distance from the ray from its perpendicular part (stable far away).
    let perp = q - d * tc;
    let h2 = p.radius * p.radius - dot(perp, perp);
    let h = sqrt(max(h2, 0.0));
    return select(vec2<f32>(1.0, 0.0), vec2<f32>(tc - h, tc + h), h2 > 0.0);
}

// Slice coordinate of view distance t on a ray of far distance far_t.
fn slice_of(t: f32, far_t: f32) -> f32 {
    return slice_coordinate(froxel, t, far_t);
}

// Distance of slice k's near boundary on a ray of far distance far_t.
fn slice_start(far_t: f32, k: u32) -> f32 {
    return far_t * pow(f32(k) / f32(froxel.slices), froxel.depth_exponent);
}

fn column_index(x: u32, y: u32, k: u32) -> u32 {
    return (k * froxel.grid_y + y) * froxel.grid_x + x;
}

// Adds particle p's chord along the sub-ray (eye, dir, far distance far_t) to the slices of
// column xy it overlaps, each weighted by a quarter of the slice's length.
fn add_chord(xy: vec2<u32>, p: Particle, dir: vec3<f32>, far_t: f32) {
    let c = chord(p, camera.position.xyz, dir);
    let a = max(c.x, 0.0);
    let b = min(c.y, far_t);
    let k0 = min(u32(slice_of(a, far_t)), froxel.slices - 1u);
    // No slice when the chord misses the ray's span (k1 = 0 ends the loop at once).
    let k1 = select(0u, min(u32(slice_of(b, far_t)), froxel.slices - 1u) + 1u, b > a);
    for (var k = k0; k < k1; k++) {
        let t0 = slice_start(far_t, k);
        let t1 = slice_start(far_t, k + 1u);
        let lo = max(a, t0);
        let hi = min(b, t1);
        let w = 0.25 * max(hi - lo, 0.0) / max(t1 - t0, 1e-12);
        let i = column_index(xy.x, xy.y, k);
        density[i].medium += vec4<f32>(p.sigma_s, p.tau) * w;
        density[i].moment.x += p.tau * w * 0.5 * (lo + hi);
        if (hi > lo) {
            // The span of the slice the particles occupy (slice_quadrature.wgsl).
            density[i].moment.y = min(density[i].moment.y, lo);
            density[i].moment.z = max(density[i].moment.z, hi);
        }
    }
}

// The ray through pixel position (x + o.x, y + o.y) · pixel_size of the grid (clamped to the
// viewport) and its far distance.
fn sub_ray(xy: vec2<u32>, o: vec2<f32>) -> vec4<f32> {
    let frag = min((vec2<f32>(xy) + o) * froxel.pixel_size, camera.viewport.xy);
    let dir = camera_ray_dir(camera, frag);
    return vec4<f32>(dir, camera_far_distance(camera, dir));
}

// One thread per froxel column: each binned particle's chords along the column's four sub-rays,
// spread over the slices they cross. (No early return inside the loops: lavapipe crashed on the
// inlined function's return inside a loop.)
@compute @workgroup_size(8, 8, 1)
fn voxelise(@builtin(global_invocation_id) id: vec3<u32>) {
    if (id.x >= froxel.grid_x || id.y >= froxel.grid_y) {
        return;
    }
    for (var k = 0u; k < froxel.slices; k++) {
        density[column_index(id.x, id.y, k)] = Voxel(vec4<f32>(0.0), vec4<f32>(0.0, 3.4e38, 0.0, 0.0));
    }
    let col = id.y * froxel.grid_x + id.x;
    let r0 = sub_ray(id.xy, vec2<f32>(0.25, 0.25));
    let r1 = sub_ray(id.xy, vec2<f32>(0.75, 0.25));
    let r2 = sub_ray(id.xy, vec2<f32>(0.25, 0.75));
    let r3 = sub_ray(id.xy, vec2<f32>(0.75, 0.75));
    for (var j = bins[col]; j < bins[col + 1u]; j++) {
        let p = particles[bins[j]];
        add_chord(id.xy, p, r0.xyz, r0.w);
        add_chord(id.xy, p, r1.xyz, r1.w);
        add_chord(id.xy, p, r2.xyz, r2.w);
        add_chord(id.xy, p, r3.xyz, r3.w);
    }
}

// The ray of column (i, j) of grid g: origin and unit direction; depth along it is t.
fn grid_ray_of(g: LightGrid, i: u32, j: u32) -> array<vec3<f32>, 2> {
    let uv = (vec2<f32>(f32(i), f32(j)) + 0.5) / f32(g.n) * 2.0 - 1.0;
    if (g.kind == 1u) {
        let o = g.origin.xyz + (g.right.xyz * uv.x + g.up.xyz * uv.y) * g.right.w;
        return array<vec3<f32>, 2>(o, g.axis.xyz);
    }
    let d = normalize(g.axis.xyz + (g.right.xyz * uv.x + g.up.xyz * uv.y) * g.right.w);
    return array<vec3<f32>, 2>(g.origin.xyz, d);
}

// One thread per column (x) of light grid z (of a cube's faces one after another).
@compute @workgroup_size(64, 1, 1)
fn extinction(@builtin(global_invocation_id) id: vec3<u32>) {
    let whole = particle_medium.grids[id.z];
    let per_face = whole.n * whole.n;
    let faces = select(1u, 6u, whole.kind == 3u);
    if (whole.kind == 0u || id.x >= faces * per_face) {
        return;
    }
    var g = whole;
    if (whole.kind == 3u) {
        g = face_grid(whole, id.x / per_face);
    }
    let column = id.x % per_face;
    let base = g.depth_at + column * g.n;
    for (var k = 0u; k < g.n; k++) {
        optical_depth[base + k] = 0.0;
    }
    let ray = grid_ray_of(g, column % g.n, column / g.n);
    let z0 = g.axis.w;
    let dz = (g.z1 - z0) / f32(g.n);
    let first = bins[g.bins_at + column];
    let last = bins[g.bins_at + column + 1u];
    for (var j = first; j < last; j++) {
        let p = particles[bins[j]];
        let c = chord(p, ray[0], ray[1]);
        let a = max(c.x, z0);
        let b = min(c.y, g.z1);
        if (b <= a) {
            continue;
        }
        let k1 = min(u32((b - z0) / dz), g.n - 1u);
        for (var k = min(u32((a - z0) / dz), k1); k <= k1; k++) {
            let s0 = z0 + f32(k) * dz;
            let overlap = max(min(b, s0 + dz) - max(a, s0), 0.0);
            optical_depth[base + k] += p.tau * overlap;
        }
    }
    var sum = 0.0;
    for (var k = 0u; k < g.n; k++) {
        sum += optical_depth[base + k];
        optical_depth[base + k] = sum;
    }
}
