//! The froxel grid's uniform (`Froxel` in grid.wgsl) and what changes in it from frame to
//! frame: the jitter offset, and temporal accumulation's blend weight and previous camera.

use anyhow::{Result, bail};
use bytemuck::{Pod, Zeroable};
use harness::{KnobRead, Params};
use scenes::CameraPose;

/// `Froxel` in grid.wgsl, field for field.
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
pub struct FroxelUniform {
    pub grid_x: u32,
    pub grid_y: u32,
    pub slices: u32,
    pub pixel_size: f32,
    frame: u32,
    jitter: u32,
    depth_exponent: f32,
    pub tiles_x: u32,
    blend: f32,
    history: u32,
    moved: u32,
    _pad: u32,
    offset: [f32; 4],
    prev_clip_from_world: [[f32; 4]; 4],
    prev_position: [f32; 4],
    prev_forward: [f32; 4],
}

impl FroxelUniform {
    /// The grid of `params` over a `width` × `height` image; fails when its volume texture (the
    /// slices as tiles) exceeds `max_texture` per side.
    pub fn new(params: &Params, (width, height): (u32, u32), max_texture: u32) -> Result<Self> {
        let columns: u32 = params.knob("columns")?;
        let slices: u32 = params.knob("slices")?;
        // A fixed number of columns (Godot, AC4), or columns of pixel_size pixels (Unreal).
        let (grid_x, pixel_size) = match columns {
            0 => {
                let ps: u32 = params.knob("pixel_size")?;
                (width.div_ceil(ps), ps as f32)
            }
            n => (n, width as f32 / n as f32),
        };
        let grid_y = ((height as f32 / pixel_size).ceil() as u32).max(1);
        let tiles_x = (slices as f64).sqrt().ceil() as u32;
        let tiles_y = slices.div_ceil(tiles_x);
        if grid_x * tiles_x > max_texture || grid_y * tiles_y > max_texture {
            bail!(
                "froxel-fog: a {grid_x}×{grid_y}×{slices} grid needs a {}×{} volume texture; this adapter allows {max_texture}² (fewer columns, larger pixel_size or fewer slices)",
                grid_x * tiles_x,
                grid_y * tiles_y
            );
        }
        let temporal: u32 = params.knob("temporal")?;
        Ok(FroxelUniform {
            grid_x,
            grid_y,
            slices,
            pixel_size,
            jitter: match (temporal, params.knob::<String>("jitter")?.as_str()) {
                (0, _) => 0,
                (_, "depth") => 1,
                _ => 2,
            },
            depth_exponent: params.knob("depth_exponent")?,
            tiles_x,
            blend: 1.0,
            ..Zeroable::zeroed()
        })
    }

    /// Froxels in the grid.
    pub fn froxels(&self) -> u64 {
        self.grid_x as u64 * self.grid_y as u64 * self.slices as u64
    }

    /// The volume texture's size (slices as tiles, `tiles_x` across).
    pub fn texture_size(&self) -> (u32, u32) {
        let tiles_y = self.slices.div_ceil(self.tiles_x);
        (self.grid_x * self.tiles_x, self.grid_y * tiles_y)
    }
}

/// Temporal accumulation's bookkeeping across frames.
pub struct Temporal {
    /// Frames blended (0: off).
    pub frames: u32,
    /// Frames rendered since prepare (the jitter sequence's index).
    pub rendered: u32,
    /// The camera of the frame the history holds.
    pub previous: Option<CameraPose>,
}

/// The radical inverse of i in base b: the Halton sequence's i-th element in that base.
fn halton(mut i: u32, b: u32) -> f32 {
    let (mut f, mut r) = (1.0f32, 0.0f32);
    while i > 0 {
        f /= b as f32;
        r += f * (i % b) as f32;
        i /= b;
    }
    r
}

impl Temporal {
    /// Fills `g`'s per-frame fields for a frame seen from `camera` (image aspect `aspect`): the
    /// jitter offset, the blend weight — a progressive average over the first N frames, then an
    /// exponential one of weight 1/N — and the camera the history was rendered with.
    pub fn fill(&self, g: &mut FroxelUniform, camera: &CameraPose, aspect: f32) {
        g.frame = self.rendered;
        let i = self.rendered + 1;
        g.offset = [halton(i, 2), halton(i, 3), halton(i, 5), 0.0];
        let held = self.previous.is_some() as u32 * self.rendered.min(self.frames);
        g.blend = match self.frames {
            0 => 1.0,
            n => (1.0 / (held + 1) as f32).max(1.0 / n as f32),
        };
        g.history = (self.frames > 0 && self.previous.is_some()) as u32;
        g.moved = 0;
        if let Some(prev) = &self.previous {
            g.moved = (prev != camera) as u32;
            g.prev_clip_from_world = prev.clip_from_world(aspect).to_cols_array_2d();
            g.prev_position = prev.position.extend(prev.far).to_array();
            g.prev_forward = prev.forward().as_vec3().extend(prev.far).to_array();
        }
    }

    /// After a frame from `camera`: the history now holds it.
    pub fn advance(&mut self, camera: &CameraPose) {
        self.rendered += 1;
        self.previous = Some(*camera);
    }
}
