//! The report built from a committed synthetic run (tests/fixtures/results.json + images the
//! fixture generates): every record is on the page, every link resolves to a file, the page
//! and the SVG plots are well-formed XML, nothing is loaded from the network, and the
//! budget table agrees with answers worked out by hand from the fixture's numbers. A second
//! fixture (tests/fixtures/stress-results.json) is a stress run: its page opens with the
//! stability table, whose verdicts are checked against the ones the fixture was written to have.

use std::collections::HashSet;
use std::path::{Path, PathBuf};

use harness::results::{Results, Status};

const FIXTURE: &str = include_str!("fixtures/results.json");
/// A synthetic `scatterbench stress` run: 4 cases × 3 methods with every verdict and fault.
const STRESS_FIXTURE: &str = include_str!("fixtures/stress-results.json");
/// A run of two methods no registry has (as a fork or an external crate would write it):
/// `lantern-cones`, published, and `flat-fog`, a baseline.
const UNREGISTERED_FIXTURE: &str = include_str!("fixtures/unregistered-results.json");

fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("scatterbench-report-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    d
}

fn build(name: &str) -> (PathBuf, Results, String) {
    build_from(name, FIXTURE)
}

fn build_from(name: &str, fixture: &str) -> (PathBuf, Results, String) {
    let dir = tmp(name);
    let results = report::fixture::write(&dir, fixture).expect("fixture");
    let index = report::generate(&dir).expect("report");
    assert_eq!(index, dir.join("report").join("index.html"));
    let html = std::fs::read_to_string(&index).unwrap();
    (dir, results, html)
}

/// The report of `fixture` without `run.<field>`: a results file written before that field.
fn build_without(name: &str, fixture: &str, field: &str) -> (PathBuf, Results, String) {
    let mut v: serde_json::Value = serde_json::from_str(fixture).unwrap();
    v["run"].as_object_mut().unwrap().remove(field);
    build_from(name, &v.to_string())
}

/// Parses strictly as XML; the DOCTYPE is the only DTD allowed.
fn parse(html: &str) -> roxmltree::Document<'_> {
    let opt = roxmltree::ParsingOptions {
        allow_dtd: true,
        ..Default::default()
    };
    roxmltree::Document::parse_with_options(html, opt).expect("index.html is well-formed XML")
}

/// Text content of a node and its descendants.
fn text(n: roxmltree::Node) -> String {
    n.descendants()
        .filter(|d| d.is_text())
        .filter_map(|d| d.text())
        .collect()
}

fn has_class(n: &roxmltree::Node, class: &str) -> bool {
    n.attribute("class")
        .is_some_and(|c| c.split_whitespace().any(|x| x == class))
}

/// Undoes the report's percent-encoding of link paths.
fn percent_decode(s: &str) -> String {
    let b = s.as_bytes();
    let mut out = Vec::new();
    let mut i = 0;
    while i < b.len() {
        if b[i] == b'%' && i + 2 < b.len() {
            let hex = std::str::from_utf8(&b[i + 1..i + 3]).unwrap();
            out.push(u8::from_str_radix(hex, 16).unwrap());
            i += 3;
        } else {
            out.push(b[i]);
            i += 1;
        }
    }
    String::from_utf8(out).unwrap()
}

#[test]
fn page_is_well_formed_and_has_every_record() {
    let (dir, results, html) = build("records");
    let doc = parse(&html);

    // One row per record, in the table of its own scene, naming method, params and status.
    let rows: Vec<roxmltree::Node> = doc
        .descendants()
        .filter(|n| n.has_tag_name("tr") && has_class(n, "record"))
        .collect();
    assert_eq!(rows.len(), results.records.len());
    for r in &results.records {
        let section = doc
            .descendants()
            .find(|n| {
                n.has_tag_name("section")
                    && n.attribute("id") == Some(&report::format::anchor(&r.scene))
            })
            .unwrap_or_else(|| panic!("no section for scene {}", r.scene));
        let params = report::format::params_text(r);
        let status = report::format::status_text(r.status);
        let found = section
            .descendants()
            .filter(|n| n.has_tag_name("tr") && has_class(n, "record"))
            .any(|row| {
                let cells: Vec<String> = row
                    .children()
                    .filter(|c| c.has_tag_name("td"))
                    .map(text)
                    .collect();
                let last = cells.last().unwrap();
                cells[0].trim_end_matches(" ★") == r.method
                    && cells[1].starts_with(&params)
                    && last.starts_with(status)
                    && last[status.len()..] == r.reason.clone().unwrap_or_default()
            });
        assert!(found, "record {} not in the table of {}", r.key(), r.scene);
    }
    // Skipped and failed reasons are shown verbatim (escaped, so "<x>" survives as text).
    assert!(html.contains("needs closed shadow casters"));
    assert!(html.contains("12 non-finite pixels"));
    assert!(text(doc.root()).contains("mode=a&b <x>"));

    // Summary matrix: one row per method, one cell per scene.
    let matrix = doc
        .descendants()
        .find(|n| n.has_tag_name("table") && has_class(n, "matrix"))
        .unwrap();
    let methods: HashSet<&str> = results.records.iter().map(|r| r.method.as_str()).collect();
    let body_rows: Vec<_> = matrix
        .descendants()
        .filter(|n| n.has_tag_name("tr"))
        .skip(1)
        .collect();
    assert_eq!(body_rows.len(), methods.len());
    // The baselines results.json names (raymarch-brute, no-scatter) come last, marked, below
    // a line.
    let baseline_rows: Vec<String> = body_rows
        .iter()
        .filter(|r| has_class(r, "baseline"))
        .map(|r| text(r.children().find(|c| c.has_tag_name("th")).unwrap()))
        .collect();
    assert_eq!(baseline_rows, ["raymarch-brute", "no-scatter"]);
    assert!(
        body_rows
            .iter()
            .rev()
            .take(2)
            .all(|r| has_class(r, "baseline"))
    );
    assert!(has_class(&body_rows[body_rows.len() - 2], "first-baseline"));
    for row in body_rows {
        assert_eq!(row.children().filter(|c| c.has_tag_name("td")).count(), 2);
    }

    // An ordinary run has no stability table.
    assert!(
        !doc.descendants()
            .any(|n| n.attribute("id") == Some("stability"))
    );

    // Machine and run info.
    for s in [
        "Synthetic <test> adapter",
        "Test CPU",
        "Fixture OS",
        "0123456789ab",
        "fixture-2026-01-01T00-00-00Z",
    ] {
        assert!(text(doc.root()).contains(s), "missing {s}");
    }
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn every_link_resolves_and_nothing_is_remote() {
    let (dir, results, html) = build("links");
    let doc = parse(&html);
    let report_dir = dir.join("report");
    let mut checked = 0;
    let mut images = 0;
    for n in doc.descendants().filter(|n| n.is_element()) {
        for attr in ["src", "href"] {
            let Some(v) = n.attribute(attr) else { continue };
            assert!(
                !v.contains("://") && !v.starts_with("//"),
                "remote resource {v}"
            );
            if let Some(id) = v.strip_prefix('#') {
                assert!(
                    doc.descendants().any(|m| m.attribute("id") == Some(id)),
                    "dangling anchor {v}"
                );
                continue;
            }
            let target = report_dir.join(percent_decode(v));
            assert!(
                target.is_file(),
                "{attr}={v} → {} does not exist",
                target.display()
            );
            checked += 1;
            images += usize::from(n.has_tag_name("img"));
        }
    }
    // One Pareto plot per scene and metric (the fixture has no headline or light-core
    // errors: verdict = rel. RMSE, rel. MSE, FLIP), plus the knob-response plots.
    let scenes: HashSet<&str> = results.records.iter().map(|r| r.scene.as_str()).collect();
    let metrics = ["verdict", "rel_mse", "flip"];
    let knob_plots = doc
        .descendants()
        .find(|n| n.attribute("id") == Some("knobs"))
        .map_or(0, |s| {
            s.descendants().filter(|n| n.has_tag_name("img")).count()
        });
    assert_eq!(images, metrics.len() * scenes.len() + knob_plots);
    assert!(checked > images, "PNG/SVG download links are checked too");
    // Every record's image is shipped inside the page for the viewer; the path with a space
    // and an ampersand was read (not reported missing).
    assert!(!html.contains("missing:"));
    let shipped = doc
        .descendants()
        .filter(|n| {
            n.has_tag_name("script") && n.attribute("type") == Some("application/octet-stream")
        })
        .count();
    // Per scene: the reference and each method with an ok, scored record; each AOV shipped.
    let mut viewer_images = 0;
    for s in &scenes {
        let methods: HashSet<&str> = results
            .records
            .iter()
            .filter(|r| &r.scene == s && r.status == Status::Ok)
            .map(|r| r.method.as_str())
            .collect();
        viewer_images += 1 + methods.len();
    }
    assert_eq!(shipped, report::view::VIEWER_AOVS.len() * viewer_images);
    // The plots are real files: well-formed SVG, PNG with the signature.
    for s in &scenes {
        for m in metrics {
            let stem = format!("{}.pareto.{m}", report::format::anchor(s));
            let plots = report_dir.join("plots");
            let svg = std::fs::read_to_string(plots.join(format!("{stem}.svg"))).unwrap();
            let svg_doc = roxmltree::Document::parse(&svg).expect("SVG is well-formed");
            assert_eq!(svg_doc.root_element().tag_name().name(), "svg");
            let png = std::fs::read(plots.join(format!("{stem}.png"))).unwrap();
            assert_eq!(&png[..8], b"\x89PNG\r\n\x1a\n");
        }
    }
    // No script or stylesheet comes from elsewhere.
    assert!(!doc.descendants().any(
        |n| (n.has_tag_name("script") && n.attribute("src").is_some())
            || (n.has_tag_name("link") && n.attribute("rel") == Some("stylesheet"))
    ));
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn missing_images_are_shown_as_missing_not_shipped() {
    let dir = tmp("missing");
    let results = report::fixture::write(&dir, FIXTURE).unwrap();
    // The first method of the first scene shows its most accurate record in the viewer.
    let scene = &results.records[0].scene;
    let r = results
        .records
        .iter()
        .filter(|r| {
            &r.scene == scene && r.status == Status::Ok && r.method == results.records[0].method
        })
        .min_by(|a, b| {
            a.errors["inscatter"]
                .rel_rmse
                .total_cmp(&b.errors["inscatter"].rel_rmse)
        })
        .unwrap();
    let gone = &r.images["inscatter"];
    std::fs::remove_file(dir.join(gone)).unwrap();
    let html = std::fs::read_to_string(report::generate(&dir).unwrap()).unwrap();
    let doc = parse(&html);
    let shown: Vec<String> = doc
        .descendants()
        .filter(|n| n.has_tag_name("span") && text(*n).starts_with("missing:"))
        .map(text)
        .collect();
    assert_eq!(shown.len(), 1, "{shown:?}");
    assert!(
        shown[0].contains(gone.as_str()),
        "the missing path is not shown: {shown:?}"
    );
    // Exactly that image is left out: one data element fewer than the full page.
    let shipped = doc
        .descendants()
        .filter(|n| {
            n.has_tag_name("script") && n.attribute("type") == Some("application/octet-stream")
        })
        .count();
    let (_, _, full) = build("missing-full");
    let full_doc = parse(&full);
    let full_shipped = full_doc
        .descendants()
        .filter(|n| {
            n.has_tag_name("script") && n.attribute("type") == Some("application/octet-stream")
        })
        .count();
    assert_eq!(shipped + 1, full_shipped);
    let _ = std::fs::remove_dir_all(dir);
}

/// Cheapest configuration under each budget, worked out by hand from the fixture:
/// sphere-point (GPU times): ≤1 % only raymarch steps=256 (0.008 at 22 ms); ≤5 % epipolar
/// lines=256 (0.03 at 4.5 ms) beats raymarch steps=64 (0.04 at 6 ms); ≤10 % epipolar
/// lines=64 (0.06 at 3 ms). clear-fog has no GPU times, so wall times: the failed no-scatter
/// record is excluded; ≤1 % nothing; ≤5 % and ≤10 % raymarch steps=64 (0.02 at 7 ms).
#[test]
fn budget_tables_match_hand_worked_answers() {
    let (dir, _, html) = build("budget");
    let doc = parse(&html);
    let table = |scene: &str| -> Vec<Vec<String>> {
        let section = doc
            .descendants()
            .find(|n| n.attribute("id") == Some(&report::format::anchor(scene)))
            .unwrap();
        let t = section
            .descendants()
            .find(|n| n.has_tag_name("table") && has_class(n, "budget"))
            .unwrap();
        t.descendants()
            .filter(|n| n.has_tag_name("tr"))
            .skip(1)
            .map(|row| {
                row.children()
                    .filter(|c| c.has_tag_name("td"))
                    .map(text)
                    .collect()
            })
            .collect()
    };
    let sp = table("sphere-point");
    assert_eq!(sp.len(), 3);
    assert_eq!(
        (sp[0][1].as_str(), sp[0][2].as_str()),
        ("raymarch-brute", "steps=256")
    );
    assert_eq!(
        (sp[1][1].as_str(), sp[1][2].as_str()),
        ("epipolar", "lines=256")
    );
    assert_eq!(
        (sp[2][1].as_str(), sp[2][2].as_str()),
        ("epipolar", "lines=64")
    );
    assert!(sp[1][3].starts_with("4.50 ms (GPU)"), "{:?}", sp[1]);
    let cf = table("clear-fog");
    assert!(cf[0][1].contains("no configuration"), "{:?}", cf[0]);
    assert_eq!(
        (cf[1][1].as_str(), cf[1][2].as_str()),
        ("raymarch-brute", "steps=64")
    );
    assert_eq!(
        (cf[2][1].as_str(), cf[2][2].as_str()),
        ("raymarch-brute", "steps=64")
    );
    assert!(cf[2][3].starts_with("7.00 ms (wall)"), "{:?}", cf[2]);
    // Pareto stars in sphere-point: no-scatter (0.5 ms), raymarch 16 (1.8), epipolar 64 (3.0),
    // epipolar 256 (4.5), raymarch 256 (22); raymarch 64 (6 ms, 0.04) is dominated by
    // epipolar 256 (4.5 ms, 0.03).
    let section = doc
        .descendants()
        .find(|n| n.attribute("id") == Some("scene-sphere-point"))
        .unwrap();
    let mut starred: Vec<String> = section
        .descendants()
        .filter(|n| {
            n.has_tag_name("tr")
                && n.descendants()
                    .any(|c| has_class(&c, "mv-verdict") && text(c).contains('★'))
        })
        .map(|row| {
            let c: Vec<String> = row
                .children()
                .filter(|c| c.has_tag_name("td"))
                .map(text)
                .collect();
            format!("{} {}", c[0].trim_end_matches(" ★"), c[1])
        })
        .collect();
    starred.sort();
    assert_eq!(
        starred,
        [
            "epipolar lines=256",
            "epipolar lines=64",
            "no-scatter (none)",
            "raymarch-brute steps=16",
            "raymarch-brute steps=256"
        ]
    );
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn bad_run_directories_are_clear_errors() {
    let dir = tmp("bad");
    std::fs::create_dir_all(&dir).unwrap();
    let e = report::generate(&dir).unwrap_err().to_string();
    assert!(e.contains("has no results.json"), "{e}");
    std::fs::write(
        dir.join("results.json"),
        "{\"schema_version\": 1, \"run\": 3}",
    )
    .unwrap();
    let e = format!("{:#}", report::generate(&dir).unwrap_err());
    assert!(
        e.contains("results.json") && e.contains("not a scatterbench results file"),
        "{e}"
    );
    let missing = Path::new("/nonexistent/scatterbench/run");
    assert!(report::generate(missing).is_err());
    let _ = std::fs::remove_dir_all(dir);
}

/// The body rows (after the header row) of the first table of class `class`.
fn body_rows<'a, 'i>(
    doc: &'a roxmltree::Document<'i>,
    class: &str,
) -> Vec<roxmltree::Node<'a, 'i>> {
    doc.descendants()
        .find(|n| n.has_tag_name("table") && has_class(n, class))
        .unwrap_or_else(|| panic!("no table of class {class}"))
        .descendants()
        .filter(|n| n.has_tag_name("tr"))
        .skip(1)
        .collect()
}

/// The matrix's method names, top to bottom, each with whether it is marked a baseline and
/// whether the separator line is drawn above it.
fn matrix_rows(doc: &roxmltree::Document) -> Vec<(String, bool, bool)> {
    body_rows(doc, "matrix")
        .into_iter()
        .map(|r| {
            let name = text(r.children().find(|c| c.has_tag_name("th")).unwrap());
            (
                name,
                has_class(&r, "baseline"),
                has_class(&r, "first-baseline"),
            )
        })
        .collect()
}

/// The "Methods" table: per row, the text of each cell (method, paper, summary, medium,
/// baseline).
fn methods_table(doc: &roxmltree::Document) -> Vec<Vec<String>> {
    body_rows(doc, "methods")
        .into_iter()
        .map(|r| r.children().filter(|c| c.is_element()).map(text).collect())
        .collect()
}

/// Methods no registry knows report from results.json alone: their papers, summaries and
/// media are on the page, and the one described as a baseline is ranked below the line.
#[test]
fn methods_no_registry_has_report_with_their_papers_and_baseline_flags() {
    let (dir, results, html) = build_from("unregistered", UNREGISTERED_FIXTURE);
    let doc = parse(&html);
    assert_eq!(
        matrix_rows(&doc),
        [
            ("lantern-cones".to_string(), false, false),
            ("flat-fog".to_string(), true, true)
        ]
    );
    let rows = methods_table(&doc);
    assert_eq!(rows.len(), 2, "{rows:?}");
    for (row, id) in rows.iter().zip(["lantern-cones", "flat-fog"]) {
        let d = &results.run.methods[id];
        let expect = [
            id,
            d.paper.as_deref().unwrap(),
            d.summary.as_deref().unwrap(),
            d.medium.as_deref().unwrap(),
            if d.baseline.unwrap() { "yes" } else { "no" },
        ];
        assert_eq!(row, &expect, "{id}");
    }
    assert!(text(doc.root()).contains("Journal of Invented Graphics 12, 2031"));
    let _ = std::fs::remove_dir_all(dir);
}

/// Results written before `run.methods` (the fixture without it: what older runs wrote) still
/// report: every method's paper, summary, medium and baseline flag read "unknown", and no row
/// is set apart as a baseline, since the file does not say which are. A partial description
/// (the fixture's `tricky` gives only its paper) shows what it gives.
#[test]
fn results_without_method_descriptions_report_unknown() {
    let (dir, results, html) = build_without("no-descriptions", FIXTURE, "methods");
    assert!(results.run.methods.is_empty());
    let doc = parse(&html);
    let matrix = matrix_rows(&doc);
    assert_eq!(matrix.len(), 6);
    assert!(matrix.iter().all(|(_, baseline, line)| !baseline && !line));
    for row in methods_table(&doc) {
        assert_eq!(row[1..], ["unknown"; 4], "{row:?}");
    }
    let _ = std::fs::remove_dir_all(dir);

    let (dir, _, html) = build("partial-description");
    let doc = parse(&html);
    let tricky = methods_table(&doc)
        .into_iter()
        .find(|r| r[0] == "tricky")
        .unwrap();
    assert_eq!(
        tricky[1..],
        [
            "Fixture: a description with only its paper",
            "unknown",
            "unknown",
            "unknown"
        ]
    );
    let _ = std::fs::remove_dir_all(dir);
}

/// The stability table's body rows: (case, [(verdict, fault, cell text)] per method column).
type StabilityRow = (String, Vec<(String, String, String)>);

fn stability_rows(doc: &roxmltree::Document) -> (Vec<String>, Vec<StabilityRow>) {
    let table = doc
        .descendants()
        .find(|n| n.has_tag_name("table") && has_class(n, "stability"))
        .expect("a stability table");
    let header: Vec<String> = table
        .descendants()
        .find(|n| n.has_tag_name("tr"))
        .unwrap()
        .children()
        .filter(|c| c.has_tag_name("th"))
        .map(text)
        .collect();
    let rows = table
        .descendants()
        .filter(|n| n.has_tag_name("tr") && has_class(n, "case"))
        .map(|row| {
            let case = row
                .children()
                .find(|c| c.has_tag_name("th"))
                .unwrap()
                .children()
                .next()
                .and_then(|t| t.text())
                .unwrap()
                .to_string();
            let cells = row
                .children()
                .filter(|c| c.has_tag_name("td"))
                .map(|td| {
                    let class = |k: &str| {
                        td.descendants()
                            .find(|n| has_class(n, k))
                            .map(text)
                            .unwrap_or_default()
                    };
                    (class("verdict"), class("fault"), text(td))
                })
                .collect();
            (case, cells)
        })
        .collect();
    (header, rows)
}

/// Verdicts the stress fixture was written to have (see the comments in its generator's
/// record list): rows in the suite's case order, columns in order of first appearance.
#[test]
fn stress_run_opens_with_a_stability_table_with_the_right_verdicts() {
    let (dir, results, html) = build_from("stress", STRESS_FIXTURE);
    let doc = parse(&html);

    // The stability section comes before every other section.
    let first = doc
        .descendants()
        .find(|n| n.has_tag_name("section"))
        .unwrap();
    assert_eq!(first.attribute("id"), Some("stability"));

    let (header, rows) = stability_rows(&doc);
    assert_eq!(header, ["case", "raymarch-brute", "no-scatter", "epipolar"]);
    // One row per case in the run, each case once, in harness::stress::CASES order.
    let cases: HashSet<&str> = results.records.iter().map(|r| r.scene.as_str()).collect();
    assert_eq!(rows.len(), cases.len());
    let names: Vec<&str> = rows.iter().map(|(c, _)| c.as_str()).collect();
    assert_eq!(
        names,
        [
            "light-near-surface",
            "camera-at-light",
            "sigma-t-1e-6",
            "open-mesh"
        ]
    );

    let expect: [(&str, [(&str, &str); 3]); 4] = [
        (
            "light-near-surface",
            [("pass", ""), ("pass", ""), ("unsupported", "")],
        ),
        (
            "camera-at-light",
            [("fail", ""), ("fail", "wgpu error"), ("fail", "panic")],
        ),
        ("sigma-t-1e-6", [("pass", ""), ("fail", ""), ("fail", "")]),
        (
            "open-mesh",
            [("pass", ""), ("fail", "device lost"), ("absent", "")],
        ),
    ];
    for ((case, cells), (want_case, want)) in rows.iter().zip(expect) {
        assert_eq!(case, want_case);
        let got: Vec<(&str, &str)> = cells
            .iter()
            .map(|(v, f, _)| (v.as_str(), f.as_str()))
            .collect();
        assert_eq!(got, want, "verdicts of {case}");
    }
    let cell = |case: usize, m: usize| rows[case].1[m].2.clone();
    // Error against the declared bound, or "(no bound)"; non-finite pixel counts.
    assert!(cell(2, 0).contains("0.0200 ≤ 0.15"), "{}", cell(2, 0));
    assert!(cell(2, 2).contains("0.250 > 0.1"), "{}", cell(2, 2));
    assert!(cell(0, 1).contains("1.20 (no bound)"), "{}", cell(0, 1));
    assert!(cell(1, 0).contains("non-finite px 12"), "{}", cell(1, 0));
    assert!(cell(0, 0).contains("non-finite px 0"), "{}", cell(0, 0));
    // Unscored failures show no numbers; the reason is in the cell (escaped: "<b> &" survives).
    assert!(cell(1, 1).contains("total rel. RMSE —"), "{}", cell(1, 1));
    assert!(
        cell(1, 1).contains("buffer <b> & binding too small"),
        "{}",
        cell(1, 1)
    );
    assert!(cell(0, 2).contains("needs closed shadow casters"));
    assert!(cell(3, 2).contains("not run"));

    // Every fail and unsupported cell is listed with its full reason below the table; the
    // ok-but-over-bound record gets the stress suite's own wording.
    let details: Vec<Vec<String>> = doc
        .descendants()
        .find(|n| n.has_tag_name("table") && has_class(n, "stability-details"))
        .unwrap()
        .descendants()
        .filter(|n| n.has_tag_name("tr"))
        .skip(1)
        .map(|row| {
            row.children()
                .filter(|c| c.has_tag_name("td"))
                .map(text)
                .collect()
        })
        .collect();
    assert_eq!(details.len(), 7);
    assert!(details.iter().any(|d| d[0] == "sigma-t-1e-6"
        && d[1] == "epipolar"
        && d[4].contains("exceeds the bound 0.1")));
    // The tallies at the top agree with the table: 4 pass, 1 unsupported, 6 fail, 1 absent.
    assert!(text(doc.root()).contains("4 pass, 1 unsupported, 6 fail."));
    // The per-scene sections are still there, after it.
    assert!(
        doc.descendants()
            .any(|n| n.attribute("id") == Some(&report::format::anchor("camera-at-light")))
    );
    let _ = std::fs::remove_dir_all(dir);
}

/// A stress results.json written before `run.kind` existed: recognised by its scene names.
#[test]
fn stress_runs_without_the_marker_are_recognised_by_case_names() {
    let mut v: serde_json::Value = serde_json::from_str(STRESS_FIXTURE).unwrap();
    v["run"].as_object_mut().unwrap().remove("kind");
    let (dir, _, html) = build_from("stress-nokind", &v.to_string());
    let (_, rows) = stability_rows(&parse(&html));
    assert_eq!(rows.len(), 4);
    let _ = std::fs::remove_dir_all(dir);
    // A scene that is not a stress case makes it an ordinary run again.
    v["records"][0]["scene"] = "sphere-point".into();
    let (dir, _, html) = build_from("stress-mixed", &v.to_string());
    assert!(
        !parse(&html)
            .descendants()
            .any(|n| n.attribute("id") == Some("stability"))
    );
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn stress_page_links_resolve() {
    let (dir, _, html) = build_from("stress-links", STRESS_FIXTURE);
    let doc = parse(&html);
    for n in doc.descendants().filter(|n| n.is_element()) {
        for attr in ["src", "href"] {
            let Some(v) = n.attribute(attr) else { continue };
            if let Some(id) = v.strip_prefix('#') {
                assert!(
                    doc.descendants().any(|m| m.attribute("id") == Some(id)),
                    "dangling anchor {v}"
                );
            } else {
                let target = dir.join("report").join(percent_decode(v));
                assert!(target.is_file(), "{attr}={v} does not exist");
            }
        }
    }
    let _ = std::fs::remove_dir_all(dir);
}

/// The equal-error table: per method, its own cheapest configuration under each budget,
/// worked out by hand from the fixture (sphere-point, GPU times).
#[test]
fn per_method_equal_error_table_matches_hand_worked_answers() {
    let (dir, _, html) = build("method-budget");
    let doc = parse(&html);
    let section = doc
        .descendants()
        .find(|n| n.attribute("id") == Some("scene-sphere-point"))
        .unwrap();
    let t = section
        .descendants()
        .find(|n| n.has_tag_name("table") && has_class(n, "budget-methods"))
        .expect("per-method budget table");
    let rows: Vec<(String, Vec<String>)> = t
        .descendants()
        .filter(|n| n.has_tag_name("tr"))
        .skip(1)
        .map(|row| {
            let head = row
                .children()
                .find(|c| c.has_tag_name("th"))
                .map(text)
                .unwrap();
            let cells = row
                .children()
                .filter(|c| c.has_tag_name("td"))
                .map(text)
                .collect();
            (head, cells)
        })
        .collect();
    let get = |m: &str| {
        rows.iter()
            .find(|r| r.0 == m)
            .unwrap_or_else(|| panic!("{m}"))
            .1
            .clone()
    };
    // raymarch-brute: 256 steps (0.008) is the only one ≤ 1 %; 64 steps (0.04) is the cheapest
    // ≤ 5 % and also ≤ 10 % (16 steps is 0.12).
    let rb = get("raymarch-brute");
    assert!(rb[0].starts_with("22.0 ms (steps=256;"), "{rb:?}");
    assert!(rb[1].starts_with("6.00 ms (steps=64;"), "{rb:?}");
    assert!(rb[2].starts_with("6.00 ms (steps=64;"), "{rb:?}");
    // epipolar: nothing ≤ 1 %; 256 lines (0.03) ≤ 5 %; 64 lines (0.06, 3 ms) ≤ 10 %.
    let ep = get("epipolar");
    assert_eq!(ep[0], "none");
    assert!(ep[1].starts_with("4.50 ms (lines=256;"), "{ep:?}");
    assert!(ep[2].starts_with("3.00 ms (lines=64;"), "{ep:?}");
    // no-scatter (error 1.0), a skipped and a failed method: within no budget.
    for m in ["no-scatter", "shadow-volumes", "polynomial"] {
        assert_eq!(get(m), vec!["none"; 3], "{m}");
    }
    let _ = std::fs::remove_dir_all(dir);
}

/// A scaling run (results.json + scaling.json): the page gets the scaling section with one
/// plot per sweep and a slope per method equal to a fit done here, independently, on the
/// fixture's times; a method failed at one point is fitted on the rest and says why.
#[test]
fn scaling_section_fits_the_slopes_of_the_records() {
    let dir = tmp("scaling");
    let mut results = report::fixture::write(&dir, FIXTURE).expect("fixture");
    // Three triangle-count variants; raymarch-brute's time ∝ x^0.25, epipolar's ∝ x^1 with
    // its middle point failed.
    let xs = [1000.0f64, 16000.0, 256000.0];
    let template = results.records[0].clone();
    results.records.clear();
    let mut points = Vec::new();
    for (i, x) in xs.iter().enumerate() {
        let scene = format!("sphere-point-tris{x}");
        points.push(report::scaling::SweepPoint {
            scene: scene.clone(),
            x: *x,
            width: 32,
            height: 32,
            triangles: *x as usize,
        });
        for (m, t) in [
            ("raymarch-brute", 2.0 * x.powf(0.25)),
            ("epipolar", x / 100.0),
        ] {
            let mut r = template.clone();
            r.scene = scene.clone();
            r.method = m.into();
            r.params.clear();
            let timing = r.timing.as_mut().unwrap();
            timing.gpu_ms.as_mut().unwrap().median = t;
            if m == "epipolar" && i == 1 {
                r.status = Status::Failed;
                r.reason = Some("out of memory".into());
                r.timing = None;
            }
            results.records.push(r);
        }
    }
    results.save(&dir.join("results.json")).unwrap();
    report::scaling::Spec {
        base_scene: "sphere-point".into(),
        sweeps: vec![report::scaling::Sweep {
            axis: "triangles".into(),
            label: "caster triangles".into(),
            note: "at 32×32".into(),
            scene: None,
            points,
        }],
    }
    .save(&dir)
    .unwrap();
    let index = report::generate(&dir).expect("report");
    let html = std::fs::read_to_string(&index).unwrap();
    let doc = parse(&html);
    let section = doc
        .descendants()
        .find(|n| n.attribute("id") == Some("scaling"))
        .expect("scaling section");
    let img = section
        .descendants()
        .find(|n| n.has_tag_name("img"))
        .and_then(|n| n.attribute("src"))
        .unwrap();
    assert!(
        dir.join("report").join(percent_decode(img)).is_file(),
        "{img}"
    );
    let table_rows = |class: &str| -> Vec<Vec<String>> {
        section
            .descendants()
            .find(|n| n.has_tag_name("table") && has_class(n, class))
            .unwrap_or_else(|| panic!("no {class} table"))
            .descendants()
            .filter(|n| n.has_tag_name("tr"))
            .skip(1)
            .map(|r| r.children().filter(|c| c.is_element()).map(text).collect())
            .collect()
    };
    let rows = table_rows("scaling");
    // Independent fit: two points suffice for epipolar, slope = Δln t / Δln x = 1.
    let slope = |a: (f64, f64), b: (f64, f64)| (b.1.ln() - a.1.ln()) / (b.0.ln() - a.0.ln());
    let rb = rows.iter().find(|r| r[0] == "raymarch-brute").unwrap();
    let expect = slope(
        (1000.0, 2.0 * 1000f64.powf(0.25)),
        (256000.0, 2.0 * 256000f64.powf(0.25)),
    );
    assert_eq!(rb[4], format!("{expect:.2}"), "{rb:?}");
    let ep = rows.iter().find(|r| r[0] == "epipolar").unwrap();
    assert!(
        ep[2].contains("failed") && ep[2].contains("out of memory"),
        "{ep:?}"
    );
    assert_eq!(
        ep[4],
        format!("{:.2}", slope((1000.0, 10.0), (256000.0, 2560.0)))
    );
    // The slopes side by side repeat each method's fitted exponent under its axis.
    let side_by_side = table_rows("scaling-slopes");
    let rb_slopes = side_by_side
        .iter()
        .find(|r| r[0] == "raymarch-brute")
        .unwrap();
    assert_eq!(rb_slopes[1..], [format!("{expect:.2}")], "{rb_slopes:?}");
    // The errors under the times are the verdict metric's, and the sweep's caption names it
    // (this fixture predates the headline: rel. RMSE).
    let label = report::metric::Metric::Verdict.label(None);
    assert!(
        text(section).contains(&format!("under each time, the record's {label}")),
        "{label}"
    );
    let _ = std::fs::remove_dir_all(dir);
}

/// An animated scene's per-frame section: one line per method, its record of lowest mean
/// headline over the frames (a sweep's worse configuration is not drawn), the plots written and
/// linked; a static scene has none.
#[test]
fn animated_scenes_get_per_frame_error_and_time_plots_of_each_methods_best_record() {
    use harness::results::{ErrorsPerFrame, FrameErrors};
    use report::fixture::synthetic::{Measured, every_pair, params, record};
    let measured = |_, _| {
        Some(Measured {
            time_ms: 5.0,
            headline: 0.02,
        })
    };
    let mut results = every_pair(
        "Synthetic",
        &["walk", "still"],
        &["lag-fog", "exact-fog"],
        &measured,
    );
    let mut worse = params();
    worse.insert("steps".into(), harness::method::ParamValue::Int(8));
    results
        .records
        .push(record("walk", "lag-fog", &worse, measured(0, 0)));
    let last = results.records.len() - 1;
    for (i, r) in results.records.iter_mut().enumerate() {
        if r.scene != "walk" {
            continue;
        }
        // The second lag-fog record (8 steps) is 10× worse on every frame.
        let scale = if i == last { 10.0 } else { 1.0 };
        let frames = (0..6u32)
            .map(|k| {
                let mut errors = r.errors.clone();
                let h = scale * 0.01 * f64::from(k + 1);
                errors.get_mut("inscatter").unwrap().headline = Some(h);
                FrameErrors {
                    frame: k,
                    errors,
                    wall_ms: Some(6.0 + f64::from(k)),
                    gpu_ms: Some(5.0 + f64::from(k)),
                }
            })
            .collect();
        r.errors_per_frame = Some(ErrorsPerFrame::new(frames));
    }
    let dir = tmp("frames");
    report::fixture::write_results(&dir, &results).expect("fixture");
    let index = report::generate(&dir).expect("report");
    let html = std::fs::read_to_string(&index).unwrap();
    let doc = parse(&html);
    let section = |scene: &str| {
        doc.descendants()
            .find(|n| n.attribute("id") == Some(format!("scene-{scene}").as_str()))
            .map(|n| text(n))
            .unwrap_or_default()
    };
    let walk = section("walk");
    assert!(walk.contains("Per frame"), "{walk}");
    assert!(
        walk.contains("steps=128") && !walk.contains("lag-fog steps=8"),
        "{walk}"
    );
    assert!(!section("still").contains("Per frame"));
    for kind in ["error", "time"] {
        let svg = dir.join(format!("report/plots/scene-walk.frames.{kind}.svg"));
        let svg =
            std::fs::read_to_string(&svg).unwrap_or_else(|e| panic!("{}: {e}", svg.display()));
        roxmltree::Document::parse(&svg).expect("well-formed SVG");
        assert!(
            svg.contains("lag-fog") && svg.contains("exact-fog"),
            "{kind}: legend"
        );
        let src = format!("plots/scene-walk.frames.{kind}.svg");
        assert!(
            doc.descendants()
                .any(|n| n.attribute("src") == Some(src.as_str())),
            "{src} is shown"
        );
        if kind == "time" {
            assert!(svg.contains("GPU time"), "every frame has GPU time");
        }
    }
}

/// The text of every element under `root` with tag `tag` and class `class`.
fn texts_of(root: roxmltree::Node, tag: &str, class: &str) -> Vec<String> {
    root.descendants()
        .filter(|n| n.has_tag_name(tag) && has_class(n, class))
        .map(text)
        .collect()
}

/// The header cells (`th` of the first row) of a table.
fn head_cells(table: roxmltree::Node) -> Vec<String> {
    table
        .descendants()
        .find(|n| n.has_tag_name("tr"))
        .map(|tr| {
            tr.children()
                .filter(|c| c.has_tag_name("th"))
                .map(text)
                .collect()
        })
        .unwrap_or_default()
}

/// Every table that ranks by a metric names it, in the rendered page, for every metric of the
/// switch (`mv-<id>`): the verdict tables' captions and budget heads, the matrix's caption,
/// the verdict in words, each scene's budget and equal-error tables, the records' columns,
/// the knob plots' caption and the tune's table; the default view is the verdict metric, the
/// headline. And what a table names is what it ranks by: on "s" the headline and rel. RMSE
/// disagree (m-fast: headline 3 %, rel. RMSE 20 %), so the 5 % winner differs between the
/// headline's table and rel. RMSE's. A run written before the headline names rel. RMSE.
#[test]
fn every_table_names_the_metric_it_ranks_by() {
    use harness::verdict::HEADLINE_NAME;
    use report::fixture::synthetic::{Measured, every_pair, params, record};
    use report::metric::{Metric, available, views};
    let measured = |_, m: usize| {
        let (time_ms, headline) = [(1.0, 1.0), (2.0, 0.03), (8.0, 0.004)][m];
        Some(Measured { time_ms, headline })
    };
    let mut results = every_pair(
        "Synthetic",
        &["s"],
        &["no-scatter", "m-fast", "m-exact"],
        &measured,
    );
    results.records[1]
        .errors
        .get_mut("inscatter")
        .unwrap()
        .rel_rmse = 0.2;
    // A sweep of m-exact's steps: three values, so the knob section has a plot; both slower
    // than steps=128 (8 ms), so they win no budget.
    for (steps, time_ms, headline) in [(16, 10.0, 0.02), (32, 12.0, 0.01)] {
        let mut p = params();
        p.insert("steps".into(), harness::method::ParamValue::Int(steps));
        let m = Measured { time_ms, headline };
        results.records.push(record("s", "m-exact", &p, Some(m)));
    }
    let dir = tmp("metric-names");
    report::fixture::write_results(&dir, &results).expect("fixture");
    report::fixture::synthetic::tune(&results)
        .save(&dir.join(harness::tune::TUNE_FILE))
        .expect("tune.json");
    let html = std::fs::read_to_string(report::generate(&dir).expect("report")).unwrap();
    let doc = parse(&html);
    let metrics = views(Some(HEADLINE_NAME), &available(&results));
    assert_eq!(metrics.len(), 5, "every metric is offered");
    assert_eq!(metrics[0].label, Metric::Verdict.label(Some(HEADLINE_NAME)));
    assert!(metrics[0].label.contains(HEADLINE_NAME) && metrics[0].short == "headline");

    // The default view is the headline: the body shows it, its button is on.
    let body = doc.descendants().find(|n| n.has_tag_name("body")).unwrap();
    assert!(has_class(&body, "metric-verdict"));
    let on: Vec<String> = doc
        .descendants()
        .filter(|n| n.has_tag_name("button") && has_class(n, "on"))
        .map(text)
        .collect();
    assert_eq!(on, [metrics[0].label.clone()]);

    let section = |id: &str| {
        doc.descendants()
            .find(|n| n.attribute("id") == Some(id))
            .unwrap_or_else(|| panic!("no #{id}"))
    };
    let (verdict, matrix, scene) = (section("verdict"), section("matrix"), section("scene-s"));
    for m in &metrics {
        let class = format!("mv-{}", m.id);
        // The verdict table: its caption names the metric in full, each budget head in short.
        let table = verdict
            .descendants()
            .find(|n| n.has_tag_name("table") && has_class(n, &class))
            .unwrap_or_else(|| panic!("no verdict table for {}", m.id));
        assert_eq!(
            texts_of(table, "caption", "small"),
            [format!("Ranked by the {}.", m.label)]
        );
        let heads = head_cells(table);
        let budgets: Vec<&String> = heads
            .iter()
            .filter(|h| h.starts_with("fastest ≤"))
            .collect();
        assert_eq!(budgets.len(), 3, "{heads:?}");
        for h in budgets {
            assert!(h.ends_with(&format!(" {}", m.short)), "{h}");
        }
        // The matrix's caption and the verdict in words.
        let caption = matrix
            .descendants()
            .find(|n| n.has_tag_name("p") && has_class(n, "matrix-metric"))
            .unwrap();
        assert_eq!(
            texts_of(caption, "b", &class),
            std::slice::from_ref(&m.label)
        );
        let words = matrix
            .descendants()
            .find(|n| n.has_tag_name("h3") && has_class(n, "words-head"))
            .unwrap();
        assert_eq!(
            texts_of(words, "span", &class),
            [format!(", by the {}", m.label)]
        );
        // The scene's budget and equal-error tables.
        let div = scene
            .descendants()
            .find(|n| {
                n.has_tag_name("div")
                    && has_class(n, &class)
                    && n.descendants().any(|d| d.has_tag_name("table"))
            })
            .unwrap_or_else(|| panic!("no budget tables for {}", m.id));
        let h3: Vec<String> = div
            .descendants()
            .filter(|n| n.has_tag_name("h3"))
            .map(text)
            .collect();
        assert_eq!(h3.len(), 2);
        for h in &h3 {
            assert!(h.contains(&format!(" {} budget", m.short)), "{h}");
        }
        let budget = div
            .descendants()
            .find(|n| n.has_tag_name("table") && has_class(n, "budget"))
            .unwrap();
        let heads = head_cells(budget);
        assert_eq!(heads[0], format!("{} budget", m.short));
        assert_eq!(heads[heads.len() - 1], m.short);
        assert!(texts_of(div, "p", "small")[0].starts_with(&format!("Ranked by the {}.", m.label)));
        // The records table has a column of it.
        let records = scene
            .descendants()
            .find(|n| n.has_tag_name("table") && has_class(n, "records"))
            .unwrap();
        assert!(head_cells(records).contains(&m.label), "{}", m.label);
    }

    // What the tables name is what they rank by: ≤ 5 % headline is m-fast (3 %), ≤ 5 % rel.
    // RMSE m-exact (m-fast's is 20 %).
    let five_percent = |id: &str| {
        let table = verdict
            .descendants()
            .find(|n| n.has_tag_name("table") && has_class(n, &format!("mv-{id}")))
            .unwrap();
        let row = body_rows_of(table);
        text(
            row[0]
                .children()
                .filter(|c| c.has_tag_name("td"))
                .nth(3)
                .unwrap(),
        )
    };
    assert!(
        five_percent("verdict").starts_with("m-fast"),
        "{}",
        five_percent("verdict")
    );
    assert!(
        five_percent("rel_rmse").starts_with("m-exact"),
        "{}",
        five_percent("rel_rmse")
    );

    // The knob plots and the tune name the headline.
    let knobs = text(section("knobs"));
    assert!(
        knobs.contains(&format!("The {} against", metrics[0].label)),
        "{knobs}"
    );
    let tune = section("tune");
    let table = tune
        .descendants()
        .find(|n| n.has_tag_name("table") && has_class(n, "tune"))
        .unwrap();
    let heads = head_cells(table);
    assert_eq!(
        (heads[1].as_str(), heads[4].as_str()),
        ("headline budget", "headline")
    );
    assert!(text(tune).contains(&format!("in-scatter headline ({HEADLINE_NAME}")));
    let _ = std::fs::remove_dir_all(dir);

    // Before the headline the verdict metric is rel. RMSE, and the tables say so.
    let (dir, old, html) = build("metric-names-old");
    let doc = parse(&html);
    let label = Metric::Verdict.label(None);
    assert!(label.contains("relative RMSE"));
    assert_eq!(views(None, &available(&old))[0].label, label);
    let table = doc
        .descendants()
        .find(|n| n.has_tag_name("table") && has_class(n, "mv-verdict"))
        .unwrap();
    assert_eq!(
        texts_of(table, "caption", "small"),
        [format!("Ranked by the {label}.")]
    );
    assert!(head_cells(table).contains(&"fastest ≤ 1 % rel. RMSE".to_string()));
    let _ = std::fs::remove_dir_all(dir);
}

/// The body rows (after the header row) of `table`.
fn body_rows_of<'a, 'i>(table: roxmltree::Node<'a, 'i>) -> Vec<roxmltree::Node<'a, 'i>> {
    table
        .descendants()
        .filter(|n| n.has_tag_name("tr"))
        .skip(1)
        .collect()
}
