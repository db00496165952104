//! `scatterbench validate SCENE...`: every problem of every scene file, exit 2 if any
//! (ARCHITECTURE §6, §8.3). A name that is not a file is a scene name (a library scene or a
//! variant, §8.2), as everywhere a scene is expected.

use std::path::PathBuf;

use anyhow::Result;
use clap::Args;

use crate::args::refuse;

#[derive(Args)]
pub struct ValidateArgs {
    /// Scene files (.json, or .gltf/.glb as scenes by themselves), or scene names (a library
    /// scene or a variant, as `list` shows them).
    #[arg(required = true, value_name = "SCENE")]
    pub files: Vec<PathBuf>,
}

pub fn run(a: ValidateArgs) -> Result<()> {
    let mut bad = 0;
    for f in &a.files {
        let loaded = if f.exists() {
            scenes::load_scene(f).map_err(|e| e.to_string())
        } else {
            scenes::library::resolve(&f.to_string_lossy())
        };
        match loaded {
            Ok(s) => println!(
                "{}: ok ({} objects, {} triangles, {} lights)",
                f.display(),
                s.desc.objects.len(),
                s.triangle_count(),
                s.desc.lights.len()
            ),
            Err(e) => {
                bad += 1;
                eprintln!("{e}");
            }
        }
    }
    if bad > 0 {
        return refuse(format!(
            "{bad} of {} scenes have problems",
            a.files.len()
        ));
    }
    Ok(())
}
