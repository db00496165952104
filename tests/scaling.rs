//! The measurement protocol's shortcuts and the scaling command, end to end on the GPU:
//! - the scored image of a static scene (the last timed frame's output, kept) equals a fresh
//!   method's render of frame 0, so keeping it changes nothing but the cost;
//! - a time budget leaves its frame counts in the record, within the requested maxima;
//! - `scatterbench scaling` writes one run whose variants have the triangle counts and
//!   resolutions `scaling.json` claims, and a report with the scaling section.

use std::process::Command;

use harness::method::PrepareContext;
use harness::runner::{AovTargets, render_frame, run};
use harness::testing::{gpu_or_skip, run_config, temp_dir};

#[test]
fn kept_scored_frame_equals_a_fresh_render_of_frame_0() {
    let Some(gpu) = gpu_or_skip() else { return };
    let scene = scenes::library::resolve("sphere-point").unwrap();
    assert_eq!(scene.frame_count(), 1, "a static scene");
    let entry = methods::find("raymarch-brute").unwrap();
    let out = temp_dir("kept-scored");
    let mut cfg = run_config(out.clone(), 32, 2);
    cfg.record.warmup = 1;
    let results = run(
        &gpu,
        std::slice::from_ref(&scene),
        &[entry],
        &cfg,
        &mut |_| {},
    )
    .unwrap();
    let rec = &results.records[0];
    assert_eq!(rec.status, harness::results::Status::Ok, "{:?}", rec.reason);
    let scored = harness::image::io::read_exr(&out.join(&rec.images["inscatter"])).unwrap();

    // Independently: a fresh instance, prepared and rendered once at frame 0.
    let mut m = entry
        .prepare(&PrepareContext {
            gpu: &gpu,
            scene: &scene,
            params: &rec.params,
            width: 32,
            height: 32,
            no_skip: false,
        })
        .unwrap();
    let aovs = AovTargets::new(&gpu, 32, 32);
    render_frame(&gpu, m.as_mut(), &scene, 0, &aovs, None).unwrap();
    let [fresh, _, _] = aovs.read(&gpu).unwrap();
    let lum = |i: &harness::image::Image| i.luminance();
    let (a, b) = (lum(&scored), lum(&fresh));
    assert!(
        b.iter().any(|v| *v > 0.0),
        "the fresh render has in-scatter"
    );
    let worst = a
        .iter()
        .zip(&b)
        .map(|(x, y)| (x - y).abs() / y.abs().max(1e-6))
        .fold(0.0f32, f32::max);
    assert!(
        worst < 1e-4,
        "scored vs fresh frame 0: worst relative difference {worst}"
    );
    let _ = std::fs::remove_dir_all(out);
}

#[test]
fn a_time_budget_records_its_frame_counts() {
    let Some(gpu) = gpu_or_skip() else { return };
    let scene = scenes::library::resolve("clear-fog").unwrap();
    let entry = methods::find("no-scatter").unwrap();
    let out = temp_dir("budget-counts");
    let mut cfg = run_config(out.clone(), 32, 6);
    cfg.record.warmup = 2;
    // A budget of 1 µs: the first frame alone overruns it, so it is the one timed frame.
    cfg.record.budget_ms = Some(1e-3);
    let results = run(&gpu, &[scene], &[entry], &cfg, &mut |_| {}).unwrap();
    let c = &results.records[0].counters;
    assert_eq!(c.get("warmup_frames"), Some(&0.0), "{c:?}");
    assert_eq!(
        c.get("timed_frames"),
        Some(&(harness::runner::MIN_TIMED_FRAMES as f64))
    );
    // Without a budget the counters are absent (the run is the plain W + K).
    cfg.record.budget_ms = None;
    cfg.record.out_dir = temp_dir("budget-none");
    let scene = scenes::library::resolve("clear-fog").unwrap();
    let results = run(&gpu, &[scene], &[entry], &cfg, &mut |_| {}).unwrap();
    assert!(!results.records[0].counters.contains_key("timed_frames"));
    let _ = std::fs::remove_dir_all(out);
    let _ = std::fs::remove_dir_all(&cfg.record.out_dir);
}

#[test]
fn scaling_command_writes_variants_as_described() {
    let Some(_gpu) = gpu_or_skip() else { return };
    let out = temp_dir("scaling-cli");
    let status = Command::new(env!("CARGO_BIN_EXE_scatterbench"))
        .args([
            "scaling",
            "--methods",
            "no-scatter",
            "--triangles",
            "1k,4k",
            "--triangles-res",
            "32",
            "--res",
            "32,48",
            "--lights",
            "1,2",
            "--lights-res",
            "16",
            "--frames",
            "1",
            "--warmup",
            "0",
            "--out",
        ])
        .arg(&out)
        .env("NODEVICE_SELECT", "1")
        .output()
        .unwrap();
    assert!(
        status.status.success(),
        "{}",
        String::from_utf8_lossy(&status.stderr)
    );
    let spec = report::scaling::Spec::load(&out)
        .unwrap()
        .expect("scaling.json");
    let results = harness::results::Results::load(&out.join("results.json")).unwrap();
    assert_eq!(results.run.kind.as_deref(), Some("scaling"));
    let tris = &spec.sweeps[0];
    assert_eq!(tris.axis, "triangles");
    let xs: Vec<f64> = tris.points.iter().map(|p| p.x).collect();
    assert_eq!(xs, vec![960.0, 3840.0]);
    let pix = &spec.sweeps[1];
    assert_eq!(pix.axis, "pixels");
    let lights = &spec.sweeps[2];
    assert_eq!(lights.axis, "lights");
    for (p, n) in lights.points.iter().zip([1, 2]) {
        // x is the local-light count: the variant has that many point lights and the sun.
        let scene = scenes::library::resolve(&p.scene).unwrap();
        assert_eq!(p.x, n as f64);
        assert_eq!(scene.features().lights, n + 1, "{}", p.scene);
    }
    for p in tris.points.iter().chain(&pix.points).chain(&lights.points) {
        let r = results
            .records
            .iter()
            .find(|r| r.scene == p.scene)
            .unwrap_or_else(|| panic!("no record of {}", p.scene));
        assert_eq!(r.status, harness::results::Status::Ok, "{:?}", r.reason);
        // Each variant was rendered at the resolution scaling.json gives it.
        let img = harness::image::io::read_exr(&out.join(&r.images["inscatter"])).unwrap();
        assert_eq!((img.width, img.height), (p.width, p.height), "{}", p.scene);
        if pix.points.contains(p) {
            assert_eq!(p.x, (p.width * p.height) as f64);
        }
    }
    let html = std::fs::read_to_string(out.join("report/index.html")).unwrap();
    assert!(html.contains("id=\"scaling\""));
    // The slopes side by side: one column per axis.
    assert!(html.contains("vs local lights") && html.contains("vs caster triangles"));
    assert!(
        out.join("report/plots/scaling-scene-triangles.svg")
            .is_file()
    );
    let _ = std::fs::remove_dir_all(out);
}
