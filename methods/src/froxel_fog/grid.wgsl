// The froxel grid's parameters and texel layout, shared by the volume and apply passes.
// Mirrors froxel_fog::FroxelUniform field for field.

struct Froxel {
    // grid size in froxels (x, y) and slices along depth
    grid_x: u32,
    grid_y: u32,
    slices: u32,
    // screen pixels per froxel in x and y
    pixel_size: u32,
    frame: u32,
    jitter: u32,
    // slice boundary k sits at view depth far · (k / slices)^depth_exponent
    depth_exponent: f32,
    // slices laid out as tiles of the 2-D volume texture, this many across
    tiles_x: u32,
};

// Texel of slice k of column (x, y) in the 2-D volume texture: slice k is tile (k % tiles_x, k / tiles_x).
fn tile_texel(g: Froxel, x: u32, y: u32, k: u32) -> vec2<u32> {
    return vec2<u32>(x + (k % g.tiles_x) * g.grid_x, y + (k / g.tiles_x) * g.grid_y);
}
