// The unshadowed in-scatter of one light over [a, b] of a view ray from the eye (ARCHITECTURE §1's
// ∫ σ_s p(θ) I(ω) e^(−σ_t (x + r)) / r² dx), shared by the volume pass (∫ from the eye to each
// volume fragment) and the resolve (∫ to the visible surface for lights without a volume).
// Point lights: Biri et al.'s Γ table (biri_shadow_volumes::LDSS_WGSL, composed before this
// file with common/wgsl/light_segments.wgsl; any phase function). Spot lights (falloff and
// pattern make it not closed-form) and point lights at `table = 0`: per-fragment
// Gauss–Legendre quadrature in the angle seen from the light over the ray's stretch inside the
// cone (light_segments.wgsl). Directional light: closed form (light_segments.wgsl).
// Needs PRELUDE and biri_shadow_volumes::LDSS_WGSL; group 1 binding 3 holds the Γ table.

@group(1) @binding(3) var gamma_table: texture_2d<f32>;

// Knobs baked per run (mod.rs): `table = 0` (point lights by quadrature too) and the number of
// two-node Gauss–Legendre panels of the quadrature (`panels`).
override QUADRATURE: bool = false;
override PANELS: u32 = 8u;

// The unshadowed in-scatter of light k over [a, b] of the view ray `dir`: biri-shadow-volumes'
// per-interval function (Γ table, directional closed form, spot quadrature), or the quadrature
// for point lights too at `table = 0`.
fn inscatter_between(k: u32, dir: vec3<f32>, a: f32, b: f32) -> vec3<f32> {
    if (QUADRATURE && light_kind(k) == LIGHT_POINT) { return local_quadrature(k, dir, a, b, PANELS); }
    return lit_between(gamma_table, k, dir, a, b, PANELS);
}
