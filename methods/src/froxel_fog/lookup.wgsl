// Reading the integrated froxel volume at a pixel's ray length: bilinear across froxel columns,
// linear between slice boundaries (boundary 0 is the eye: no in-scatter, transmittance 1). A
// module that composes this declares `froxel: Froxel` (uniform) and `volume: texture_2d<f32>`.
// Needs PRELUDE and grid.wgsl.

// The volume of column (x, y) at slice boundary b ∈ [0, slices]: rgb in-scatter, a the particles'
// transmittance.
fn boundary(x: i32, y: i32, b: i32) -> vec4<f32> {
    let cx = u32(clamp(x, 0, i32(froxel.grid_x) - 1));
    let cy = u32(clamp(y, 0, i32(froxel.grid_y) - 1));
    let k = u32(clamp(b, 1, i32(froxel.slices)) - 1);
    let v = textureLoad(volume, vec2<i32>(tile_texel(froxel, cx, cy, k)), 0);
    // Boundary 0 is the eye (a select, not an early return).
    return select(v, vec4<f32>(0.0, 0.0, 0.0, 1.0), b <= 0);
}

// Linear in slice coordinate between the two boundaries around `f`.
fn column(x: i32, y: i32, f: f32) -> vec4<f32> {
    let b = i32(floor(f));
    return mix(boundary(x, y, b), boundary(x, y, b + 1), f - floor(f));
}

// The volume at distance d along the ray through framebuffer position frag (direction dir).
fn volume_at(frag: vec2<f32>, dir: vec3<f32>, d: f32) -> vec4<f32> {
    let far_t = camera_far_distance(camera, dir);
    let f = slice_coordinate(froxel, d, far_t);
    let g = frag / froxel.pixel_size - 0.5;
    let g0 = floor(g);
    let w = g - g0;
    let x0 = i32(g0.x);
    let y0 = i32(g0.y);
    return mix(
        mix(column(x0, y0, f), column(x0 + 1, y0, f), w.x),
        mix(column(x0, y0 + 1, f), column(x0 + 1, y0 + 1, f), w.x),
        w.y,
    );
}
