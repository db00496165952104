// Step 3 of Biri et al. (lit surface fragments and the far plane): per pixel, L_dss from the
// eye to the visible surface for every light (`lit_between`: eq. 7 for point lights), plus the
// surface AOV and ambient.
// With shadow planes (config.shadowed = 1) the signed sum of the lit surface and plane terms is
// read from binding 4 and the eye's term −C Γ(w(0)) is added for the point lights whose eye is
// lit (bit k of config.eye_lit, light_bit; the other kinds' crossing terms are 0 at the eye).
// Needs PRELUDE, FULLSCREEN and ldss.wgsl.

// Mirrors `ConfigUniform` in mod.rs, field for field.
struct Config {
    shadowed: u32,  // 1 when binding 4 holds the accumulated crossing terms
    spot_panels: u32,  // the `spot_panels` knob (lit_between)
    _pad0: u32,
    _pad1: u32,
    eye_lit: vec4<u32>,  // bit k (light_bit) set when light k sees the eye
};
@group(1) @binding(2) var<uniform> config: Config;
@group(1) @binding(3) var gamma_table: texture_2d<f32>;
@group(1) @binding(4) var crossings: texture_2d<f32>;

@fragment
fn fs(@builtin(position) frag: vec4<f32>) -> Out {
    let px = vec2<i32>(frag.xy);
    let dir = camera_ray_dir(camera, frag.xy);
    let d = pixel_ray_length(px, dir);
    var l_in = vec3<f32>(0.0);
    for (var k = 0u; k < light_count(); k++) {
        if (config.shadowed == 0u) {
            l_in += lit_between(gamma_table, k, dir, 0.0, d, config.spot_panels);
        } else if (light_kind(k) == LIGHT_POINT && light_bit(config.eye_lit, k)) {
            l_in -= ldss_term(gamma_table, k, dir, 0.0);
        }
    }
    if (config.shadowed != 0u) {
        l_in = max(l_in + textureLoad(crossings, px, 0).rgb, vec3<f32>(0.0));
    }
    let surf = textureLoad(surface, px, 0).rgb;
    let ambient = ambient_fog(dir, d);
    return Out(vec4<f32>(l_in, 1.0), vec4<f32>(surf + l_in + ambient, 1.0));
}
