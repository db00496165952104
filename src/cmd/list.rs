//! `scatterbench list [--json]`: scenes with their features; methods with their knobs and
//! support per library scene (ARCHITECTURE §8.1).

use std::collections::BTreeMap;

use anyhow::{Result, anyhow};
use clap::Args;

#[derive(Args)]
pub struct ListArgs {
    /// Print JSON instead of a table.
    #[arg(long)]
    pub json: bool,
}

pub fn run(a: ListArgs) -> Result<()> {
    let mut scenes_out = Vec::new();
    for name in scenes::library::names() {
        let s = scenes::library::resolve(name).map_err(|e| anyhow!(e))?;
        scenes_out.push(s);
    }
    if a.json {
        let v = serde_json::json!({
            "scenes": scenes_out.iter().map(|s| serde_json::json!({"name": s.name, "description": s.desc.description, "features": s.features()})).collect::<Vec<_>>(),
            "methods": methods_json(&scenes_out),
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
    }
    print_methods();
    Ok(())
}

/// Every registered method: id, paper, summary, knobs, and its support of each library scene.
fn methods_json(library: &[scenes::Scene]) -> serde_json::Value {
    serde_json::Value::Array(
        methods::REGISTRY
            .iter()
            .map(|m| {
                let info = m.info();
                let support: BTreeMap<String, serde_json::Value> = library
                    .iter()
                    .map(|s| (s.name.clone(), serde_json::to_value(m.support(&s.features(), wgpu::Features::all())).unwrap_or_default()))
                    .collect();
                serde_json::json!({"id": info.id, "paper": info.paper, "summary": info.summary, "params": m.knobs(), "support": support})
            })
            .collect(),
    )
}

fn print_methods() {
    println!("methods:");
    for m in methods::REGISTRY {
        let info = m.info();
        println!("  {:<20} {}", info.id, info.summary);
        for p in m.knobs() {
            let sweep: Vec<String> = p.sweep.iter().map(|v| v.to_string()).collect();
            println!(
                "  {:<20}   {} = {} ({}; sweep: {}) — {}",
                "",
                p.name,
                p.default,
                p.range,
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
