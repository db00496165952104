// biri-polynomial, eval = fragment with a spot: eq. 7 split at the ray. Every plane fragment and
// the surface stage of a pixel share the pixel's eye ray, and all of eq. 7 but θ_M, γ_b and the
// Δ_i(γ_b) lookups depends on that ray alone; `cs_spot_rays` stores it once per pixel and light
// (layers of `spot_rays`), so a fragment pays one atan and the γ_b lookups. After spot.wgsl and
// passes.wgsl (the `poly`, `delta` bindings).
//
// Layers: 0: (t, h, β, γ_a), γ_a = 2 (> π/2, so γ_b ≤ γ_a) where the ray's plane is outside the
// tables; 1: the half-circle cell (iu, ip, wu, wp); 2: Σ_i c_i Δ_i(γ_a); 3 + i: c_i — the
// coefficients scaled by σ_s I / h, i = 0…n. Γ(M) = Σ_i c_i Δ_i(γ_b) − layer 2.
//
// Chebyshev fits Λ on [θ_0, θ_far] here, where per vertex the range is stretched to contain θ_M:
// a fragment lies inside the frustum, so θ_M ≤ θ_far but for rounding.

@group(1) @binding(4) var spot_rays: texture_2d_array<f32>;
@group(1) @binding(5) var spot_rays_out: texture_storage_2d_array<rgba32float, write>;

const SPOT_RAY_COEFFICIENTS: u32 = 3u;

@compute @workgroup_size(8, 8)
fn cs_spot_rays(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(spot_rays_out);
    if id.x >= size.x || id.y >= size.y {
        return;
    }
    let px = id.xy;
    // the pixel centre, as a fragment's @builtin(position) sees it
    let dir = camera_ray_dir(camera, vec2<f32>(px) + 0.5);
    let g = biri_spot_geometry(dir);
    if !g.lit {
        textureStore(spot_rays_out, px, 0, vec4<f32>(g.t, g.h, 0.0, 2.0));
        return;
    }
    let n = ORDER;
    let k = poly.light;
    let scale = medium.sigma_s.rgb * lights.lights[k].intensity.rgb / g.h;
    let c = biri_spot_coefficients(g, biri_spot_far_theta(g, dir));
    let cell = biri_spot_cell(g.m);
    var base = vec3<f32>(0.0);
    for (var i = 0u; i < 9u; i++) {
        if i <= n {
            let ci = scale * c[i];
            base += ci * biri_delta(cell, g.ga, i);
            textureStore(spot_rays_out, px, SPOT_RAY_COEFFICIENTS + i, vec4<f32>(ci, 0.0));
        }
    }
    textureStore(spot_rays_out, px, 0, vec4<f32>(g.t, g.h, g.beta, g.ga));
    textureStore(spot_rays_out, px, 1, vec4<f32>(f32(cell.iu), f32(cell.ip), cell.wu, cell.wp));
    textureStore(spot_rays_out, px, 2, vec4<f32>(base, 0.0));
}

// σ_s I Γ(M) for a spot, M at distance x on the eye ray of pixel `px`, from `cs_spot_rays`.
fn biri_spot_gamma_pixel(px: vec2<i32>, x: f32) -> vec3<f32> {
    let ray = textureLoad(spot_rays, px, 0, 0);
    let thm = atan((x - ray.x) / ray.y);
    let gb = clamp(thm + ray.z, -0.5 * BIRI_PI, 0.5 * BIRI_PI);
    if gb <= ray.w {
        return vec3<f32>(0.0);
    }
    let q = textureLoad(spot_rays, px, 1, 0);
    let cell = SpotCell(u32(q.x), u32(q.y), q.z, q.w);
    var out = -textureLoad(spot_rays, px, 2, 0).rgb;
    for (var i = 0u; i <= ORDER; i++) {
        out += textureLoad(spot_rays, px, SPOT_RAY_COEFFICIENTS + i, 0).rgb * biri_delta(cell, gb, i);
    }
    return out;
}
