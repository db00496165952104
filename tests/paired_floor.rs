//! `run --paired-floor` (ARCHITECTURE §4.5): every record but the floor's also times the floor
//! (no-scatter at the record's shadow-map settings, its defaults otherwise) on the same frames, in process and in a worker; the floor it
//! times is the floor's work (its passes are those of the run's no-scatter record on the same
//! scene); and a run without the floor among its methods is refused before any work.

use harness::method::ParamValue;
use harness::results::{Results, Status};
use harness::testing::{gpu_or_skip, temp_dir};

mod common;
use common::{cli, scatterbench};

const FLOOR: &str = "no-scatter";

/// `run` of froxel-fog and the floor on two scenes at 32², 2 timed frames; its results.
fn paired_run(name: &str, extra: &[&str]) -> Results {
    paired_run_in(name, extra).0
}

/// [`paired_run`] and the run's directory.
fn paired_run_in(name: &str, extra: &[&str]) -> (Results, std::path::PathBuf) {
    let out = temp_dir(name);
    let out_arg = out.to_string_lossy().into_owned();
    let mut args = vec![
        "run",
        "--scenes",
        "clear-fog,sphere-point",
        "--methods",
        "froxel-fog,no-scatter",
        "--res",
        "32",
        "--frames",
        "2",
        "--warmup",
        "1",
        "--time-budget",
        "0",
        "--out",
        &out_arg,
    ];
    args.extend_from_slice(extra);
    let (code, _, err) = scatterbench(&args);
    assert_eq!(code, 0, "{args:?}: {err}");
    let results = Results::load(&out.join("results.json")).expect("results.json loads");
    (results, out)
}

/// Every ok record but the floor's carries a paired floor of 2 timed frames, with GPU time
/// exactly where the record has it, that ran the passes of the floor's own record on that
/// scene; the floor's records carry none.
fn assert_paired(results: &Results) {
    assert_eq!(results.records.len(), 4);
    for r in &results.records {
        assert_eq!(
            r.status,
            Status::Ok,
            "{} {}: {:?}",
            r.scene,
            r.method,
            r.reason
        );
        let timing = r.timing.as_ref().expect("an ok record is timed");
        if r.method == FLOOR {
            assert!(
                timing.floor.is_none(),
                "{}: the floor paired with itself",
                r.scene
            );
            continue;
        }
        let floor = timing
            .floor
            .as_ref()
            .unwrap_or_else(|| panic!("{}: no paired floor", r.scene));
        assert_eq!(floor.frames, 2, "{}", r.scene);
        assert!(
            floor.interleaved,
            "{}: timed apart from the record",
            r.scene
        );
        assert_eq!(
            floor.gpu_ms.is_some(),
            timing.gpu_ms.is_some(),
            "{}",
            r.scene
        );
        let own = results
            .records
            .iter()
            .find(|o| o.scene == r.scene && o.method == FLOOR)
            .and_then(|o| o.passes.as_ref())
            .expect("the floor's record on the scene");
        assert_eq!(
            floor.passes, own.run,
            "{}: the paired floor ran other passes",
            r.scene
        );
        let mine = r.passes.as_ref().expect("passes").run.clone();
        assert_ne!(
            floor.passes, mine,
            "{}: the paired floor timed the method",
            r.scene
        );
    }
}

#[test]
fn every_record_times_the_floor_beside_it_in_a_worker_and_in_process() {
    if gpu_or_skip().is_none() {
        return;
    }
    let paired = paired_run("paired-worker", &["--paired-floor"]);
    assert_paired(&paired);
    assert_paired(&paired_run(
        "paired-in-process",
        &["--paired-floor", "--isolate", "off"],
    ));
    let unpaired = paired_run("unpaired", &[]);
    // The floor renders into the same targets between the method's frames: what is scored
    // must still be the method's alone, as without the pairing (every method here renders
    // the same image each frame).
    for (p, u) in paired.records.iter().zip(&unpaired.records) {
        let headline = |r: &harness::results::Record| {
            r.errors
                .get("inscatter")
                .and_then(|e| e.headline)
                .expect("scored")
        };
        let (hp, hu) = (headline(p), headline(u));
        assert!(
            (hp - hu).abs() <= 1e-6 * hu.abs().max(1e-9),
            "{} {}: {hp} paired, {hu} alone",
            p.scene,
            p.method
        );
    }
    assert!(
        unpaired
            .records
            .iter()
            .all(|r| r.timing.as_ref().is_some_and(|t| t.floor.is_none())),
        "a run without --paired-floor timed a paired floor"
    );
}

/// The paired floor rasterises the scene as the record's method does: it takes the record's
/// shadow-map size and budget (the knobs it shares with the method), so a coarser shadow map,
/// which shadows the method's surfaces too, is not read as cheaper in-scatter.
#[test]
fn the_paired_floor_takes_the_records_shadow_map_settings() {
    if gpu_or_skip().is_none() {
        return;
    }
    let run = paired_run(
        "paired-matched",
        &["--paired-floor", "--param", "froxel-fog.shadow_map=256"],
    );
    assert_paired(&run);
    for r in run.records.iter().filter(|r| r.method != FLOOR) {
        let floor = r.timing.as_ref().and_then(|t| t.floor.as_ref()).unwrap();
        for knob in ["shadow_map", "local_shadow_budget"] {
            assert_eq!(
                floor.params.get(knob),
                r.params.get(knob),
                "{}: the floor's {knob}",
                r.scene
            );
        }
        assert_eq!(floor.params.get("shadow_map"), Some(&ParamValue::Int(256)));
    }
}

#[test]
fn paired_floor_without_the_floor_method_is_refused() {
    let (code, err) = cli(&[
        "run",
        "--scenes",
        "clear-fog",
        "--methods",
        "froxel-fog",
        "--paired-floor",
        "--res",
        "16",
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("--paired-floor") && err.contains(FLOOR),
        "{err}"
    );
    assert!(!err.contains("panicked"), "{err}");
}

/// `confirm` (ARCHITECTURE §4.5) re-times what `report::candidates` picks from a run — each
/// with the knobs it ran with — and each scene's floor, at the run's resolution, with paired
/// floors on the frames asked for, into a run of its own.
#[test]
fn confirm_re_times_the_chosen_configurations_beside_paired_floors() {
    if gpu_or_skip().is_none() {
        return;
    }
    let (source, src) = paired_run_in("confirm-source", &["--param", "froxel-fog.slices=32"]);
    let chosen: Vec<String> = report::candidates::candidates(&source, 1)
        .iter()
        .map(|r| r.key())
        .collect();
    assert!(!chosen.is_empty(), "nothing under 10 % to confirm");
    let out = temp_dir("confirm-out");
    let dst = out.to_string_lossy().into_owned();
    let args = [
        "confirm",
        src.to_str().unwrap(),
        "--top",
        "1",
        "--frames",
        "3",
        "--warmup",
        "0",
        "--out",
        &dst,
    ];
    let (code, stdout, err) = scatterbench(&args);
    assert_eq!(code, 0, "{err}");
    assert!(stdout.contains("| scene | floor |"), "{stdout}");
    let confirmed = Results::load(&out.join("results.json")).expect("results.json loads");
    assert_eq!(confirmed.run.resolution, source.run.resolution);
    assert_eq!(confirmed.run.frames, 3);
    let (floors, others): (Vec<_>, Vec<_>) =
        confirmed.records.iter().partition(|r| r.method == FLOOR);
    assert_eq!(floors.len(), 2, "one floor per scene");
    let mut got: Vec<String> = others.iter().map(|r| r.key()).collect();
    let mut want = chosen;
    got.sort();
    want.sort();
    assert_eq!(got, want);
    for r in others {
        let t = r.timing.as_ref().expect("timed");
        assert_eq!(t.floor.as_ref().map(|f| f.frames), Some(3), "{}", r.key());
    }
}

/// A run whose record names a method this build does not have, or knobs its method refuses,
/// is refused before any work (exit 2), naming the record; so is a directory without a run.
#[test]
fn confirm_refuses_records_this_build_cannot_run() {
    use report::fixture::synthetic::{Measured, params, record, run};
    let dir = temp_dir("confirm-refused");
    let write = |method: &str, knobs: harness::method::Params| {
        let mut results = run("lavapipe", 32);
        let m = Some(Measured {
            time_ms: 2.0,
            headline: 0.001,
        });
        results.records.push(record("clear-fog", method, &knobs, m));
        std::fs::create_dir_all(&dir).unwrap();
        results.save(&dir.join("results.json")).unwrap();
    };
    let d = dir.to_str().unwrap();
    write("gone-method", params());
    let (code, err) = cli(&["confirm", d, "--out", &format!("{d}/out")]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("gone-method") && err.contains("registry"),
        "{err}"
    );
    let mut knobs = harness::method::Params::new();
    knobs.insert("slices".into(), harness::method::ParamValue::Int(1 << 30));
    write("froxel-fog", knobs);
    let (code, err) = cli(&["confirm", d, "--out", &format!("{d}/out")]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("froxel-fog") && err.contains("slices"),
        "{err}"
    );
    let (code, err) = cli(&["confirm", &format!("{d}/nowhere")]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("no results.json"), "{err}");
    assert!(!dir.join("out").exists());
    let _ = std::fs::remove_dir_all(dir);
}
