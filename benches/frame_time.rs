//! Criterion bench: frame time of every registered method × library scene at the method's
//! default parameters, 256² (and 512² with `SCATTERBENCH_BENCH_512=1`).
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

use criterion::{BenchmarkId, Criterion, SamplingMode};
use harness::method::{PrepareContext, Support, resolve_params};
use harness::runner::{AovTargets, render_frame};
use harness::{Gpu, gpu::GpuTimer};

fn gpu() -> Option<Gpu> {
    match Gpu::new() {
        Ok(g) => Some(g),
        Err(e) if std::env::var_os("CI").is_some() => {
            panic!("CI is set and there is no GPU adapter: {e}")
        }
        Err(e) => {
            eprintln!("skipping frame_time bench: {e}");
            None
        }
    }
}

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

fn frame_time(c: &mut Criterion) {
    let Some(gpu) = gpu() else { return };
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
    let filter = std::env::var("SCATTERBENCH_BENCH_FILTER").unwrap_or_default();
    let scenes: Vec<scenes::Scene> = scenes::library::names()
        .into_iter()
        .filter_map(|n| match scenes::library::resolve(n) {
            Ok(s) => Some(s),
            Err(e) => {
                eprintln!("skipping scene {n}: {e}");
                None
            }
        })
        .collect();
    for res in resolutions() {
        let mut group = c.benchmark_group(format!("frame_time/{res}x{res}"));
        // Frames take milliseconds to seconds on a software adapter: few, flat samples.
        group
            .sampling_mode(SamplingMode::Flat)
            .sample_size(10)
            .warm_up_time(Duration::from_millis(500))
            .measurement_time(Duration::from_secs(2));
        for scene in &scenes {
            for entry in methods::REGISTRY {
                let id = format!("{}/{}", scene.name, entry.id());
                if !id.contains(&filter) {
                    continue;
                }
                if let Support::No(why) = entry.support(&scene.features(), gpu.features()) {
                    eprintln!("skip {id}: {why}");
                    continue;
                }
                let params = match resolve_params(*entry, &Default::default()) {
                    Ok(p) => p,
                    Err(e) => {
                        eprintln!("skip {id}: default params: {e}");
                        continue;
                    }
                };
                let _ = gpu.take_errors();
                let prepared = entry.prepare(&PrepareContext {
                    gpu: &gpu,
                    scene,
                    params: &params,
                    width: res,
                    height: res,
                    no_skip: false,
                });
                let aovs = AovTargets::new(&gpu, res, res);
                let mut method = match prepared {
                    Ok(m) => m,
                    Err(e) => {
                        eprintln!("skip {id}: prepare: {e:#}");
                        let _ = gpu.take_errors();
                        continue;
                    }
                };
                // One untimed frame: a pair that cannot render is skipped, not benchmarked.
                let trial = render_frame(&gpu, method.as_mut(), scene, 0, &aovs, timer.as_ref())
                    .map(|_| ());
                let errors = gpu.take_errors();
                if let Err(e) = trial.and_then(|_| {
                    errors
                        .is_empty()
                        .then_some(())
                        .ok_or_else(|| errors.join("; "))
                }) {
                    eprintln!("skip {id}: {e}");
                    continue;
                }
                let mut frame = 1u32;
                group.bench_function(BenchmarkId::new(entry.id(), &scene.name), |b| {
                    b.iter_custom(|iters| {
                        let mut total = Duration::ZERO;
                        for _ in 0..iters {
                            let t = render_frame(
                                &gpu,
                                method.as_mut(),
                                scene,
                                frame,
                                &aovs,
                                timer.as_ref(),
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
        }
        group.finish();
    }
}

criterion::criterion_group!(benches, frame_time);
criterion::criterion_main!(benches);
