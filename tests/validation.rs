//! Validation-clean Vulkan (issue 30): every registered method, under the Khronos validation
//! layer, on scenes that cover every light kind (point, spot, directional), both media, a
//! textured light and indirect scattering, raises no validation message at all. A driver is
//! entitled to crash or misrender on undefined state, so an image that is right on lavapipe
//! proves nothing where the layer objects.
//!
//! Also: `run --validate` reaches the worker processes (the counter is recorded there). The
//! rule that a validation error fails its record is unit-tested in `harness::runner`.
//!
//! Needs Debian's `vulkan-validationlayers` (scripts/test.sh installs it). Without the layer or
//! an adapter the tests skip with a message — except when `CI` is set, where they fail.

mod common;

use harness::Gpu;
use harness::gpu::DeviceChoice;
use harness::results::{Results, Status};
use harness::runner::run;

/// Scenes covering every light kind, both media, a patterned spot and indirect scattering.
const SCENES: [&str; 7] = [
    "sphere-point",       // point light, homogeneous
    "fence-spot",         // spot light
    "window-sun",         // directional light
    "stained-glass-spot", // spot with a projected pattern (textured light)
    "indirect-point",     // indirect single scattering
    "smoke-point",        // particles, point light
    "cloud-plane",        // particles, sun, a floor
];

fn validating_gpu() -> Option<Gpu> {
    let choice = DeviceChoice {
        adapter: None,
        validate: true,
    };
    match Gpu::open(&choice) {
        Ok(g) => Some(g),
        Err(e) if std::env::var_os("CI").is_some() => {
            panic!("CI is set and the validation layer or an adapter is missing: {e}")
        }
        Err(e) => {
            eprintln!("skipping validation test: {e}");
            None
        }
    }
}

#[test]
fn every_method_is_validation_clean_on_every_light_kind_and_medium() {
    let Some(gpu) = validating_gpu() else { return };
    let scenes: Vec<scenes::Scene> = SCENES
        .iter()
        .map(|n| scenes::library::resolve(n).expect("library scene"))
        .collect();
    let out = harness::testing::temp_dir("validation");
    let mut cfg = harness::testing::run_config(out, 32, 1);
    cfg.record.cache_dir = Some(harness::testing::temp_dir("validation-cache"));
    let results = run(&gpu, &scenes, methods::REGISTRY, &cfg, &mut |_| {}).unwrap();
    let mut problems = Vec::new();
    for r in &results.records {
        let who = format!("{} × {}", r.scene, r.method);
        match r.status {
            Status::Skipped => continue,
            Status::Failed => problems.push(format!("{who}: failed: {:?}", r.reason)),
            Status::Ok => {}
        }
        let count = r.counters.get("validation_messages").copied();
        match count {
            Some(0.0) => {}
            Some(n) => problems.push(format!("{who}: {n} messages, first: {:?}", r.validation)),
            None => problems.push(format!("{who}: no validation_messages counter")),
        }
    }
    let rendered = results
        .records
        .iter()
        .filter(|r| r.status != Status::Skipped)
        .count();
    assert!(rendered >= SCENES.len(), "only {rendered} records rendered");
    assert!(problems.is_empty(), "{}", problems.join("\n"));
    // In the same test: the layer's messages are process-wide, and a second test opening a
    // device in parallel would take some of them.
    run_validate_reaches_the_workers();
}

fn run_validate_reaches_the_workers() {
    let out = harness::testing::temp_dir("validation-cli");
    let cache = harness::testing::temp_dir("validation-cli-cache");
    let (code, err) = common::cli(&[
        "run",
        "--validate",
        "--scenes",
        "sphere-point",
        "--methods",
        "no-scatter",
        "--res",
        "16",
        "--frames",
        "1",
        "--warmup",
        "0",
        "--isolate",
        "on",
        "--cache",
        cache.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    let results = Results::load(&out.join("results.json")).unwrap();
    let r = &results.records[0];
    assert_eq!(r.status, Status::Ok, "{:?}", r.reason);
    assert_eq!(
        r.counters.get("validation_messages"),
        Some(&0.0),
        "the worker ran under the layer and counted its messages"
    );
}
