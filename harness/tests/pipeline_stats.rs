//! Work counts (pipeline statistics) against counts known from the draw and dispatch calls
//! themselves: a compute dispatch runs exactly workgroups × workgroup size invocations, a
//! non-indexed 6-vertex draw runs its vertex shader 6 times and produces two triangles, and
//! two triangles covering the whole target run the fragment shader at least once per pixel.
//! Skips without an adapter, fails with `CI` set.

use harness::testing::gpu_or_skip;

const SHADER: &str = r#"
@vertex fn vs(@builtin(vertex_index) i: u32) -> @builtin(position) vec4<f32> {
    // Two triangles covering exactly the viewport (on the clip boundary: nothing to clip).
    var corners = array<vec2<f32>, 6>(
        vec2<f32>(-1.0, -1.0), vec2<f32>(1.0, -1.0), vec2<f32>(1.0, 1.0),
        vec2<f32>(-1.0, -1.0), vec2<f32>(1.0, 1.0), vec2<f32>(-1.0, 1.0));
    return vec4<f32>(corners[i], 0.0, 1.0);
}
@fragment fn fs() -> @location(0) vec4<f32> { return vec4<f32>(1.0); }

@group(0) @binding(0) var<storage, read_write> sink: array<u32>;
@compute @workgroup_size(8, 8, 1) fn cs(@builtin(global_invocation_id) id: vec3<u32>) {
    sink[id.y * 64u + id.x] = 1u;
}
"#;

const SIZE: u32 = 64;

#[test]
fn counted_passes_report_the_work_of_their_draws_and_dispatches() {
    let Some(gpu) = gpu_or_skip() else { return };
    if !gpu.counts_work() {
        assert!(
            std::env::var_os("CI").is_none() || !gpu.summary.software,
            "lavapipe has pipeline statistics queries; the device was opened without them"
        );
        eprintln!("skipping: the adapter has no pipeline statistics queries");
        return;
    }
    let device = &gpu.device;
    let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some("stats test"),
        source: wgpu::ShaderSource::Wgsl(SHADER.into()),
    });
    let format = wgpu::TextureFormat::Rgba8Unorm;
    let draw = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some("stats draw"),
        layout: None,
        vertex: wgpu::VertexState {
            module: &module,
            entry_point: Some("vs"),
            compilation_options: Default::default(),
            buffers: &[],
        },
        primitive: Default::default(),
        depth_stencil: None,
        multisample: Default::default(),
        fragment: Some(wgpu::FragmentState {
            module: &module,
            entry_point: Some("fs"),
            compilation_options: Default::default(),
            targets: &[Some(format.into())],
        }),
        multiview_mask: None,
        cache: None,
    });
    let dispatch = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: Some("stats dispatch"),
        layout: None,
        module: &module,
        entry_point: Some("cs"),
        compilation_options: Default::default(),
        cache: None,
    });
    let sink = gpu.buffer(&wgpu::BufferDescriptor {
        label: Some("sink"),
        size: 4 * 64 * 64,
        usage: wgpu::BufferUsages::STORAGE,
        mapped_at_creation: false,
    });
    let bind = device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: None,
        layout: &dispatch.get_bind_group_layout(0),
        entries: &[wgpu::BindGroupEntry {
            binding: 0,
            resource: sink.as_entire_binding(),
        }],
    });
    let target = gpu.texture_2d(
        "stats target",
        SIZE,
        SIZE,
        format,
        wgpu::TextureUsages::RENDER_ATTACHMENT,
    );
    let view = target.create_view(&Default::default());

    // Two frames: the second must count only its own work.
    for _ in 0..2 {
        gpu.stats_begin_frame();
        let mut enc = device.create_command_encoder(&Default::default());
        {
            let mut pass = gpu.render_pass(
                &mut enc,
                &wgpu::RenderPassDescriptor {
                    label: None,
                    color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                        view: &view,
                        depth_slice: None,
                        resolve_target: None,
                        ops: wgpu::Operations {
                            load: wgpu::LoadOp::Clear(wgpu::Color::BLACK),
                            store: wgpu::StoreOp::Store,
                        },
                    })],
                    ..Default::default()
                },
            );
            pass.set_pipeline(&draw);
            pass.draw(0..6, 0..1);
        }
        {
            let mut pass = gpu.compute_pass(&mut enc, &Default::default());
            pass.set_pipeline(&dispatch);
            pass.set_bind_group(0, &bind, &[]);
            pass.dispatch_workgroups(8, 8, 1);
        }
        gpu.stats_resolve(&mut enc);
        gpu.queue.submit([enc.finish()]);
        gpu.wait().unwrap();
        let work = gpu.stats_read().unwrap().expect("a resolved frame");
        assert!(gpu.take_errors().is_empty());
        assert_eq!(work.compute_invocations, 8 * 8 * 64, "{work:?}");
        assert_eq!(work.vertex_invocations, 6, "{work:?}");
        assert_eq!(work.clipper_primitives, 2, "{work:?}");
        let pixels = (SIZE * SIZE) as u64;
        // At least one invocation per covered pixel; helper lanes and block rasterisers add at
        // most a border of blocks, not another image.
        assert!(
            work.fragment_invocations >= pixels && work.fragment_invocations < 2 * pixels,
            "{work:?}"
        );
        assert_eq!(work.uncounted_passes, 0);
    }
}
