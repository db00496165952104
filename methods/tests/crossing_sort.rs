//! The crossing lists' per-pixel sort (`common/shadow_volumes/crossing_lists.wgsl`,
//! `crossing_sorted`) on
//! the GPU against a stable sort by |distance| on the CPU: lists of every length class — empty,
//! one, short, the private merge sort's cap and past it (the pool's insertion-sort fallback),
//! and nearly sorted lists under the cap (insertion sort too) — with ties of |distance| and both
//! signs, so every path must order exactly as the walk expects.

use harness::testing::gpu_or_skip;
use methods::common::shadow_volumes::crossing_lists::WGSL as CROSSING_LISTS;
use methods::common::wgsl::compose;

/// One invocation per list: list i is "pixel" (i, 0) of a width × 1 image.
const KERNEL: &str = r#"
@compute @workgroup_size(64)
fn sort_lists(@builtin(global_invocation_id) gid: vec3<u32>) {
    if (gid.x >= crossing_cfg.width) {
        return;
    }
    crossing_sorted(vec2<u32>(gid.x, 0u));
}
"#;

fn lcg(seed: &mut u64) -> f64 {
    *seed = seed
        .wrapping_mul(6364136223846793005)
        .wrapping_add(1442695040888963407);
    (*seed >> 11) as f64 / (1u64 << 53) as f64
}

/// Lists of the given lengths: signed distances in ±[0.1, 50), one in four repeating an earlier
/// magnitude (ties), the sign random.
fn lists(lengths: &[usize]) -> Vec<Vec<f32>> {
    let mut seed = 32;
    lengths
        .iter()
        .map(|&n| {
            let mut v: Vec<f32> = Vec::with_capacity(n);
            for k in 0..n {
                let magnitude = if k > 0 && lcg(&mut seed) < 0.25 {
                    v[(lcg(&mut seed) * k as f64) as usize].abs()
                } else {
                    (0.1 + 49.9 * lcg(&mut seed)) as f32
                };
                v.push(if lcg(&mut seed) < 0.5 {
                    -magnitude
                } else {
                    magnitude
                });
            }
            v
        })
        .collect()
}

#[test]
fn crossing_lists_sort_stably_by_distance_on_both_paths() {
    let Some(gpu) = gpu_or_skip() else { return };
    let lengths = [
        0, 1, 2, 3, 5, 16, 17, 64, 65, 100, 163, 255, 256, 257, 300, 7, 128,
    ];
    let mut input = lists(&lengths);
    // Nearly sorted lists (0, 1 and 2 descents, under the cap: the insertion-sort path), as
    // planes drawn near to far leave them.
    for (n, descents) in [(20, 0), (23, 1), (40, 2)] {
        let mut v = lists(&[n]).remove(0);
        v.sort_by(|a, b| a.abs().total_cmp(&b.abs()));
        v.dedup_by(|a, b| a.abs() == b.abs());
        for d in 0..descents {
            v.swap(3 + 9 * d, 4 + 9 * d);
        }
        input.push(v);
    }
    let mut offsets = vec![0u32];
    for l in &input {
        offsets.push(offsets.last().unwrap() + l.len() as u32);
    }
    let pool: Vec<f32> = input.concat();
    let counts: Vec<u32> = input.iter().map(|l| l.len() as u32).collect();
    // CrossingCfg: list 0, width = the lists, height 1, one list per "pixel".
    let cfg: [u32; 8] = [0, input.len() as u32, 1, 1, 0, 0, 0, 0];
    let storage = wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC;
    let buffers = [
        gpu.buffer_init(
            "cfg",
            bytemuck::cast_slice(&cfg),
            wgpu::BufferUsages::UNIFORM,
        ),
        gpu.buffer_init("counts", bytemuck::cast_slice(&counts), storage),
        gpu.buffer_init("offsets", bytemuck::cast_slice(&offsets), storage),
        gpu.buffer_init("pool", bytemuck::cast_slice(&pool), storage),
        gpu.buffer_init("stats", &[0u8; 16], storage),
    ];
    let module = gpu
        .device
        .create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("crossing-sort"),
            source: wgpu::ShaderSource::Wgsl(compose(&[CROSSING_LISTS], KERNEL).into()),
        });
    // Group 2 as the passes bind it (groups 0 and 1 empty): explicit, since an automatic layout
    // leaves the unused groups out and the pass would not validate.
    let entry = |binding: u32, ty: wgpu::BufferBindingType| wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::COMPUTE,
        ty: wgpu::BindingType::Buffer {
            ty,
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    };
    let storage_rw = wgpu::BufferBindingType::Storage { read_only: false };
    let layout = |entries: &[wgpu::BindGroupLayoutEntry]| {
        gpu.device
            .create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: None,
                entries,
            })
    };
    let empty = layout(&[]);
    let lists_layout = layout(&[
        entry(0, wgpu::BufferBindingType::Uniform),
        entry(1, storage_rw),
        entry(2, storage_rw),
        entry(3, storage_rw),
        entry(4, storage_rw),
    ]);
    let pipeline_layout = methods::common::pipeline::layout(
        &gpu.device,
        "crossing-sort",
        &[&empty, &empty, &lists_layout],
    );
    let pipeline = gpu
        .device
        .create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some("crossing-sort"),
            layout: Some(&pipeline_layout),
            module: &module,
            entry_point: Some("sort_lists"),
            compilation_options: Default::default(),
            cache: None,
        });
    let group = |layout: &wgpu::BindGroupLayout, entries: &[wgpu::BindGroupEntry]| {
        gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: None,
            layout,
            entries,
        })
    };
    let entries: Vec<wgpu::BindGroupEntry> = buffers
        .iter()
        .enumerate()
        .map(|(i, b)| wgpu::BindGroupEntry {
            binding: i as u32,
            resource: b.as_entire_binding(),
        })
        .collect();
    let (empty_group, lists_group) = (group(&empty, &[]), group(&lists_layout, &entries));
    let mut enc = gpu.device.create_command_encoder(&Default::default());
    {
        let mut pass = enc.begin_compute_pass(&Default::default());
        pass.set_pipeline(&pipeline);
        pass.set_bind_group(0, &empty_group, &[]);
        pass.set_bind_group(1, &empty_group, &[]);
        pass.set_bind_group(2, &lists_group, &[]);
        pass.dispatch_workgroups(1, 1, 1);
    }
    gpu.queue.submit([enc.finish()]);
    let read = |b: &wgpu::Buffer| {
        let copy = gpu.buffer(&wgpu::BufferDescriptor {
            label: Some("read"),
            size: b.size(),
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let mut enc = gpu.device.create_command_encoder(&Default::default());
        enc.copy_buffer_to_buffer(b, 0, &copy, 0, b.size());
        gpu.queue.submit([enc.finish()]);
        harness::gpu::map_read(&gpu, &copy).expect("read back")
    };
    let sorted: Vec<f32> = bytemuck::cast_slice(&read(&buffers[3])).to_vec();
    assert_eq!(gpu.take_errors(), Vec::<String>::new(), "wgpu errors");
    let stats: Vec<u32> = bytemuck::cast_slice(&read(&buffers[4])).to_vec();
    assert_eq!(stats[2], 0, "no list's count disagreed with its length");
    for (k, list) in input.iter().enumerate() {
        let mut want = list.clone();
        want.sort_by(|a, b| a.abs().total_cmp(&b.abs())); // stable: ties keep their order
        let got = &sorted[offsets[k] as usize..offsets[k + 1] as usize];
        assert_eq!(got, want.as_slice(), "list {k} of length {}", list.len());
    }
}
