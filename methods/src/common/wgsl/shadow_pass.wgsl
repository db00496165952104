// Renders one shadow-map face: distance from the light to the nearest caster. Needs scene.wgsl.
struct Face {
    clip_from_world: mat4x4<f32>,
    // xyz: light position (w = 0) or propagation direction (w = 1)
    light: vec4<f32>,
};
@group(0) @binding(0) var<uniform> face: Face;
@group(0) @binding(1) var<storage, read> objects: array<ObjectData>;

struct VsOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
};

@vertex
fn vs(v: VertexIn) -> VsOut {
    let world = objects[v.object].world_from_local * vec4<f32>(v.position, 1.0);
    return VsOut(face.clip_from_world * world, world.xyz);
}

@fragment
fn fs(i: VsOut) -> @location(0) vec4<f32> {
    let d = select(length(i.world - face.light.xyz), dot(i.world, face.light.xyz), face.light.w > 0.5);
    return vec4<f32>(d, 0.0, 0.0, 0.0);
}
