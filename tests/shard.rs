//! Sharding and merging: two shards of a tiny run, merged, equal the unsharded run in
//! everything but timing; `merge` refuses runs that do not compare, with a clear message.

use harness::testing::{gpu_or_skip as gpu, temp_dir as tmp};
use std::path::{Path, PathBuf};
use std::process::Command;

use harness::merge::{MergeOptions, merge};
use harness::record::RecordSettings;
use harness::results::{Record, Results};
use harness::runner::{RunConfig, run, run_shard};
use harness::shard::Shard;

fn config(out: PathBuf) -> RunConfig {
    RunConfig::new(RecordSettings::new(out, (32, 32), (1, 0)), "shard-test")
}

/// A record without its timing and memory (the only fields that legitimately differ
/// between two runs of the same work).
fn untimed(r: &Record) -> Record {
    Record {
        timing: None,
        memory_bytes: None,
        ..r.clone()
    }
}

#[test]
fn two_shards_merged_equal_the_unsharded_run() {
    let Some(gpu) = gpu() else { return };
    let names = ["sphere-point", "clear-fog", "fence-spot"];
    let scenes: Vec<scenes::Scene> = names
        .iter()
        .map(|n| scenes::library::resolve(n).expect("library scene"))
        .collect();
    let entry = methods::find("no-scatter").expect("registered");
    let whole = run(&gpu, &scenes, &[entry], &config(tmp("whole")), &mut |_| {}).unwrap();
    assert_eq!(whole.records.len(), 3);

    let mut dirs = Vec::new();
    // Shard 2 first: merge must order by shard index, not by argument order.
    for i in [2, 1] {
        let dir = tmp(&format!("part{i}"));
        let shard = Shard { index: i, count: 2 };
        let r = run_shard(
            &gpu,
            &scenes,
            &[entry],
            &config(dir.clone()),
            shard,
            &mut |_| {},
        )
        .unwrap();
        assert_eq!(r.run.shard, Some(shard));
        // Contiguous halves of 3 items: 1 then 2.
        assert_eq!(r.records.len(), if i == 1 { 1 } else { 2 });
        dirs.push(dir);
    }
    let out = tmp("merged");
    let m = merge(&dirs, &out, &MergeOptions::default()).unwrap();
    assert!(m.warnings.is_empty(), "{:?}", m.warnings);
    let loaded = Results::load(&out.join("results.json")).unwrap();
    assert_eq!(loaded, m.results);
    assert_eq!(loaded.run.shard, None);
    assert_eq!(loaded.run.resolution, [32, 32]);
    // Each shard described its method; the merged run describes it once.
    let described: Vec<(&str, Option<bool>)> = loaded
        .run
        .methods
        .iter()
        .map(|(id, d)| (id.as_str(), d.baseline))
        .collect();
    assert_eq!(described, [("no-scatter", Some(true))]);
    let a: Vec<Record> = whole.records.iter().map(untimed).collect();
    let b: Vec<Record> = loaded.records.iter().map(untimed).collect();
    assert_eq!(a, b, "merged records differ from the unsharded run");
    // Every image a record names, and each scene's reference, was copied.
    for r in &loaded.records {
        assert!(!r.images.is_empty());
        for rel in r.images.values() {
            assert!(out.join(rel).is_file(), "missing {rel}");
        }
        assert!(out.join(&r.scene).join("reference/inscatter.exr").is_file());
    }
    // Merging into a directory that already holds a run is refused.
    let e = merge(&dirs, &out, &MergeOptions::default()).unwrap_err();
    assert!(e.contains("already holds a results.json"), "{e}");
    // A shard given twice is refused.
    let e = merge(
        &[dirs[0].clone(), dirs[0].clone()],
        &tmp("twice"),
        &MergeOptions::default(),
    )
    .unwrap_err();
    assert!(e.contains("both shard 2/2"), "{e}");
    // A missing shard merges with a warning.
    let m = merge(&dirs[..1], &tmp("partial"), &MergeOptions::default()).unwrap();
    assert!(
        m.warnings.iter().any(|w| w.contains("1/2")),
        "{:?}",
        m.warnings
    );
}

/// Writes a run directory holding only a results.json (no GPU needed).
fn fake_run(name: &str, res: [u32; 2], scene: &str) -> PathBuf {
    let dir = tmp(name);
    std::fs::create_dir_all(&dir).unwrap();
    let text = serde_json::json!({
        "schema_version": harness::results::SCHEMA_VERSION,
        "run": {
            "id": name, "git_commit": "abc", "resolution": res, "frames": 1, "warmup": 0,
            "machine": {"adapter": "a", "backend": "b", "driver": "d", "cpu": "c", "cores": 1, "os": "o"},
            "scored_frame": 0, "note": ""
        },
        "records": [{
            "scene": scene, "method": "m", "params": {}, "status": "skipped",
            "reason": "unsupported", "timing": null, "memory_bytes": null, "passes": null
        }]
    });
    std::fs::write(dir.join("results.json"), text.to_string()).unwrap();
    dir
}

fn merge_cli(dirs: &[&Path], out: &Path, flags: &[&str]) -> (bool, String) {
    let o = Command::new(env!("CARGO_BIN_EXE_scatterbench"))
        .arg("merge")
        .args(dirs)
        .args(flags)
        .arg("--out")
        .arg(out)
        .env("NODEVICE_SELECT", "1")
        .output()
        .unwrap();
    (
        o.status.success(),
        String::from_utf8_lossy(&o.stderr).into_owned(),
    )
}

#[test]
fn merge_refuses_mismatched_resolution_and_schema() {
    let a = fake_run("res-a", [32, 32], "s1");
    let b = fake_run("res-b", [64, 64], "s2");
    let (ok, err) = merge_cli(&[&a, &b], &tmp("res-out"), &[]);
    assert!(!ok);
    assert!(
        err.contains("resolution differs") && err.contains("32x32") && err.contains("64x64"),
        "{err}"
    );
    // Same resolution, different scenes: merges.
    let c = fake_run("res-c", [32, 32], "s3");
    let out = tmp("res-ok");
    let (ok, err) = merge_cli(&[&a, &c], &out, &[]);
    assert!(ok, "{err}");
    let r = Results::load(&out.join("results.json")).unwrap();
    let scenes: Vec<&str> = r.records.iter().map(|r| r.scene.as_str()).collect();
    assert_eq!(scenes, ["s1", "s3"]);
    // A results file of another schema version is refused by name.
    let d = fake_run("schema", [32, 32], "s4");
    let text = std::fs::read_to_string(d.join("results.json"))
        .unwrap()
        .replace(
            &format!("\"schema_version\":{}", harness::results::SCHEMA_VERSION),
            "\"schema_version\":999",
        );
    std::fs::write(d.join("results.json"), text).unwrap();
    let (ok, err) = merge_cli(&[&a, &d], &tmp("schema-out"), &[]);
    assert!(!ok);
    assert!(err.contains("schema_version 999"), "{err}");
    // The same record in two runs is refused.
    let e = fake_run("dup", [32, 32], "s1");
    let (ok, err) = merge_cli(&[&a, &e], &tmp("dup-out"), &[]);
    assert!(!ok);
    assert!(
        err.contains("is in both") && err.contains("--replace"),
        "{err}"
    );
}

/// `--replace`: a record in a later run takes the earlier one's place (a method re-run after a
/// fix, folded into a sweep); the merge says how many it replaced.
#[test]
fn merge_replace_keeps_the_later_runs_record_in_the_earlier_ones_place() {
    let a = fake_run("rep-a", [32, 32], "s1");
    let b = fake_run("rep-b", [32, 32], "s2");
    let again = fake_run("rep-again", [32, 32], "s1");
    let path = again.join("results.json");
    let text = std::fs::read_to_string(&path).unwrap();
    std::fs::write(&path, text.replace("\"unsupported\"", "\"re-run\"")).unwrap();
    let out = tmp("rep-out");
    let (ok, err) = merge_cli(&[&a, &b, &again], &out, &["--replace"]);
    assert!(ok, "{err}");
    assert!(err.contains("1 records of earlier runs replaced"), "{err}");
    let r = Results::load(&out.join("results.json")).unwrap();
    let got: Vec<(&str, Option<&str>)> = r
        .records
        .iter()
        .map(|r| (r.scene.as_str(), r.reason.as_deref()))
        .collect();
    assert_eq!(got, [("s1", Some("re-run")), ("s2", Some("unsupported"))]);
}

/// Sets `run.methods` of the results.json in `dir`.
fn describe(dir: &Path, methods: serde_json::Value) {
    let path = dir.join("results.json");
    let mut v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
    v["run"]["methods"] = methods;
    std::fs::write(path, v.to_string()).unwrap();
}

/// The merged `run.methods` is the union of the runs' (a run written before descriptions
/// existed adds none); a method described differently in two runs keeps the first run's
/// description, and the merge warns naming the method and the run.
#[test]
fn merge_unions_the_method_descriptions() {
    let a = fake_run("desc-a", [32, 32], "s1");
    describe(
        &a,
        serde_json::json!({"m": {"paper": "P", "baseline": false}}),
    );
    let b = fake_run("desc-b", [32, 32], "s2");
    describe(
        &b,
        serde_json::json!({
            "m": {"paper": "P", "baseline": true},
            "n": {"paper": "Q", "baseline": true, "medium": "both"}
        }),
    );
    let older = fake_run("desc-older", [32, 32], "s3");
    let out = tmp("desc-out");
    let (ok, err) = merge_cli(&[&a, &b, &older], &out, &[]);
    assert!(ok, "{err}");
    assert!(
        err.contains("warning:")
            && err.contains("'m'")
            && err.contains("described differently")
            && err.contains("desc-b"),
        "{err}"
    );
    let r = Results::load(&out.join("results.json")).unwrap();
    let m = &r.run.methods;
    assert_eq!(m.len(), 2);
    assert_eq!(
        (m["m"].paper.as_deref(), m["m"].baseline),
        (Some("P"), Some(false))
    );
    assert_eq!(
        (m["n"].medium.as_deref(), m["n"].baseline),
        (Some("both"), Some(true))
    );
}
