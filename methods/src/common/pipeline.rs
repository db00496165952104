//! One description of a render pipeline for every pass of every method: a vertex entry, an
//! optional vertex layout, an optional fragment entry with its targets, the primitive state and
//! an optional depth-stencil state, compiled with the pass's WGSL overrides
//! (`specialize::compile_options`) on both stages; its compute twin [`ComputeStage`]; and the
//! blend states the passes accumulate with.

use crate::common::specialize::compile_options;

/// `operation` over source and destination at full weight (both factors One).
pub const fn one_one(operation: wgpu::BlendOperation) -> wgpu::BlendComponent {
    wgpu::BlendComponent {
        src_factor: wgpu::BlendFactor::One,
        dst_factor: wgpu::BlendFactor::One,
        operation,
    }
}

/// src + dst.
pub const ADD: wgpu::BlendComponent = one_one(wgpu::BlendOperation::Add);
/// dst − src: subtracting a term from what is accumulated.
pub const REVERSE_SUBTRACT: wgpu::BlendComponent = one_one(wgpu::BlendOperation::ReverseSubtract);
/// min(src, dst): the nearest of several depths.
pub const MIN: wgpu::BlendComponent = one_one(wgpu::BlendOperation::Min);
/// max(src, dst): the farthest of several depths.
pub const MAX: wgpu::BlendComponent = one_one(wgpu::BlendOperation::Max);
/// Premultiplied "over": src + (1 − src.a)·dst, for compositing back to front.
pub const OVER: wgpu::BlendComponent = wgpu::BlendComponent {
    src_factor: wgpu::BlendFactor::One,
    dst_factor: wgpu::BlendFactor::OneMinusSrcAlpha,
    operation: wgpu::BlendOperation::Add,
};

/// The same blending of colour and alpha.
pub const fn both(component: wgpu::BlendComponent) -> wgpu::BlendState {
    wgpu::BlendState {
        color: component,
        alpha: component,
    }
}

/// Colour blended by `component`, alpha replaced by the source's.
pub const fn color_only(component: wgpu::BlendComponent) -> wgpu::BlendState {
    wgpu::BlendState {
        color: component,
        alpha: wgpu::BlendComponent::REPLACE,
    }
}

/// Additive blending of colour and alpha: what accumulating passes use.
pub const ADDITIVE: wgpu::BlendState = both(ADD);

/// A colour target writing every channel.
pub fn target(
    format: wgpu::TextureFormat,
    blend: Option<wgpu::BlendState>,
) -> Option<wgpu::ColorTargetState> {
    Some(wgpu::ColorTargetState {
        format,
        blend,
        write_mask: wgpu::ColorWrites::ALL,
    })
}

/// The depth state of a pass that redraws the scene's surfaces over their own depth and must
/// touch exactly the visible surface once (removing a light from it): depth test `Equal`, no
/// depth write. The surface pass's vertex stage writes an `@invariant` position, so the same
/// meshes under the same depth clipping give the very same depth; a biased `LessEqual` also let
/// hidden surfaces just behind the visible one through (the floor under a wall, a sill's top
/// behind its face) and removed their light as well — negative radiance along every seam.
pub fn visible_surface_depth(
    format: wgpu::TextureFormat,
    stencil: wgpu::StencilState,
) -> wgpu::DepthStencilState {
    wgpu::DepthStencilState {
        format,
        depth_write_enabled: Some(false),
        depth_compare: Some(wgpu::CompareFunction::Equal),
        stencil,
        bias: Default::default(),
    }
}

/// A pipeline layout of these bind groups, in order.
pub fn layout(
    device: &wgpu::Device,
    label: &str,
    groups: &[&wgpu::BindGroupLayout],
) -> wgpu::PipelineLayout {
    let groups: Vec<_> = groups.iter().map(|g| Some(*g)).collect();
    device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some(label),
        bind_group_layouts: &groups,
        immediate_size: 0,
    })
}

/// One pass's pipeline, described.
pub struct Stage<'a> {
    pub label: &'a str,
    pub vs: &'a str,
    pub vertices: Option<wgpu::VertexBufferLayout<'a>>,
    /// The fragment entry and its targets; None: depth / stencil only.
    pub fragment: Option<(&'a str, &'a [Option<wgpu::ColorTargetState>])>,
    pub primitive: wgpu::PrimitiveState,
    pub depth: Option<wgpu::DepthStencilState>,
}

impl<'a> Stage<'a> {
    /// Vertex entry `vs`; no vertex buffer, no fragment, triangle lists without culling, no depth.
    pub fn new(label: &'a str, vs: &'a str) -> Self {
        Stage {
            label,
            vs,
            vertices: None,
            fragment: None,
            primitive: wgpu::PrimitiveState {
                cull_mode: None,
                ..Default::default()
            },
            depth: None,
        }
    }

    pub fn vertices(self, layout: wgpu::VertexBufferLayout<'a>) -> Self {
        Stage {
            vertices: Some(layout),
            ..self
        }
    }

    pub fn fragment(self, fs: &'a str, targets: &'a [Option<wgpu::ColorTargetState>]) -> Self {
        Stage {
            fragment: Some((fs, targets)),
            ..self
        }
    }

    pub fn depth(self, state: wgpu::DepthStencilState) -> Self {
        Stage {
            depth: Some(state),
            ..self
        }
    }

    pub fn cull(mut self, face: Option<wgpu::Face>) -> Self {
        self.primitive.cull_mode = face;
        self
    }

    pub fn front_face(mut self, winding: wgpu::FrontFace) -> Self {
        self.primitive.front_face = winding;
        self
    }

    /// Depth clamped instead of clipped at the near and far planes (needs
    /// `Features::DEPTH_CLIP_CONTROL`).
    pub fn unclipped_depth(mut self, unclipped: bool) -> Self {
        self.primitive.unclipped_depth = unclipped;
        self
    }

    /// The pipeline, from `module` under `layout`, with `constants` on both stages.
    pub fn build(
        self,
        device: &wgpu::Device,
        layout: &wgpu::PipelineLayout,
        module: &wgpu::ShaderModule,
        constants: &[(&str, f64)],
    ) -> wgpu::RenderPipeline {
        device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some(self.label),
            layout: Some(layout),
            vertex: wgpu::VertexState {
                module,
                entry_point: Some(self.vs),
                compilation_options: compile_options(constants),
                buffers: &self.vertices.into_iter().map(Some).collect::<Vec<_>>(),
            },
            primitive: self.primitive,
            depth_stencil: self.depth,
            multisample: Default::default(),
            fragment: self.fragment.map(|(fs, targets)| wgpu::FragmentState {
                module,
                entry_point: Some(fs),
                compilation_options: compile_options(constants),
                targets,
            }),
            multiview_mask: None,
            cache: None,
        })
    }
}

/// One compute pass's pipeline, described: the compute twin of [`Stage`].
pub struct ComputeStage<'a> {
    pub label: &'a str,
    pub entry: &'a str,
}

impl<'a> ComputeStage<'a> {
    /// Entry point `entry`, labelled `label`.
    pub fn new(label: &'a str, entry: &'a str) -> Self {
        ComputeStage { label, entry }
    }

    /// The pipeline, from `module` under `layout`, with `constants` (zeroed workgroup memory, as
    /// every stage here).
    pub fn build(
        self,
        device: &wgpu::Device,
        layout: &wgpu::PipelineLayout,
        module: &wgpu::ShaderModule,
        constants: &[(&str, f64)],
    ) -> wgpu::ComputePipeline {
        device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some(self.label),
            layout: Some(layout),
            module,
            entry_point: Some(self.entry),
            compilation_options: compile_options(constants),
            cache: None,
        })
    }
}
