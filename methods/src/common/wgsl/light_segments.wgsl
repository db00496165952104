// The unshadowed in-scatter of one light over a stretch [a, b] of a view ray from the eye
// (ARCHITECTURE §1's ∫ σ_s p(θ) I(ω) e^(−σ_t (x + r)) / r² dx, or σ_s p(θ) E ∫ e^(−σ_t x) dx for a
// directional light) where no table applies: directional light in closed form (the scattering
// angle is constant along the ray), spot lights (falloff and pattern make it not closed-form) by
// Gauss–Legendre quadrature in the angle seen from the light over the ray's stretch inside the
// outer cone. Shared by polygonal-light-volumes, biri-shadow-volumes (through ldss.wgsl's
// `lit_between`) and biri-polynomial (directional Γ). Needs PRELUDE.

// σ_s E p(θ) ∫_a^b e^(−σ_t x) dx of directional light k (no 1/r², constant angle; the light leg
// is not attenuated, ARCHITECTURE §1).
fn sunlight_between(k: u32, dir: vec3<f32>, a: f32, b: f32) -> vec3<f32> {
    let st = max(medium.sigma_t.rgb, vec3<f32>(1e-12));
    let cos_theta = dot(lights.lights[k].direction.xyz, -dir);
    return medium.sigma_s.rgb * lights.lights[k].intensity.rgb * phase(medium, cos_theta)
        * (exp(-st * a) - exp(-st * b)) / st;
}

// I(ω) p(θ) e^(−σ_t (x + r)) at angle φ of local light k's ray geometry (x₀, h).
fn angular_sample(k: u32, dir: vec3<f32>, x0: f32, h: f32, phi: f32) -> vec3<f32> {
    let c = cos(phi);
    // sin/cos, not tan(): lavapipe (Mesa 22.3) crashes compiling tan() in a loop.
    let x = x0 + h * sin(phi) / c;
    let r = h / c;
    let w = camera.position.xyz + dir * x - lights.lights[k].position.xyz;
    return light_intensity(k, w) * phase(medium, dot(w, -dir) / r) * transmittance(medium, x + r);
}

// σ_s ∫_a^b I(x) p(θ) e^(−σ_t (x + r)) / r² dx of local light k by `panels` two-node
// Gauss–Legendre panels uniform in φ = atan((x − x₀)/h) (x₀: the ray's closest approach to the
// light, h: the distance there), where dx / r² = dφ / h: the 1/r² peak is flattened. `panels`
// must be uniform across invocations (a knob), never per pixel.
fn local_quadrature(k: u32, dir: vec3<f32>, a: f32, b: f32, panels: u32) -> vec3<f32> {
    if (b <= a) { return vec3<f32>(0.0); }
    let to_light = lights.lights[k].position.xyz - camera.position.xyz;
    let x0 = dot(to_light, dir);
    let h = max(length(to_light - dir * x0), 1e-6);
    let pa = atan((a - x0) / h);
    let dphi = (atan((b - x0) / h) - pa) / f32(panels);
    return angular_panels(k, dir, x0, h, pa, dphi, panels);
}

// The panels of `local_quadrature`: σ_s/h × `panels` two-node Gauss–Legendre panels of width
// dphi from angle pa.
fn angular_panels(k: u32, dir: vec3<f32>, x0: f32, h: f32, pa: f32, dphi: f32, panels: u32) -> vec3<f32> {
    // Gauss–Legendre nodes ±1/√3 of each panel (at ½ ∓ 1/(2√3) of it), weight ½ each.
    let node = 0.28867513459;
    var sum = vec3<f32>(0.0);
    for (var p = 0u; p < panels; p++) {
        let mid = pa + (f32(p) + 0.5) * dphi;
        sum += angular_sample(k, dir, x0, h, mid - node * dphi) + angular_sample(k, dir, x0, h, mid + node * dphi);
    }
    return medium.sigma_s.rgb * sum * (0.5 * dphi / h);
}

// The stretch [near, far] of the ray inside spot k's outer cone (empty: near ≥ far). Points
// x = eye + t·dir with (w·axis)² ≥ cos²·|w|² and w·axis ≥ 0, w = x − light: a quadratic in t.
fn cone_stretch(k: u32, dir: vec3<f32>) -> vec2<f32> {
    return cone_stretch_at(k, dir, lights.lights[k].intensity.w);
}

// `cone_stretch` for the cone of half-angle cosine `cos_half` around spot k's axis (the inner
// cone: lights[k].direction.w).
fn cone_stretch_at(k: u32, dir: vec3<f32>, cos_half: f32) -> vec2<f32> {
    let axis = lights.lights[k].direction.xyz;
    let cos2 = cos_half * cos_half;
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

// σ_s ∫_a^b of spot k (falloff and pattern) by `panels` Gauss–Legendre panels over [a, b] ∩ the
// ray's stretch inside the outer cone.
fn spot_between(k: u32, dir: vec3<f32>, a: f32, b: f32, panels: u32) -> vec3<f32> {
    let cone = cone_stretch(k, dir);
    return local_quadrature(k, dir, max(a, cone.x), min(b, cone.y), panels);
}
