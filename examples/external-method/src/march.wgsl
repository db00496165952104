// Single scattering without shadows: N midpoint steps from the eye to the visible surface (or the
// far plane), the exact integrand at each step with visibility 1 (with exponential height fog:
// σ_s(x) and each leg's optical depth, methods::common's height_fog.wgsl). Composed after
// common::resolve::source (PRELUDE, FULLSCREEN, resolve_io).

// Mirrors `MarchUniform` in lib.rs, field for field.
struct March {
    steps: u32,  // the `steps` knob, 1 … 4096
    _pad0: u32,
    _pad1: u32,
    _pad2: u32,
};
@group(1) @binding(2) var<uniform> march: March;

// Radiance scattered toward the eye at distance t along `dir`, per metre (no shadows).
fn inscatter_at(dir: vec3<f32>, t: f32) -> vec3<f32> {
    let x = camera.position.xyz + dir * t;
    var sum = vec3<f32>(0.0);
    for (var k = 0u; k < light_count(); k++) {
        if (light_kind(k) == LIGHT_DIRECTIONAL) {
            let dir_l = lights.lights[k].direction.xyz;
            let path = sun_path(medium, camera.position.xyz, dir, t);
            sum += lights.lights[k].intensity.rgb * phase(medium, dot(dir_l, -dir)) * path;
        } else {
            let w = x - lights.lights[k].position.xyz;
            let r2 = max(dot(w, w), 1e-12);
            let r = sqrt(r2);
            let path = scattering_path(medium, camera.position.xyz, dir, t, -w / r, r);
            sum += light_intensity(k, w) * phase(medium, dot(w / r, -dir)) * path / r2;
        }
    }
    return medium.sigma_s.rgb * sum;
}

@fragment
fn fs(@builtin(position) frag: vec4<f32>) -> Out {
    let px = vec2<i32>(frag.xy);
    let dir = camera_ray_dir(camera, frag.xy);
    let d = pixel_ray_length(px, dir);
    let dt = d / f32(march.steps);
    var l_in = vec3<f32>(0.0);
    for (var k = 0u; k < march.steps; k++) {
        l_in += inscatter_at(dir, (f32(k) + 0.5) * dt);
    }
    l_in *= dt;
    let surf = textureLoad(surface, px, 0).rgb;
    return Out(vec4<f32>(l_in, 1.0), vec4<f32>(surf + l_in + ambient_fog(dir, d), 1.0));
}
