// Particle media: the light-space extinction grids (one per light; froxel_fog::particles::
// LightGrid) and the optical depth from a light to a point read from them. A module that
// composes this declares `particle_medium: ParticleMedium` (uniform) and `optical_depth:
// array<f32>` (storage). Mirrors froxel_fog::particle_passes::ParticleUniform.

struct LightGrid {
    // xyz: the sun's grid centre or the local light's position
    origin: vec4<f32>,
    // xyz: unit right; w: half-extent (m, sun) or tan of the cone's half-angle (local light)
    right: vec4<f32>,
    // xyz: unit up
    up: vec4<f32>,
    // xyz: unit axis (the sun's direction or the cone's); w: depth z0 of the first slab
    axis: vec4<f32>,
    // depth of the last slab's far end
    z1: f32,
    // 0 none, 1 orthographic (sun), 2 perspective (local light), 3 a cube of six perspective
    // faces around a local light (face_grid), depths and bins face after face
    kind: u32,
    // columns per side and slabs per column
    n: u32,
    // first value of this grid in optical_depth: column-major, n slabs per column, each the
    // optical depth from z0 to the slab's far end
    depth_at: u32,
    // first column offset of this grid's bins in the bins buffer
    bins_at: u32,
    _pad0: u32,
    _pad1: u32,
    _pad2: u32,
};

// A froxel's particles (particles.wgsl's voxelise): medium rgb their mean σ_s, a their mean τ
// (1/m) over the froxel; moment.x Σ τ · length · t over their chords in it, so moment.x / (τ d)
// is the extinction-weighted mean distance t of the particles in the slice (length d); moment.y
// and moment.z the nearest and farthest distance of those chords in the slice (3.4e38 and 0
// where none).
struct Voxel {
    medium: vec4<f32>,
    moment: vec4<f32>,
};

struct ParticleMedium {
    // rgb: sky radiance behind the cloud
    sky: vec4<f32>,
    // particles in the particle buffer
    count: u32,
    _pad0: u32,
    _pad1: u32,
    _pad2: u32,
    grids: array<LightGrid, 4>,  // particle_passes::PARTICLE_GRIDS
};

// Axis of cube face f: +x, −x, +y, −y, +z, −z (common::shadow_maps::CUBE_FACE_AXES).
fn cube_axis(f: u32) -> vec3<f32> {
    let s = select(1.0, -1.0, (f & 1u) == 1u);
    let a = f / 2u;
    return vec3<f32>(select(0.0, s, a == 0u), select(0.0, s, a == 1u), select(0.0, s, a == 2u));
}

// The cube face whose 90° cone holds direction q.
fn cube_face(q: vec3<f32>) -> u32 {
    let a = abs(q);
    if (a.x >= a.y && a.x >= a.z) {
        return select(0u, 1u, q.x < 0.0);
    }
    if (a.y >= a.z) {
        return select(2u, 3u, q.y < 0.0);
    }
    return select(4u, 5u, q.z < 0.0);
}

// Face f of cube grid g as a perspective grid of its own (particles.rs basis and cube_grid).
fn face_grid(g: LightGrid, f: u32) -> LightGrid {
    let axis = cube_axis(f);
    let helper = select(vec3<f32>(1.0, 0.0, 0.0), vec3<f32>(0.0, 1.0, 0.0), abs(axis.y) < 0.9);
    let right = normalize(cross(axis, helper));
    var face = g;
    face.kind = 2u;
    face.right = vec4<f32>(right, 1.0);
    face.up = vec4<f32>(cross(right, axis), 0.0);
    face.axis = vec4<f32>(axis, 0.0);
    face.depth_at = g.depth_at + f * g.n * g.n * g.n;
    face.bins_at = g.bins_at + f * g.n * g.n;
    return face;
}

// Grid position of world point x: (u, v) in [−1, 1]² across the columns, z the depth along the
// column's ray; w < 0 when x lies outside the grid's cone (local light, behind it).
fn light_grid_coord(g: LightGrid, x: vec3<f32>) -> vec4<f32> {
    let q = x - g.origin.xyz;
    let a = dot(q, g.axis.xyz);
    let uv = vec2<f32>(dot(q, g.right.xyz), dot(q, g.up.xyz));
    if (g.kind == 1u) {
        return vec4<f32>(uv / g.right.w, a, 1.0);
    }
    return vec4<f32>(uv / (max(a, 1e-12) * g.right.w), length(q), select(-1.0, 1.0, a > 0.0));
}

// Optical depth from z0 to slab coordinate s ∈ [0, n] along column `col` (linear between slab ends).
fn column_depth(g: LightGrid, col: u32, s: f32) -> f32 {
    let sc = clamp(s, 0.0, f32(g.n));
    let b = u32(floor(sc));
    let base = g.depth_at + col * g.n;
    let before = select(optical_depth[base + max(b, 1u) - 1u], 0.0, b == 0u);
    let after = optical_depth[base + min(b, g.n - 1u)];
    return mix(before, after, sc - floor(sc));
}

// Particle optical depth between light k and world point x (0 without particles or outside the grid).
fn particle_depth_to_light(k: u32, x: vec3<f32>) -> f32 {
    var g = particle_medium.grids[k];
    if (g.kind == 0u) {
        return 0.0;
    }
    if (g.kind == 3u) {
        g = face_grid(g, cube_face(x - g.origin.xyz));
    }
    let c = light_grid_coord(g, x);
    if (c.w < 0.0 || any(abs(c.xy) > vec2<f32>(1.0))) {
        return 0.0;
    }
    let n = f32(g.n);
    let p = clamp((c.xy * 0.5 + 0.5) * n - 0.5, vec2<f32>(0.0), vec2<f32>(n - 1.0));
    let i0 = vec2<u32>(floor(p));
    let i1 = min(i0 + 1u, vec2<u32>(g.n - 1u));
    let f = p - floor(p);
    let s = (c.z - g.axis.w) / max(g.z1 - g.axis.w, 1e-12) * n;
    let d00 = column_depth(g, i0.y * g.n + i0.x, s);
    let d10 = column_depth(g, i0.y * g.n + i1.x, s);
    let d01 = column_depth(g, i1.y * g.n + i0.x, s);
    let d11 = column_depth(g, i1.y * g.n + i1.x, s);
    return mix(mix(d00, d10, f.x), mix(d01, d11, f.x), f.y);
}
