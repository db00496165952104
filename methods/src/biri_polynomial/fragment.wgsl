// biri-polynomial, `eval: fragment`, unshadowed scenes: per pixel, the medium contribution of
// the whole ray [0, d] toward each point light in constant time (eq. 3 + eq. 6), per colour
// channel since σ_t is RGB. Needs PRELUDE, FULLSCREEN and kernel.wgsl.

struct Poly {
    // x: order n; y: fit (0 Taylor, 1 Chebyshev)
    config: vec4<u32>,
    // Taylor series in θ of p(θ + π/2), coefficients 0…8 (k-independent; from the CPU).
    series: array<vec4<f32>, 3>,
};
@group(1) @binding(0) var ray_distance: texture_2d<f32>;
@group(1) @binding(1) var surface: texture_2d<f32>;
@group(1) @binding(2) var<uniform> poly: Poly;

struct Out {
    @location(0) inscatter: vec4<f32>,
    @location(1) total: vec4<f32>,
};

fn biri_phase(c: f32) -> f32 {
    return phase(medium, c);
}

@fragment
fn fs(@builtin(position) frag: vec4<f32>) -> Out {
    let px = vec2<i32>(frag.xy);
    let dir = camera_ray_dir(camera, frag.xy);
    let d = camera_ray_length(camera, dir, textureLoad(ray_distance, px, 0).r);
    var ps: array<f32, 9>;
    for (var i = 0u; i < 9u; i++) {
        ps[i] = poly.series[i / 4u][i % 4u];
    }
    var l_in = vec3<f32>(0.0);
    for (var k = 0u; k < lights.count.x; k++) {
        let v = lights.lights[k].position.xyz - camera.position.xyz;
        let t = dot(v, dir);
        let h = length(v - t * dir);
        var seg: vec3<f32>;
        for (var c = 0u; c < 3u; c++) {
            seg[c] = biri_segment(poly.config.y, medium.sigma_t[c], poly.config.x, t, h, 0.0, d, ps);
        }
        l_in += lights.lights[k].intensity.rgb * seg;
    }
    l_in *= medium.sigma_s.rgb;
    let surf = textureLoad(surface, px, 0).rgb;
    let ambient = medium.ambient.rgb * (vec3<f32>(1.0) - transmittance(medium, d));
    return Out(vec4<f32>(l_in, 1.0), vec4<f32>(surf + l_in + ambient, 1.0));
}
