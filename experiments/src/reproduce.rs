//! `scatterbench reproduce` (ARCHITECTURE §9.6): re-creates the papers' headline tables as
//! one results run (with its report) and writes, for each table, the measured configurations
//! and the paper's claim next to the measured value, as ratios within this run, then the
//! equal-error table (each method's cheapest configuration under 1 %, 5 %, 10 % in-scatter
//! relative RMSE per scene).
//!
//! Papers whose method is not in the registry given to [`plan`] get "skipped: method not
//! registered yet".
//! The tables are defined in [`crate::papers`] (scenes may be tessellated variants,
//! `<scene>-sub<L>`, see `scenes::variants`); the text is also written to `OUT/reproduce.md`.

use std::collections::BTreeSet;
use std::fmt::Write as _;

use anyhow::{Result, anyhow};
use harness::Gpu;
use harness::method::{Method, Params, find, parse_knob, resolve_params};
use harness::record::RecordSettings;
use harness::results::{Record, Results, Status, record_key};
use harness::runner::{Event, WorkItem, run_items};
use report::analysis::{self, BUDGETS, TimeBasis};
use scenes::Scene;

use crate::papers::{Config, Experiment, Section, experiments};

/// The methods a plan resolves its configurations against.
type Registry<'r> = &'r [&'static dyn Method];

/// How to measure the tables.
pub struct Options {
    /// Resolution, timed and warm-up frames per configuration, the run directory
    /// (results.json, images, reproduce.md) and the reference cache; no time budget
    /// (ARCHITECTURE §4.2).
    pub record: RecordSettings,
    pub run_id: String,
    /// Worker processes and the watchdog for every record (ARCHITECTURE §6).
    pub isolation: harness::isolate::Isolation,
}

/// The tables that can run with the registered methods, and their joint work list.
pub struct Plan {
    /// The methods the plan was made with (the tables' configurations resolve against it).
    pub registry: Vec<&'static dyn Method>,
    /// What was left out because a method is not registered (printed before the tables).
    pub notes: String,
    pub experiments: Vec<Experiment>,
    pub scenes: Vec<Scene>,
    /// One item per distinct (scene, method, parameter set) over every table.
    pub work: Vec<WorkItem<'static>>,
}

/// The plan for `papers` (names from [`crate::papers::PAPERS`]) over the methods of `registry`.
pub fn plan(papers: &[&str], registry: &[&'static dyn Method]) -> Result<Plan> {
    let mut notes = String::new();
    let mut runnable = Vec::new();
    for mut e in experiments()
        .into_iter()
        .filter(|e| papers.contains(&e.paper))
    {
        let missing: Vec<&str> = e
            .needs
            .iter()
            .copied()
            .filter(|m| find(registry, m).is_none())
            .collect();
        if !missing.is_empty() {
            let _ = writeln!(
                notes,
                "## {}\n\nskipped: method not registered yet: {}\n",
                e.title,
                missing.join(", ")
            );
            continue;
        }
        // Rows of other, optional methods that are not registered are left out, and said so.
        let absent: Vec<&str> = e
            .configs
            .iter()
            .filter(|c| find(registry, c.method).is_none())
            .map(|c| c.label)
            .collect();
        if !absent.is_empty() {
            e.configs.retain(|c| find(registry, c.method).is_some());
            e.claims
                .retain(|c| !absent.contains(&c.faster) && !absent.contains(&c.slower));
            let _ = writeln!(
                notes,
                "note ({}): left out, method not registered: {}\n",
                e.paper,
                absent.join(", ")
            );
        }
        runnable.push(e);
    }
    // One work list for every runnable table, without duplicates.
    let mut scene_names: Vec<&str> = Vec::new();
    for e in &runnable {
        for s in e.scenes {
            if !scene_names.contains(s) {
                scene_names.push(s);
            }
        }
    }
    let scenes: Vec<Scene> = scene_names
        .iter()
        .map(|n| scenes::library::resolve(n).map_err(|e| anyhow!(e)))
        .collect::<Result<_>>()?;
    let mut work: Vec<WorkItem<'static>> = Vec::new();
    let mut keys = BTreeSet::new();
    for e in &runnable {
        for (si, s) in scene_names.iter().enumerate() {
            if !e.scenes.contains(s) {
                continue;
            }
            for c in &e.configs {
                let (entry, params) = resolve(registry, c)?;
                if keys.insert(record_key(s, entry.id(), &params)) {
                    work.push(WorkItem {
                        scene: si,
                        entry,
                        params,
                    });
                }
            }
        }
    }
    // The floor of every scene at its defaults, so each equal-error time has its floor ratio
    // (ARCHITECTURE §4.5); a registry without the floor method prints times alone.
    let floor = Config {
        label: "floor",
        method: analysis::FLOOR_METHOD,
        params: &[],
    };
    if find(registry, floor.method).is_some() {
        let (entry, params) = resolve(registry, &floor)?;
        for (si, s) in scene_names.iter().enumerate() {
            if keys.insert(record_key(s, entry.id(), &params)) {
                work.push(WorkItem {
                    scene: si,
                    entry,
                    params: params.clone(),
                });
            }
        }
    }
    Ok(Plan {
        registry: registry.to_vec(),
        notes,
        experiments: runnable,
        scenes,
        work,
    })
}

/// Runs the plan into `opts.record.out_dir` (results.json, images) and returns the tables' text, which
/// is also written to `OUT/reproduce.md`.
pub fn run(
    gpu: &Gpu,
    plan: &Plan,
    opts: &Options,
    on_event: &mut dyn FnMut(Event),
) -> Result<String> {
    let cfg = crate::run_config(&opts.record, &opts.run_id, &opts.isolation);
    let results =
        run_items(gpu, &plan.scenes, &plan.work, &cfg, None, on_event).map_err(|e| anyhow!(e))?;
    let mut text = plan.notes.clone();
    let _ = writeln!(
        text,
        "# Paper reproductions — {}x{}, {} timed frames, {}\n",
        opts.record.width, opts.record.height, opts.record.frames, results.run.machine.adapter
    );
    let registry = &plan.registry;
    for e in &plan.experiments {
        text.push_str(&match e.section {
            Section::Configs => experiment_text(registry, e, &results, &opts.record.out_dir),
            Section::Triangles => triangles_text(registry, e, &results, &plan.scenes),
            Section::Breakdown => breakdown_text(registry, e, &results),
        });
    }
    text.push_str(&equal_error_text(registry, &results));
    let md = opts.record.out_dir.join("reproduce.md");
    std::fs::write(&md, &text).map_err(|e| anyhow!("{}: {e}", md.display()))?;
    Ok(text)
}

/// A configuration's registry entry and full parameter set.
fn resolve(registry: Registry, c: &Config) -> Result<(&'static dyn Method, Params)> {
    let entry = find(registry, c.method).ok_or_else(|| anyhow!("unknown method {}", c.method))?;
    let mut overrides = Params::new();
    for (k, v) in c.params {
        overrides.insert(k.to_string(), parse_knob(entry, k, v)?);
    }
    Ok((entry, resolve_params(entry, &overrides)?))
}

/// The record of configuration `c` on `scene`, if the run has it.
fn record<'a>(
    registry: Registry,
    results: &'a Results,
    scene: &str,
    c: &Config,
) -> Option<&'a Record> {
    let (entry, params) = resolve(registry, c).ok()?;
    let key = record_key(scene, entry.id(), &params);
    results.records.iter().find(|r| r.key() == key)
}

/// Mean in-scatter luminance of a record over the reference's (1 = unbiased), from the EXRs.
fn mean_ratio(out: &std::path::Path, r: &Record) -> Option<f64> {
    let path = r.images.get("inscatter")?;
    let img = harness::image::io::read_exr(&out.join(path)).ok()?;
    let reference =
        harness::image::io::read_exr(&out.join(format!("{}/reference/inscatter.exr", r.scene)))
            .ok()?;
    let mean = |v: Vec<f32>| v.iter().map(|x| *x as f64).sum::<f64>() / v.len().max(1) as f64;
    let (m, rm) = (mean(img.luminance()), mean(reference.luminance()));
    (rm > 0.0).then(|| m / rm)
}

fn experiment_text(
    registry: Registry,
    e: &Experiment,
    results: &Results,
    out: &std::path::Path,
) -> String {
    let mut t = String::new();
    let _ = writeln!(t, "## {}\n\n{}\n", e.title, e.note);
    for scene in e.scenes {
        let recs: Vec<Option<&Record>> = e
            .configs
            .iter()
            .map(|c| record(registry, results, scene, c))
            .collect();
        let basis = TimeBasis::for_records(recs.iter().flatten().copied());
        let time = |label: &str| -> Option<f64> {
            let i = e.configs.iter().position(|c| c.label == label)?;
            let r = recs[i]?;
            (r.status == Status::Ok).then(|| basis.time_ms(r)).flatten()
        };
        let base = time(e.configs[0].label);
        let _ = writeln!(t, "### {scene} ({})\n", basis.label());
        let _ = writeln!(
            t,
            "| configuration | ms | speed vs {} | in-scatter rel RMSE | mean in-scatter / reference |",
            e.configs[0].label
        );
        let _ = writeln!(t, "|---|---|---|---|---|");
        for (c, r) in e.configs.iter().zip(&recs) {
            match r {
                Some(r) if r.status == Status::Ok => {
                    let ms = time(c.label);
                    let speed = match (base, ms) {
                        (Some(b), Some(m)) if m > 0.0 => format!("{:.2}×", b / m),
                        _ => "-".into(),
                    };
                    let _ = writeln!(
                        t,
                        "| {} | {} | {speed} | {} | {} |",
                        c.label,
                        ms.map_or("-".into(), |m| format!("{m:.2}")),
                        analysis::inscatter_error(r).map_or("-".into(), |v| format!("{v:.4}")),
                        mean_ratio(out, r).map_or("-".into(), |v| format!("{v:.3}"))
                    );
                }
                Some(r) => {
                    let _ = writeln!(
                        t,
                        "| {} | {:?}: {} | | | |",
                        c.label,
                        r.status,
                        r.reason.as_deref().unwrap_or("")
                    );
                }
                None => {
                    let _ = writeln!(t, "| {} | not run | | | |", c.label);
                }
            }
        }
        let _ = writeln!(t);
        for claim in &e.claims {
            if claim.scene.is_some_and(|s| s != *scene) {
                continue;
            }
            let measured = match (time(claim.faster), time(claim.slower)) {
                (Some(f), Some(s)) if f > 0.0 => format!("{:.2}×", s / f),
                _ => "not measured".into(),
            };
            let _ = writeln!(
                t,
                "- {}: {} vs {} — paper {}, measured {measured}",
                claim.what, claim.faster, claim.slower, claim.paper
            );
        }
        let _ = writeln!(t);
    }
    for q in e.qualitative {
        let _ = writeln!(t, "- paper: {q}");
    }
    let _ = writeln!(t);
    t
}

/// The paper's exponent for Biri et al. 2006, Table II: 31 → 7.6 fps over 14 785 → 136 266
/// triangles (direct scattering and shadows).
fn biri_table2_exponent() -> f64 {
    (31.0f64 / 7.6).ln() / (136_266.0f64 / 14_785.0).ln()
}

/// A scene family of Biri 2006 Table II and its measured points: (triangles, silhouette edges,
/// ms) per variant, in the order run.
type Family<'a> = (&'a str, Vec<(f64, f64, f64)>);

/// Biri 2006 Table II: per scene variant its triangles, silhouette edges, shadow-plane
/// counters and time; per family the fitted exponent of time vs triangles and vs silhouette
/// edges, next to the paper's.
fn triangles_text(
    registry: Registry,
    e: &Experiment,
    results: &Results,
    scenes: &[Scene],
) -> String {
    let mut t = String::new();
    let _ = writeln!(t, "## {}\n\n{}\n", e.title, e.note);
    let c = &e.configs[0];
    let recs: Vec<(&str, Option<&Record>)> = e
        .scenes
        .iter()
        .map(|s| (*s, record(registry, results, s, c)))
        .collect();
    let basis = TimeBasis::for_records(recs.iter().filter_map(|r| r.1));
    let _ = writeln!(t, "{} ({})\n", c.method, basis.label());
    let _ = writeln!(
        t,
        "| scene | triangles | silhouette edges | shadow-plane counters | ms | × time of the family's first |"
    );
    let _ = writeln!(t, "|---|---|---|---|---|---|");
    let mut families: Vec<Family> = Vec::new();
    for (scene, r) in &recs {
        let tris = scenes
            .iter()
            .find(|s| s.name == *scene)
            .map_or(0, |s| s.triangle_count());
        let Some(r) = r.filter(|r| r.status == Status::Ok) else {
            let why = r.map_or("not run".to_string(), |r| {
                format!("{:?}: {}", r.status, r.reason.as_deref().unwrap_or(""))
            });
            let _ = writeln!(t, "| {scene} | {tris} | | | {why} | |");
            continue;
        };
        let edges = r.counters.get("silhouette_edges").copied();
        let planes: Vec<String> = r
            .counters
            .iter()
            .filter(|(k, _)| k.contains("plane"))
            .map(|(k, v)| format!("{k}={v:.0}"))
            .collect();
        let ms = basis.time_ms(r);
        let fam = scenes::variants::family(scene);
        if !families.iter().any(|f| f.0 == fam) {
            families.push((fam, Vec::new()));
        }
        let pts = &mut families.iter_mut().find(|f| f.0 == fam).expect("pushed").1;
        if let Some(ms) = ms {
            pts.push((tris as f64, edges.unwrap_or(f64::NAN), ms));
        }
        let first = pts.first().map(|p| p.2);
        let _ = writeln!(
            t,
            "| {scene} | {tris} | {} | {} | {} | {} |",
            edges.map_or("-".into(), |v| format!("{v:.0}")),
            if planes.is_empty() {
                "(none reported)".into()
            } else {
                planes.join(" ")
            },
            ms.map_or("-".into(), |m| format!("{m:.2}")),
            match (ms, first) {
                (Some(m), Some(f)) if f > 0.0 => format!("{:.2}×", m / f),
                _ => "-".into(),
            }
        );
    }
    let _ = writeln!(t);
    let paper = biri_table2_exponent();
    for (fam, pts) in &families {
        if pts.len() < 2 {
            continue;
        }
        let vs_tris: Vec<(f64, f64)> = pts.iter().map(|p| (p.0, p.2)).collect();
        let vs_edges: Vec<(f64, f64)> = pts.iter().map(|p| (p.1, p.2)).collect();
        let fit = |v: &[(f64, f64)]| {
            report::scaling::loglog_fit(v).map_or("not fitted".into(), |f| {
                format!("^{:.2} (r² {:.2})", f.slope, f.r2)
            })
        };
        let (lo, hi) = (pts[0], pts[pts.len() - 1]);
        let _ = writeln!(
            t,
            "- {fam}: time ∝ triangles{} and ∝ silhouette edges{}; {:.0} → {:.0} triangles ({:.1}×) cost {:.2}× the time — paper: time ∝ triangles^{paper:.2} (14 785 → 136 266, 9.2×, cost 4.08×); measured exponent / paper's: {}",
            fit(&vs_tris),
            fit(&vs_edges),
            lo.0,
            hi.0,
            hi.0 / lo.0,
            hi.2 / lo.2,
            report::scaling::loglog_fit(&vs_tris)
                .map_or("-".into(), |f| format!("{:.2}", f.slope / paper))
        );
    }
    for q in e.qualitative {
        let _ = writeln!(t, "- paper: {q}");
    }
    let _ = writeln!(t);
    t
}

/// Biri 2003 Table 1: the method's per-frame phase counters (`*_ms`) as shares of the median
/// wall time, next to the paper's work loads.
fn breakdown_text(registry: Registry, e: &Experiment, results: &Results) -> String {
    let mut t = String::new();
    let _ = writeln!(t, "## {}\n\n{}\n", e.title, e.note);
    let c = &e.configs[0];
    let mut names: Vec<String> = Vec::new();
    let recs: Vec<(&str, Option<&Record>)> = e
        .scenes
        .iter()
        .map(|s| {
            let r = record(registry, results, s, c);
            (*s, r.filter(|r| r.status == Status::Ok))
        })
        .collect();
    for (_, r) in &recs {
        for k in r.iter().flat_map(|r| r.counters.keys()) {
            let timed = k.ends_with("_ms") || k.starts_with("gpu_ms_");
            if timed && !names.contains(k) {
                names.push(k.clone());
            }
        }
    }
    // The paper's column order; anything else after it.
    const ORDER: [&str; 6] = [
        "silhouette_ms",
        "gpu_ms_first_pass",
        "sort_ms",
        "gpu_ms_second_pass_surfaces",
        "gpu_ms_second_pass_volumes",
        "gpu_ms_resolve",
    ];
    names.sort_by_key(|n| ORDER.iter().position(|o| o == n).unwrap_or(ORDER.len()));
    if !names.iter().any(|n| n.starts_with("gpu_ms")) {
        let _ = writeln!(
            t,
            "The method reports no GPU phase counters (gpu_ms_*) yet: only its CPU stages are split out.\n"
        );
    }
    let _ = writeln!(
        t,
        "| scene | wall ms (median) | {} | rest |",
        names.join(" | ")
    );
    let _ = writeln!(t, "|---|---|{}---|", "---|".repeat(names.len()));
    for (scene, r) in &recs {
        let Some(r) = r else {
            let _ = writeln!(t, "| {scene} | not run or not ok | |");
            continue;
        };
        let Some(wall) = r.timing.as_ref().map(|t| t.wall_ms.median) else {
            continue;
        };
        // GPU phases nest inside the frame; CPU stages too (they run inside `render`).
        let mut accounted = 0.0;
        let cells: Vec<String> = names
            .iter()
            .map(|n| match r.counters.get(n) {
                Some(v) => {
                    accounted += v;
                    format!("{v:.2} ms ({:.1} %)", 100.0 * v / wall)
                }
                None => "-".into(),
            })
            .collect();
        let _ = writeln!(
            t,
            "| {scene} | {wall:.2} | {} | {:.1} % |",
            cells.join(" | "),
            100.0 * (1.0 - accounted / wall)
        );
    }
    let _ = writeln!(
        t,
        "\n- paper (30 / 10 triangles per shadow plane): silhouettes 1 % / 1.7 %, first pass 8.7 % / 14 %, ordering 9.6 % / 16 %, second pass surfaces 21.7 % / 33.6 %, volumes 59 % / 34.7 %"
    );
    let _ = writeln!(
        t,
        "- mapping: silhouettes ↔ silhouette_ms, ordering ↔ sort_ms, the passes ↔ gpu_ms_* (when reported)\n"
    );
    t
}

/// Each scene × method: the cheapest configuration of this run under each error budget.
fn equal_error_text(registry: Registry, results: &Results) -> String {
    let mut t = format!(
        "## Equal error: cheapest configuration per method under each in-scatter headline budget\n\n\
         Ranked by the in-scatter headline (`{}`, the verdict metric, ARCHITECTURE §4.4); the \
         % in each cell is that headline. The profile tables above show the in-scatter rel RMSE.\n\n",
        harness::verdict::HEADLINE_NAME
    );
    let mut scenes: Vec<&str> = results.records.iter().map(|r| r.scene.as_str()).collect();
    scenes.dedup();
    let header: Vec<String> = BUDGETS
        .iter()
        .map(|b| format!("≤ {:.0} %", b * 100.0))
        .collect();
    for scene in scenes {
        let recs = analysis::scene_records(results, scene);
        let clock = analysis::Clock::for_records(&recs);
        let _ = writeln!(t, "### {scene} ({})\n", clock.label());
        let _ = match clock.floor_ms {
            Some(f) => writeln!(
                t,
                "Floor ({}, no in-scatter): {f:.2} ms; each time below is also given as a multiple of it \
                 (of the record's own paired floor where it has one: --paired-floor; the time \
                 is then drift-corrected to this floor, ARCHITECTURE §4.5).\n",
                analysis::FLOOR_METHOD
            ),
            None => writeln!(t, "No floor in this run: floor ratios are undefined.\n"),
        };
        let _ = writeln!(t, "| method | {} |", header.join(" | "));
        let _ = writeln!(t, "|---|{}", "---|".repeat(BUDGETS.len()));
        let recs = analysis::contenders(&recs);
        let mut ids: Vec<&str> = recs.iter().map(|r| r.method.as_str()).collect();
        ids.sort();
        ids.dedup();
        for id in ids {
            let mine: Vec<&Record> = recs.iter().copied().filter(|r| r.method == id).collect();
            let pts = analysis::points(&mine, clock);
            let cells: Vec<String> = BUDGETS
                .iter()
                .map(|&b| match analysis::cheapest_under_budget(&pts, b) {
                    Some(p) => format!(
                        "{:.2} ms{} ({}, {:.2} %)",
                        p.time,
                        clock
                            .floor_ratio(mine[p.index])
                            .map(|r| format!(" = {r:.2}× floor"))
                            .unwrap_or_default(),
                        crate::params_text(registry, id, &mine[p.index].params),
                        p.error * 100.0
                    ),
                    None => "none".into(),
                })
                .collect();
            let _ = writeln!(t, "| {id} | {} |", cells.join(" | "));
        }
        let _ = writeln!(t);
    }
    t
}

#[cfg(test)]
mod tests {
    use super::*;
    use report::fixture::synthetic::{Measured, paired_floor, record, run};

    /// A record's equal-error time is divided by its own paired floor where it has one
    /// (`--paired-floor`), else by the scene's floor record: 6 / 3 and 8 / 4 by hand. Times
    /// are shown drift-corrected to the scene's floor, the median paired floor (3 ms): 6 ms
    /// stays, 8 ms beside a 4 ms floor record reads 8 × 3 / 4 = 6 ms.
    #[test]
    fn equal_error_ratios_use_a_records_paired_floor() {
        let none = Params::new();
        let mut results = run("lavapipe", 64);
        let m = |time_ms, headline| Some(Measured { time_ms, headline });
        results
            .records
            .push(record("s", analysis::FLOOR_METHOD, &none, m(4.0, 1.0)));
        let mut paired = record("s", "m-paired", &none, m(6.0, 0.001));
        paired.timing.as_mut().expect("measured").floor = Some(paired_floor(3.0));
        results.records.push(paired);
        results
            .records
            .push(record("s", "m-alone", &none, m(8.0, 0.001)));
        let text = equal_error_text(&[], &results);
        let line = |id: &str| {
            text.lines()
                .find(|l| l.starts_with(&format!("| {id} |")))
                .unwrap_or_else(|| panic!("no row for {id} in\n{text}"))
                .to_string()
        };
        assert!(line("m-paired").contains("6.00 ms = 2.00× floor"), "{text}");
        assert!(line("m-alone").contains("6.00 ms = 2.00× floor"), "{text}");
        assert!(
            text.contains("Floor (no-scatter, no in-scatter): 3.00 ms"),
            "{text}"
        );
        assert!(
            !text.contains(&format!("| {} |", analysis::FLOOR_METHOD)),
            "{text}"
        );
    }
}
