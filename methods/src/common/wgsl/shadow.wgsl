// Shadow-map visibility. The map stores, per texel, the distance from the light to the nearest
// caster (local lights) or the depth along the light direction (directional light); it is an
// atlas (common::shadow_maps): an R32Float array of layers, a directional face filling a layer,
// local faces tiles of shadow.z² texels. Needs lights.wgsl and
// frame_bindings.wgsl.

// What a shadow map holds where nothing is stored (no map, or outside every face): "no caster".
const SHADOW_NONE: f32 = 3.0e38;

// Where face `face` of light k lies in the atlas: (texel origin x, y, layer). Its tiles are
// consecutive, counted in tiles of its own side, 2^shadow.y to a row. Shifts and masks, not
// divisions: lavapipe scalarises integer division per lane, and this runs per shadow lookup
// (raymarch-brute's 1-light frame was ~30 % slower with them). Mirrors
// common::uniforms::ShadowSlot::face_tile.
fn shadow_face_origin(k: u32, face: u32) -> vec3<u32> {
    let sh = lights.lights[k].shadow;
    let size = u32(sh.z + 0.5);
    let row_shift = u32(sh.y + 0.5);
    let tile = u32(sh.x + 0.5) + face;
    let in_layer = tile & ((1u << (2u * row_shift)) - 1u);
    let col = in_layer & ((1u << row_shift) - 1u);
    return vec3<u32>(col * size, (in_layer >> row_shift) * size, tile >> (2u * row_shift));
}

// The stored value of texel `texel` (within the face, 0 … size − 1) of light k's face `face`.
fn shadow_load(k: u32, face: u32, texel: vec2<i32>) -> f32 {
    let o = shadow_face_origin(k, face);
    return textureLoad(shadow_maps, vec2<i32>(o.xy) + texel, i32(o.z), 0).r;
}

// Where world point x falls in light k's shadow map: (texel x, texel y within the face, face,
// 1) as floats, or w = 0 without a map or outside its faces.
fn shadow_texel(k: u32, x: vec3<f32>) -> vec4<f32> {
    let sh = lights.lights[k].shadow;
    let base = sh.x;
    if (base < 0.0) { return vec4<f32>(0.0); }
    let size = sh.z;
    var face = 0u;
    if (light_kind(k) != LIGHT_DIRECTIONAL) {
        let w = x - lights.lights[k].position.xyz;
        let a = abs(w);
        if (a.x >= a.y && a.x >= a.z) { face = select(1u, 0u, w.x > 0.0); }
        else if (a.y >= a.z) { face = select(3u, 2u, w.y > 0.0); }
        else { face = select(5u, 4u, w.z > 0.0); }
    }
    let c = lights.lights[k].faces[face] * vec4<f32>(x, 1.0);
    let ndc = c.xy / c.w;
    if (any(abs(ndc) > vec2<f32>(1.0))) { return vec4<f32>(0.0); }
    let uv = vec2<f32>(ndc.x * 0.5 + 0.5, 0.5 - ndc.y * 0.5);
    let texel = min(floor(uv * size), vec2<f32>(size - 1.0));
    return vec4<f32>(texel, f32(face), 1.0);
}

// The stored caster distance (local lights) or depth (directional) of light k in the texel that
// world point x projects to; SHADOW_NONE without a map or outside its faces.
fn shadow_stored(k: u32, x: vec3<f32>) -> f32 {
    let t = shadow_texel(k, x);
    if (t.w == 0.0) { return SHADOW_NONE; }
    return shadow_load(k, u32(t.z), vec2<i32>(t.xy));
}

// The depth test as an affine bound: x is lit iff dist · b.x ≤ stored + b.y, where dist is the
// distance to the light (local) or the depth along its direction (directional). Bias of
// `shadow.w` texels: a cube-face texel spans ~2·dist/size metres at distance dist, so the bias
// grows with dist; for directional light shadow.w already holds the texel size times the bias.
fn shadow_bound(k: u32) -> vec2<f32> {
    let sh = lights.lights[k].shadow;
    if (light_kind(k) == LIGHT_DIRECTIONAL) { return vec2<f32>(1.0, sh.w + 1e-4); }
    return vec2<f32>(1.0 - sh.w * 2.0 / max(sh.z, 1.0), 1e-4);
}

// The light-space distance `shadow_stored` is compared with: to the light, or along its direction.
fn shadow_distance(k: u32, x: vec3<f32>) -> f32 {
    if (light_kind(k) == LIGHT_DIRECTIONAL) { return dot(x, lights.lights[k].direction.xyz); }
    return length(x - lights.lights[k].position.xyz);
}

// Visibility of world point x from light k: 1 lit, 0 shadowed.
fn shadow_visibility(k: u32, x: vec3<f32>) -> f32 {
    let b = shadow_bound(k);
    return select(0.0, 1.0, shadow_distance(k, x) * b.x <= shadow_stored(k, x) + b.y);
}

// Percentage-closer filtering (Reeves et al. 1987): the fraction of the 3 × 3 texels around x's
// texel (clamped to its face) whose stored depth x passes, with shadow_visibility's bias.
fn shadow_visibility_pcf(k: u32, x: vec3<f32>) -> f32 {
    let t = shadow_texel(k, x);
    if (t.w == 0.0) { return 1.0; }
    let b = shadow_bound(k);
    let d = shadow_distance(k, x) * b.x - b.y;
    let last = i32(lights.lights[k].shadow.z) - 1;
    let o = shadow_face_origin(k, u32(t.z));
    var lit = 0.0;
    for (var j = -1; j <= 1; j++) {
        for (var i = -1; i <= 1; i++) {
            let texel = clamp(vec2<i32>(t.xy) + vec2<i32>(i, j), vec2<i32>(0), vec2<i32>(last));
            let stored = textureLoad(shadow_maps, vec2<i32>(o.xy) + texel, i32(o.z), 0).r;
            lit += select(0.0, 1.0, d <= stored);
        }
    }
    return lit / 9.0;
}
