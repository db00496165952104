// §3.3: low-resolution scattering back to full resolution with a 3×3 Gaussian that, with
// `bilateral`, ignores low-resolution samples whose ray length differs from this pixel's (so
// shafts do not bleed across depth discontinuities). Adds the surface and ambient terms.
// Needs PRELUDE and FULLSCREEN.

// Mirrors `UpsampleUniform` in mod.rs, field for field.
struct Upsample {
    scale: f32,      // the `scale` knob: full-resolution pixels per low-resolution texel, per side
    bilateral: u32,  // the `bilateral` knob (0/1)
    _pad0: u32,
    _pad1: u32,
};
@group(1) @binding(2) var<uniform> upsample: Upsample;
@group(1) @binding(3) var low: texture_2d<f32>;

@fragment
fn fs(@builtin(position) frag: vec4<f32>) -> Out {
    let px = vec2<i32>(frag.xy);
    let dir = camera_ray_dir(camera, frag.xy);
    let len = pixel_ray_length(px, dir);
    let scale = upsample.scale;
    let size = vec2<i32>(textureDimensions(low));
    // This pixel's position in low-resolution texel units (texel centres at integers).
    let c = (frag.xy - 0.5 - floor(0.5 * scale)) / scale;
    let n = vec2<i32>(round(c));
    var sum = vec3<f32>(0.0);
    var weight = 0.0;
    var nearest = vec3<f32>(0.0);
    var nearest_dz = 3.4e38;
    for (var dy = -1; dy <= 1; dy++) {
        for (var dx = -1; dx <= 1; dx++) {
            let t = clamp(n + vec2<i32>(dx, dy), vec2<i32>(0), size - 1);
            let s = textureLoad(low, t, 0);
            let d = vec2<f32>(t) - c;
            // σ = ½ texel: the 3×3 window then holds the kernel to 3σ, so it does not jump as the
            // window re-centres from one block to the next (σ = 1 left seams every `scale` pixels).
            var w = exp(-2.0 * dot(d, d));
            let dz = abs(s.a - len);
            if (upsample.bilateral != 0u) {
                let rel = dz / max(0.02 * len, 1e-4);
                w *= exp(-rel * rel);
            }
            sum += w * s.rgb;
            weight += w;
            if (dz < nearest_dz) {
                nearest_dz = dz;
                nearest = s.rgb;
            }
        }
    }
    // Every neighbour across a depth edge: take the one nearest in depth.
    let l_in = select(nearest, sum / weight, weight > 1e-6);
    let base = textureLoad(surface, px, 0).rgb + ambient_fog(dir, len);
    return Out(vec4<f32>(l_in, 1.0), vec4<f32>(base + l_in, 1.0));
}
