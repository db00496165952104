// The adapter calibration's two passes (calibrate.rs): the same per-pixel work, `work`, run once
// per fragment of a full-screen triangle and once per invocation of a compute grid of the same
// size, written to targets of the same format, so that their times differ only in how the
// adapter runs fragments and invocations.

// vec4 fused multiply-adds per pixel: enough that the passes are bound by shading, not by the
// write.
override ITERATIONS: u32 = 16u;

fn work(p: vec2<u32>) -> vec4<f32> {
    var v = vec4<f32>(vec2<f32>(p) * 1e-3, 0.25, 0.5);
    for (var i = 0u; i < ITERATIONS; i++) {
        v = fma(v, vec4<f32>(0.999), vec4<f32>(1e-4));
    }
    return v;
}

@vertex
fn full_screen(@builtin(vertex_index) i: u32) -> @builtin(position) vec4<f32> {
    let uv = vec2<f32>(f32((i << 1u) & 2u), f32(i & 2u));
    return vec4<f32>(uv * 2.0 - 1.0, 0.0, 1.0);
}

@fragment
fn shade_fragment(@builtin(position) position: vec4<f32>) -> @location(0) vec4<f32> {
    return work(vec2<u32>(position.xy));
}

@group(0) @binding(0) var out_texture: texture_storage_2d<rgba32float, write>;

@compute @workgroup_size(8, 8)
fn shade_invocation(@builtin(global_invocation_id) id: vec3<u32>) {
    textureStore(out_texture, id.xy, work(id.xy));
}

// The memory pass: one 16-byte element read and one written per invocation.
@group(0) @binding(0) var<storage, read> copy_from: array<vec4<u32>>;
@group(0) @binding(1) var<storage, read_write> copy_to: array<vec4<u32>>;

@compute @workgroup_size(64)
fn copy_elements(@builtin(global_invocation_id) id: vec3<u32>) {
    if (id.x < arrayLength(&copy_from)) {
        copy_to[id.x] = copy_from[id.x];
    }
}
