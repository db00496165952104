// Shared by every pass of umenhoffer-particle-blocks and particle-splat: the method's bindings
// (group 1; each pass's layout holds only the bindings its entry points use), billboard frames,
// the light map's projection, impostor-tile and analytic-sphere intervals, the slice lookup
// (Umenhoffer et al. §2.3) and the light's radiance arriving at a point. Needs PRELUDE.

// One light map (a "view" of a light): a single perspective or orthographic map, or one face of
// a cube of six perspective maps around a local light (mod.rs, `light_views`).
struct View {
    // xyz: light-map right axis; w: projection (0 orthographic / directional, 1 perspective)
    u: vec4<f32>,
    // xyz: light-map up axis; w: unused
    v: vec4<f32>,
    // xyz: light-map axis (directional: the propagation direction); w: unused
    w: vec4<f32>,
    // xyz: map centre (orthographic) or light position (perspective);
    // w: half extent (m, orthographic) or tan of the half angle (perspective)
    p: vec4<f32>,
    // x: depth where the cloud starts along the light; y: where it ends (m); z: slice count S;
    // w: unused. Slice s (0 ≤ s < S) lies at depth x + (y − x)(s + 1)/S (`slice_depth`).
    range: vec4<f32>,
};

// Views per light: light k's maps are views 6k .. 6k + 5 (slice-array layers likewise).
const FACES: u32 = 6u;

// passes::MAX_LIGHTS lights' views (FACES each), the eye's view (EYE_SLICES: view FACES·L of L
// lights, `camera_view`) and map counts.
struct Pb {
    views: array<View, 97>,
    // per light, x: its views this frame (0: no light map, 1: one map, 6: a cube); y, z, w: unused
    maps: array<vec4<f32>, 16>,
    // x: tile columns; y: tile resolution (texels); z: impostor particles per direction; w: atlas size
    atlas: vec4<f32>,
    // x: clip_fix (0/1); y: background-medium march steps (0: none); z: the cloud dims the
    // background medium's in-scatter (0/1); w: the dominant spheres' count
    flags: vec4<f32>,
    // x: the primitive lists' stride C (the gathering's list at 0, light k's at (k + 1)·C);
    // y: impostor tiles per light T (light k's tiles are offset by k·T);
    // z: light-map resolution (texels); w: camera tiles per impostor particle K (the
    // prototype's direction bins, camera_bins.rs; else 1)
    counts: vec4<f32>,
    // rgb: sky radiance
    sky: vec4<f32>,
    // The dominant spheres (dominant.rs; `dominant_count()` of them), two rows each: centre and
    // radius (m); x: extinction σ (1/m), y: index in the gathering's list.
    dominant: array<vec4<f32>, 16>,
};

struct Prim {
    // xyz: centre (m); w: billboard half-size (m)
    center: vec4<f32>,
    // rgb: albedo; w: τ of an analytic sphere (1/m) or an instance's extinction multiplier
    albedo: vec4<f32>,
    // x: instance scale; y: first light's tile (< 0: an analytic sphere); z: camera tile;
    // w: unused
    extra: vec4<f32>,
};

struct Tile {
    // xyz: right; w: half-extent (prototype m)
    right: vec4<f32>,
    up: vec4<f32>,
    fwd: vec4<f32>,
};

struct ImpParticle {
    // xyz: offset from the block centroid (prototype m); w: radius
    pos: vec4<f32>,
    // x: τ; y: light tile; z: camera tile; w: unused
    data: vec4<f32>,
};

@group(1) @binding(0) var<uniform> pb: Pb;
@group(1) @binding(1) var<storage, read> prims: array<Prim>;
@group(1) @binding(2) var<storage, read> tiles: array<Tile>;
@group(1) @binding(3) var<storage, read> imp: array<ImpParticle>;
// Impostor atlas: r = min front depth, g = min(−back depth), a = Σ τ·chord (prototype units).
@group(1) @binding(4) var atlas: texture_2d<f32>;
// Light slices: accumulated particle optical depth up to each slice depth, four slices (one
// group) per RGBA texel. Group g of view vi is layer vi·SLICE_PASSES + g/2 of slices0 (g even)
// or slices1 (g odd): one light pass writes one layer of each (`slice_at`).
@group(1) @binding(5) var slices0: texture_2d_array<f32>;
@group(1) @binding(6) var slices1: texture_2d_array<f32>;
@group(1) @binding(7) var ray_distance: texture_2d<f32>;
// rgb: the cloud's in-scatter; a: its accumulated opacity.
@group(1) @binding(8) var gathered: texture_2d<f32>;
// x: the nearest ray parameter where the cloud contributes; y: minus the farthest (m).
@group(1) @binding(10) var extents: texture_2d<f32>;
// The shared surface pass's output (mesh shadows, background attenuation; no particle shadows).
@group(1) @binding(9) var surface_in: texture_2d<f32>;
// Impostor moments beside the atlas: x = Σ τ·chord·z̄, y = Σ τ·chord·(z̄² + h²/3) (prototype
// units; impostor.wgsl). Read only with MOMENTS.
@group(1) @binding(11) var atlas_moments: texture_2d<f32>;

// Corner v (0..5) of a quad of two triangles, in [−1, 1]².
fn quad_corner(v: u32) -> vec2<f32> {
    let x = select(-1.0, 1.0, v == 1u || v == 2u || v == 4u);
    let y = select(-1.0, 1.0, v == 2u || v == 4u || v == 5u);
    return vec2<f32>(x, y);
}

// How much larger than its bounding radius R a billboard at distance d from a perspective
// viewer must be: the bounding sphere's silhouette cone meets the billboard plane at radius
// R/√(1 − R²/d²). Capped at 4: a viewer nearer than `covers_viewer` draws a full-view quad.
fn grow_for(radius: f32, d: f32) -> f32 {
    let s = clamp(radius / max(d, 1e-6), 0.0, 0.97);
    return min(1.0 / sqrt(1.0 - s * s), 4.0);
}

// Whether a viewer at distance d from a primitive's centre lies inside (or so near) its bounds
// of radius R that no billboard can cover what it sees of it: the primitive is then drawn as a
// quad over the whole view, each fragment finding its interval along its own ray.
// (held.rs replaces a block holding a viewer by its particles; spheres can still hold one.)
override COVERS: f32 = 1.1;

fn covers_viewer(radius: f32, d: f32) -> bool {
    return d < COVERS * radius;
}

struct Basis {
    right: vec3<f32>,
    up: vec3<f32>,
};

// Same rule as blocks::basis_of in Rust.
fn basis_of(dir: vec3<f32>) -> Basis {
    var up_ref = vec3<f32>(0.0, 1.0, 0.0);
    if (abs(dir.y) > 0.99) { up_ref = vec3<f32>(1.0, 0.0, 0.0); }
    let right = normalize(cross(dir, up_ref));
    return Basis(right, cross(right, dir));
}

// Modes baked per run (passes.rs, `Passes::new`): lavapipe executes both sides of a branch on a
// uniform value under a mask, so a uniform knob tested in a hot loop costs its untaken side too
// (the forward-scattering taps made smoke-point's resolve 3.4× slower with the knob off).
override FORWARD_SCATTERING: bool = false;
// Slice groups G = S/4 (1, 2, 4, 8: S = 4 … 32 slices). One light pass renders two groups (two
// RGBA targets), so a view takes SLICE_PASSES = max(G/2, 1) passes (passes.rs).
override SLICE_GROUPS: u32 = 1u;

fn slice_passes() -> u32 {
    return max(SLICE_GROUPS / 2u, 1u);
}

// Depth of slice s of view vi along the light (m).
fn slice_depth(vi: u32, s: f32) -> f32 {
    let r = pb.views[vi].range;
    return r.x + (r.y - r.x) * (s + 1.0) / r.z;
}
// Primitives are impostor blocks (false: analytic spheres, the splat).
override BLOCKS: bool = true;
// A block pixel's interval is the uniform one with its optical depth's mean and variance in
// depth (knob `interval = moments`); false: [front, back] (the paper).
override MOMENTS: bool = true;
// Nodes of gather.wgsl's quadrature along a primitive's interval (knob `chord_steps`; 0: the
// closed form). It converges the closed form's three approximations: the light's optical depth
// linear along the interval, the phase and I at the midpoint only, and the mean 1/r² multiplied
// with the mean transmittance rather than integrated with it.
override CHORD_STEPS: u32 = 0u;
// The eye's own slices (knob `eye_slices`): the light pass run once more from the eye, so the
// particles' optical depth along each pixel's ray is known at any depth; the gathering then
// attenuates every primitive by everything in front of it, overlaps included, and adds instead
// of compositing "over" in centre order (gather.wgsl, resolve.wgsl).
override EYE_SLICES: bool = false;

// The eye's slice view: after every light's FACES views.
fn camera_view() -> u32 {
    return FACES * light_count();
}

// The particles' optical depth from the eye to x (EYE_SLICES only), from the eye's slices.
fn eye_optical_depth(x: vec3<f32>) -> f32 {
    let vi = camera_view();
    let c = light_coord(vi, x);
    if (c.depth <= 0.0) { return 0.0; }
    return depth_from_slices(vi, c.uv, c.depth);
}

fn is_perspective(vi: u32) -> bool {
    return pb.views[vi].u.w > 0.5;
}

// Clip position of world point x in light map vi.
fn light_clip(vi: u32, x: vec3<f32>) -> vec4<f32> {
    let q = x - pb.views[vi].p.xyz;
    let t = pb.views[vi].p.w;
    let xy = vec2<f32>(dot(q, pb.views[vi].u.xyz), dot(q, pb.views[vi].v.xyz)) / t;
    if (is_perspective(vi)) {
        return vec4<f32>(xy, 0.0, dot(q, pb.views[vi].w.xyz));
    }
    return vec4<f32>(xy, 0.0, 1.0);
}

struct LightCoord {
    uv: vec2<f32>,
    // depth along the light: x·dir (directional) or the distance to the light (m)
    depth: f32,
    // metres per unit of uv at x
    span: f32,
    ok: bool,
};

fn light_coord(vi: u32, x: vec3<f32>) -> LightCoord {
    let c = light_clip(vi, x);
    if (c.w <= 1e-6) { return LightCoord(vec2<f32>(0.0), 0.0, 1.0, false); }
    let ndc = c.xy / c.w;
    let uv = vec2<f32>(0.5 + 0.5 * ndc.x, 0.5 - 0.5 * ndc.y);
    let inside = all(uv >= vec2<f32>(0.0)) && all(uv <= vec2<f32>(1.0));
    let pw = pb.views[vi].p;
    if (is_perspective(vi)) {
        return LightCoord(uv, length(x - pw.xyz), 2.0 * c.w * pw.w, inside);
    }
    return LightCoord(uv, dot(x, pb.views[vi].w.xyz), 2.0 * pw.w, inside);
}

// The ray along which light map vi sees world point x: origin at depth 0, unit direction.
struct Ray {
    origin: vec3<f32>,
    dir: vec3<f32>,
};

fn light_ray(vi: u32, x: vec3<f32>) -> Ray {
    if (is_perspective(vi)) {
        return Ray(pb.views[vi].p.xyz, normalize(x - pb.views[vi].p.xyz));
    }
    let d = pb.views[vi].w.xyz;
    return Ray(x - d * dot(x, d), d);
}

// The map of light k that sees x: its only one, or the cube face of x's major axis from the
// light (faces +X, −X, +Y, −Y, +Z, −Z as in mod.rs).
fn view_of(k: u32, x: vec3<f32>) -> u32 {
    let base = k * FACES;
    if (pb.maps[k].x < 5.5) { return base; }
    let q = x - lights.lights[k].position.xyz;
    let a = abs(q);
    if (a.x >= a.y && a.x >= a.z) { return base + select(1u, 0u, q.x >= 0.0); }
    if (a.y >= a.z) { return base + select(3u, 2u, q.y >= 0.0); }
    return base + select(5u, 4u, q.z >= 0.0);
}

// A primitive's extent along a ray: [near, far] (ray parameter, m), its optical depth, and the
// ray parameter of its billboard plane (what plain billboard clipping compares with).
struct Interval {
    near: f32,
    far: f32,
    tau: f32,
    plane: f32,
    ok: bool,
};

// Bilinear optical depth and the min front / max back depth of the non-empty texels around
// quad coordinate q of a tile.
struct TileSample {
    front: f32,
    back: f32,
    tau: f32,
    // bilinear Σ τ·chord·z̄ and Σ τ·chord·(z̄² + h²/3) (MOMENTS only)
    m1: f32,
    m2: f32,
};

fn sample_tile(tile: u32, q: vec2<f32>) -> TileSample {
    let cols = u32(pb.atlas.x);
    let res = pb.atlas.y;
    let origin = vec2<f32>(f32(tile % cols), f32(tile / cols)) * res;
    let f = vec2<f32>(0.5 + 0.5 * q.x, 0.5 - 0.5 * q.y) * res - 0.5;
    let i0 = floor(f);
    let w = f - i0;
    var s = TileSample(1e30, -1e30, 0.0, 0.0, 0.0);
    for (var k = 0u; k < 4u; k++) {
        let hx = (k & 1u) == 1u;
        let hy = (k >> 1u) == 1u;
        let o = vec2<f32>(select(0.0, 1.0, hx), select(0.0, 1.0, hy));
        let ij = clamp(i0 + o, vec2<f32>(0.0), vec2<f32>(res - 1.0));
        let t = textureLoad(atlas, vec2<i32>(origin + ij), 0);
        let wk = select(1.0 - w.x, w.x, hx) * select(1.0 - w.y, w.y, hy);
        if (MOMENTS) {
            let m = textureLoad(atlas_moments, vec2<i32>(origin + ij), 0).xy;
            s.m1 += wk * m.x;
            s.m2 += wk * m.y;
        }
        if (t.a > 0.0) {
            s.tau += wk * t.a;
            s.front = min(s.front, t.r);
            s.back = max(s.back, -t.g);
        }
    }
    return s;
}

// Primitive p along ray r. Analytic spheres use the exact chord; blocks read their impostor
// tile (`tile`) at the ray's perpendicular offset from the block centre, in a frame
// perpendicular to the ray itself — not at the billboard-plane intersection — so a perspective
// ray sees the orthographic impostor as if it were rendered along that ray (exact for a sphere;
// the plane intersection overstates the offset by 1/cos of the ray's angle to the axis).
fn prim_interval(p: Prim, tile: f32, r: Ray) -> Interval {
    let oc = p.center.xyz - r.origin;
    let tc = dot(oc, r.dir);
    let off = r.dir * tc - oc;
    let b = basis_of(r.dir);
    let q = vec2<f32>(dot(off, b.right), dot(off, b.up)) / p.center.w;
    // Analytic spheres: every primitive of the splat, and a block's particles standing in for a
    // block that holds the viewer (light.y < 0; held.rs).
    if (!BLOCKS || p.extra.y < 0.0) {
        let rad = p.center.w;
        let h2 = rad * rad - (dot(oc, oc) - tc * tc);
        if (h2 <= 0.0) { return Interval(0.0, 0.0, 0.0, tc, false); }
        let h = sqrt(h2);
        return Interval(tc - h, tc + h, p.albedo.w * 2.0 * h, tc, true);
    }
    if (any(abs(q) > vec2<f32>(1.0))) { return Interval(0.0, 0.0, 0.0, tc, false); }
    let s = sample_tile(u32(tile), q);
    if (s.tau <= 0.0) { return Interval(0.0, 0.0, 0.0, tc, false); }
    let d = tile_depths(s);
    let scale = p.extra.x;
    return Interval(tc + d.x * scale, tc + d.y * scale, s.tau * scale * p.albedo.w, tc, true);
}

// The depth interval (prototype units) over which a block pixel spreads its optical depth
// uniformly. The paper: [front, back], the extreme particle surfaces, whatever lies between.
// MOMENTS (a modernisation): the uniform interval with the same mean m and variance v as the
// optical depth along the ray, [m − √(3v), m + √(3v)], kept within [front, back] — where the
// particles actually are, so the light's and the eye's attenuation are taken there.
fn tile_depths(s: TileSample) -> vec2<f32> {
    if (!MOMENTS) { return vec2<f32>(s.front, s.back); }
    let mean = clamp(s.m1 / s.tau, s.front, s.back);
    let half = sqrt(3.0 * max(s.m2 / s.tau - mean * mean, 0.0));
    return vec2<f32>(max(s.front, mean - half), max(min(s.back, mean + half), mean));
}

// Slice s's accumulated optical depth at texel ij of view vi (s < 0: the cloud's start, 0).
fn slice_at(vi: u32, ij: vec2<i32>, s: i32) -> f32 {
    if (s < 0) { return 0.0; }
    let g = u32(s) / 4u;
    let layer = vi * slice_passes() + g / 2u;
    var t: vec4<f32>;
    if ((g & 1u) == 0u) {
        t = textureLoad(slices0, ij, layer, 0);
    } else {
        t = textureLoad(slices1, ij, layer, 0);
    }
    return t[u32(s) % 4u];
}

// Optical depth at light depth d in map vi around uv: linear between the two enclosing slices
// (§2.3), bilinear across texels (by hand: Rgba32Float is not filterable everywhere).
fn depth_from_slices(vi: u32, uv: vec2<f32>, d: f32) -> f32 {
    let r = pb.views[vi].range;
    let f = clamp((d - r.x) / max(r.y - r.x, 1e-6) * r.z, 0.0, r.z);
    let j0 = min(floor(f), r.z - 1.0);
    let t = f - j0;
    let s0 = i32(j0) - 1;
    let res = pb.counts.z;
    let q = uv * res - 0.5;
    let i0 = floor(q);
    let w = q - i0;
    var tau = 0.0;
    for (var k = 0u; k < 4u; k++) {
        let hx = (k & 1u) == 1u;
        let hy = (k >> 1u) == 1u;
        let o = vec2<f32>(select(0.0, 1.0, hx), select(0.0, 1.0, hy));
        let ij = vec2<i32>(clamp(i0 + o, vec2<f32>(0.0), vec2<f32>(res - 1.0)));
        let wk = select(1.0 - w.x, w.x, hx) * select(1.0 - w.y, w.y, hy);
        tau += wk * mix(slice_at(vi, ij, s0), slice_at(vi, ij, s0 + 1), t);
    }
    return tau;
}

// Particle optical depth between light k and x: the slices' (every particle but the dominant
// spheres) plus the dominant spheres' exact chords.
fn light_optical_depth(k: u32, x: vec3<f32>) -> f32 {
    return slices_optical_depth(k, x) + dominant_light_depth(k, x);
}

// The dominant spheres (dominant.rs, knob `dominant`): the few particles (holding the eye or a
// local light, or optically thick, or huge) left out of the light passes and handled exactly:
// their chords toward the lights here, their eye leg in gather.wgsl.
fn dominant_count() -> u32 {
    return select(0u, u32(pb.flags.w), DOMINANT);
}

// Whether dominant spheres can occur in this scene (dominant.rs `possible`): without, their code
// folds away (lavapipe executes a loop's bookkeeping even when it runs no iteration).
override DOMINANT: bool = false;

// Where the ray o + dir·t crosses dominant sphere j: [t0, t1] (t1 ≤ t0: it misses).
fn dominant_chord(j: u32, o: vec3<f32>, dir: vec3<f32>) -> vec2<f32> {
    let s = pb.dominant[2u * j];
    let oc = s.xyz - o;
    let tc = dot(oc, dir);
    let h2 = s.w * s.w - (dot(oc, oc) - tc * tc);
    let h = sqrt(max(h2, 0.0));
    return select(vec2<f32>(0.0), vec2<f32>(tc - h, tc + h), h2 > 0.0);
}

// The dominant spheres' optical depth along o + dir·[a, b] (dir a unit vector).
fn dominant_depth(o: vec3<f32>, dir: vec3<f32>, a: f32, b: f32) -> f32 {
    var tau = 0.0;
    for (var j = 0u; j < dominant_count(); j++) {
        let c = dominant_chord(j, o, dir);
        tau += pb.dominant[2u * j + 1u].x * max(min(c.y, b) - max(c.x, a), 0.0);
    }
    return tau;
}

// The dominant spheres' optical depth between light k and x: from x back toward a directional
// light, from a local light's position to x.
fn dominant_light_depth(k: u32, x: vec3<f32>) -> f32 {
    if (light_kind(k) == LIGHT_DIRECTIONAL) {
        return dominant_depth(x, -normalize(lights.lights[k].direction.xyz), 0.0, 1e30);
    }
    let lp = lights.lights[k].position.xyz;
    let r = length(x - lp);
    return dominant_depth(lp, (x - lp) / max(r, 1e-9), 0.0, r);
}

// The slices' optical depth between light k and x. With the forward-scattering approximation
// the transmittance is averaged over a cone of taps around the light ray, widening with the
// depth travelled in the cloud (light scattered slightly forward fills in shadows).
fn slices_optical_depth(k: u32, x: vec3<f32>) -> f32 {
    if (pb.maps[k].x < 0.5) { return 0.0; }
    let vi = view_of(k, x);
    let c = light_coord(vi, x);
    if (!c.ok) { return 0.0; }
    if (!FORWARD_SCATTERING) {
        return depth_from_slices(vi, c.uv, c.depth);
    }
    let radius = 0.2 * max(c.depth - pb.views[vi].range.x, 0.0) / c.span;
    var t = exp(-depth_from_slices(vi, c.uv, c.depth));
    t += exp(-depth_from_slices(vi, c.uv + vec2<f32>(radius, 0.0), c.depth));
    t += exp(-depth_from_slices(vi, c.uv - vec2<f32>(radius, 0.0), c.depth));
    t += exp(-depth_from_slices(vi, c.uv + vec2<f32>(0.0, radius), c.depth));
    t += exp(-depth_from_slices(vi, c.uv - vec2<f32>(0.0, radius), c.depth));
    return -log(max(t / 5.0, 1e-30));
}

// p(θ) · I(ω) · V (· e^(−σt r) · inv_r2 for local lights) of light k at x, toward the eye along
// `to_eye`, without the particles' shadow; inv_r2 stands for 1/r² (or its mean over a segment).
fn light_radiance_with(k: u32, x: vec3<f32>, to_eye: vec3<f32>, inv_r2: f32) -> vec3<f32> {
    let vis = shadow_visibility(k, x);
    if (light_kind(k) == LIGHT_DIRECTIONAL) {
        let l = lights.lights[k].direction.xyz;
        return lights.lights[k].intensity.rgb * (phase(medium, dot(l, to_eye)) * vis);
    }
    let w = x - lights.lights[k].position.xyz;
    let r = max(length(w), 1e-6);
    return light_intensity(k, w) * transmittance(medium, r) * (phase(medium, dot(w / r, to_eye)) * vis * inv_r2);
}

fn light_radiance(k: u32, x: vec3<f32>, to_eye: vec3<f32>) -> vec3<f32> {
    let w = x - lights.lights[k].position.xyz;
    return light_radiance_with(k, x, to_eye, 1.0 / max(dot(w, w), 1e-12));
}

// The mean of 1/r² over the segment o + dir·[a, b] (r: the distance to light k), in Biri's angle
// variable: ∫ dt / r² = Δφ / h with h the light's distance from the ray's line. Exact; for a
// segment through a local light's neighbourhood it replaces the midpoint's 1/r², which can be
// off by orders of magnitude there.
fn mean_inv_r2(k: u32, o: vec3<f32>, dir: vec3<f32>, a: f32, b: f32) -> f32 {
    let w0 = o - lights.lights[k].position.xyz;
    let t0 = -dot(w0, dir);
    let h = length(w0 + dir * t0);
    let mid = w0 + dir * (0.5 * (a + b));
    let point = 1.0 / max(dot(mid, mid), 1e-12);
    if (b - a < 1e-4 * max(h, 1e-3) || h < 1e-6) { return point; }
    return (atan((b - t0) / h) - atan((a - t0) / h)) / (h * (b - a));
}

// A midpoint rule of n nodes over the ray segment eye + dir·[near, far]: equal steps in t, or —
// about a local light at lp — equal steps in Biri's angle φ (t = t0 + h tan φ, dt = h dφ/cos² φ,
// h: the light's distance from the ray's line), which flattens the light's 1/r² peak.
struct AngleMarch {
    t0: f32,
    h: f32,
    a: f32,
    step: f32,
    angular: bool,
};

fn angle_march(eye: vec3<f32>, dir: vec3<f32>, near: f32, far: f32, n: u32, local: bool, lp: vec3<f32>) -> AngleMarch {
    var t0 = 0.0;
    var h = 0.0;
    if (local) {
        let w0 = eye - lp;
        t0 = -dot(w0, dir);
        h = length(w0 + dir * t0);
    }
    let angular = h > 1e-4 * max(far - near, 1e-6);
    let a = select(near, atan((near - t0) / h), angular);
    let b = select(far, atan((far - t0) / h), angular);
    return AngleMarch(t0, h, a, (b - a) / f32(n), angular);
}

// Node i of march m: x = its ray parameter t (m), y = its weight (dt/du times the step).
fn march_node(m: AngleMarch, i: u32) -> vec2<f32> {
    let u = m.a + (f32(i) + 0.5) * m.step;
    if (!m.angular) { return vec2<f32>(u, m.step); }
    let c = cos(u);
    return vec2<f32>(m.t0 + m.h * tan(u), m.h / (c * c) * m.step);
}

// What σ_s multiplies in ARCHITECTURE §1's L_in at x: every light's radiance times the particles'
// transmittance toward it (from its slices), summed.
fn incident(x: vec3<f32>, to_eye: vec3<f32>) -> vec3<f32> {
    var l = vec3<f32>(0.0);
    for (var k = 0u; k < light_count(); k++) {
        l += light_radiance(k, x, to_eye) * exp(-light_optical_depth(k, x));
    }
    return l;
}
