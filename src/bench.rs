//! The criterion frame-time bench (`cargo bench --bench frame_time`, benches/README.md): every
//! method of the registry it is given × library scene at the method's default parameters, 256²
//! (and 512² with `SCATTERBENCH_BENCH_512=1`).
//!
//! Each pair is prepared once outside the timed loop (tables, pipelines, shadow-map
//! allocation), rendered once untimed to check it works, then timed frame by frame through
//! `iter_custom`: the sum of GPU timestamp-query times when the adapter has them, else the
//! wall time of encode + submit + wait (the AOV clear between frames is never timed). The
//! frames cycle through the scene's animation like the runner does. Unsupported pairs and
//! pairs that fail to prepare or render are skipped with a message.
//!
//! `cargo test --all-targets` runs this in criterion's test mode (no `--bench` argument):
//! each pair renders once at 32² so the test stays fast; `cargo bench` runs the real matrix.
//! Environment: `SCATTERBENCH_BENCH_512=1` adds 512²; `SCATTERBENCH_BENCH_FILTER=substr`
//! keeps only pairs whose `scene/method` contains it (criterion's own filter still applies
//! to the ids, but this one also skips the preparation of filtered-out pairs).

use std::time::Duration;

use criterion::{BenchmarkGroup, BenchmarkId, Criterion, SamplingMode, measurement::WallTime};
use harness::method::{Method, PrepareContext, Prepared, Support, resolve_params};
use harness::runner::{AovTargets, render_frame};
use harness::{Gpu, gpu::GpuTimer};
use scenes::Scene;

/// True under `cargo bench` (criterion passes `--bench`), false in test mode.
fn bench_mode() -> bool {
    std::env::args().any(|a| a == "--bench")
}

fn resolutions() -> Vec<u32> {
    if !bench_mode() {
        return vec![32];
    }
    let mut r = vec![256];
    if std::env::var_os("SCATTERBENCH_BENCH_512").is_some_and(|v| v != "0") {
        r.push(512);
    }
    r
}

/// The library scenes (one that does not load is skipped with a message).
fn library_scenes() -> Vec<Scene> {
    scenes::library::names()
        .into_iter()
        .filter_map(|n| match scenes::library::resolve(n) {
            Ok(s) => Some(s),
            Err(e) => {
                eprintln!("skipping scene {n}: {e}");
                None
            }
        })
        .collect()
}

/// The GPU and its timestamp timer (None: wall time), shared by every pair.
struct Bench {
    gpu: Gpu,
    timer: Option<GpuTimer>,
}

/// The frame-time bench over `registry` × the library scenes (registered as a criterion
/// function by `benches/frame_time.rs`, or by a crate's own bench with its registry).
pub fn frame_time(c: &mut Criterion, registry: &[&dyn Method]) {
    let Some(gpu) = harness::testing::gpu_or_skip() else {
        return;
    };
    let timer = GpuTimer::new(&gpu);
    let basis = if timer.is_some() {
        "GPU timestamps"
    } else {
        "wall time"
    };
    eprintln!(
        "frame_time: {} ({}), timing from {basis}",
        gpu.summary.adapter, gpu.summary.backend
    );
    let bench = Bench { gpu, timer };
    let filter = std::env::var("SCATTERBENCH_BENCH_FILTER").unwrap_or_default();
    let scenes = library_scenes();
    for res in resolutions() {
        let mut group = c.benchmark_group(format!("frame_time/{res}x{res}"));
        // Frames take milliseconds to seconds on a software adapter: few, flat samples.
        group
            .sampling_mode(SamplingMode::Flat)
            .sample_size(10)
            .warm_up_time(Duration::from_millis(500))
            .measurement_time(Duration::from_secs(2));
        for scene in &scenes {
            for entry in registry {
                if format!("{}/{}", scene.name, entry.id()).contains(&filter) {
                    bench.pair(&mut group, scene, *entry, res);
                }
            }
        }
        group.finish();
    }
}

impl Bench {
    /// Benchmarks one method on one scene, or says why it is skipped.
    fn pair(&self, group: &mut BenchmarkGroup<WallTime>, scene: &Scene, m: &dyn Method, res: u32) {
        let id = format!("{}/{}", scene.name, m.id());
        let aovs = AovTargets::new(&self.gpu, res, res);
        let mut method = match self.ready(scene, m, res, &aovs) {
            Ok(p) => p,
            Err(why) => {
                eprintln!("skip {id}: {why}");
                return;
            }
        };
        let mut frame = 1u32;
        group.bench_function(BenchmarkId::new(m.id(), &scene.name), |b| {
            b.iter_custom(|iters| {
                let mut total = Duration::ZERO;
                for _ in 0..iters {
                    let t = render_frame(
                        &self.gpu,
                        method.as_mut(),
                        scene,
                        frame,
                        &aovs,
                        self.timer.as_ref(),
                    )
                    .unwrap_or_else(|e| panic!("{id}: frame {frame}: {e}"));
                    frame = frame.wrapping_add(1);
                    let ms = t.gpu_ms.unwrap_or(t.wall_ms);
                    total += Duration::from_secs_f64(ms * 1e-3);
                }
                total
            })
        });
    }

    /// The method prepared at its defaults and rendered once untimed (a pair that cannot
    /// render is skipped, not benchmarked), or why not.
    fn ready(
        &self,
        scene: &Scene,
        m: &dyn Method,
        res: u32,
        aovs: &AovTargets,
    ) -> Result<Box<dyn Prepared>, String> {
        let gpu = &self.gpu;
        if let Support::No(why) = m.support(&scene.features(), gpu.features()) {
            return Err(why);
        }
        let params =
            resolve_params(m, &Default::default()).map_err(|e| format!("default params: {e}"))?;
        let _ = gpu.take_errors();
        let prepared = m.prepare(&PrepareContext {
            gpu,
            scene,
            params: &params,
            width: res,
            height: res,
            no_skip: false,
        });
        let mut method = prepared.map_err(|e| {
            let _ = gpu.take_errors();
            format!("prepare: {e:#}")
        })?;
        let trial = render_frame(gpu, method.as_mut(), scene, 0, aovs, self.timer.as_ref());
        let errors = gpu.take_errors();
        trial?;
        if !errors.is_empty() {
            return Err(errors.join("; "));
        }
        Ok(method)
    }
}
