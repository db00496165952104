// Shadow-map visibility. The map stores, per texel, the distance from the light to the nearest
// caster (local lights) or the depth along the light direction (directional light); it is an
// R32Float array with one layer per face. Needs lights.wgsl and frame_bindings.wgsl.

// Visibility of world point x from light k: 1 lit, 0 shadowed.
fn shadow_visibility(k: u32, x: vec3<f32>) -> f32 {
    let sh = lights.lights[k].shadow;
    let base = sh.x;
    if (base < 0.0) { return 1.0; }
    let size = sh.z;
    let directional = light_kind(k) == LIGHT_DIRECTIONAL;
    var face = 0u;
    var dist = 0.0;
    if (directional) {
        dist = dot(x, lights.lights[k].direction.xyz);
    } else {
        let w = x - lights.lights[k].position.xyz;
        let a = abs(w);
        if (a.x >= a.y && a.x >= a.z) { face = select(1u, 0u, w.x > 0.0); }
        else if (a.y >= a.z) { face = select(3u, 2u, w.y > 0.0); }
        else { face = select(5u, 4u, w.z > 0.0); }
        dist = length(w);
    }
    let c = lights.lights[k].faces[face] * vec4<f32>(x, 1.0);
    let ndc = c.xy / c.w;
    if (any(abs(ndc) > vec2<f32>(1.0))) { return 1.0; }
    let uv = vec2<f32>(ndc.x * 0.5 + 0.5, 0.5 - ndc.y * 0.5);
    let texel = min(vec2<i32>(uv * size), vec2<i32>(i32(size) - 1));
    let stored = textureLoad(shadow_maps, texel, i32(base + 0.5) + i32(face), 0).r;
    // Bias of `shadow.w` texels: a cube-face texel spans ~2·dist/size metres at distance dist;
    // for directional light shadow.w already holds the texel size times the bias in texels.
    let span = select(dist * 2.0 / size, 1.0, directional);
    let bias = sh.w * span + 1e-4;
    return select(0.0, 1.0, dist <= stored + bias);
}
