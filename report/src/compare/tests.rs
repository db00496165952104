//! Two hand-made runs that differ in known ways, compared; every expected number is worked
//! out by hand in the comments.

use std::collections::BTreeMap;
use std::path::PathBuf;

use harness::method::{ParamValue, Params};
use harness::results::{Results, Status};

use super::runs::Run;
use super::*;
use crate::fixture::synthetic::{Measured, record, run};

fn m(time_ms: f64, headline: f64) -> Option<Measured> {
    Some(Measured { time_ms, headline })
}

type Spec<'a> = [(&'a str, &'a str, Option<Measured>)];

fn results(adapter: &str, spec: &Spec) -> Results {
    let mut r = run(adapter, 128);
    let none = Params::new();
    for (scene, method, measured) in spec {
        r.records.push(record(scene, method, &none, *measured));
    }
    r
}

/// Run A and run B. B is slower everywhere, and:
/// - on s1 it reorders m-a against m-b and m-c, and m-a's error moves 4 % (within tolerance)
///   while m-c's goes from 0.004 % to 0.111 % (flagged, as issue 30 measured);
/// - on s2 its floor was skipped, and it has one configuration A lacks.
fn pair() -> Vec<Run> {
    let a = results(
        "lavapipe",
        &[
            ("s1", FLOOR_METHOD, m(10.0, 1.0)),
            ("s1", "m-a", m(20.0, 0.05)),
            ("s1", "m-b", m(30.0, 0.008)),
            ("s1", "m-c", m(40.0, 0.00004)),
            ("s2", FLOOR_METHOD, m(5.0, 1.0)),
            ("s2", "m-a", m(10.0, 0.2)),
            ("s2", "m-b", m(15.0, 0.03)),
            ("s2", "m-c", m(50.0, 0.001)),
        ],
    );
    let mut b = results(
        "SwiftShader",
        &[
            ("s1", FLOOR_METHOD, m(50.0, 1.0)),
            ("s1", "m-a", m(200.0, 0.052)),
            ("s1", "m-b", m(150.0, 0.008)),
            ("s1", "m-c", m(160.0, 0.00111)),
            ("s2", FLOOR_METHOD, None),
            ("s2", "m-a", m(20.0, 0.2)),
            ("s2", "m-b", m(30.0, 0.03)),
            ("s2", "m-c", m(100.0, 0.001)),
        ],
    );
    let mut steps = BTreeMap::new();
    steps.insert("steps".to_string(), ParamValue::Int(512));
    b.records.push(record("s2", "m-a", &steps, m(80.0, 0.01)));
    [a, b]
        .into_iter()
        .enumerate()
        .map(|(i, results)| Run {
            dir: PathBuf::from(format!("run-{i}")),
            label: runs::label(i),
            results,
        })
        .collect()
}

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() < 1e-12
}

#[test]
fn times_are_ratios_to_each_runs_floor() {
    let c = compare(&pair());
    let s1 = &c.scenes[0];
    assert_eq!(s1.scene, "s1");
    assert_eq!(s1.time_basis, "gpu");
    assert_eq!(s1.floor_ms, [Some(10.0), Some(50.0)]);
    let ratios: Vec<[Option<f64>; 2]> = s1
        .rows
        .iter()
        .map(|r| [r.runs[0].ratio, r.runs[1].ratio])
        .collect();
    // 10 20 30 40 ms over 10 ms; 50 200 150 160 ms over 50 ms. The floor's own row comes first.
    assert_eq!(s1.rows[0].method, FLOOR_METHOD);
    assert!(s1.rows[0].floor);
    let want = [[1.0, 1.0], [2.0, 4.0], [3.0, 3.0], [4.0, 3.2]];
    for (got, want) in ratios.iter().zip(want) {
        assert!(
            close(got[0].unwrap(), want[0]) && close(got[1].unwrap(), want[1]),
            "{got:?}"
        );
    }
    // s2: B has no floor, so no ratio there ("—"), while its times are kept.
    let s2 = &c.scenes[1];
    assert_eq!(s2.floor_ms, [Some(5.0), None]);
    assert!(s2.rows.iter().all(|r| r.runs[1].ratio.is_none()));
    assert_eq!(s2.rows[1].runs[1].time_ms, Some(20.0));
    assert_eq!(s2.rows[1].runs[0].ratio, Some(2.0));
}

/// s1: A = 10 20 30 40, B = 50 200 150 160 (floor, m-a, m-b, m-c). Of the 6 pairs, (m-a, m-b)
/// and (m-a, m-c) are discordant: τ = (4 − 2) / 6 = 1/3. s2: B's floor was skipped, so τ is
/// over m-a, m-b, m-c: 10 15 50 vs 20 30 100, all 3 concordant: τ = 1. Mean 2/3; pooled
/// (4 + 3 − 2) / 9 = 5/9.
#[test]
fn kendall_tau_per_scene_and_overall() {
    let c = compare(&pair());
    assert!(close(c.scenes[0].tau[0].tau.unwrap(), 1.0 / 3.0));
    assert_eq!(c.scenes[1].tau[0].counts.items, 3);
    assert_eq!(c.scenes[1].tau[0].tau, Some(1.0));
    let overall = &c.tau[0];
    assert_eq!((overall.a, overall.b, overall.scenes), (0, 1, 2));
    assert!(close(overall.mean.unwrap(), 2.0 / 3.0));
    assert!(close(overall.pooled.unwrap(), 5.0 / 9.0));
}

/// s1, without the floor: A's front is m-a (20, 5 %), m-b (30, 0.8 %), m-c (40, 0.004 %); B's is
/// m-b (150, 0.8 %), m-c (160, 0.111 %): m-a (200, 5.2 %) is slower and worse than m-b.
/// Fastest ≤ 1 %: m-b on both; ≤ 5 %: m-a (exactly 5 %) vs m-b; ≤ 10 %: m-a vs m-b.
/// s2 orders and scores alike on both: nothing changes.
#[test]
fn verdicts_leave_the_floor_out_and_mark_what_changed() {
    let c = compare(&pair());
    let s1 = &c.scenes[0];
    let names =
        |v: &model::Verdict| -> Vec<String> { v.front.iter().map(|p| p.method.clone()).collect() };
    assert_eq!(names(&s1.verdicts[0]), ["m-a", "m-b", "m-c"]);
    assert_eq!(names(&s1.verdicts[1]), ["m-b", "m-c"]);
    let winners = |v: &model::Verdict| -> Vec<String> {
        v.budgets
            .iter()
            .map(|p| p.as_ref().map_or("none".into(), |p| p.method.clone()))
            .collect()
    };
    assert_eq!(winners(&s1.verdicts[0]), ["m-b", "m-a", "m-a"]);
    assert_eq!(winners(&s1.verdicts[1]), ["m-b", "m-b", "m-b"]);
    assert_eq!(
        s1.changed,
        model::Changed {
            front: true,
            budgets: vec![false, true, true]
        }
    );
    let s2 = &c.scenes[1];
    assert!(!s2.changed.any(), "{:?}", s2.changed);
    assert!(
        c.scenes
            .iter()
            .flat_map(|s| &s.verdicts)
            .flat_map(|v| v.front.iter().chain(v.budgets.iter().flatten()))
            .all(|p| p.method != FLOOR_METHOD)
    );
}

/// Only m-c on s1 differs by more than max(2e-4, 10 % of the smaller): 0.111 % − 0.004 % =
/// 0.107 % > 0.02 %. m-a's 5 % vs 5.2 % is within 10 % of 5 %.
#[test]
fn headlines_that_differ_beyond_the_tolerance_are_flagged() {
    let c = compare(&pair());
    assert_eq!(c.headline_flags.len(), 1, "{:?}", c.headline_flags.len());
    let f = &c.headline_flags[0];
    assert_eq!((f.scene.as_str(), f.method.as_str()), ("s1", "m-c"));
    assert_eq!(f.headlines, [Some(0.00004), Some(0.00111)]);
    assert!(close(f.difference, 0.00107) && close(f.allowed, tolerance::ABS));
    let m_a = &c.scenes[0].rows[1];
    assert_eq!(m_a.method, "m-a");
    assert_eq!(m_a.headlines_agree, Some(true));
    // The skipped floor of s2 has one headline only: nothing to compare.
    assert_eq!(c.scenes[1].rows[0].headlines_agree, None);
}

#[test]
fn work_in_one_run_only_and_status_changes_are_listed() {
    let c = compare(&pair());
    assert_eq!(c.not_in_every_run.len(), 1);
    let u = &c.not_in_every_run[0];
    assert_eq!((u.scene.as_str(), u.method.as_str()), ("s2", "m-a"));
    assert_eq!(u.in_runs, ["B"]);
    assert!(u.key.contains("512"));
    // …and left out of the rows: s2 has its 4 common configurations.
    assert_eq!(c.scenes[1].rows.len(), 4);
    assert_eq!(c.status_differs.len(), 1);
    let s = &c.status_differs[0];
    assert_eq!(s.method, FLOOR_METHOD);
    assert_eq!(s.statuses, [Status::Ok, Status::Skipped]);
    assert!(c.notes.is_empty(), "{:?}", c.notes);
}

/// Below 128 px edge rasterisation alone exceeds the tolerance: the comparison says so.
#[test]
fn a_comparison_below_128_px_warns_that_flags_may_be_rasterisation() {
    let mut runs = pair();
    for r in &mut runs {
        r.results.run.resolution = [64, 64];
    }
    let c = compare(&runs);
    assert_eq!(c.notes.len(), 1, "{:?}", c.notes);
    assert!(c.notes[0].contains("at 64 px high") && c.notes[0].contains("128 px"));
}

#[test]
fn json_and_page_state_the_tolerance_and_the_summary_names_the_changes() {
    let c = compare(&pair());
    let json = serde_json::to_value(&c).unwrap();
    assert_eq!(json["schema"], model::SCHEMA);
    assert_eq!(json["tolerance"]["abs"], tolerance::ABS);
    assert_eq!(json["tolerance"]["rel"], tolerance::REL);
    assert_eq!(json["runs"][1]["machine"]["adapter"], "SwiftShader");
    let rule = c.tolerance.rule;
    assert!(rule.contains("2e-4") && rule.contains("10 %"), "{rule}");
    let html = page::render(&c).unwrap();
    assert!(html.contains(&format!("Tolerance: {rule}")));
    let opt = roxmltree::ParsingOptions {
        allow_dtd: true,
        ..Default::default()
    };
    let doc = roxmltree::Document::parse_with_options(&html, opt).expect("well-formed XML");
    let with_class = |tag: &str, class: &str| {
        doc.descendants()
            .filter(|n| n.has_tag_name(tag))
            .filter(|n| {
                n.attribute("class")
                    .is_some_and(|c| c.split(' ').any(|x| x == class))
            })
            .count()
    };
    // Every table that shows or ranks by an error names it: the verdicts' caption in full and
    // each budget head in short, the headline values of the flags, the per-scene heads.
    let label = Metric::Verdict.label(Some(harness::verdict::HEADLINE_NAME));
    assert_eq!(c.metric, label);
    let node_text = |n: roxmltree::Node| -> String {
        n.descendants()
            .filter(|d| d.is_text())
            .filter_map(|d| d.text())
            .collect()
    };
    let table = |class: &str| {
        doc.descendants()
            .find(|n| {
                n.has_tag_name("table")
                    && n.attribute("class")
                        .is_some_and(|c| c.split(' ').any(|x| x == class))
            })
            .unwrap_or_else(|| panic!("no table.{class}"))
    };
    let heads = |t: roxmltree::Node| -> Vec<String> {
        t.descendants()
            .find(|n| n.has_tag_name("tr"))
            .unwrap()
            .children()
            .filter(|c| c.has_tag_name("th"))
            .map(node_text)
            .collect()
    };
    let verdicts = table("verdicts");
    let caption = verdicts
        .children()
        .find(|n| n.has_tag_name("caption"))
        .map(node_text);
    assert_eq!(caption, Some(format!("Ranked by the {label}.")));
    assert_eq!(
        heads(verdicts)[4..],
        [
            "fastest ≤ 1 % headline",
            "fastest ≤ 5 % headline",
            "fastest ≤ 10 % headline"
        ]
    );
    assert!(html.contains(&format!("Values: each run's {label}.")));
    assert_eq!(
        heads(table("ratios"))[3..],
        ["headline A", "headline B", "headlines agree"]
    );
    // s1's front, ≤ 5 % and ≤ 10 % are marked; m-c's row in the flag table and in s1's table.
    assert_eq!(with_class("td", "changed"), 3);
    assert_eq!(with_class("tr", "differ"), 2);
    assert_eq!(with_class("section", "scene"), 2);
    let text = summary::lines(&c).join("\n");
    assert!(text.contains("verdicts changed on 1 of 2 scenes"), "{text}");
    // m-a 20 / 10 ms, m-b 150 / 50 ms: each as a multiple of its own run's floor.
    assert!(
        text.contains("s1: fastest ≤ 5 %: A m-a (2.00× floor), B m-b (3.00× floor)"),
        "{text}"
    );
    assert!(text.contains("s1 m-c: A 0.00400 %, B 0.111 %"), "{text}");
    assert!(
        text.contains("mean τ 0.67 over 2 scenes, pooled τ 0.56"),
        "{text}"
    );
}

fn temp(name: &str) -> PathBuf {
    let d = harness::testing::temp_dir(&format!("compare-{name}"));
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn save(dir: &std::path::Path, r: &Results) {
    r.save(&dir.join("results.json")).unwrap();
}

/// Different work is refused (exit 2 in the CLI), an unreadable file is not a refusal (exit 1).
#[test]
fn runs_of_different_work_are_refused_and_unreadable_files_fail() {
    let root = temp("load");
    let [a, b, c, d] = ["a", "b", "c", "d"].map(|n| root.join(n));
    let mut runs = pair().into_iter().map(|r| r.results);
    let (ra, rb) = (runs.next().unwrap(), runs.next().unwrap());
    for (dir, r) in [(&a, &ra), (&b, &rb)] {
        std::fs::create_dir_all(dir).unwrap();
        save(dir, r);
    }
    let loaded = load(&[a.clone(), b.clone()]).expect("same work");
    assert_eq!(loaded.len(), 2);
    assert_eq!(loaded[1].label, "B");

    let mut other = rb.clone();
    other.run.resolution = [256, 256];
    std::fs::create_dir_all(&c).unwrap();
    save(&c, &other);
    match load(&[a.clone(), c.clone()]) {
        Err(CompareError::Refused(m)) => {
            assert!(
                m.contains("resolution") && m.contains("128x128") && m.contains("256x256"),
                "{m}"
            )
        }
        other => panic!("expected a refusal, got {:?}", other.err()),
    }
    let mut frames = rb.clone();
    frames.run.frames = 10;
    save(&c, &frames);
    assert!(
        matches!(load(&[a.clone(), c.clone()]), Err(CompareError::Refused(m)) if m.contains("frames"))
    );

    // No results.json: a refusal naming the directory; one run: a refusal.
    assert!(
        matches!(load(&[a.clone(), d.clone()]), Err(CompareError::Refused(m)) if m.contains("holds no results.json"))
    );
    assert!(matches!(
        load(std::slice::from_ref(&a)),
        Err(CompareError::Refused(_))
    ));
    // A results.json that does not parse: unreadable.
    std::fs::create_dir_all(&d).unwrap();
    std::fs::write(d.join("results.json"), "{ not json").unwrap();
    assert!(
        matches!(load(&[a, d]), Err(CompareError::Unreadable(m)) if m.contains("results.json"))
    );
    let _ = std::fs::remove_dir_all(root);
}

/// Issue 47: run B's adapter shades fragments 30× slower than invocations (the H200's 4 raster
/// SMs of 132), run A's about as fast; compare flags B, and only B, in compare.json, in the
/// page's runs table and notes, and in the summary.
#[test]
fn a_raster_limited_adapter_is_flagged_in_compare() {
    let cal = |raster: f64, compute: f64| harness::gpu::Calibration {
        raster_fragments_per_s: raster,
        compute_invocations_per_s: compute,
        memory_bytes_per_s: 4e12,
        basis: "gpu".into(),
        ms: 80.0,
    };
    let mut runs = pair();
    runs[0].results.run.machine.calibration = Some(cal(1.0e9, 1.1e9));
    runs[1].results.run.machine.calibration = Some(cal(2.0e11, 6.0e12));
    let c = compare(&runs);
    assert!(c.runs[0].raster_limited.is_none());
    let flag = c.runs[1].raster_limited.as_ref().expect("B flagged");
    assert!(close(flag.ratio, 2.0 / 60.0) && close(flag.others_median, 1.0 / 1.1));
    let json = serde_json::to_value(&c).unwrap();
    assert!(json["runs"][0]["raster_limited"].is_null());
    assert_eq!(
        json["runs"][1]["machine"]["calibration"]["compute_invocations_per_s"],
        6.0e12
    );
    let html = page::render(&c).unwrap();
    assert_eq!(html.matches(">raster-limited</span>").count(), 1, "one flag");
    assert!(html.contains("B is raster-limited"));
    assert!(html.contains("raster 1.00 Gfrag"));
    let text = summary::lines(&c).join("\n");
    assert!(text.contains("flag: B is raster-limited"), "{text}");
    assert!(!text.contains("flag: A"), "{text}");
}
