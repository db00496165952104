// Shadow-volume quads seen from the eye: per light k (channel k % 4 of layer k / 4, one pass
// per layer drawing that layer's lights), the nearest and farthest
// distance along each pixel's ray at which it crosses a shadow polygon. Min and max blending
// into two targets; no depth test (polygons behind the visible surface still count: the
// resolve clamps to the ray's length, so a ray ending inside a shadow marches to its end).
// Needs PRELUDE.

struct VolumeVertex {
    @location(0) position: vec3<f32>,
    @location(1) light: u32,
};

struct VsOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) @interpolate(flat) light: u32,
};

@vertex
fn vs(v: VolumeVertex) -> VsOut {
    return VsOut(camera.clip_from_world * vec4<f32>(v.position, 1.0), v.position, v.light);
}

struct Out {
    @location(0) front: vec4<f32>,
    @location(1) back: vec4<f32>,
};

const NO_FRONT: f32 = 1e30;
const NO_BACK: f32 = -1.0;

@fragment
fn fs(i: VsOut) -> Out {
    let d = length(i.world - camera.position.xyz);
    let mine = vec4<u32>(0u, 1u, 2u, 3u) == vec4<u32>(i.light % 4u);
    return Out(select(vec4<f32>(NO_FRONT), vec4<f32>(d), mine), select(vec4<f32>(NO_BACK), vec4<f32>(d), mine));
}
