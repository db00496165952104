// Particle media into froxels (Hillaire 2015's unified volumes). `voxelise`: each froxel sums,
// over the particles binned to its column and along 2 × 2 sub-rays spread over the column's
// pixels, the exact chord of every sphere within its slice's depth interval: the froxel's mean
// σ_s and τ along those rays (exact in depth, supersampled across). `extinction`: each column of a light's
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
// Per froxel: rgb the particles' mean σ_s, a their mean τ (1/m).
@group(1) @binding(4) var<storage, read_write> density: array<vec4<f32>>;
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

fn slice_start(far_t: f32, k: u32) -> f32 {
    return far_t * pow(f32(k) / f32(froxel.slices), froxel.depth_exponent);
}

fn column_index(x: u32, y: u32, k: u32) -> u32 {
    return (k * froxel.grid_y + y) * froxel.grid_x + x;
}

// One thread per froxel: its slice's overlap with every binned particle's chord, on each sub-ray.
@compute @workgroup_size(4, 4, 4)
fn voxelise(@builtin(global_invocation_id) id: vec3<u32>) {
    if (id.x >= froxel.grid_x || id.y >= froxel.grid_y || id.z >= froxel.slices) {
        return;
    }
    let col = id.y * froxel.grid_x + id.x;
    let first = bins[col];
    let last = bins[col + 1u];
    let ps = froxel.pixel_size;
    let eye = camera.position.xyz;
    var sum = vec4<f32>(0.0);
    for (var sub = 0u; sub < 4u; sub++) {
        let o = vec2<f32>(0.25 + 0.5 * f32(sub & 1u), 0.25 + 0.5 * f32(sub >> 1u));
        let frag = min((vec2<f32>(f32(id.x), f32(id.y)) + o) * ps, camera.viewport.xy);
        let dir = camera_ray_dir(camera, frag);
        let far_t = camera_far_distance(camera, dir);
        let t0 = slice_start(far_t, id.z);
        let t1 = slice_start(far_t, id.z + 1u);
        var acc = vec4<f32>(0.0);
        for (var j = first; j < last; j++) {
            let p = particles[bins[j]];
            let c = chord(p, eye, dir);
            let overlap = max(min(c.y, t1) - max(c.x, t0), 0.0);
            acc += vec4<f32>(p.sigma_s, p.tau) * overlap;
        }
        sum += acc / max(t1 - t0, 1e-12);
    }
    density[column_index(id.x, id.y, id.z)] = 0.25 * sum;
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

// One thread per column (x) of light grid z.
@compute @workgroup_size(64, 1, 1)
fn extinction(@builtin(global_invocation_id) id: vec3<u32>) {
    let g = particle_medium.grids[id.z];
    if (g.kind == 0u || id.x >= g.n * g.n) {
        return;
    }
    let base = g.depth_at + id.x * g.n;
    for (var k = 0u; k < g.n; k++) {
        optical_depth[base + k] = 0.0;
    }
    let ray = grid_ray_of(g, id.x % g.n, id.x / g.n);
    let z0 = g.axis.w;
    let dz = (g.z1 - z0) / f32(g.n);
    let first = bins[g.bins_at + id.x];
    let last = bins[g.bins_at + id.x + 1u];
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
