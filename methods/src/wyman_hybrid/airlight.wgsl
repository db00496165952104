// Sun et al.'s airlight (see airlight.rs for F(u,v) and the constant in the project's
// convention), shared by the hybrid resolve and the per-frame F' table. Group 1 bindings 2 and 5.
// Mirrors `HybridUniform` in mod.rs, field for field. (The knobs airlight and fprime are the
// overrides AIRLIGHT and FPRIME of hybrid.wgsl.)
struct Hybrid {
    samples: u32,       // the `samples` knob: steps between the shadow polygons, 1 … 4096
    table_nu: u32,      // F table width (u samples)
    table_nv: u32,      // F table height (v samples)
    _pad0: u32,
    table_u_max: f32,   // u = σ_t h at the F table's last column
    scale: f32,         // the `scale` knob: scattering resolution divisor
    _pad1: f32,
    _pad2: f32,
    fprime_x_max: f32,  // §3.4's F'(cos γ, x) table: x at its last row (m)
    fprime_ng: f32,     // cos γ samples
    fprime_nx: f32,     // x samples
    _pad3: f32,
};
@group(1) @binding(2) var<uniform> hybrid: Hybrid;
@group(1) @binding(5) var f_table: texture_2d<f32>;

// The F' table's bands (one per light, FPRIME_SIZE² texels) per row: light k's band starts at
// column (k % FPRIME_BANDS_PER_ROW) · n_γ, row (k / FPRIME_BANDS_PER_ROW) · n_x. Mirrors
// `FPRIME_BANDS_PER_ROW` in mod.rs.
const FPRIME_BANDS_PER_ROW: u32 = 16u;

// Light k's F' band's first texel (column, row).
fn fprime_band(k: u32) -> vec2<u32> {
    let band = vec2<u32>(k % FPRIME_BANDS_PER_ROW, k / FPRIME_BANDS_PER_ROW);
    return band * vec2<u32>(u32(hybrid.fprime_ng), u32(hybrid.fprime_nx));
}

// The light this pipeline handles (set per pipeline; see common::resolve::ResolvePass::per_light).
override LIGHT: u32 = 0u;

const HALF_PI: f32 = 1.5707963267948966;
const QUARTER_PI: f32 = 0.7853981633974483;

// F(u, v) = ∫_0^v exp(−u tan ξ) dξ, bilinear from the table (clamped).
fn f_lookup(u: f32, v: f32) -> f32 {
    let nu = f32(hybrid.table_nu);
    let nv = f32(hybrid.table_nv);
    let fu = clamp(u / hybrid.table_u_max, 0.0, 1.0) * (nu - 1.0);
    let fv = clamp(v / HALF_PI, 0.0, 1.0) * (nv - 1.0);
    let i0 = u32(fu);
    let j0 = u32(fv);
    let i1 = min(i0 + 1u, hybrid.table_nu - 1u);
    let j1 = min(j0 + 1u, hybrid.table_nv - 1u);
    let tu = fu - f32(i0);
    let tv = fv - f32(j0);
    let a = mix(textureLoad(f_table, vec2<u32>(i0, j0), 0).r, textureLoad(f_table, vec2<u32>(i1, j0), 0).r, tu);
    let b = mix(textureLoad(f_table, vec2<u32>(i0, j1), 0).r, textureLoad(f_table, vec2<u32>(i1, j1), 0).r, tu);
    return mix(a, b, tv);
}

// The ray's geometry relative to a local light: t0 (closest approach), h (distance there).
struct Approach {
    t0: f32,
    h: f32,
};

fn approach(k: u32, dir: vec3<f32>) -> Approach {
    let w0 = lights.lights[k].position.xyz - camera.position.xyz;
    let t0 = dot(w0, dir);
    let h = max(length(w0 - dir * t0), 1e-5 * (length(w0) + 1e-3));
    return Approach(t0, h);
}

// F(u, x) per channel: one lookup where the scene's σ_t is grey (GREY_SIGMA_T, baked in
// medium.wgsl: the channels' u are then equal), else three.
fn f_rgb(u: vec3<f32>, x: f32) -> vec3<f32> {
    if (GREY_SIGMA_T) { return vec3<f32>(f_lookup(u.x, x)); }
    return vec3<f32>(f_lookup(u.x, x), f_lookup(u.y, x), f_lookup(u.z, x));
}

// Unshadowed in-scatter over [a, b] of isotropic point light k: Sun et al.'s airlight (airlight.rs).
fn airlight(k: u32, ap: Approach, a: f32, b: f32) -> vec3<f32> {
    if (b <= a) { return vec3<f32>(0.0); }
    let xa = QUARTER_PI + 0.5 * atan((a - ap.t0) / ap.h);
    let xb = QUARTER_PI + 0.5 * atan((b - ap.t0) / ap.h);
    var f = vec3<f32>(0.0);
    let st = medium.sigma_t.rgb;
    let u = st * ap.h;
    f = (f_rgb(u, xb) - f_rgb(u, xa)) * exp(-st * ap.t0);
    return medium.sigma_s.rgb * lights.lights[k].intensity.rgb * (2.0 / (4.0 * PI * ap.h)) * max(f, vec3<f32>(0.0));
}

