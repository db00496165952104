//! Light leaking through walls, measured from a run's images (scenes/README.md, `corridor-walk`).
//!
//! Run the methods on scenes where the reference is exactly dark behind a wall — the
//! `scenes/probes/corridor-lamp-*.json` probes: the corridor lit only by the lamp behind its
//! 3 cm wall, whose light enters through the doorway alone — then
//!
//! ```text
//! cargo run --release -p harness --example wall_leak -- RUN_DIR
//! ```
//!
//! For each record, from its frame-0 `inscatter` against the scene's reference (radiance averaged
//! over RGB; `peak` the reference's 99th percentile; the dark set D = pixels where the reference
//! is ≤ 1e-3 · peak, i.e. no lamp light reaches any point of their ray):
//! - `leak` = Σ_D method / Σ_all reference: the light a method shows where there is none, as a
//!   share of all the in-scattered lamp light the frame really holds;
//! - `glowing` = the share of D where the method shows more than 1 % of the peak (a visible leak);
//! - `max` = the brightest pixel of D / peak.
//!
//! Prints one Markdown row per scene × record and, per method, the mean over the scenes.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use harness::image::Image;
use harness::image::io::read_exr;

fn grey(img: &Image) -> Vec<f64> {
    img.pixels
        .iter()
        .map(|p| {
            p.iter()
                .map(|&c| if c.is_finite() { c as f64 } else { 0.0 })
                .sum::<f64>()
                / 3.0
        })
        .collect()
}

/// (leak, glowing, max) of `method` against `reference`, or None when the reference is all dark.
fn leak(method: &[f64], reference: &[f64]) -> Option<(f64, f64, f64)> {
    let mut sorted = reference.to_vec();
    sorted.sort_by(f64::total_cmp);
    let peak = sorted[(sorted.len() - 1) * 99 / 100];
    let total: f64 = reference.iter().sum();
    if peak <= 0.0 || total <= 0.0 {
        return None;
    }
    let dark: Vec<usize> = (0..reference.len())
        .filter(|&i| reference[i] <= 1e-3 * peak)
        .collect();
    if dark.is_empty() {
        return Some((0.0, 0.0, 0.0));
    }
    let leaked: f64 = dark.iter().map(|&i| method[i].max(0.0)).sum();
    let glowing = dark.iter().filter(|&&i| method[i] > 1e-2 * peak).count();
    let max = dark.iter().map(|&i| method[i]).fold(0.0, f64::max);
    Some((
        leaked / total,
        glowing as f64 / dark.len() as f64,
        max / peak,
    ))
}

fn read(run: &Path, rel: &str) -> Result<Vec<f64>, String> {
    Ok(grey(&read_exr(&run.join(rel))?))
}

fn main() -> Result<(), String> {
    let run = PathBuf::from(std::env::args().nth(1).ok_or("usage: wall_leak RUN_DIR")?);
    let text = std::fs::read_to_string(run.join("results.json"))
        .map_err(|e| format!("{}: {e}", run.join("results.json").display()))?;
    let results: serde_json::Value = serde_json::from_str(&text).map_err(|e| e.to_string())?;
    let records = results["records"]
        .as_array()
        .ok_or("results.json: no records")?;
    let mut per_method: BTreeMap<String, Vec<(f64, f64, f64)>> = BTreeMap::new();
    println!("| scene | method | leak | glowing | max / peak |\n|---|---|---|---|---|");
    for r in records {
        let (scene, method) = (
            r["scene"].as_str().unwrap_or("?"),
            r["method"].as_str().unwrap_or("?"),
        );
        let Some(img) = r["images"]["inscatter"].as_str() else {
            println!("| {scene} | {method} | {} | | |", r["status"]);
            continue;
        };
        let reference = read(&run, &format!("{scene}/reference/inscatter.exr"))?;
        let Some(l) = leak(&read(&run, img)?, &reference) else {
            println!("| {scene} | {method} | reference all dark | | |");
            continue;
        };
        println!(
            "| {scene} | {method} | {:.2} % | {:.1} % | {:.3} |",
            100.0 * l.0,
            100.0 * l.1,
            l.2
        );
        per_method.entry(method.to_string()).or_default().push(l);
    }
    println!("\n| method | mean leak | mean glowing | worst max / peak |\n|---|---|---|---|");
    for (m, ls) in &per_method {
        let n = ls.len() as f64;
        println!(
            "| {m} | {:.2} % | {:.1} % | {:.3} |",
            100.0 * ls.iter().map(|l| l.0).sum::<f64>() / n,
            100.0 * ls.iter().map(|l| l.1).sum::<f64>() / n,
            ls.iter().map(|l| l.2).fold(0.0, f64::max)
        );
    }
    Ok(())
}
