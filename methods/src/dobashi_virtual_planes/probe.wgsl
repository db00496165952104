// Diagnostic (tests): the light map at given world points, through the same `light_map` the
// plane pass uses. Needs PRELUDE and dobashi.wgsl.

// xyz: world point; w: light index
@group(1) @binding(0) var<storage, read> probe_points: array<vec4<f32>>;
@group(1) @binding(1) var<storage, read_write> probe_values: array<vec4<f32>>;

@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) g: vec3<u32>) {
    let i = g.x;
    if (i >= arrayLength(&probe_points)) { return; }
    let p = probe_points[i];
    probe_values[i] = vec4<f32>(light_map(u32(p.w + 0.5), p.xyz), 1.0);
}
