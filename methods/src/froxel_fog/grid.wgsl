// The froxel grid's parameters and texel layout, shared by the volume and apply passes.
// Mirrors froxel_fog::state::FroxelUniform field for field.

struct Froxel {
    // grid size in froxels (x, y) and slices along depth
    grid_x: u32,
    grid_y: u32,
    slices: u32,
    // screen pixels per froxel in x and y (fractional for a fixed number of columns)
    pixel_size: f32,
    // frames rendered since prepare (the jitter sequence's index)
    frame: u32,
    // where the sample point moves from frame to frame: 0 nowhere (no temporal accumulation),
    // 1 along the column's centre ray, 2 over the whole froxel (knob `jitter`)
    jitter: u32,
    // slice boundary k sits at view depth far · (k / slices)^depth_exponent
    depth_exponent: f32,
    // slices laid out as tiles of the 2-D volume texture, this many across
    tiles_x: u32,
    // temporal accumulation: weight of this frame's injection (1: no history)
    blend: f32,
    // 1 when the history holds an earlier frame
    history: u32,
    // 1 when the camera moved since that frame (reproject; else read the same froxel)
    moved: u32,
    _pad: u32,
    // this frame's jitter offset in [0, 1)³ (Halton 2, 3, 5), rotated per froxel
    offset: vec4<f32>,
    // the previous frame's camera: clip_from_world, eye (w: far plane depth), forward (w: the
    // same far plane depth, as Camera.forward)
    prev_clip_from_world: mat4x4<f32>,
    prev_position: vec4<f32>,
    prev_forward: vec4<f32>,
};

// Texel of slice k of column (x, y) in the 2-D volume texture: slice k is tile (k % tiles_x, k / tiles_x).
fn tile_texel(g: Froxel, x: u32, y: u32, k: u32) -> vec2<u32> {
    return vec2<u32>(x + (k % g.tiles_x) * g.grid_x, y + (k / g.tiles_x) * g.grid_y);
}

// Continuous slice coordinate (slice k spans [k, k + 1)) of distance d along a ray whose far
// plane lies at distance far_t: slice boundary k sits at far_t · (k / slices)^depth_exponent.
fn slice_coordinate(g: Froxel, d: f32, far_t: f32) -> f32 {
    return f32(g.slices) * pow(clamp(d / far_t, 0.0, 1.0), 1.0 / g.depth_exponent);
}
