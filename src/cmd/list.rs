//! `scatterbench list [--json]`: scenes with their features (and methods, once registered).

use anyhow::{Result, anyhow};

pub fn run(json: bool) -> Result<()> {
    let mut scenes_out = Vec::new();
    for name in scenes::library::names() {
        let s = scenes::library::resolve(name).map_err(|e| anyhow!(e))?;
        scenes_out.push((s.name.clone(), s.desc.description.clone(), s.features()));
    }
    if json {
        let v = serde_json::json!({
            "scenes": scenes_out.iter().map(|(n, d, f)| serde_json::json!({"name": n, "description": d, "features": f})).collect::<Vec<_>>(),
            "methods": super::run::methods_json(),
        });
        println!("{}", serde_json::to_string_pretty(&v)?);
        return Ok(());
    }
    println!("scenes:");
    for (n, d, f) in &scenes_out {
        println!("  {n:<20} {d}");
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
    super::run::print_methods();
    Ok(())
}
