//! Render-pass attachments as every pass writes them: loaded or cleared, stored — except a
//! depth buffer a pass only tests against and nothing reads after it ([`depth_scratch_attachment`]).

/// A colour attachment of `view`: `load` (e.g. `LoadOp::Load`, or a clear), stored.
pub fn color_attachment(
    view: &wgpu::TextureView,
    load: wgpu::LoadOp<wgpu::Color>,
) -> Option<wgpu::RenderPassColorAttachment<'_>> {
    Some(wgpu::RenderPassColorAttachment {
        view,
        depth_slice: None,
        resolve_target: None,
        ops: wgpu::Operations {
            load,
            store: wgpu::StoreOp::Store,
        },
    })
}

/// A depth attachment of `view` (a format without stencil): loaded or cleared, stored.
pub fn depth_attachment(
    view: &wgpu::TextureView,
    depth: wgpu::LoadOp<f32>,
) -> wgpu::RenderPassDepthStencilAttachment<'_> {
    depth_only(view, depth, wgpu::StoreOp::Store)
}

/// A depth attachment of `view` (a format without stencil) that only serves this pass's depth
/// test: loaded or cleared, then discarded (nothing reads it after the pass).
pub fn depth_scratch_attachment(
    view: &wgpu::TextureView,
    depth: wgpu::LoadOp<f32>,
) -> wgpu::RenderPassDepthStencilAttachment<'_> {
    depth_only(view, depth, wgpu::StoreOp::Discard)
}

fn depth_only(
    view: &wgpu::TextureView,
    load: wgpu::LoadOp<f32>,
    store: wgpu::StoreOp,
) -> wgpu::RenderPassDepthStencilAttachment<'_> {
    wgpu::RenderPassDepthStencilAttachment {
        view,
        depth_ops: Some(wgpu::Operations { load, store }),
        stencil_ops: None,
    }
}

/// A depth-stencil attachment of `view`: depth and stencil each loaded or cleared, both stored.
pub fn depth_stencil_attachment(
    view: &wgpu::TextureView,
    depth: wgpu::LoadOp<f32>,
    stencil: wgpu::LoadOp<u32>,
) -> wgpu::RenderPassDepthStencilAttachment<'_> {
    let store = wgpu::StoreOp::Store;
    wgpu::RenderPassDepthStencilAttachment {
        view,
        depth_ops: Some(wgpu::Operations { load: depth, store }),
        stencil_ops: Some(wgpu::Operations {
            load: stencil,
            store,
        }),
    }
}
