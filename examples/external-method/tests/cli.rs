//! The whole command line over this crate's registry, through its own three-line binary
//! (src/main.rs): `list` shows unshadowed-march beside the built-in methods; `run` runs it beside
//! no-scatter on a library scene with process isolation on — the worker is this same binary, so a
//! record of a method only it knows comes back ok only if the worker serves the same registry;
//! `stress` runs it on one case; `report` names its paper, from results.json alone.
//!
//! Without an adapter the GPU commands are skipped with a message — except when `CI` is set.

use std::path::Path;
use std::process::Command;

use external_method::UnshadowedMarch;
use harness::method::Method;
use harness::results::{Results, Status};
use harness::testing::{gpu_or_skip, temp_dir};

const BIN: &str = env!("CARGO_BIN_EXE_external-method");
const ID: &str = "unshadowed-march";

/// Runs the binary; panics with its output unless it exits 0. Returns stdout.
fn ok(args: &[&str]) -> String {
    let out = Command::new(BIN)
        .args(args)
        .env("NODEVICE_SELECT", "1")
        .output()
        .expect("the external-method binary starts");
    let (stdout, stderr) = (
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    );
    assert!(
        out.status.success(),
        "{args:?}: {}\nstdout:\n{stdout}\nstderr:\n{stderr}",
        out.status
    );
    stdout
}

fn path(p: &Path) -> &str {
    p.to_str().expect("a UTF-8 temp path")
}

#[test]
fn lists_its_method_beside_the_built_in_ones() {
    let json: serde_json::Value = serde_json::from_str(&ok(&["list", "--json"])).unwrap();
    let listed: Vec<&serde_json::Value> = json["methods"].as_array().unwrap().iter().collect();
    let ids: Vec<&str> = listed.iter().map(|m| m["id"].as_str().unwrap()).collect();
    let built_in: Vec<&str> = methods::REGISTRY.iter().map(|m| m.id()).collect();
    assert_eq!(
        ids[..built_in.len()],
        built_in[..],
        "built-in methods first"
    );
    assert_eq!(ids[built_in.len()..], [ID]);
    let mine = listed.last().unwrap();
    assert_eq!(mine["paper"], UnshadowedMarch.info().paper);
    assert_eq!(mine["baseline"], false);
    assert_eq!(mine["medium"], "homogeneous");
    assert!(
        mine["params"]
            .as_array()
            .unwrap()
            .iter()
            .any(|k| k["name"] == "steps")
    );
    assert!(ok(&["list"]).contains(ID));
}

#[test]
fn runs_stresses_and_reports_its_method_beside_a_built_in_one() {
    if gpu_or_skip().is_none() {
        return;
    }
    let (out, stress_out, cache) = (
        temp_dir("external-cli-run"),
        temp_dir("external-cli-stress"),
        temp_dir("external-cli-cache"),
    );
    let small = ["--res", "32", "--cache", path(&cache), "--isolate", "on"];
    let methods = format!("{ID},no-scatter");
    let run = [
        "run",
        "--scenes",
        "sphere-point",
        "--methods",
        &methods,
        "--frames",
        "1",
        "--warmup",
        "0",
        "--out",
        path(&out),
    ];
    ok(&[&run[..], &small].concat());
    let results = Results::load(&out.join("results.json")).unwrap();
    let got: Vec<(&str, Status)> = results
        .records
        .iter()
        .map(|r| (r.method.as_str(), r.status))
        .collect();
    assert_eq!(got, [(ID, Status::Ok), ("no-scatter", Status::Ok)]);
    let described = &results.run.methods;
    assert_eq!(
        described[ID].paper.as_deref(),
        Some(UnshadowedMarch.info().paper)
    );
    assert_eq!(described[ID].baseline, Some(false));
    assert_eq!(described["no-scatter"].baseline, Some(true));

    let stress = ["stress", "--methods", ID, "--cases", "sigma-t-10", "--out"];
    ok(&[&stress[..], &[path(&stress_out)], &small].concat());
    let stressed = Results::load(&stress_out.join("results.json")).unwrap();
    assert_eq!(stressed.records.len(), 1);
    assert_eq!(
        stressed.records[0].status,
        Status::Ok,
        "{:?}",
        stressed.records[0].reason
    );

    ok(&["report", path(&out)]);
    let html = std::fs::read_to_string(out.join("report/index.html")).unwrap();
    // The page escapes '/' (minijinja's HTML escaping).
    let paper = UnshadowedMarch.info().paper.replace('/', "&#x2f;");
    assert!(html.contains(&paper), "its paper ({paper}) is on the page");
    for d in [out, stress_out, cache] {
        let _ = std::fs::remove_dir_all(d);
    }
}
