// Brute-force ray march (Wyman & Ramsey's baseline): N equal steps from the eye to the visible
// surface (or the far plane), shadow-map visibility and the exact integrand at each step.
// Needs PRELUDE and FULLSCREEN.

// Mirrors MarchUniform in mod.rs (field for field).
struct March {
    steps: u32,   // the `steps` knob, 1 … 65536
    jitter: u32,  // the `jitter` knob (0/1)
    frame: u32,   // frame index (decorrelates the jitter)
    _pad: u32,
};
@group(1) @binding(2) var<uniform> march: March;

// Integer hash → [0, 1): decorrelated per pixel and frame (jittered step offsets).
fn hash01(p: vec2<u32>, f: u32) -> f32 {
    var h = p.x * 1973u + p.y * 9277u + f * 26699u;
    h = (h ^ (h >> 13u)) * 0x5bd1e995u;
    h = h ^ (h >> 15u);
    return f32(h & 0xffffffu) / 16777216.0;
}

// Single-scattered radiance reaching the eye from distance t along `dir`, per metre.
fn inscatter_at(dir: vec3<f32>, t: f32) -> vec3<f32> {
    let x = camera.position.xyz + dir * t;
    var sum = vec3<f32>(0.0);
    for (var k = 0u; k < light_count(); k++) {
        if (light_kind(k) == LIGHT_DIRECTIONAL) {
            let dir_l = lights.lights[k].direction.xyz;
            let vis = shadow_visibility(k, x);
            let path = sun_path(medium, camera.position.xyz, dir, t);
            sum += lights.lights[k].intensity.rgb * phase(medium, dot(dir_l, -dir)) * vis * path;
        } else {
            let w = x - lights.lights[k].position.xyz;
            let r2 = max(dot(w, w), 1e-12);
            let r = sqrt(r2);
            // No early `continue` where i = 0 (outside a spot's cone): a divergent continue in
            // this loop makes lavapipe's march ~5× slower; the product is 0 there anyway.
            let i = light_intensity(k, w);
            let vis = shadow_visibility(k, x);
            let path = scattering_path(medium, camera.position.xyz, dir, t, -w / r, r);
            sum += i * phase(medium, dot(w / r, -dir)) * vis * path / r2;
        }
    }
    return medium.sigma_s.rgb * sum;
}

@fragment
fn fs(@builtin(position) frag: vec4<f32>) -> Out {
    let px = vec2<i32>(frag.xy);
    let dir = camera_ray_dir(camera, frag.xy);
    let d = pixel_ray_length(px, dir);
    let n = march.steps;
    let dt = d / f32(n);
    let offset = select(0.5, hash01(vec2<u32>(px), march.frame), march.jitter != 0u);
    var l_in = vec3<f32>(0.0);
    for (var k = 0u; k < n; k++) {
        l_in += inscatter_at(dir, (f32(k) + offset) * dt);
    }
    l_in *= dt;
    let surf = textureLoad(surface, px, 0).rgb;
    let ambient = ambient_fog(dir, d);
    return Out(vec4<f32>(l_in, 1.0), vec4<f32>(surf + l_in + ambient, 1.0));
}
