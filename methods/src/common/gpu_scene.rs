//! The scene's geometry on the GPU: one vertex and index buffer for all objects (local space,
//! each vertex tagged with its object), and a storage buffer of per-object transforms and
//! materials updated each frame.

use bytemuck::{Pod, Zeroable};
use glam::Mat3;
use harness::Gpu;
use scenes::{FrameState, Scene};

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
pub struct Vertex {
    pub position: [f32; 3],
    pub object: u32,
    pub normal: [f32; 3],
    pub _pad: u32,
}

impl Vertex {
    pub const LAYOUT: wgpu::VertexBufferLayout<'static> = wgpu::VertexBufferLayout {
        array_stride: std::mem::size_of::<Vertex>() as u64,
        step_mode: wgpu::VertexStepMode::Vertex,
        attributes: &wgpu::vertex_attr_array![0 => Float32x3, 1 => Uint32, 2 => Float32x3],
    };
}

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
pub struct ObjectData {
    pub world_from_local: [[f32; 4]; 4],
    pub normal_from_local: [[f32; 4]; 4],
    pub albedo: [f32; 4],
    pub phong: [f32; 4],
}

/// One object's index range.
#[derive(Clone, Copy, Debug)]
pub struct Draw {
    pub first_index: u32,
    pub index_count: u32,
    pub casts_shadow: bool,
}

pub struct GpuScene {
    pub vertices: wgpu::Buffer,
    pub indices: wgpu::Buffer,
    pub objects: wgpu::Buffer,
    pub draws: Vec<Draw>,
    object_count: usize,
}

impl GpuScene {
    /// Binds the scene's vertex and index buffers and draws every object (pipeline and bind
    /// groups are the caller's).
    pub fn draw(&self, pass: &mut wgpu::RenderPass<'_>) {
        pass.set_vertex_buffer(0, self.vertices.slice(..));
        pass.set_index_buffer(self.indices.slice(..), wgpu::IndexFormat::Uint32);
        for d in &self.draws {
            pass.draw_indexed(d.first_index..d.first_index + d.index_count, 0, 0..1);
        }
    }

    pub fn new(gpu: &Gpu, scene: &Scene) -> GpuScene {
        let mut verts = Vec::new();
        let mut idx = Vec::new();
        let mut draws = Vec::new();
        for (k, (mesh, obj)) in scene.meshes.iter().zip(&scene.desc.objects).enumerate() {
            let base = verts.len() as u32;
            let first = idx.len() as u32;
            for (p, n) in mesh.positions.iter().zip(&mesh.normals) {
                verts.push(Vertex {
                    position: p.to_array(),
                    object: k as u32,
                    normal: n.to_array(),
                    _pad: 0,
                });
            }
            for t in &mesh.indices {
                idx.extend(t.iter().map(|i| base + i));
            }
            draws.push(Draw {
                first_index: first,
                index_count: idx.len() as u32 - first,
                casts_shadow: obj.casts_volumetric_shadow,
            });
        }
        if verts.is_empty() {
            // wgpu refuses zero-sized vertex buffers; a scene without objects draws nothing.
            verts.push(Vertex::zeroed());
            idx.extend([0u32; 3]);
        }
        let n = scene.meshes.len().max(1);
        GpuScene {
            vertices: gpu.buffer_init(
                "scene vertices",
                bytemuck::cast_slice(&verts),
                wgpu::BufferUsages::VERTEX,
            ),
            indices: gpu.buffer_init(
                "scene indices",
                bytemuck::cast_slice(&idx),
                wgpu::BufferUsages::INDEX,
            ),
            objects: gpu.buffer(&wgpu::BufferDescriptor {
                label: Some("scene objects"),
                size: (n * std::mem::size_of::<ObjectData>()) as u64,
                usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            }),
            draws,
            object_count: scene.meshes.len(),
        }
    }

    /// Writes this frame's transforms and materials.
    pub fn update(&self, gpu: &Gpu, scene: &Scene, frame: &FrameState) {
        if self.object_count == 0 {
            return;
        }
        let data: Vec<ObjectData> = scene
            .desc
            .objects
            .iter()
            .zip(&frame.world_from_local)
            .map(|(o, world)| {
                let nm = Mat3::from_mat4(*world).inverse().transpose();
                let mat = &o.material;
                ObjectData {
                    world_from_local: world.to_cols_array_2d(),
                    normal_from_local: glam::Mat4::from_mat3(nm).to_cols_array_2d(),
                    albedo: mat
                        .albedo
                        .extend(if mat.two_sided { 1.0 } else { 0.0 })
                        .to_array(),
                    phong: mat
                        .phong
                        .as_ref()
                        .map_or([0.0; 4], |p| p.ks.extend(p.shininess).to_array()),
                }
            })
            .collect();
        gpu.queue
            .write_buffer(&self.objects, 0, bytemuck::cast_slice(&data));
    }

    pub fn has_casters(&self) -> bool {
        self.draws
            .iter()
            .any(|d| d.casts_shadow && d.index_count > 0)
    }
}

/// A depth-tested (Depth32Float, less), uncull'd pipeline drawing the scene's vertex buffer with
/// `vs`/`fs` of `module`: what the shadow-map and surface passes share. `constants`: the
/// pipeline-overridable constants (`common::specialize`), or none.
pub fn mesh_pipeline(
    device: &wgpu::Device,
    label: &str,
    layout: &wgpu::PipelineLayout,
    module: &wgpu::ShaderModule,
    targets: &[Option<wgpu::ColorTargetState>],
    constants: &[(&str, f64)],
) -> wgpu::RenderPipeline {
    let depth = wgpu::DepthStencilState {
        format: wgpu::TextureFormat::Depth32Float,
        depth_write_enabled: Some(true),
        depth_compare: Some(wgpu::CompareFunction::Less),
        stencil: Default::default(),
        bias: Default::default(),
    };
    crate::common::pipeline::Stage::new(label, "vs")
        .vertices(Vertex::LAYOUT)
        .fragment("fs", targets)
        .depth(depth)
        .build(device, layout, module, constants)
}

/// Writes `bytes` to the vertex buffer in `slot`, first replacing it with one of the next power
/// of two in size when it is missing or too small: for vertices rebuilt on the CPU per frame
/// (shadow planes, shadow-volume quads), so a buffer is allocated only when a frame outgrows it.
pub fn write_vertices(gpu: &Gpu, slot: &mut Option<wgpu::Buffer>, label: &str, bytes: &[u8]) {
    let fits = slot
        .as_ref()
        .is_some_and(|b| b.size() >= bytes.len() as u64);
    if !fits {
        *slot = Some(gpu.buffer(&wgpu::BufferDescriptor {
            label: Some(label),
            size: (bytes.len() as u64).next_power_of_two(),
            usage: wgpu::BufferUsages::VERTEX | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        }));
    }
    let buffer = slot.as_ref().expect("allocated above");
    gpu.queue.write_buffer(buffer, 0, bytes);
}
