//! wyman-hybrid's shadow volumes (§3.1): the quads extruded from the casters' silhouettes as
//! seen from each light, and the pipeline that rasterises them from the eye into the nearest and
//! farthest polygon distance per pixel.

use glam::Vec3;
use harness::Gpu;
use scenes::{FrameState, LightState};

use super::{State, VOLUME_FORMAT, VolumeVertex, volumes_source};
use crate::common::gpu_scene::mesh_pipeline_with;
use crate::common::renderer::SceneRenderer;
use crate::common::silhouette::{LightPos, extrude};
use crate::common::wgsl;

/// The pipeline that draws the shadow-volume quads from the eye into the nearest (min blending)
/// and farthest (max blending) polygon distance per pixel, one channel per light.
pub(super) fn pipeline(gpu: &Gpu, renderer: &SceneRenderer) -> wgpu::RenderPipeline {
    let module = wgsl::module(&gpu.device, "shadow volumes", &volumes_source());
    let layout = gpu
        .device
        .create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("shadow volumes"),
            bind_group_layouts: &[Some(&renderer.frame_layout)],
            immediate_size: 0,
        });
    let blend = |op| wgpu::BlendState {
        color: wgpu::BlendComponent {
            src_factor: wgpu::BlendFactor::One,
            dst_factor: wgpu::BlendFactor::One,
            operation: op,
        },
        alpha: wgpu::BlendComponent {
            src_factor: wgpu::BlendFactor::One,
            dst_factor: wgpu::BlendFactor::One,
            operation: op,
        },
    };
    let targets = [
        Some(wgpu::ColorTargetState {
            format: VOLUME_FORMAT,
            blend: Some(blend(wgpu::BlendOperation::Min)),
            write_mask: wgpu::ColorWrites::ALL,
        }),
        Some(wgpu::ColorTargetState {
            format: VOLUME_FORMAT,
            blend: Some(blend(wgpu::BlendOperation::Max)),
            write_mask: wgpu::ColorWrites::ALL,
        }),
    ];
    let vertex_layout = wgpu::VertexBufferLayout {
        array_stride: std::mem::size_of::<VolumeVertex>() as u64,
        step_mode: wgpu::VertexStepMode::Vertex,
        attributes: &wgpu::vertex_attr_array![0 => Float32x3, 1 => Uint32],
    };
    mesh_pipeline_with(
        &gpu.device,
        "shadow volumes",
        &layout,
        &module,
        vertex_layout,
        None,
        &targets,
        &[],
    )
}

/// Silhouettes of every caster from every light, extruded past everything visible.
pub(super) fn build(gpu: &Gpu, st: &mut State, frame: &FrameState) {
    let cam = frame.camera.position;
    let mut verts: Vec<VolumeVertex> = Vec::new();
    let mut edges = 0;
    for (k, light) in frame.lights.iter().enumerate() {
        let pos = match light {
            LightState::Directional { direction, .. } => LightPos::Direction(*direction),
            _ => LightPos::Point(light.position().expect("local light")),
        };
        let reach =
            2.0 * (frame.camera.far + light.position().map_or(0.0, |p| (p - cam).length())) + 1.0;
        for (obj, mesh) in &st.casters {
            for e in mesh.silhouette(&frame.world_from_local[*obj], pos) {
                edges += 1;
                verts.extend(extrude(e, pos, reach).map(|p: Vec3| VolumeVertex {
                    position: p.to_array(),
                    light: k as u32,
                }));
            }
        }
    }
    st.silhouette_edges = edges;
    st.vertex_count = verts.len() as u32;
    if verts.is_empty() {
        return;
    }
    let bytes: &[u8] = bytemuck::cast_slice(&verts);
    let fits = st
        .vertex_buffer
        .as_ref()
        .is_some_and(|b| b.size() >= bytes.len() as u64);
    if !fits {
        st.vertex_buffer = Some(gpu.buffer(&wgpu::BufferDescriptor {
            label: Some("shadow-volume quads"),
            size: (bytes.len() as u64).next_power_of_two(),
            usage: wgpu::BufferUsages::VERTEX | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        }));
    }
    gpu.queue.write_buffer(
        st.vertex_buffer.as_ref().expect("allocated above"),
        0,
        bytes,
    );
}
