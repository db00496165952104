// Biri et al. 2006, Fig. 8 (indirect single scattering) in the project convention, per point
// light k at distance l, λ = σ_t l per channel (see biri_shadow_volumes::indirect):
//   Lambert: (albedo/π) σ_s I e^(−λ)/l · Γ_L(λ, φ_n),        φ_n = ∠(n, to light)
//   Phong:   ks (m+2)/(2π) (n·v) σ_s I e^(−λ)/l · Γ_P(λ, ψ_s), ψ_s = ∠(v mirrored about n, to light)
// attenuated to the eye by e^(−σ_t d) and added to the surface AOV. Tables: rows u = λ/(1+λ),
// columns angle/π; Γ_P tables stacked by rows, one per shininess in `iss.shininess`.
// Needs PRELUDE and the shared surface pass (its `vs` and VsOut, so depths match exactly).

struct IssConfig {
    shininess: vec4<f32>,
    // x: table size; y: number of Γ_P tables
    dims: vec4<u32>,
};
@group(1) @binding(0) var gamma_lambert: texture_2d<f32>;
@group(1) @binding(1) var gamma_phong: texture_2d<f32>;
@group(1) @binding(2) var<uniform> iss: IssConfig;

// Bilinear lookup in rows [row0, row0 + n) of a table with n columns.
fn iss_lookup(tab: texture_2d<f32>, row0: u32, lambda: f32, angle: f32) -> f32 {
    let n = iss.dims.x;
    let fn_ = f32(n);
    let fi = clamp(lambda / (1.0 + lambda) * fn_, 0.0, fn_ - 1.0);
    let fj = clamp(angle / PI * (fn_ - 1.0), 0.0, fn_ - 1.0);
    let i0 = u32(fi);
    let j0 = u32(fj);
    let i1 = min(i0 + 1u, n - 1u);
    let j1 = min(j0 + 1u, n - 1u);
    let a = fi - f32(i0);
    let b = fj - f32(j0);
    let r0 = mix(textureLoad(tab, vec2<u32>(j0, row0 + i0), 0).r, textureLoad(tab, vec2<u32>(j1, row0 + i0), 0).r, b);
    let r1 = mix(textureLoad(tab, vec2<u32>(j0, row0 + i1), 0).r, textureLoad(tab, vec2<u32>(j1, row0 + i1), 0).r, b);
    return mix(r0, r1, a);
}

// One lookup where the scene's σ_t is grey (GREY_SIGMA_T: the channels' λ are equal), else three.
fn iss_lookup3(tab: texture_2d<f32>, row0: u32, lambda: vec3<f32>, angle: f32) -> vec3<f32> {
    if (GREY_SIGMA_T) { return vec3<f32>(iss_lookup(tab, row0, lambda.r, angle)); }
    return vec3<f32>(
        iss_lookup(tab, row0, lambda.r, angle),
        iss_lookup(tab, row0, lambda.g, angle),
        iss_lookup(tab, row0, lambda.b, angle));
}

// The Γ_P table of shininess m, or 4u if none. A select chain: early returns of an i32 here
// crash lavapipe's rasteriser threads (Mesa 22.3).
fn iss_layer(m: f32) -> u32 {
    let s = iss.shininess;
    let c = iss.dims.y;
    var k = 4u;
    k = select(k, 3u, c > 3u && s.w == m);
    k = select(k, 2u, c > 2u && s.z == m);
    k = select(k, 1u, c > 1u && s.y == m);
    k = select(k, 0u, c > 0u && s.x == m);
    return k;
}

@fragment
fn fs_indirect(i: VsOut, @builtin(front_facing) front: bool) -> @location(0) vec4<f32> {
    let o = objects[i.object];
    var n = normalize(i.normal);
    if (!front) {
        // Lit on the side the normal faces only, unless two-sided (as the surface pass).
        if (o.albedo.w < 0.5) { return vec4<f32>(0.0); }
        n = -n;
    }
    let to_eye = camera.position.xyz - i.world;
    let d = length(to_eye);
    let v = to_eye / d;
    let r_v = 2.0 * dot(n, v) * n - v;
    let layer = iss_layer(o.phong.w);
    var out = vec3<f32>(0.0);
    for (var k = 0u; k < lights.count.x; k++) {
        if (light_kind(k) != LIGHT_POINT) { continue; }
        let w = lights.lights[k].position.xyz - i.world;
        let l = length(w);
        if (l <= 0.0) { continue; }
        let us = w / l;
        let lam = medium.sigma_t.rgb * l;
        let c = medium.sigma_s.rgb * lights.lights[k].intensity.rgb * exp(-lam) / l;
        let phi_n = acos(clamp(dot(n, us), -1.0, 1.0));
        out += o.albedo.rgb / PI * c * iss_lookup3(gamma_lambert, 0u, lam, phi_n);
        if (o.phong.w > 0.0 && layer < 4u) {
            let psi_s = acos(clamp(dot(r_v, us), -1.0, 1.0));
            let lobe = o.phong.rgb * (o.phong.w + 2.0) / (2.0 * PI) * max(dot(n, v), 0.0);
            out += lobe * c * iss_lookup3(gamma_phong, layer * iss.dims.x, lam, psi_s);
        }
    }
    // Alpha 0: the AOV's alpha is left as the surface pass wrote it.
    return vec4<f32>(out * transmittance(medium, d), 0.0);
}
