// Froxel apply pass: each pixel reads the integrated volume at its ray length (the visible
// surface or the far plane) — bilinear across froxel columns, linear between slice boundaries
// (boundary 0 is the eye: zero in-scatter). Needs the resolve prelude and grid.wgsl.

@group(1) @binding(2) var<uniform> froxel: Froxel;
@group(1) @binding(3) var volume: texture_2d<f32>;

// Integrated in-scatter of column (x, y) at slice boundary b ∈ [0, slices].
fn boundary(x: i32, y: i32, b: i32) -> vec3<f32> {
    let cx = u32(clamp(x, 0, i32(froxel.grid_x) - 1));
    let cy = u32(clamp(y, 0, i32(froxel.grid_y) - 1));
    let k = u32(clamp(b, 1, i32(froxel.slices)) - 1);
    let l = textureLoad(volume, vec2<i32>(tile_texel(froxel, cx, cy, k)), 0).rgb;
    // Boundary 0 is the eye: no in-scatter yet (a select, not an early return).
    return select(l, vec3<f32>(0.0), b <= 0);
}

// Linear in slice coordinate between the two boundaries around `f`.
fn column(x: i32, y: i32, f: f32) -> vec3<f32> {
    let b = i32(floor(f));
    return mix(boundary(x, y, b), boundary(x, y, b + 1), f - floor(f));
}

@fragment
fn fs(@builtin(position) frag: vec4<f32>) -> Out {
    let px = vec2<i32>(frag.xy);
    let dir = camera_ray_dir(camera, frag.xy);
    let d = pixel_ray_length(px, dir);
    let far_t = camera_far_distance(camera, dir);
    let f = f32(froxel.slices) * pow(clamp(d / far_t, 0.0, 1.0), 1.0 / froxel.depth_exponent);
    let g = frag.xy / f32(froxel.pixel_size) - 0.5;
    let g0 = floor(g);
    let w = g - g0;
    let x0 = i32(g0.x);
    let y0 = i32(g0.y);
    let l_in = mix(
        mix(column(x0, y0, f), column(x0 + 1, y0, f), w.x),
        mix(column(x0, y0 + 1, f), column(x0 + 1, y0 + 1, f), w.x),
        w.y,
    );
    let surf = textureLoad(surface, px, 0).rgb;
    return Out(vec4<f32>(l_in, 1.0), vec4<f32>(surf + l_in + ambient_fog(d), 1.0));
}
