//! The render pipelines of the shadow planes: the scene depth, and the stencil resolve's passes
//! (z-pass count, lit surfaces, planes under step 5's rules in float or the paper's unorm8, the
//! stencil step after each plane).

use wgpu::{CompareFunction as C, StencilOperation as S};

use super::types::Options;
use crate::common::gpu_scene::Vertex;
use crate::common::pipeline::{ADD, REVERSE_SUBTRACT, Stage, color_only};
use crate::common::shadow_volumes::stencil::{self, PLANE_LAYOUT, PipelineBuilder};

/// The plane pipelines of the stencil resolve.
pub(super) struct StencilPipes {
    pub count: wgpu::RenderPipeline,
    pub surface: wgpu::RenderPipeline,
    /// Float, every crossing: all planes in one draw.
    pub all: wgpu::RenderPipeline,
    /// Per-plane draws: the colour pipelines (one, or front/back for unorm8) ...
    pub color: Vec<wgpu::RenderPipeline>,
    /// ... and, with the rules, the stencil step after each plane's colour.
    pub step: Option<wgpu::RenderPipeline>,
}

/// Colour blended by `component` (alpha replaced) into the accumulation target.
fn color(
    format: wgpu::TextureFormat,
    component: wgpu::BlendComponent,
    writes: wgpu::ColorWrites,
) -> [Option<wgpu::ColorTargetState>; 1] {
    [Some(wgpu::ColorTargetState {
        format,
        blend: Some(color_only(component)),
        write_mask: writes,
    })]
}

/// The scene's depth (stencil kept), before any plane pass.
pub(super) fn depth_pipe(b: &PipelineBuilder) -> wgpu::RenderPipeline {
    let keep = stencil::face(C::Always, S::Keep, S::Keep);
    b.build(
        Stage::new("biri scene depth", "vs_scene")
            .vertices(Vertex::LAYOUT)
            .depth(stencil::depth_stencil(C::Less, true, keep, keep)),
    )
}

/// A plane stage (`vs_plane`) with an optional fragment.
fn plane<'a>(
    label: &'a str,
    fragment: Option<(&'a str, &'a [Option<wgpu::ColorTargetState>])>,
    cull: Option<wgpu::Face>,
    depth: wgpu::DepthStencilState,
) -> Stage<'a> {
    let stage = Stage::new(label, "vs_plane")
        .vertices(PLANE_LAYOUT)
        .cull(cull)
        .depth(depth);
    match fragment {
        Some((fs, targets)) => stage.fragment(fs, targets),
        None => stage,
    }
}

impl StencilPipes {
    pub fn new(b: &PipelineBuilder, opts: &Options, acc_format: wgpu::TextureFormat) -> Self {
        let ds = stencil::depth_stencil;
        let keep = stencil::face(C::Always, S::Keep, S::Keep);
        let all_writes = wgpu::ColorWrites::ALL;
        let add = color(acc_format, ADD, all_writes);
        // z-pass count: entering a volume (front face) +1, leaving (back face) −1.
        let count = b.build(plane(
            "biri plane count",
            None,
            None,
            ds(
                C::Less,
                false,
                stencil::face(C::Always, S::IncrementWrap, S::Keep),
                stencil::face(C::Always, S::DecrementWrap, S::Keep),
            ),
        ));
        // Lit ray ends: stencil == reference 0.
        let equal = stencil::face(C::Equal, S::Keep, S::Keep);
        let surface_fs = if opts.unorm8 {
            "fs_surface_full"
        } else {
            "fs_surface"
        };
        let surface = b.build(
            Stage::new("biri lit surfaces", "vs_fullscreen")
                .fragment(surface_fs, &add)
                .depth(ds(C::Always, false, equal, equal)),
        );
        // Every crossing, float: one draw, order irrelevant.
        let all = b.build(plane(
            "biri planes",
            Some(("fs_plane", &add)),
            None,
            ds(C::Less, false, keep, keep),
        ));
        StencilPipes {
            count,
            surface,
            all,
            color: color_pipes(b, opts, acc_format),
            step: opts.rules.then(|| step_pipe(b, acc_format)),
        }
    }
}

/// Step 5 with reference 1: a front face (its far side, where the walk from the visible point
/// towards the eye comes from, is in shadow) counts on stencil == 1, a back face on stencil == 0
/// (1 > stencil). The stencil itself is stepped by a second draw of the same plane (`step_pipe`),
/// because a stencil op on a failed stencil test cannot be told apart from one on a plane behind
/// the visible point (the test comes before the depth test).
fn color_pipes(
    b: &PipelineBuilder,
    opts: &Options,
    acc_format: wgpu::TextureFormat,
) -> Vec<wgpu::RenderPipeline> {
    let keep = stencil::face(C::Always, S::Keep, S::Keep);
    let test = |cmp| {
        if opts.rules {
            stencil::face(cmp, S::Keep, S::Keep)
        } else {
            keep
        }
    };
    let tested = stencil::depth_stencil(C::Less, false, test(C::Equal), test(C::Greater));
    let all_writes = wgpu::ColorWrites::ALL;
    let add = color(acc_format, ADD, all_writes);
    if !opts.unorm8 {
        return vec![b.build(plane("biri planes", Some(("fs_plane", &add)), None, tested))];
    }
    // The paper's blending: front faces add, back faces reverse-subtract, L_dss from the eye.
    let subtract = color(acc_format, REVERSE_SUBTRACT, all_writes);
    vec![
        b.build(plane(
            "biri planes front",
            Some(("fs_plane_full", &add)),
            Some(wgpu::Face::Back),
            tested.clone(),
        )),
        b.build(plane(
            "biri planes back",
            Some(("fs_plane_full", &subtract)),
            Some(wgpu::Face::Front),
            tested,
        )),
    ]
}

/// Walking from the visible point towards the eye: a front face leaves a volume (−1), a back
/// face enters one (+1); planes behind the visible point fail the depth test. No colour written.
fn step_pipe(b: &PipelineBuilder, acc_format: wgpu::TextureFormat) -> wgpu::RenderPipeline {
    let none = color(acc_format, ADD, wgpu::ColorWrites::empty());
    b.build(plane(
        "biri plane stencil step",
        Some(("fs_plane", &none)),
        None,
        stencil::depth_stencil(
            C::Less,
            false,
            stencil::face(C::Always, S::DecrementWrap, S::Keep),
            stencil::face(C::Always, S::IncrementWrap, S::Keep),
        ),
    ))
}
