// §3.4: this frame's F'(γ, x) = A₀ F(A₁, A₂(x)) for light LIGHT, so the hybrid's airlight is
// two texture lookups: L = F'(γ, b) − F'(γ, a). The table holds one band of γ samples × x
// samples per light (fprime_band); this pipeline draws its light's band only (scissored).
// Needs PRELUDE, FULLSCREEN and airlight.wgsl.

@fragment
fn fs(@builtin(position) frag: vec4<f32>) -> Out {
    let ng = hybrid.fprime_ng;
    if (light_kind(LIGHT) != LIGHT_POINT) { return Out(vec4<f32>(0.0), vec4<f32>(0.0)); }
    let within = frag.xy - 0.5 - vec2<f32>(fprime_band(LIGHT));
    let cg = cos(PI * within.x / (ng - 1.0));
    let x = within.y / (hybrid.fprime_nx - 1.0) * hybrid.fprime_x_max;
    let dl = length(lights.lights[LIGHT].position.xyz - camera.position.xyz);
    let sg = sqrt(max(1.0 - cg * cg, 0.0));
    let ap = Approach(dl * cg, max(dl * sg, 1e-5 * (dl + 1e-3)));
    // F' up to a constant: airlight from 0 to x.
    return Out(vec4<f32>(airlight(LIGHT, ap, 0.0, x), 1.0), vec4<f32>(0.0));
}
