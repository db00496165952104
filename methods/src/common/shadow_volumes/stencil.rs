//! Pipeline state of stencil shadow-volume passes, shared by the methods that draw shadow planes
//! into a depth-stencil buffer (both Biri methods, `common::shadow_volumes::stencil_surfaces`).

use glam::Vec3;

use crate::common::pipeline::{self, Stage};

/// The depth-stencil format of every shadow-plane pass.
pub const DEPTH_STENCIL: wgpu::TextureFormat = wgpu::TextureFormat::Depth24PlusStencil8;

/// Shadow-plane vertices ([`PlaneVertex`]): world position, the unit normal of the plane.
pub const PLANE_LAYOUT: wgpu::VertexBufferLayout<'static> = wgpu::VertexBufferLayout {
    array_stride: std::mem::size_of::<PlaneVertex>() as u64,
    step_mode: wgpu::VertexStepMode::Vertex,
    attributes: &wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3],
};

/// The WGSL side of [`PLANE_LAYOUT`]: `vs_plane`, its output `PlaneFrag` and `plane_distance`
/// (where a fragment's pixel ray crosses its plane, exact whatever the rasteriser's sub-pixel
/// precision). Needs PRELUDE.
pub const PLANE_WGSL: &str = include_str!("shadow_plane.wgsl");

/// One shadow-plane vertex as [`PLANE_LAYOUT`] reads it.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct PlaneVertex {
    pub position: [f32; 3],
    /// The unit normal of the vertex's plane.
    pub normal: [f32; 3],
}

impl PlaneVertex {
    /// `points` on the quad [p, q, q', p, q', p'] (`silhouette::extrude`), each with the quad's
    /// unit normal, taken across its edge q − p and its extrusion p' − p: both are accurate to
    /// rounding, where the long near-parallel diagonals of a short edge's quad are not.
    pub fn on_quad(
        quad: &[Vec3; 6],
        points: impl IntoIterator<Item = Vec3>,
    ) -> impl Iterator<Item = PlaneVertex> {
        let normal = (quad[1] - quad[0])
            .cross(quad[5] - quad[0])
            .normalize_or_zero()
            .to_array();
        points.into_iter().map(move |p| PlaneVertex {
            position: p.to_array(),
            normal,
        })
    }
}

/// One face's stencil test: `pass` where stencil and depth tests pass, `fail` where the stencil
/// test fails (applied with no depth test), the stencil kept where only the depth test fails.
pub fn face(
    compare: wgpu::CompareFunction,
    pass: wgpu::StencilOperation,
    fail: wgpu::StencilOperation,
) -> wgpu::StencilFaceState {
    wgpu::StencilFaceState {
        compare,
        fail_op: fail,
        depth_fail_op: wgpu::StencilOperation::Keep,
        pass_op: pass,
    }
}

/// A `DEPTH_STENCIL` state with full stencil masks and no depth bias (a test that never reads
/// the reference as [`reads_reference`] words it).
pub fn depth_stencil(
    compare: wgpu::CompareFunction,
    write: bool,
    front: wgpu::StencilFaceState,
    back: wgpu::StencilFaceState,
) -> wgpu::DepthStencilState {
    wgpu::DepthStencilState {
        format: DEPTH_STENCIL,
        depth_write_enabled: Some(write),
        depth_compare: Some(compare),
        stencil: reads_reference(wgpu::StencilState {
            front,
            back,
            read_mask: 0xff,
            write_mask: 0xff,
        }),
        bias: Default::default(),
    }
}

/// The same stencil test, worded so that it reads the reference. wgpu 30 makes the stencil
/// reference dynamic state of every Vulkan pipeline (wgpu-hal `vulkan/device.rs`,
/// `create_render_pipeline`) but sets it only when a pipeline whose test reads it is bound
/// (wgpu-core `device/resource.rs`, `PipelineFlags::STENCIL_REFERENCE` from `needs_ref_value`;
/// `command/render.rs`, `set_pipeline`). A counting pass (faces `Always`, ops `IncrementWrap` /
/// `DecrementWrap`) drawn before any such pipeline in its command buffer then draws with the
/// reference unset: undefined state that the Khronos validation layer reports
/// (VUID-vkCmdDraw-commandBuffer-02701, which layer 1.3.239 mislabels
/// VK_DYNAMIC_STATE_LINE_WIDTH). `Always` is `Equal` under a zero read mask (0 = 0), which does
/// read the reference, so wgpu sets it; nothing else changes. A test that already reads it, or
/// no test at all (both faces `IGNORE`), is returned as it is.
pub fn reads_reference(state: wgpu::StencilState) -> wgpu::StencilState {
    let always = |f: &wgpu::StencilFaceState| f.compare == wgpu::CompareFunction::Always;
    if !state.is_enabled()
        || state.needs_ref_value()
        || !always(&state.front)
        || !always(&state.back)
    {
        return state;
    }
    let equal = |f: wgpu::StencilFaceState| wgpu::StencilFaceState {
        compare: wgpu::CompareFunction::Equal,
        ..f
    };
    wgpu::StencilState {
        front: equal(state.front),
        back: equal(state.back),
        read_mask: 0,
        ..state
    }
}

/// Builds a shadow-plane method's render pipelines from one module and one layout (the
/// renderer's group 0 and the method's group 1), with the method's overrides.
pub struct PipelineBuilder<'a> {
    device: &'a wgpu::Device,
    layout: wgpu::PipelineLayout,
    module: &'a wgpu::ShaderModule,
    constants: &'a [(&'static str, f64)],
}

impl<'a> PipelineBuilder<'a> {
    /// `groups`: the bind group layouts, group 0 first (the renderer's frame group, the
    /// method's group 1, and for the crossing-list passes
    /// `common::shadow_volumes::crossing_lists`' group 2).
    pub fn new<const N: usize>(
        device: &'a wgpu::Device,
        label: &str,
        groups: [&wgpu::BindGroupLayout; N],
        module: &'a wgpu::ShaderModule,
        constants: &'a [(&'static str, f64)],
    ) -> Self {
        PipelineBuilder {
            device,
            layout: pipeline::layout(device, label, &groups),
            module,
            constants,
        }
    }

    pub fn build(&self, stage: Stage) -> wgpu::RenderPipeline {
        // silhouette::extrude winds quads outward in a right-handed sense, which wgpu's y-up
        // clip space rasterises clockwise: "front" (entering a shadow) is Cw here.
        stage
            .front_face(wgpu::FrontFace::Cw)
            .unclipped_depth(near_plane_safe(self.device))
            .build(self.device, &self.layout, self.module, self.constants)
    }
}

/// Whether shadow planes can be drawn with depth clamping instead of near/far clipping
/// (Everitt & Kilgard 2002): a plane crossing between the eye and the near plane is then still
/// rasterised (at depth 0) and counted, so z-pass counts seeded with the eye's count stay exact
/// with the camera anywhere. Without the feature such crossings are lost (ARCHITECTURE §6).
pub fn near_plane_safe(device: &wgpu::Device) -> bool {
    device
        .features()
        .contains(wgpu::Features::DEPTH_CLIP_CONTROL)
}

#[cfg(test)]
mod tests {
    use super::*;
    use wgpu::{CompareFunction as C, StencilOperation as S};

    /// Whether `face`'s test passes for the value `stencil` against the reference `reference`,
    /// both through `state`'s read mask.
    fn passes(
        state: &wgpu::StencilState,
        face: &wgpu::StencilFaceState,
        reference: u32,
        stencil: u32,
    ) -> bool {
        let (r, s) = (reference & state.read_mask, stencil & state.read_mask);
        match face.compare {
            C::Always => true,
            C::Equal => r == s,
            C::NotEqual => r != s,
            other => panic!("not expected here: {other:?}"),
        }
    }

    /// A counting test (both faces `Always`) comes back reading the reference — what makes wgpu
    /// set it — and passing whatever the reference and the stencil, with the same operations.
    #[test]
    fn a_counting_test_reads_the_reference_and_still_always_passes() {
        let ds = depth_stencil(
            C::Less,
            false,
            face(C::Always, S::IncrementWrap, S::Keep),
            face(C::Always, S::DecrementWrap, S::Keep),
        );
        let st = &ds.stencil;
        assert!(st.is_enabled() && st.needs_ref_value());
        assert_eq!(
            (st.front.pass_op, st.back.pass_op),
            (S::IncrementWrap, S::DecrementWrap)
        );
        assert_eq!(st.write_mask, 0xff);
        for (reference, stencil) in [(0, 0), (0, 1), (1, 0), (1, 255), (3, 7)] {
            assert!(passes(st, &st.front, reference, stencil));
            assert!(passes(st, &st.back, reference, stencil));
        }
    }

    /// A test that reads the reference already, and no test at all, are left as they are.
    #[test]
    fn other_tests_are_unchanged() {
        let keep = face(C::Always, S::Keep, S::Keep);
        let equal = face(C::Equal, S::Keep, S::Keep);
        for (front, back) in [(keep, keep), (equal, equal), (equal, keep)] {
            let ds = depth_stencil(C::Less, false, front, back);
            assert_eq!((ds.stencil.front, ds.stencil.back), (front, back));
            assert_eq!(ds.stencil.read_mask, 0xff);
        }
    }
}
