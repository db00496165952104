//! `scatterbench list [--json]`: scenes with their features; methods with their knobs and
//! support per library scene (ARCHITECTURE §8.1).

use std::collections::BTreeMap;

use anyhow::{Result, anyhow};
use clap::Args;

use crate::registry::Registry;

#[derive(Args)]
pub struct ListArgs {
    /// Print JSON instead of a table.
    #[arg(long)]
    pub json: bool,
    /// Scenes to list instead of the library: comma-separated names, variants or paths
    /// (.json, .gltf, .glb), as for `run --scenes`.
    #[arg(long)]
    pub scenes: Option<String>,
}

pub fn run(a: ListArgs, registry: Registry) -> Result<()> {
    let mut scenes_out = Vec::new();
    if let Some(spec) = &a.scenes {
        scenes_out = crate::args::pick_scenes(spec)?;
    }
    for name in scenes::library::names()
        .into_iter()
        .filter(|_| a.scenes.is_none())
    {
        let s = scenes::library::resolve(name).map_err(|e| anyhow!(e))?;
        scenes_out.push(s);
    }
    if a.json {
        let v = serde_json::json!({
            "scenes": scenes_out.iter().map(|s| serde_json::json!({"name": s.name, "description": s.desc.description, "features": s.features(), "ignored": s.ignored})).collect::<Vec<_>>(),
            "methods": methods_json(registry, &scenes_out),
        });
        println!("{}", serde_json::to_string_pretty(&v)?);
        return Ok(());
    }
    println!("scenes:");
    for s in &scenes_out {
        let f = s.features();
        println!("  {:<20} {}", s.name, s.desc.description);
        println!(
            "  {:<20} lights: {} | phase: {} | occluders: {} | textured light: {} | animated: {} | {} triangles",
            "",
            f.light_kinds.join("+"),
            f.phase,
            f.volumetric_occluders,
            f.textured_light,
            f.animated,
            f.triangles
        );
        if f.height_fog {
            println!(
                "  {:<20} medium: homogeneous with exponential height fog",
                ""
            );
        }
        for line in &s.ignored {
            println!("  {:<20} ignored: {line}", "");
        }
    }
    print_methods(registry);
    Ok(())
}

/// Every method of `registry`: id, paper, summary, baseline, medium, knobs, and its support of
/// each library scene.
fn methods_json(registry: Registry, library: &[scenes::Scene]) -> serde_json::Value {
    serde_json::Value::Array(
        registry
            .iter()
            .map(|m| {
                let info = m.info();
                let support: BTreeMap<String, serde_json::Value> = library
                    .iter()
                    .map(|s| (s.name.clone(), serde_json::to_value(m.support(&s.features(), wgpu::Features::all())).unwrap_or_default()))
                    .collect();
                serde_json::json!({"id": info.id, "paper": info.paper, "summary": info.summary, "baseline": info.baseline, "medium": info.medium, "params": m.knobs(), "support": support})
            })
            .collect(),
    )
}

fn print_methods(registry: Registry) {
    println!("methods:");
    for m in registry {
        let info = m.info();
        let baseline = if info.baseline { " (baseline)" } else { "" };
        println!("  {:<20} {}{baseline}", info.id, info.summary);
        for p in m.knobs() {
            let sweep: Vec<String> = p.sweep.iter().map(|v| v.to_string()).collect();
            println!(
                "  {:<20}   {} = {} ({}; sweep: {}) — {}",
                "",
                p.name,
                p.default,
                p.allowed(),
                if sweep.is_empty() {
                    "-".into()
                } else {
                    sweep.join(", ")
                },
                p.meaning
            );
        }
    }
}
