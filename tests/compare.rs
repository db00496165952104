//! `scatterbench compare` from the outside: two runs that differ in known ways give exit 0,
//! compare.json and compare.html in `--out`, and a summary naming the changed verdict and the
//! flagged headline; runs of different work exit 2 and an unreadable results.json exits 1,
//! each naming the file. Also keeps the report's list of every method id (its layout
//! fixtures) equal to the registry's.

use std::path::Path;

use harness::method::Params;
use harness::results::Results;
use harness::testing::temp_dir;
use report::fixture::synthetic::{Measured, record, run};

mod common;
use common::scatterbench as cli;

/// One scene: the floor, a fast rough method and an exact one. `exact_error` is the exact
/// method's headline, `rough_ms` the rough one's time.
fn one_scene(adapter: &str, rough_ms: f64, exact_error: f64) -> Results {
    let mut r = run(adapter, 64);
    let none = Params::new();
    let m = |time_ms, headline| Some(Measured { time_ms, headline });
    for (method, measured) in [
        ("no-scatter", m(10.0, 1.0)),
        ("froxel-fog", m(rough_ms, 0.03)),
        ("biri-shadow-volumes", m(40.0, exact_error)),
    ] {
        r.records
            .push(record("fence-spot", method, &none, measured));
    }
    r
}

fn save(dir: &Path, r: &Results) -> String {
    std::fs::create_dir_all(dir).unwrap();
    r.save(&dir.join("results.json")).unwrap();
    dir.to_str().unwrap().to_string()
}

#[test]
fn compare_writes_json_and_html_and_names_the_changes() {
    let root = temp_dir("cli-compare");
    // B: froxel-fog slower than the exact method (the ≤ 5 % verdict changes, τ = 1/3) and the
    // exact method's error 0.004 % → 0.111 % (flagged).
    let a = save(&root.join("a"), &one_scene("lavapipe", 20.0, 0.00004));
    let b = save(&root.join("b"), &one_scene("SwiftShader", 50.0, 0.00111));
    let out = root.join("out");
    let (code, stdout, stderr) = cli(&["compare", &a, &b, "--out", out.to_str().unwrap()]);
    assert_eq!(code, 0, "{stderr}");
    for needle in [
        "A = lavapipe",
        "B = SwiftShader",
        "mean τ 0.33 over 1 scenes",
        "verdicts changed on 1 of 1 scenes",
        // froxel-fog 20 / 10 ms on A, biri-shadow-volumes 40 / 10 ms on B.
        "fence-spot: fastest ≤ 5 %: A froxel-fog (2.00× floor), B biri-shadow-volumes (4.00× floor)",
        "fence-spot biri-shadow-volumes: A 0.00400 %, B 0.111 %",
        "compare.html",
    ] {
        assert!(
            stdout.contains(needle),
            "'{needle}' missing from:\n{stdout}"
        );
    }
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("compare.json")).unwrap()).unwrap();
    assert_eq!(json["schema"], "scatterbench-compare/1");
    assert_eq!(json["headline_flags"].as_array().unwrap().len(), 1);
    assert_eq!(
        json["scenes"][0]["floor_ms"],
        serde_json::json!([10.0, 10.0])
    );
    assert_eq!(json["scenes"][0]["rows"][1]["runs"][1]["ratio"], 5.0);
    let html = std::fs::read_to_string(out.join("compare.html")).unwrap();
    assert!(
        html.contains("SwiftShader") && !html.contains("http://") && !html.contains("https://")
    );
    let _ = std::fs::remove_dir_all(root);
}

#[test]
fn runs_of_different_work_exit_2_and_unreadable_results_exit_1() {
    let root = temp_dir("cli-compare-refused");
    let a = save(&root.join("a"), &one_scene("lavapipe", 20.0, 0.0));
    let mut big = one_scene("SwiftShader", 20.0, 0.0);
    big.run.resolution = [256, 256];
    let b = save(&root.join("b"), &big);
    let out = root.join("out");
    let o = out.to_str().unwrap();
    let (code, _, err) = cli(&["compare", &a, &b, "--out", o]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("resolution") && err.contains("64x64") && err.contains("256x256"),
        "{err}"
    );
    assert!(!out.join("compare.json").exists());

    let (code, _, err) = cli(&["compare", &a, "--out", o]);
    assert_eq!(code, 2, "one run: {err}");
    let missing = root.join("nothing-here");
    let (code, _, err) = cli(&["compare", &a, missing.to_str().unwrap(), "--out", o]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("nothing-here") && err.contains("no results.json"),
        "{err}"
    );

    let bad = root.join("bad");
    std::fs::create_dir_all(&bad).unwrap();
    std::fs::write(bad.join("results.json"), "{\"schema_version\": 1").unwrap();
    let (code, _, err) = cli(&["compare", &a, bad.to_str().unwrap(), "--out", o]);
    assert_eq!(code, 1, "{err}");
    assert!(
        err.contains("results.json") && !err.contains("panicked"),
        "{err}"
    );
    let _ = std::fs::remove_dir_all(root);
}

/// The report's layout tests generate a run of every method id in
/// report/tests/fixtures/method-ids.txt; it must be the registry's list.
#[test]
fn the_reports_method_id_list_is_the_registry() {
    let (code, stdout, stderr) = cli(&["list", "--json"]);
    assert_eq!(code, 0, "{stderr}");
    let list: serde_json::Value = serde_json::from_str(&stdout).unwrap();
    let registry: Vec<&str> = list["methods"]
        .as_array()
        .unwrap()
        .iter()
        .map(|m| m["id"].as_str().unwrap())
        .collect();
    let fixture = include_str!("../report/tests/fixtures/method-ids.txt");
    let listed: Vec<&str> = fixture.lines().filter(|l| !l.is_empty()).collect();
    assert_eq!(
        listed, registry,
        "report/tests/fixtures/method-ids.txt is out of date: write `scatterbench list --json`'s \
         method ids into it, one a line"
    );
}
