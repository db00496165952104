//! The pages in a real browser (headless Chromium, `--dump-dom`).
//!
//! The viewer: the page built from the synthetic fixture run is opened with `#selftest=X,Y`;
//! the page's self-test drives the first scene's viewer
//! through its real event handlers (wheel and `+` zoom at the pixel, key `1` to a method,
//! `F` to flip back, `E` for the error map), reads the pixel out and writes a JSON verdict
//! into the DOM, which `--dump-dom` prints. This test then checks that verdict against the
//! EXR files on disk, read independently here: the read-out equals the EXR's linear value to
//! the stated half-float precision, the displayed colour is the harness tone map of that
//! value, the flips change what is shown, and the page logged no error.
//!
//! The layout: the report of a run with every library scene and every registered method
//! (generated, the widest a default run can be) and the compare page of two such runs, opened
//! with `#layout` in a 1280 px window, must not scroll sideways (the shared self-check script
//! measures `scrollWidth` against the window and names what sticks out).
//!
//! Chromium is Debian's `chromium` (scripts/test.sh installs it). Without it the tests are
//! skipped with a message — except when `CI` is set, where they fail.

use std::path::{Path, PathBuf};
use std::process::Command;

use harness::image::io::read_exr;
use harness::image::metrics::{ToneMap, quantize_u8};
use harness::results::{Results, Status};
use report::fixture::{self, synthetic};
use serde_json::Value;

const FIXTURE: &str = include_str!("fixtures/results.json");
/// Every registered method id, as `scatterbench list --json` gives them (the root crate's
/// tests/compare.rs fails when the registry and this list part).
const METHOD_IDS: &str = include_str!("fixtures/method-ids.txt");
/// The window width the pages must fit (the `--window-size` of [`dump_dom`]).
const WINDOW: u64 = 1280;
/// The pixel the self-test reads: inside the fixture's glow, so the values are not zero.
const PIXEL: (u32, u32) = (13, 9);

/// Chromium, or None (with a message) when it is not installed and CI is not set.
fn chromium() -> Option<PathBuf> {
    let found = ["/usr/bin/chromium", "/usr/bin/chromium-browser"]
        .iter()
        .map(PathBuf::from)
        .find(|p| p.is_file());
    if found.is_none() {
        if std::env::var_os("CI").is_some() {
            panic!("CI is set and chromium is not installed: run scripts/test.sh (it installs it)");
        }
        eprintln!("browser test skipped: chromium is not installed (apt-get install -y chromium)");
    }
    found
}

fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!(
        "scatterbench-browser-{name}-{}",
        std::process::id()
    ));
    let _ = std::fs::remove_dir_all(&d);
    d
}

/// Runs headless Chromium on `url` and returns (dumped DOM, stderr).
fn dump_dom(chromium: &Path, url: &str, profile: &Path) -> (String, String) {
    let out = Command::new(chromium)
        .args([
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--disable-background-networking",
            "--disable-component-update",
            "--disable-sync",
            "--no-first-run",
            "--enable-logging=stderr",
            "--v=0",
            "--window-size=1280,800",
            // Lets the page's promises (image inflation) and timers finish before the dump.
            "--virtual-time-budget=30000",
        ])
        .arg(format!("--user-data-dir={}", profile.display()))
        .arg("--dump-dom")
        .arg(url)
        .output()
        .expect("running chromium");
    assert!(
        out.status.success(),
        "chromium failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    (
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// The page logged no error (its own record, and Chromium's console on stderr).
fn assert_no_errors(t: &Value, stderr: &str) {
    assert_eq!(t["pageErrors"], serde_json::json!([]), "page errors: {t:#}");
    for line in stderr.lines() {
        assert!(
            !(line.contains("CONSOLE") && (line.contains("Uncaught") || line.contains("Error"))),
            "console error: {line}"
        );
    }
}

/// The self-test's JSON from the dumped DOM (text content is HTML-escaped there).
fn selftest_json(dom: &str) -> Value {
    let start = dom
        .find("<pre id=\"selftest-result\">")
        .unwrap_or_else(|| panic!("no self-test result in the DOM (the script did not finish)"));
    let rest = &dom[start + "<pre id=\"selftest-result\">".len()..];
    let end = rest.find("</pre>").expect("unterminated result");
    let text = rest[..end]
        .replace("&lt;", "<")
        .replace("&gt;", ">")
        .replace("&quot;", "\"")
        .replace("&amp;", "&");
    serde_json::from_str(&text).unwrap_or_else(|e| panic!("self-test JSON {e}: {text}"))
}

fn rgb(v: &Value) -> [f32; 3] {
    let a = v.as_array().unwrap_or_else(|| panic!("not an array: {v}"));
    [0, 1, 2].map(|i| a[i].as_f64().expect("number") as f32)
}

fn shown(v: &Value) -> [u8; 3] {
    let a = v.as_array().unwrap_or_else(|| panic!("not an array: {v}"));
    [0, 1, 2].map(|i| a[i].as_u64().expect("byte") as u8)
}

/// The stated precision: half float (relative 2^-11), absolute 2^-25 for tiny values.
fn assert_half_equal(what: &str, got: [f32; 3], exr: [f32; 3]) {
    for c in 0..3 {
        let tol = exr[c].abs() * 2f32.powi(-11) + 2f32.powi(-25);
        assert!(
            (got[c] - exr[c]).abs() <= tol,
            "{what} channel {c}: viewer read {} but the EXR holds {} (tolerance {tol})",
            got[c],
            exr[c]
        );
    }
}

/// The displayed colour is the tone map of the linear value (±1 for the rounding of 8 bits).
fn assert_displayed(what: &str, got: [u8; 3], tone: &ToneMap, exr: [f32; 3]) {
    let want = tone.apply(exr).map(quantize_u8);
    for c in 0..3 {
        assert!(
            (got[c] as i32 - want[c] as i32).abs() <= 1,
            "{what}: canvas shows {got:?}, the tone-mapped EXR is {want:?}"
        );
    }
}

#[test]
fn viewer_flips_zooms_and_reads_out_the_exr_value() {
    let Some(chromium) = chromium() else {
        return;
    };
    let dir = tmp("viewer");
    let results = report::fixture::write(&dir, FIXTURE).expect("fixture");
    let index = report::generate(&dir).expect("report");
    let profile = dir.join("chromium-profile");
    let url = format!(
        "file://{}#selftest={},{}",
        index.display(),
        PIXEL.0,
        PIXEL.1
    );
    let (dom, stderr) = dump_dom(&chromium, &url, &profile);
    let t = selftest_json(&dom);

    assert_eq!(t["ok"], Value::Bool(true), "self-test failed: {t:#}");
    assert_no_errors(&t, &stderr);
    assert_eq!(t["pixel"]["x"], PIXEL.0);
    assert_eq!(t["pixel"]["y"], PIXEL.1);
    // 32² in a 512² canvas fits at 16×; one wheel notch and one `+` make 64×.
    assert_eq!(t["zoom"].as_f64(), Some(64.0), "{t:#}");

    // Independently: the first scene, its reference, and the first method's shown record
    // (the ok record with the lowest in-scatter error; the fixture has no headline).
    let scene = &results.records[0].scene;
    assert_eq!(t["scene"], Value::String(report::format::anchor(scene)));
    assert_eq!(t["aov"], "in-scatter");
    let at = |path: &Path| {
        let img = read_exr(path).unwrap();
        img.get(PIXEL.0, PIXEL.1)
    };
    let reference = at(&dir.join(scene).join("reference/inscatter.exr"));
    let tone = ToneMap::auto(&read_exr(&dir.join(scene).join("reference/total.exr")).unwrap());
    assert!((t["exposure"].as_f64().unwrap() as f32 - tone.exposure).abs() < 1e-3);
    let first_method = &results
        .records
        .iter()
        .find(|r| &r.scene == scene && r.status == Status::Ok)
        .unwrap()
        .method;
    let record = results
        .records
        .iter()
        .filter(|r| &r.scene == scene && &r.method == first_method && r.status == Status::Ok)
        .min_by(|a, b| {
            a.errors["inscatter"]
                .rel_rmse
                .total_cmp(&b.errors["inscatter"].rel_rmse)
        })
        .unwrap();
    let method = at(&dir.join(&record.images["inscatter"]));
    assert!(
        (0..3).any(|c| (method[c] - reference[c]).abs() > 1e-3 * reference[c].abs()),
        "the fixture's method image must differ from the reference at the pixel"
    );

    // Reference, then key 1 (the first method, compared with the reference), then F back.
    assert!(
        t["reference"]["label"]
            .as_str()
            .unwrap()
            .contains("reference")
    );
    assert_half_equal("reference", rgb(&t["reference"]["rgb"]), reference);
    assert_displayed(
        "reference",
        shown(&t["reference"]["shown"]),
        &tone,
        reference,
    );
    assert!(
        t["method1"]["label"]
            .as_str()
            .unwrap()
            .contains(first_method.as_str()),
        "{t:#}"
    );
    assert_half_equal("method 1", rgb(&t["method1"]["rgb"]), method);
    assert_half_equal(
        "method 1's B",
        rgb(&t["method1"]["comparedWith"]),
        reference,
    );
    assert_displayed("method 1", shown(&t["method1"]["shown"]), &tone, method);
    assert_half_equal("flipped back", rgb(&t["flippedBack"]["rgb"]), reference);
    assert_displayed(
        "flipped back",
        shown(&t["flippedBack"]["shown"]),
        &tone,
        reference,
    );
    // The error map is a different picture from the radiance at that pixel.
    assert_ne!(shown(&t["errorShown"]), shown(&t["reference"]["shown"]));
    // The read-out text names the pixel.
    assert!(
        t["readout"]
            .as_str()
            .unwrap()
            .contains(&format!("pixel ({}, {})", PIXEL.0, PIXEL.1))
    );
    let _ = std::fs::remove_dir_all(dir);
}

fn method_ids() -> Vec<&'static str> {
    METHOD_IDS.lines().filter(|l| !l.is_empty()).collect()
}

/// Opens `page` with `#layout` and returns the page's layout verdict, having checked that the
/// page logged no error and that the window is [`WINDOW`] wide.
fn layout(chromium: &Path, page: &Path, profile: &Path) -> Value {
    let url = format!("file://{}#layout", page.display());
    let (dom, stderr) = dump_dom(chromium, &url, profile);
    let t = selftest_json(&dom);
    assert_no_errors(&t, &stderr);
    assert_eq!(t["layout"]["innerWidth"], WINDOW, "{t:#}");
    t
}

/// No horizontal scroll: the document is no wider than the window's content area.
fn assert_fits(t: &Value) {
    let l = &t["layout"];
    let width = |k: &str| l[k].as_u64().unwrap_or_else(|| panic!("{k} in {t:#}"));
    let (scroll, client) = (width("scrollWidth"), width("clientWidth"));
    assert!(
        scroll <= client && scroll <= WINDOW,
        "the page scrolls sideways in a {WINDOW} px window: scrollWidth {scroll} > {client}; \
         sticking out: {}",
        l["overflowing"]
    );
    assert_eq!(t["ok"], Value::Bool(true), "{t:#}");
}

fn widest(adapter: &str) -> Results {
    synthetic::widest(adapter, &scenes::library::names(), &method_ids())
}

#[test]
fn the_report_of_every_scene_and_method_fits_a_1280_px_window() {
    let Some(chromium) = chromium() else {
        return;
    };
    let scenes = scenes::library::names();
    let dir = tmp("widest");
    let run = widest("llvmpipe (LLVM 15.0.6, 256 bits)");
    fixture::write_results(&dir, &run).expect("fixture");
    // The run is as wide as promised: the first scene's front lists every ok method but the
    // floor, which is no contender (ARCHITECTURE §4.5).
    let tables = report::verdict::tables(&run, &[report::metric::Metric::Verdict]);
    let ok = |s: &str| {
        run.records
            .iter()
            .filter(|r| r.scene == s && r.status == Status::Ok)
            .filter(|r| r.method != report::analysis::FLOOR_METHOD)
            .count()
    };
    assert_eq!(tables[0].rows[0].front.len(), ok(scenes[0]));
    assert!(method_ids().len() >= 11 && scenes.len() >= 14);

    let index = report::generate(&dir).expect("report");
    let t = layout(&chromium, &index, &dir.join("chromium-profile"));
    assert_fits(&t);
    let counts = &t["layout"]["counts"];
    assert_eq!(counts["section.scene"], scenes.len(), "{t:#}");
    assert_eq!(counts["table.records"], scenes.len(), "{t:#}");
    assert_eq!(counts["table.matrix"], 1, "{t:#}");
    assert!(counts["table.verdicts"].as_u64() >= Some(1), "{t:#}");
    // The matrix fits without scrolling inside its box either.
    let scrolling = t["layout"]["scrolling"].as_array().expect("scrolling");
    assert!(
        !scrolling
            .iter()
            .any(|s| s.as_str().unwrap().contains("matrix")),
        "{t:#}"
    );
    let _ = std::fs::remove_dir_all(dir);
}

/// Two runs of every scene × method: B is 5× slower, its order reversed on the first scene,
/// and the longest-named method's error 30× larger on the second (which changes that
/// scene's verdict). The page must fit and show exactly the changes the comparison found.
#[test]
fn the_compare_page_of_every_scene_and_method_fits_and_marks_the_changes() {
    let Some(chromium) = chromium() else {
        return;
    };
    let scenes = scenes::library::names();
    let root = tmp("compare");
    let a = widest("llvmpipe (LLVM 15.0.6, 256 bits)");
    let mut b = widest("SwiftShader Device (Subzero) (0x0000C0DE)");
    let longest = method_ids().into_iter().max_by_key(|m| m.len()).unwrap();
    for r in &mut b.records {
        let reverse = r.scene == scenes[0];
        if let Some(t) = r.timing.as_mut() {
            for stat in [Some(&mut t.wall_ms), t.gpu_ms.as_mut()]
                .into_iter()
                .flatten()
            {
                stat.median = if reverse {
                    10_000.0 - stat.median
                } else {
                    5.0 * stat.median
                };
            }
        }
        if r.scene == scenes[1] && r.method == longest {
            let e = r.errors.get_mut("inscatter").unwrap();
            e.headline = e.headline.map(|h| 30.0 * h);
        }
    }
    let dirs = [root.join("a"), root.join("b")];
    for (dir, run) in dirs.iter().zip([&a, &b]) {
        std::fs::create_dir_all(dir).unwrap();
        run.save(&dir.join("results.json")).unwrap();
    }
    let runs = report::compare::load(&dirs).expect("same work");
    let c = report::compare::compare(&runs);
    assert_eq!(c.scenes[0].tau[0].tau, Some(-1.0));
    assert_eq!(c.scenes[2].tau[0].tau, Some(1.0));
    assert_eq!(c.headline_flags.len(), 1);
    assert!(c.scenes[1].changed.any());
    let written = report::compare::write(&root.join("out"), &c).expect("written");

    let t = layout(&chromium, &written.html, &root.join("chromium-profile"));
    assert_fits(&t);
    let counts = &t["layout"]["counts"];
    let changed: usize = c
        .scenes
        .iter()
        .map(|s| usize::from(s.changed.front) + s.changed.budgets.iter().filter(|&&b| b).count())
        .sum();
    assert!(changed > 0);
    assert_eq!(counts["td.changed"], changed, "{t:#}");
    // The flagged record: once in the flag table, once in its scene's table.
    assert_eq!(counts["tr.differ"], 2, "{t:#}");
    assert_eq!(counts["section.scene"], scenes.len(), "{t:#}");
    // Runs, τ, verdicts, flags, and one table per scene.
    assert_eq!(counts["table"], 4 + scenes.len(), "{t:#}");
    let _ = std::fs::remove_dir_all(root);
}
