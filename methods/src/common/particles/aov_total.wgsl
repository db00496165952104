// `total` = `inscatter` + `surface`, read back from a resolve pass's two targets: three
// Rgba32Float targets exceed the 32 bytes per sample a render pass may write, and evaluating a
// resolve (a background-haze march above all) a second time for `total` doubled its cost. Used
// by every particle method. Needs FULLSCREEN only.

@group(0) @binding(0) var inscatter_in: texture_2d<f32>;
@group(0) @binding(1) var surface_aov: texture_2d<f32>;

@fragment
fn fs_total(@builtin(position) frag: vec4<f32>) -> @location(0) vec4<f32> {
    let px = vec2<i32>(frag.xy);
    return vec4<f32>(textureLoad(inscatter_in, px, 0).rgb + textureLoad(surface_aov, px, 0).rgb, 1.0);
}
