// The unshadowed in-scatter of one light over [a, b] of a view ray from the eye (DESIGN §1's
// ∫ σ_s p(θ) I(ω) e^(−σ_t (x + r)) / r² dx), shared by the volume pass (∫ from the eye to each
// volume fragment) and the resolve (∫ to the visible surface for lights without a volume).
// Point lights: Biri et al.'s Γ table (biri_shadow_volumes::LDSS_WGSL, composed before this
// file; any phase function). Spot lights (falloff and pattern make it not closed-form) and
// point lights at `table = 0`: per-fragment Gauss–Legendre quadrature in the angle seen from
// the light over the ray's stretch inside the cone. Directional light: closed form.
// Needs PRELUDE and ldss.wgsl; group 1 binding 3 holds the Γ table.

@group(1) @binding(3) var gamma_table: texture_2d<f32>;

// Knobs baked per run (mod.rs): `table = 0` (point lights by quadrature too) and the number of
// two-node Gauss–Legendre panels of the quadrature (`panels`).
override QUADRATURE: bool = false;
override PANELS: u32 = 8u;

// I(ω) p(θ) e^(−σ_t (x + r)) at angle φ of local light k's ray geometry (x₀, h).
fn angular_sample(k: u32, dir: vec3<f32>, x0: f32, h: f32, phi: f32) -> vec3<f32> {
    let c = cos(phi);
    // sin/cos, not tan(): lavapipe (Mesa 22.3) crashes compiling tan() in a loop.
    let x = x0 + h * sin(phi) / c;
    let r = h / c;
    let w = camera.position.xyz + dir * x - lights.lights[k].position.xyz;
    return light_intensity(k, w) * phase(medium, dot(w, -dir) / r) * transmittance(medium, x + r);
}

// σ_s ∫_a^b I(x) p(θ) e^(−σ_t (x + r)) / r² dx of local light k by PANELS two-node
// Gauss–Legendre panels uniform in φ = atan((x − x₀)/h) (x₀: the ray's closest approach to the
// light, h: the distance there), where dx / r² = dφ / h: the 1/r² peak is flattened.
fn quadrature(k: u32, dir: vec3<f32>, a: f32, b: f32) -> vec3<f32> {
    if (b <= a) { return vec3<f32>(0.0); }
    let to_light = lights.lights[k].position.xyz - camera.position.xyz;
    let x0 = dot(to_light, dir);
    let h = max(length(to_light - dir * x0), 1e-6);
    let pa = atan((a - x0) / h);
    let dphi = (atan((b - x0) / h) - pa) / f32(PANELS);
    // Gauss–Legendre nodes ±1/√3 of each panel (at ½ ∓ 1/(2√3) of it), weight ½ each.
    let node = 0.28867513459;
    var sum = vec3<f32>(0.0);
    for (var p = 0u; p < PANELS; p++) {
        let mid = pa + (f32(p) + 0.5) * dphi;
        sum += angular_sample(k, dir, x0, h, mid - node * dphi) + angular_sample(k, dir, x0, h, mid + node * dphi);
    }
    return medium.sigma_s.rgb * sum * (0.5 * dphi / h);
}

// The stretch [near, far] of the ray inside spot k's outer cone (empty: near ≥ far). Points
// x = eye + t·dir with (w·axis)² ≥ cos²·|w|² and w·axis ≥ 0, w = x − light: a quadratic in t.
fn cone_stretch(k: u32, dir: vec3<f32>) -> vec2<f32> {
    let axis = lights.lights[k].direction.xyz;
    let cos2 = lights.lights[k].intensity.w * lights.lights[k].intensity.w;
    let w0 = camera.position.xyz - lights.lights[k].position.xyz;
    let da = dot(dir, axis);
    let wa = dot(w0, axis);
    // q(t) = A t² + 2 B t + C ≥ 0 inside either nappe.
    let qa = da * da - cos2;
    let qb = wa * da - cos2 * dot(w0, dir);
    let qc = wa * wa - cos2 * dot(w0, w0);
    let empty = vec2<f32>(1.0, 0.0);
    let disc = qb * qb - qa * qc;
    if (abs(qa) < 1e-9 || disc < 0.0) {
        return select(empty, vec2<f32>(0.0, 3.4e38), wa > 0.0 && qc >= 0.0);
    }
    let s = sqrt(disc);
    let r1 = (-qb - s) / qa;
    let r2 = (-qb + s) / qa;
    let lo = min(r1, r2);
    let hi = max(r1, r2);
    if (qa < 0.0) {
        // Inside between the roots, on the forward nappe only.
        return select(empty, vec2<f32>(lo, hi), dot(w0 + dir * (0.5 * (lo + hi)), axis) > 0.0);
    }
    // Outside between the roots: the forward nappe is the side the ray moves toward along the axis.
    return select(vec2<f32>(-3.4e38, lo), vec2<f32>(hi, 3.4e38), da > 0.0);
}

// σ_s E p(θ) ∫_a^b e^(−σ_t x) dx of directional light k (no 1/r², constant angle).
fn sunlight_between(k: u32, dir: vec3<f32>, a: f32, b: f32) -> vec3<f32> {
    let st = max(medium.sigma_t.rgb, vec3<f32>(1e-12));
    let cos_theta = dot(lights.lights[k].direction.xyz, -dir);
    return medium.sigma_s.rgb * lights.lights[k].intensity.rgb * phase(medium, cos_theta)
        * (exp(-st * a) - exp(-st * b)) / st;
}

// The unshadowed in-scatter of light k over [a, b] of the view ray `dir`.
fn inscatter_between(k: u32, dir: vec3<f32>, a: f32, b: f32) -> vec3<f32> {
    if (b <= a) { return vec3<f32>(0.0); }
    let kind = light_kind(k);
    if (kind == LIGHT_DIRECTIONAL) { return sunlight_between(k, dir, a, b); }
    if (kind == LIGHT_SPOT) {
        let cone = cone_stretch(k, dir);
        return quadrature(k, dir, max(a, cone.x), min(b, cone.y));
    }
    if (QUADRATURE) { return quadrature(k, dir, a, b); }
    return ldss_between(gamma_table, k, dir, a, b);
}
