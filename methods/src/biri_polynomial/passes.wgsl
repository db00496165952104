// biri-polynomial's passes, one light at a time (poly.light), after PRELUDE, FULLSCREEN and
// kernel.wgsl. Every stage writes Γ(M) of eq. 11 — the medium contribution from the eye O to a
// point M at distance x along the ray through M, σ_s I e^(−σ_t t)/h ∫_{θ0}^{θM} Λ (eq. 3 + 6), which
// is 0 at the eye — so that eq. 12's sum of differences is a signed sum of Γ terms:
//   lit surface point P: +Γ(P); front-facing shadow plane (entering a shadow from light): +Γ;
//   back-facing plane (leaving a shadow into light): −Γ; the stencil decides which count (§4.4).
// `_frag` entry points evaluate Γ per fragment (the pixel's own ray); `_vert` ones per vertex,
// Gouraud-interpolated by the rasteriser (the paper's choice).

// Mirrors `PolyUniform` in types.rs, field for field.
struct Poly {
    light: u32,          // the light this pipeline slot handles
    // 1 when plane fragments output a signed value (float target), 0 when the blend operation
    // subtracts (unorm8 target: the output must stay positive)
    signed_output: u32,
    _pad0: u32,
    _pad1: u32,
    // Taylor series in θ of p(θ + π/2), coefficients 0…8 (k-independent; from the CPU).
    series: array<vec4<f32>, 3>,
    // spot tables (spot.wgsl): [offset, n_u, n_phi, m] into `delta`
    spot: vec4<u32>,
    // x: u_max; y: 1 when the light is a spot (Γ by eq. 7)
    spot_f: vec4<f32>,
};
// The order n (≤ 8) and the fit (0 Taylor, 1 Chebyshev), baked (passes.rs): the kernel's loops
// to n get constant trip counts, so their small arrays stay in registers, and the fit not chosen
// is not evaluated (lavapipe runs both sides of a branch on a uniform value).
override ORDER: u32 = 4u;
override FIT: u32 = 0u;

@group(1) @binding(0) var ray_distance: texture_2d<f32>;
@group(1) @binding(1) var<uniform> poly: Poly;
@group(1) @binding(2) var surface: texture_2d<f32>;
@group(1) @binding(3) var<storage, read> delta: array<vec4<f32>>;

fn biri_phase(c: f32) -> f32 {
    return phase(medium, c);
}

// Γ(M) per unit σ_s·I for a point light, M at distance x from the eye along the unit `dir`.
fn biri_point_gamma(dir: vec3<f32>, x: f32) -> vec3<f32> {
    let k = poly.light;
    let v = lights.lights[k].position.xyz - camera.position.xyz;
    let t = dot(v, dir);
    let h = length(v - t * dir);
    var ps: array<f32, 9>;
    for (var i = 0u; i < 9u; i++) {
        ps[i] = poly.series[i / 4u][i % 4u];
    }
    let fit = FIT;
    let n = ORDER;
    let st = medium.sigma_t.rgb;
    return vec3<f32>(
        biri_segment(fit, st.r, n, t, h, 0.0, x, ps),
        biri_segment(fit, st.g, n, t, h, 0.0, x, ps),
        biri_segment(fit, st.b, n, t, h, 0.0, x, ps));
}

fn biri_light_scale() -> vec3<f32> {
    return medium.sigma_s.rgb * lights.lights[poly.light].intensity.rgb;
}

// Which of the scene's lights are spots, baked (passes.rs): the light index is a uniform here,
// and lavapipe runs both sides of a branch on a uniform, so without these a point light paid for
// the spot path and a spot for the point path.
override ANY_SPOT: bool = true;
override ALL_SPOT: bool = false;

fn is_spot() -> bool {
    return ALL_SPOT || (ANY_SPOT && poly.spot_f.y > 0.5);
}

// Directional light (modernised, kernel-free): the scattering angle is constant along the ray, so
// Γ(M) = σ_s E p(θ) (1 − e^(−σ_t x))/σ_t in closed form (common light_segments.wgsl).
// Folds to false in scenes without a directional light (the kinds are baked).
fn is_directional() -> bool {
    return scene_has_light_kind(LIGHT_DIRECTIONAL) && light_kind(poly.light) == LIGHT_DIRECTIONAL;
}

// Γ(M) for light poly.light, M at distance x from the eye along the unit direction `dir`.
fn biri_gamma(dir: vec3<f32>, x: f32) -> vec3<f32> {
    if is_directional() {
        return sunlight_between(poly.light, dir, 0.0, x);
    }
    if is_spot() {
        return biri_light_scale() * biri_spot_gamma(dir, x);
    }
    return biri_light_scale() * biri_point_gamma(dir, x);
}

// Γ(M) per fragment, on the ray of pixel `frag`: spots read the ray's part of eq. 7 from
// `cs_spot_rays` (spot_rays.wgsl).
fn biri_gamma_frag(frag: vec2<f32>, x: f32) -> vec3<f32> {
    if is_directional() {
        return sunlight_between(poly.light, camera_ray_dir(camera, frag), 0.0, x);
    }
    if is_spot() {
        return biri_spot_gamma_pixel(vec2<i32>(frag), x);
    }
    return biri_light_scale() * biri_point_gamma(camera_ray_dir(camera, frag), x);
}

// Γ at world point p, on the eye ray through p.
fn biri_gamma_at(p: vec3<f32>) -> vec3<f32> {
    let v = p - camera.position.xyz;
    let x = length(v);
    return biri_gamma(v / max(x, 1e-6), x);
}

struct Gouraud {
    @builtin(position) @invariant clip: vec4<f32>,
    @location(0) value: vec3<f32>,
};

fn scene_world(v: VertexIn) -> vec4<f32> {
    return objects[v.object].world_from_local * vec4<f32>(v.position, 1.0);
}

// Depth (and, in the count pass, stencil) only.
@vertex
fn vs_scene(v: VertexIn) -> @builtin(position) @invariant vec4<f32> {
    return camera.clip_from_world * scene_world(v);
}

// Surface stage, per vertex: Γ(P) at each vertex of the tessellated surfaces.
@vertex
fn vs_scene_gouraud(v: VertexIn) -> Gouraud {
    let w = scene_world(v);
    return Gouraud(camera.clip_from_world * w, biri_gamma_at(w.xyz));
}

// Surface stage, per vertex, where no surface is hit: a grid on the far plane (NDC xy given),
// Γ at the far-plane point of each grid vertex's ray.
@vertex
fn vs_far_grid(@location(0) ndc: vec2<f32>) -> Gouraud {
    let p = camera.world_from_clip * vec4<f32>(ndc, 1.0, 1.0);
    let dir = normalize(p.xyz / p.w - camera.position.xyz);
    return Gouraud(vec4<f32>(ndc, 1.0, 1.0), biri_gamma(dir, camera_far_distance(camera, dir)));
}

@fragment
fn fs_gouraud(v: Gouraud) -> @location(0) vec4<f32> {
    return vec4<f32>(v.value, 0.0);
}

// Surface stage, per fragment (full screen, stencil = lit): Γ at the visible point or far plane.
@fragment
fn fs_surface_frag(@builtin(position) frag: vec4<f32>) -> @location(0) vec4<f32> {
    let dir = camera_ray_dir(camera, frag.xy);
    let d = camera_ray_length(camera, dir, textureLoad(ray_distance, vec2<i32>(frag.xy), 0).r);
    return vec4<f32>(biri_gamma_frag(frag.xy, d), 0.0);
}

// §5.2's first pass for the unorm8 target: the attenuated surface term and the ambient fog.
@fragment
fn fs_first_pass(@builtin(position) frag: vec4<f32>) -> @location(0) vec4<f32> {
    let px = vec2<i32>(frag.xy);
    let dir = camera_ray_dir(camera, frag.xy);
    let d = camera_ray_length(camera, dir, textureLoad(ray_distance, px, 0).r);
    let ambient = medium.ambient.rgb * (vec3<f32>(1.0) - transmittance(medium, d));
    return vec4<f32>(textureLoad(surface, px, 0).rgb + ambient, 0.0);
}

fn plane_sign(front: bool, g: vec3<f32>) -> vec3<f32> {
    return select(g, select(-g, g, front), poly.signed_output == 1u);
}

// Shadow planes, per fragment: ±Γ at the plane point, on the pixel's own ray.
@fragment
fn fs_plane_frag(v: PlaneFrag, @builtin(front_facing) front: bool) -> @location(0) vec4<f32> {
    let g = biri_gamma_frag(v.clip.xy, plane_distance(v));
    return vec4<f32>(plane_sign(front, g), 0.0);
}

// Shadow planes, per vertex of the meshed planes (finer near the light).
@vertex
fn vs_plane_gouraud(@location(0) p: vec3<f32>) -> Gouraud {
    return Gouraud(camera.clip_from_world * vec4<f32>(p, 1.0), biri_gamma_at(p));
}

@fragment
fn fs_plane_gouraud(v: Gouraud, @builtin(front_facing) front: bool) -> @location(0) vec4<f32> {
    return vec4<f32>(plane_sign(front, v.value), 0.0);
}
