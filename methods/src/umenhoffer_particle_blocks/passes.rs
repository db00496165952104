//! GPU side: the impostor atlas (and its depth moments, `interval = moments`), the light slices (one layer per light map), the gather
//! targets, the four pipelines (impostor, light, gather, resolve) and their bind groups (the
//! per-light surface-shadow pass is `surface_shadow.rs`). Every pass uses the shared frame bind
//! group at group 0 and its own subset of the method's bindings (blocks.wgsl) at group 1.

use bytemuck::{Pod, Zeroable};
use harness::gpu::{Counted, color_attachment};
use harness::method::AOV_FORMAT;
use harness::{Gpu, Targets};

use super::dominant::MAX_DOMINANT;
use super::primitives::{ImpParticle, Prim, Tile};
use super::shaders::{GATHER_WGSL, IMPOSTOR_WGSL, LIGHT_WGSL, RESOLVE_WGSL, source, total_source};
use super::surface_shadow::SurfaceShadow;
use crate::common::layouts::{
    float_texture, float_texture_array, storage_buffer, uniform_buffer, view_entry,
};
use crate::common::pipeline::{self, ADD, ADDITIVE, MIN, OVER, Stage, both, target};
use crate::common::renderer::SceneRenderer;
use crate::common::wgsl;

/// Light maps per light: one, or the six faces of a cube (`View`s 6k … 6k + 5 of light k).
pub const FACES: usize = 6;
/// Lights the method's uniform has room for: six light-map views each (672 B), so 16 lights
/// take 11 KB of it; `support` refuses more. (The shared renderer holds more; these methods'
/// per-light cost, a primitive list and up to six light passes and slice layers per light, is
/// the reason not to size the uniform for all of them.)
pub const MAX_LIGHTS: usize = 16;

/// One light map; mirrors `View` in blocks.wgsl.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct ViewUniform {
    pub u: [f32; 4],
    pub v: [f32; 4],
    pub w: [f32; 4],
    pub p: [f32; 4],
    pub range: [f32; 4],
}

/// Mirrors `Pb` in blocks.wgsl.
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
pub struct PbUniform {
    /// Every light's FACES views, then the eye's (`eye_slices`; index FACES · lights).
    pub views: [ViewUniform; FACES * MAX_LIGHTS + 1],
    pub maps: [[f32; 4]; MAX_LIGHTS],
    pub atlas: [f32; 4],
    pub flags: [f32; 4],
    pub counts: [f32; 4],
    pub sky: [f32; 4],
    /// The dominant spheres (dominant.rs; `flags[3]` of them): centre and radius, then σ and
    /// the index in the gathering's list.
    pub dominant: [[f32; 4]; 2 * MAX_DOMINANT],
}

/// Impostor atlas texels: min-blendable, and 16-bit floats are ample for depths within a block.
pub const ATLAS_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;
/// The impostor atlas's depth moments (additive; 32-bit floats: the variance is a difference).
pub const MOMENT_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rg32Float;
/// Slices and the gather target accumulate many small terms: 32-bit floats.
pub const ACCUM_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;
/// The gathered cloud's near and far ray parameters (min blending).
pub const EXTENT_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rg32Float;
/// An empty extent texel: no cloud on the ray.
const NO_EXTENT: f64 = 1e9;

pub struct Sizes {
    /// The capacity C of each primitive list (the gathering's, then one per light).
    pub prims: usize,
    pub imp: usize,
    pub tiles: usize,
    /// Atlas side (texels), tile columns and tile resolution.
    pub atlas: u32,
    pub cols: u32,
    pub tile_res: u32,
    pub light_res: u32,
    /// Light-pass slices S (4, 8, 16 or 32; knob `slices`).
    pub slices: u32,
    /// The scene's lights (each has FACES slice layers).
    pub lights: usize,
    /// Camera tiles per impostor particle: the prototype's direction bins (1 otherwise).
    pub camera_tiles: u32,
}

/// What the shaders compile in (blocks.wgsl's overrides), beside the scene's light layout.
pub struct Modes {
    /// Primitives are impostor blocks (false: analytic spheres, `particle-splat`).
    pub blocks: bool,
    pub forward_scattering: bool,
    /// Block pixels' intervals from the impostors' depth moments (knob `interval = moments`).
    pub moments: bool,
    /// Quadrature nodes along a primitive's interval in the gathering (knob `chord_steps`; 0:
    /// the closed form).
    pub chord_steps: u32,
    /// The eye's own slices attenuate the gathering, which then adds (knob `eye_slices`).
    pub eye_slices: bool,
    /// Dominant spheres can occur in this scene (dominant.rs `possible`): their code is compiled
    /// in; without, it is not (lavapipe ran its empty loops at 1.8× the gathering's cost).
    pub dominant: bool,
}

/// The buffers and textures the stages bind (blocks.wgsl's group 1, by binding number).
pub struct Resources {
    pub uniform: wgpu::Buffer,
    pub prims: wgpu::Buffer,
    pub tiles: wgpu::Buffer,
    pub imp: wgpu::Buffer,
    atlas_view: wgpu::TextureView,
    moments_view: wgpu::TextureView,
    /// Both slice textures as arrays (sampled) and one layer of each per view and light pass
    /// (rendered; index `view · slice_passes + pass`).
    slice_views: [wgpu::TextureView; 2],
    slice_layers: Vec<[wgpu::TextureView; 2]>,
    gather_view: wgpu::TextureView,
    extents_view: wgpu::TextureView,
    pub surface_view: wgpu::TextureView,
}

pub struct Passes {
    pub res: Resources,
    impostor: wgpu::RenderPipeline,
    light: wgpu::RenderPipeline,
    gather: wgpu::RenderPipeline,
    resolve: wgpu::RenderPipeline,
    total: wgpu::RenderPipeline,
    total_layout: wgpu::BindGroupLayout,
    bind_impostor: wgpu::BindGroup,
    bind_light: wgpu::BindGroup,
    bind_gather: wgpu::BindGroup,
    bind_resolve: wgpu::BindGroup,
    surface_shadow: SurfaceShadow,
    pub sizes: Sizes,
}

fn storage(gpu: &Gpu, label: &str, bytes: usize) -> wgpu::Buffer {
    gpu.buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size: bytes.max(64) as u64,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    })
}

/// Render passes per light map: each writes two groups of four slices (two RGBA targets).
pub fn slice_passes(slices: u32) -> u32 {
    (slices / 8).max(1)
}

/// Layers of each slice texture: one per light pass of every light's FACES views and of the
/// eye's view (`eye_slices`; allocated always, a few layers).
pub fn slice_layers(sizes: &Sizes) -> u32 {
    slice_layers_for(sizes.lights, sizes.slices)
}

/// [`slice_layers`] for `lights` lights and `slices` slices.
pub fn slice_layers_for(lights: usize, slices: u32) -> u32 {
    (FACES * lights.max(1) + 1) as u32 * slice_passes(slices)
}

/// Binding `b` of blocks.wgsl's group 1, as a layout entry: the uniform, the primitive, tile
/// and impostor-particle lists, the slice arrays (5, 6) and 2-D textures.
fn entry(b: u32) -> wgpu::BindGroupLayoutEntry {
    let vf = wgpu::ShaderStages::VERTEX_FRAGMENT;
    match b {
        0 => uniform_buffer(b, vf),
        1..=3 => storage_buffer(b, vf, true),
        5 | 6 => float_texture_array(b, vf),
        _ => float_texture(b, vf),
    }
}

impl Resources {
    fn new(gpu: &Gpu, renderer: &SceneRenderer, sizes: &Sizes) -> Resources {
        let tex = |label: &str, w: u32, h: u32, format: wgpu::TextureFormat| {
            gpu.texture_2d(
                label,
                w.max(1),
                h.max(1),
                format,
                wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
            )
            .create_view(&Default::default())
        };
        let layers = slice_layers(sizes);
        let slices = |label| {
            gpu.device.create_texture(&wgpu::TextureDescriptor {
                label: Some(label),
                size: wgpu::Extent3d {
                    width: sizes.light_res,
                    height: sizes.light_res,
                    depth_or_array_layers: layers,
                },
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format: ACCUM_FORMAT,
                usage: wgpu::TextureUsages::RENDER_ATTACHMENT
                    | wgpu::TextureUsages::TEXTURE_BINDING,
                view_formats: &[],
            })
        };
        let slice_tex = [
            slices("light slices, even groups of four"),
            slices("light slices, odd groups of four"),
        ];
        let array = |t: &wgpu::Texture| {
            t.create_view(&wgpu::TextureViewDescriptor {
                dimension: Some(wgpu::TextureViewDimension::D2Array),
                ..Default::default()
            })
        };
        let layer = |t: &wgpu::Texture, l: u32| {
            t.create_view(&wgpu::TextureViewDescriptor {
                dimension: Some(wgpu::TextureViewDimension::D2),
                base_array_layer: l,
                array_layer_count: Some(1),
                ..Default::default()
            })
        };
        let (w, h) = (renderer.width, renderer.height);
        Resources {
            uniform: gpu.buffer(&wgpu::BufferDescriptor {
                label: Some("particle blocks uniform"),
                size: std::mem::size_of::<PbUniform>() as u64,
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            }),
            prims: storage(
                gpu,
                "primitives",
                (1 + sizes.lights) * sizes.prims * size_of::<Prim>(),
            ),
            tiles: storage(gpu, "impostor tiles", sizes.tiles * size_of::<Tile>()),
            imp: storage(
                gpu,
                "impostor particles",
                sizes.imp * size_of::<ImpParticle>(),
            ),
            // Splat mode has no tiles: a 1×1 atlas keeps the bindings valid.
            atlas_view: tex("impostor atlas", sizes.atlas, sizes.atlas, ATLAS_FORMAT),
            moments_view: tex("impostor moments", sizes.atlas, sizes.atlas, MOMENT_FORMAT),
            slice_views: [array(&slice_tex[0]), array(&slice_tex[1])],
            slice_layers: (0..layers)
                .map(|l| [layer(&slice_tex[0], l), layer(&slice_tex[1], l)])
                .collect(),
            gather_view: tex("gather", w, h, ACCUM_FORMAT),
            extents_view: tex("gather extents", w, h, EXTENT_FORMAT),
            surface_view: tex("surface (unshadowed)", w, h, AOV_FORMAT),
        }
    }

    /// Binding `b` of group 1 (`distance` is the renderer's distance AOV, binding 7).
    fn binding<'a>(&'a self, b: u32, distance: &'a wgpu::TextureView) -> wgpu::BindingResource<'a> {
        let view = wgpu::BindingResource::TextureView;
        match b {
            0 => self.uniform.as_entire_binding(),
            1 => self.prims.as_entire_binding(),
            2 => self.tiles.as_entire_binding(),
            3 => self.imp.as_entire_binding(),
            4 => view(&self.atlas_view),
            5 => view(&self.slice_views[0]),
            6 => view(&self.slice_views[1]),
            7 => view(distance),
            8 => view(&self.gather_view),
            10 => view(&self.extents_view),
            11 => view(&self.moments_view),
            _ => view(&self.surface_view),
        }
    }
}

/// Builds one stage: its group-1 layout and bind group from a subset of the bindings, its module
/// (blocks.wgsl plus its own source) and its pipeline (no vertex buffers, no depth).
struct StageBuilder<'a> {
    pub device: &'a wgpu::Device,
    pub renderer: &'a SceneRenderer,
    pub res: &'a Resources,
    pub constants: Vec<(&'static str, f64)>,
}

impl StageBuilder<'_> {
    /// A group-1 layout of these bindings and its bind group.
    pub fn group(&self, label: &str, bindings: &[u32]) -> (wgpu::BindGroupLayout, wgpu::BindGroup) {
        let dev = self.device;
        let entries: Vec<_> = bindings.iter().map(|&b| entry(b)).collect();
        let bgl = dev.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some(label),
            entries: &entries,
        });
        let distance = &self.renderer.distance_view;
        let entries: Vec<_> = bindings
            .iter()
            .map(|&b| wgpu::BindGroupEntry {
                binding: b,
                resource: self.res.binding(b, distance),
            })
            .collect();
        let bind = dev.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some(label),
            layout: &bgl,
            entries: &entries,
        });
        (bgl, bind)
    }

    fn stage(
        &self,
        label: &'static str,
        bindings: &[u32],
        own: &str,
        (vs, fs): (&str, &str),
        targets: &[Option<wgpu::ColorTargetState>],
    ) -> (wgpu::RenderPipeline, wgpu::BindGroup) {
        let dev = self.device;
        let (bgl, bind) = self.group(label, bindings);
        let layout = pipeline::layout(dev, label, &[&self.renderer.frame_layout, &bgl]);
        let module = wgsl::module(dev, label, &source(own));
        let pipeline = Stage::new(label, vs).fragment(fs, targets).build(
            dev,
            &layout,
            &module,
            &self.constants,
        );
        (pipeline, bind)
    }
}

/// The total AOV (in-scatter + surface), a full-screen pass over the harness's targets.
fn total_pipeline(dev: &wgpu::Device) -> (wgpu::RenderPipeline, wgpu::BindGroupLayout) {
    let aov_texture = crate::common::layouts::fragment_texture;
    let layout = dev.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("particle total"),
        entries: &[aov_texture(0), aov_texture(1)],
    });
    let module = wgsl::module(dev, "particle total", &total_source());
    let pipeline = crate::common::resolve::fullscreen_pipeline(
        dev,
        "particle total",
        &pipeline::layout(dev, "particle total", &[&layout]),
        &module,
        "fs_total",
        &[],
        &[target(AOV_FORMAT, None)],
    );
    (pipeline, layout)
}

impl Passes {
    pub fn new(gpu: &Gpu, renderer: &SceneRenderer, sizes: Sizes, modes: Modes) -> Passes {
        let flag = crate::common::specialize::flag;
        let res = Resources::new(gpu, renderer, &sizes);
        let b = StageBuilder {
            device: &gpu.device,
            renderer,
            res: &res,
            constants: renderer.specialization.with(&[
                ("BLOCKS", flag(modes.blocks)),
                ("FORWARD_SCATTERING", flag(modes.forward_scattering)),
                ("MOMENTS", flag(modes.moments)),
                ("CHORD_STEPS", modes.chord_steps as f64),
                ("EYE_SLICES", flag(modes.eye_slices)),
                ("DOMINANT", flag(modes.dominant)),
                ("SLICE_GROUPS", (sizes.slices / 4) as f64),
                ("COVERS", super::held::COVERS as f64),
            ]),
        };
        // Front/back depths by min blending, optical depth by additive alpha (§2.1, one pass).
        let minmax = wgpu::BlendState {
            color: MIN,
            alpha: ADD,
        };
        let (impostor, bind_impostor) = b.stage(
            "particle impostors",
            &[0, 2, 3],
            IMPOSTOR_WGSL,
            ("vs_impostor", "fs_impostor"),
            &[
                target(ATLAS_FORMAT, Some(minmax)),
                target(MOMENT_FORMAT, Some(ADDITIVE)),
            ],
        );
        let additive = Some(ADDITIVE);
        let eight = sizes.slices > 4;
        let light_targets = [
            target(ACCUM_FORMAT, additive),
            target(ACCUM_FORMAT, additive),
        ];
        let (light, bind_light) = b.stage(
            "particle light pass",
            &[0, 1, 2, 4, 11],
            LIGHT_WGSL,
            ("vs_light", if eight { "fs_light8" } else { "fs_light4" }),
            &light_targets[..if eight { 2 } else { 1 }],
        );
        // Premultiplied "over", back to front; alpha accumulates the opacity. With the eye's
        // slices each primitive's in-scatter is already attenuated by what lies in front: added
        // (the opacity still "over", which needs no order).
        let composite = if modes.eye_slices {
            wgpu::BlendState {
                color: ADD,
                alpha: OVER,
            }
        } else {
            both(OVER)
        };
        let (gather, bind_gather) = b.stage(
            "particle gather",
            &[0, 1, 2, 4, 5, 6, 7, 11],
            GATHER_WGSL,
            ("vs_gather", "fs_gather"),
            &[
                target(ACCUM_FORMAT, Some(composite)),
                target(EXTENT_FORMAT, Some(both(MIN))),
            ],
        );
        let (resolve, bind_resolve) = b.stage(
            "particle resolve",
            &[0, 5, 6, 7, 8, 9, 10],
            RESOLVE_WGSL,
            ("vs_fullscreen", "fs_resolve"),
            &[target(AOV_FORMAT, None), target(AOV_FORMAT, None)],
        );
        let (shadow_layout, shadow_bind) =
            b.group("particle surface shadow", &super::surface_shadow::BINDINGS);
        let surface_shadow = SurfaceShadow::new(
            &gpu.device,
            renderer,
            &[(&shadow_layout, &shadow_bind)],
            &b.constants,
            sizes.lights,
            &super::shaders::surface_shadow_source(),
        );
        let (total, total_layout) = total_pipeline(&gpu.device);
        Passes {
            res,
            impostor,
            light,
            gather,
            resolve,
            total,
            total_layout,
            bind_impostor,
            bind_light,
            bind_gather,
            bind_resolve,
            surface_shadow,
            sizes,
        }
    }

    fn pass<'e>(
        renderer: &SceneRenderer,
        enc: &'e mut wgpu::CommandEncoder,
        label: &str,
        views: &[&wgpu::TextureView],
        clear: wgpu::Color,
    ) -> Counted<wgpu::RenderPass<'e>> {
        let attachments: Vec<_> = views
            .iter()
            .map(|v| color_attachment(v, wgpu::LoadOp::Clear(clear)))
            .collect();
        renderer.passes.render_pass(
            enc,
            &wgpu::RenderPassDescriptor {
                label: Some(label),
                color_attachments: &attachments,
                ..Default::default()
            },
        )
    }

    /// Renders every impostor particle into its light tile and its camera tile.
    pub fn encode_impostors(&self, enc: &mut wgpu::CommandEncoder, renderer: &SceneRenderer) {
        // Empty texels: far-away front/back depths and zero optical depth.
        let empty = wgpu::Color {
            r: 1e4,
            g: 1e4,
            b: 1e4,
            a: 0.0,
        };
        // The moments clear to zero (one pass, two clear values: set by hand).
        let attachments = [
            color_attachment(&self.res.atlas_view, wgpu::LoadOp::Clear(empty)),
            color_attachment(
                &self.res.moments_view,
                wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
            ),
        ];
        let mut p = renderer.passes.render_pass(
            enc,
            &wgpu::RenderPassDescriptor {
                label: Some("particle impostors"),
                color_attachments: &attachments,
                ..Default::default()
            },
        );
        p.set_pipeline(&self.impostor);
        p.set_bind_group(0, &renderer.frame_bind, &[]);
        p.set_bind_group(1, &self.bind_impostor, &[]);
        // The camera tiles, then each light's tiles.
        let groups = self.sizes.camera_tiles + self.sizes.lights as u32;
        p.draw(0..6, 0..groups * self.sizes.imp as u32);
    }

    /// The light pass into the slices of each view in `views` (each cleared to zero optical
    /// depth), then each light's shadow on the surfaces; then, if `eye` (the gathering list's
    /// length) is not 0, the eye's view (`eye_slices`). `views[k]`: light k's maps this frame;
    /// `lists[k]`: the length of light k's primitive list; `dominant`: dominant spheres exist,
    /// so every light's surface-shadow pass runs, maps or not.
    pub fn encode_light(
        &self,
        enc: &mut wgpu::CommandEncoder,
        renderer: &SceneRenderer,
        views: &[u32],
        lists: &[usize],
        eye: usize,
        dominant: bool,
    ) {
        let passes = slice_passes(self.sizes.slices);
        for (k, &count) in views.iter().enumerate() {
            let len = lists[k] as u32;
            let first = (FACES * k) as u32 * passes;
            // Light k's views, each in `passes` passes (light.wgsl decodes the instance index).
            for slot in first..first + count * passes {
                self.encode_slices(enc, renderer, slot, len);
            }
            // Dominant spheres shadow surfaces without any light map (dominant.rs).
            if count > 0 || dominant {
                self.surface_shadow
                    .encode(enc, renderer, &self.res.surface_view, k);
            }
        }
        if eye > 0 {
            let first = (FACES * views.len()) as u32 * passes;
            for slot in first..first + passes {
                self.encode_slices(enc, renderer, slot, eye as u32);
            }
        }
    }

    /// One light pass: slot `slot` (view · passes + pass) from the first `len` primitives of the
    /// view's list, into that slot's layer of both slice arrays.
    fn encode_slices(
        &self,
        enc: &mut wgpu::CommandEncoder,
        renderer: &SceneRenderer,
        slot: u32,
        len: u32,
    ) {
        let n = if self.sizes.slices > 4 { 2 } else { 1 };
        let stride = self.sizes.prims as u32;
        let layer = &self.res.slice_layers[slot as usize];
        let targets: Vec<&wgpu::TextureView> = layer.iter().collect();
        let mut p = Self::pass(
            renderer,
            enc,
            "particle light pass",
            &targets[..n],
            wgpu::Color::TRANSPARENT,
        );
        p.set_pipeline(&self.light);
        p.set_bind_group(0, &renderer.frame_bind, &[]);
        p.set_bind_group(1, &self.bind_light, &[]);
        p.draw(0..6, slot * stride..slot * stride + len);
    }

    /// Back-to-front gathering of the first `count` primitives (the buffer holds them in that
    /// order).
    pub fn encode_gather(
        &self,
        enc: &mut wgpu::CommandEncoder,
        renderer: &SceneRenderer,
        count: usize,
    ) {
        // The extents clear to "no cloud" (one pass, two clear values: set by hand).
        let far = wgpu::Color {
            r: NO_EXTENT,
            g: NO_EXTENT,
            b: 0.0,
            a: 0.0,
        };
        let attachments = [
            color_attachment(
                &self.res.gather_view,
                wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
            ),
            color_attachment(&self.res.extents_view, wgpu::LoadOp::Clear(far)),
        ];
        let mut p = renderer.passes.render_pass(
            enc,
            &wgpu::RenderPassDescriptor {
                label: Some("particle gather"),
                color_attachments: &attachments,
                ..Default::default()
            },
        );
        p.set_pipeline(&self.gather);
        p.set_bind_group(0, &renderer.frame_bind, &[]);
        p.set_bind_group(1, &self.bind_gather, &[]);
        p.draw(0..6, 0..count as u32);
    }

    pub fn encode_resolve(
        &self,
        gpu: &Gpu,
        enc: &mut wgpu::CommandEncoder,
        renderer: &SceneRenderer,
        targets: &Targets,
    ) {
        let mut p = Self::pass(
            renderer,
            enc,
            "particle resolve",
            &[targets.inscatter, targets.surface],
            wgpu::Color::TRANSPARENT,
        );
        p.set_pipeline(&self.resolve);
        p.set_bind_group(0, &renderer.frame_bind, &[]);
        p.set_bind_group(1, &self.bind_resolve, &[]);
        p.draw(0..3, 0..1);
        drop(p);
        let mut p = Self::pass(
            renderer,
            enc,
            "particle total",
            &[targets.total],
            wgpu::Color::TRANSPARENT,
        );
        // The harness owns the AOV textures, so this group is built per frame.
        let sum = gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("particle total"),
            layout: &self.total_layout,
            entries: &[
                view_entry(0, targets.inscatter),
                view_entry(1, targets.surface),
            ],
        });
        p.set_pipeline(&self.total);
        p.set_bind_group(0, &sum, &[]);
        p.draw(0..3, 0..1);
    }
}
