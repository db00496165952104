//! The few lines `scatterbench compare` prints: who was compared, τ, the verdicts that
//! changed, the headlines that differ, and what was left out.

use super::model::{Comparison, Pick, SceneComparison};
use super::page::percent;

/// "biri-polynomial (7.75× floor)"; the ratio is left out where the pick has no floor.
fn pick_text(p: Option<&Pick>) -> String {
    let Some(p) = p else {
        return "none".into();
    };
    match p.floor_ratio {
        Some(r) => format!("{} ({} floor)", p.method, crate::verdict::times_floor(r)),
        None => p.method.clone(),
    }
}

/// "window-sun: fastest ≤ 1 %: A biri-polynomial (7.75× floor), B biri-shadow-volumes (4.80× floor)".
fn changed_lines(s: &SceneComparison, labels: &[&str], budgets: &[f64]) -> Vec<String> {
    let per_run = |f: &dyn Fn(usize) -> String| {
        labels
            .iter()
            .enumerate()
            .map(|(i, l)| format!("{l} {}", f(i)))
            .collect::<Vec<_>>()
            .join(", ")
    };
    let mut out = Vec::new();
    if s.changed.front {
        out.push(format!(
            "{}: Pareto front: {}",
            s.scene,
            per_run(&|i| {
                let names: Vec<&str> = s.verdicts[i]
                    .front
                    .iter()
                    .map(|p| p.method.as_str())
                    .collect();
                format!("[{}]", names.join(", "))
            })
        ));
    }
    for (b, budget) in budgets.iter().enumerate() {
        if s.changed.budgets[b] {
            out.push(format!(
                "{}: fastest ≤ {}: {}",
                s.scene,
                crate::verdict::pct(*budget),
                per_run(&|i| pick_text(s.verdicts[i].budgets[b].as_ref()))
            ));
        }
    }
    out
}

/// The summary, one line per entry.
pub fn lines(c: &Comparison) -> Vec<String> {
    let labels: Vec<&str> = c.runs.iter().map(|r| r.label.as_str()).collect();
    let mut out: Vec<String> = c
        .runs
        .iter()
        .map(|r| format!("{} = {} ({})", r.label, r.machine.adapter, r.dir))
        .collect();
    for r in &c.runs {
        if let Some(c) = &r.machine.calibration {
            out.push(format!("{} calibration: {}", r.label, crate::calibration::text(c)));
        }
        if let Some(f) = &r.raster_limited {
            out.push(format!("flag: {}", f.message));
        }
    }
    let tau = |t: Option<f64>| t.map_or("—".to_string(), |t| format!("{t:.2}"));
    for t in &c.tau {
        out.push(format!(
            "rank agreement {}–{}: mean τ {} over {} scenes, pooled τ {}",
            labels[t.a],
            labels[t.b],
            tau(t.mean),
            t.scenes,
            tau(t.pooled)
        ));
    }
    let changed: Vec<String> = c
        .scenes
        .iter()
        .flat_map(|s| changed_lines(s, &labels, &c.budgets))
        .collect();
    let changed_scenes = c.scenes.iter().filter(|s| s.changed.any()).count();
    out.push(format!(
        "verdicts changed on {changed_scenes} of {} scenes",
        c.scenes.len()
    ));
    out.extend(changed.into_iter().map(|l| format!("  {l}")));
    out.push(format!(
        "headlines differing beyond the tolerance (max({:e}, {} % of the smaller)): {}",
        c.tolerance.abs,
        c.tolerance.rel * 100.0,
        c.headline_flags.len()
    ));
    for f in &c.headline_flags {
        let values: Vec<String> = f
            .headlines
            .iter()
            .zip(&labels)
            .map(|(h, l)| format!("{l} {}", h.map_or("—".into(), percent)))
            .collect();
        out.push(format!(
            "  {} {}: {} (allowed {})",
            f.scene,
            f.method,
            values.join(", "),
            percent(f.allowed)
        ));
    }
    out.push(format!(
        "not in every run: {}; status differs: {}",
        c.not_in_every_run.len(),
        c.status_differs.len()
    ));
    out.extend(c.notes.iter().map(|n| format!("note: {n}")));
    out
}
