//! `scatterbench tune` end to end on lavapipe (ARCHITECTURE §4.6): a short tune of two methods
//! on one static scene writes tune.json, tune.md, results.json and the report's tune section;
//! every verdict's winner is under its budget with an interval around its ratio; the error the
//! tune scored on the headline alone (`record::Contender`) is the headline the full record of
//! the same configuration scored through the runner's own path; and bad budgets are refused.

use harness::results::Results;
use harness::testing::{gpu_or_skip, temp_dir};
use harness::tune::{TUNE_FILE, TuneResults};

mod common;
use common::{cli, scatterbench};

#[test]
fn a_short_tune_writes_consistent_verdicts_and_records() {
    if gpu_or_skip().is_none() {
        return;
    }
    let out = temp_dir("tune");
    let out_arg = out.to_string_lossy().into_owned();
    let args = [
        "tune",
        "--scenes",
        "sphere-point",
        "--methods",
        "froxel-fog,wyman-hybrid,no-scatter",
        "--res",
        "32",
        "--time-limit",
        "20",
        "--out",
        &out_arg,
    ];
    let (code, stdout, err) = scatterbench(&args);
    assert_eq!(code, 0, "{err}");
    assert!(
        stdout.contains("| scene | budget | winner | runner-up |"),
        "{stdout}"
    );
    let tune = TuneResults::load(&out.join(TUNE_FILE)).expect("tune.json loads");
    assert_eq!(tune.run.kind.as_deref(), Some("tune"));
    assert_eq!(tune.budgets, vec![0.01, 0.05, 0.10]);
    let scene = &tune.scenes[0];
    assert!(scene.screened.len() >= 2, "{:?}", scene.screened);
    assert_eq!(scene.verdicts.len(), 3);
    let results = Results::load(&out.join("results.json")).expect("results.json loads");
    let mut winners = 0;
    for v in &scene.verdicts {
        let Some(w) = v.winner else { continue };
        winners += 1;
        let c = &scene.candidates[w];
        assert!(c.error <= v.budget, "{c:?} over {}", v.budget);
        let ratio = c.ratio.expect("a winner is timed");
        assert!(
            ratio.low <= ratio.estimate && ratio.estimate <= ratio.high,
            "{ratio:?}"
        );
        // The winner's full record, scored by the runner's path, has the same headline.
        let rec = results
            .records
            .iter()
            .find(|r| r.method == c.method && r.params == c.params)
            .expect("the winner's record is in results.json");
        let full = harness::verdict::headline(rec, "inscatter").expect("scored");
        assert!(
            (full - c.error).abs() <= 1e-9 + 1e-6 * full.abs(),
            "tune {} vs record {full}",
            c.error
        );
        for r in v.runner_up.iter().chain(&v.tie) {
            assert_ne!(scene.candidates[*r].method, c.method);
        }
    }
    assert!(winners > 0, "no verdict had a winner: {:?}", scene.verdicts);
    assert!(results.records.iter().any(|r| r.method == "no-scatter"));
    let page = std::fs::read_to_string(out.join("report/index.html")).expect("the report");
    assert!(page.contains("id=\"tune\""), "no tune section");
    assert!(out.join("tune.md").is_file());
}

#[test]
fn bad_budgets_and_limits_are_refused_naming_the_range() {
    let (code, err) = cli(&["tune", "--budgets", "0.01,-1"]);
    assert_eq!(code, 2);
    assert!(err.contains("(0, 10]"), "{err}");
    let (code, err) = cli(&["tune", "--budgets", "one"]);
    assert_eq!(code, 2);
    assert!(err.contains("not a number"), "{err}");
    let (code, err) = cli(&["tune", "--time-limit", "5"]);
    assert_eq!(code, 2);
    assert!(err.contains("10..=86400"), "{err}");
}
