//! biri-polynomial's render pipelines: the depth pre-pass, the z-pass count, the unorm8 first
//! pass, the lit surfaces (per vertex or per fragment), the far-plane grid and the shadow planes
//! under §4.4's stencil rules (one signed pipeline, or an entering / leaving pair for unorm8).

use wgpu::{CompareFunction as C, StencilOperation as S};

use super::types::{Accumulate, Config, Eval};
use crate::common::gpu_scene::Vertex;
use crate::common::pipeline::{ADDITIVE, REVERSE_SUBTRACT, Stage, both};
use crate::common::shadow_volumes::stencil::{self, PipelineBuilder};

pub(super) struct Pipelines {
    pub depth: wgpu::RenderPipeline,
    pub count: wgpu::RenderPipeline,
    pub first: wgpu::RenderPipeline,
    pub surface: wgpu::RenderPipeline,
    pub grid: wgpu::RenderPipeline,
    /// Float: one pipeline (signed output). unorm8: [entering (add), leaving (reverse subtract)].
    pub planes: Vec<wgpu::RenderPipeline>,
}

/// The passes' builder: every stage draws into the accumulation target (or none).
struct Builder<'a> {
    inner: PipelineBuilder<'a>,
    acc_format: wgpu::TextureFormat,
}

impl Builder<'_> {
    /// One pipeline: vertex entry and buffer, optional (fragment entry, blend), depth-stencil.
    fn pipe(
        &self,
        label: &str,
        vs: &str,
        vertices: Option<wgpu::VertexBufferLayout>,
        fs: Option<(&str, wgpu::BlendState)>,
        depth: wgpu::DepthStencilState,
    ) -> wgpu::RenderPipeline {
        let targets = [fs.map(|(_, b)| wgpu::ColorTargetState {
            format: self.acc_format,
            blend: Some(b),
            write_mask: wgpu::ColorWrites::ALL,
        })];
        let mut stage = Stage::new(label, vs).depth(depth);
        if let Some(layout) = vertices {
            stage = stage.vertices(layout);
        }
        if let Some((fs, _)) = fs {
            stage = stage.fragment(fs, &targets);
        }
        self.inner.build(stage)
    }
}

impl Pipelines {
    /// `layouts`: the renderer's group 0 and the passes' group 1.
    pub fn new(
        device: &wgpu::Device,
        layouts: [&wgpu::BindGroupLayout; 2],
        module: &wgpu::ShaderModule,
        constants: &[(&'static str, f64)],
        acc_format: wgpu::TextureFormat,
        cfg: &Config,
    ) -> Pipelines {
        let b = Builder {
            inner: PipelineBuilder::new(device, "biri-poly passes", layouts, module, constants),
            acc_format,
        };
        let ds = stencil::depth_stencil;
        let keep = stencil::face(C::Always, S::Keep, S::Keep);
        let add = ADDITIVE;
        // z-pass count: entering a volume (front face) +1, leaving (back face) −1.
        let count_faces = (
            stencil::face(C::Always, S::IncrementWrap, S::IncrementWrap),
            stencil::face(C::Always, S::DecrementWrap, S::DecrementWrap),
        );
        Pipelines {
            depth: b.pipe(
                "biri-poly depth",
                "vs_scene",
                Some(Vertex::LAYOUT),
                None,
                ds(C::Less, true, keep, keep),
            ),
            count: b.pipe(
                "biri-poly count",
                "vs_plane",
                Some(stencil::PLANE_LAYOUT),
                None,
                ds(C::Less, false, count_faces.0, count_faces.1),
            ),
            first: b.pipe(
                "biri-poly first pass",
                "vs_fullscreen",
                None,
                Some(("fs_first_pass", add)),
                ds(C::Always, false, keep, keep),
            ),
            surface: surface(&b, cfg.eval),
            grid: grid(&b),
            planes: planes(&b, cfg),
        }
    }
}

/// Lit points: stencil == reference 0; Γ per vertex of the tessellated scene or per fragment.
fn surface(b: &Builder, eval: Eval) -> wgpu::RenderPipeline {
    let lit = stencil::face(C::Equal, S::Keep, S::Keep);
    let add = ADDITIVE;
    match eval {
        Eval::Vertex => b.pipe(
            "biri-poly surfaces (vertex)",
            "vs_scene_gouraud",
            Some(Vertex::LAYOUT),
            Some(("fs_gouraud", add)),
            stencil::depth_stencil(C::LessEqual, false, lit, lit),
        ),
        Eval::Fragment => b.pipe(
            "biri-poly surfaces (fragment)",
            "vs_fullscreen",
            None,
            Some(("fs_surface_frag", add)),
            stencil::depth_stencil(C::Always, false, lit, lit),
        ),
    }
}

/// The far plane's Gouraud grid (vertex evaluation), lit where the stencil is 0.
fn grid(b: &Builder) -> wgpu::RenderPipeline {
    let lit = stencil::face(C::Equal, S::Keep, S::Keep);
    let grid_layout = wgpu::VertexBufferLayout {
        array_stride: 8,
        step_mode: wgpu::VertexStepMode::Vertex,
        attributes: &wgpu::vertex_attr_array![0 => Float32x2],
    };
    b.pipe(
        "biri-poly far grid",
        "vs_far_grid",
        Some(grid_layout),
        Some(("fs_gouraud", ADDITIVE)),
        stencil::depth_stencil(C::LessEqual, false, lit, lit),
    )
}

/// The shadow planes. §4.4 with reference 1, front to back: an entering (front) face counts when
/// the stencil is 0 (1 > s), a leaving (back) face when it is 1; entering always +1, leaving −1.
fn planes(b: &Builder, cfg: &Config) -> Vec<wgpu::RenderPipeline> {
    let (enter, leave) = if cfg.stencil_rules {
        (
            stencil::face(C::Greater, S::IncrementWrap, S::IncrementWrap),
            stencil::face(C::Equal, S::DecrementWrap, S::DecrementWrap),
        )
    } else {
        (
            stencil::face(C::Always, S::IncrementWrap, S::IncrementWrap),
            stencil::face(C::Always, S::DecrementWrap, S::DecrementWrap),
        )
    };
    let (vs, fs) = match cfg.eval {
        Eval::Vertex => ("vs_plane_gouraud", "fs_plane_gouraud"),
        Eval::Fragment => ("vs_plane", "fs_plane_frag"),
    };
    let ds = stencil::depth_stencil;
    let add = ADDITIVE;
    let layout = || Some(stencil::PLANE_LAYOUT);
    match cfg.accumulate {
        Accumulate::Float => vec![b.pipe(
            "biri-poly planes",
            vs,
            layout(),
            Some((fs, add)),
            ds(C::Less, false, enter, leave),
        )],
        // One pipeline per side (the CPU knows each planar quad's side): the blend operation
        // differs, and a unorm target cannot hold a negative output.
        Accumulate::Unorm8 => vec![
            b.pipe(
                "biri-poly entering planes",
                vs,
                layout(),
                Some((fs, add)),
                ds(C::Less, false, enter, enter),
            ),
            b.pipe(
                "biri-poly leaving planes",
                vs,
                layout(),
                Some((fs, both(REVERSE_SUBTRACT))),
                ds(C::Less, false, leave, leave),
            ),
        ],
    }
}
