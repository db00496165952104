// biri-polynomial's last pass: reads the accumulation target of the passes (passes.wgsl) and
// writes the AOVs. Float target (mode.unorm8 = 0): it holds the signed sum of Γ terms, L_in itself.
// unorm8 target (mode.unorm8 = 1): it holds the paper's frame buffer — surface + ambient fog first,
// then the medium contributions, each blend clamped to [0, 1] and quantised to 8 bits (§5.2) —
// so the total is read back and L_in is what is left after the surface and fog.
// Needs PRELUDE and FULLSCREEN.

// Mirrors `ResolveUniform` in mod.rs, field for field.
struct Mode {
    unorm8: u32,  // the `accumulate` knob: 0 float, 1 unorm8
    _pad0: u32,
    _pad1: u32,
    _pad2: u32,
};
@group(1) @binding(2) var<uniform> mode: Mode;
@group(1) @binding(3) var accumulated: texture_2d<f32>;

@fragment
fn fs(@builtin(position) frag: vec4<f32>) -> Out {
    let px = vec2<i32>(frag.xy);
    let dir = camera_ray_dir(camera, frag.xy);
    let d = pixel_ray_length(px, dir);
    let surf = textureLoad(surface, px, 0).rgb;
    let ambient = ambient_fog(dir, d);
    let acc = textureLoad(accumulated, px, 0).rgb;
    if (mode.unorm8 == 1u) {
        return Out(vec4<f32>(acc - surf - ambient, 1.0), vec4<f32>(acc, 1.0));
    }
    return Out(vec4<f32>(acc, 1.0), vec4<f32>(surf + acc + ambient, 1.0));
}
