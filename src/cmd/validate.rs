//! `scatterbench validate FILE...`: every problem of every file, exit 2 if any (ARCHITECTURE
//! §6, §8.3).

use std::path::PathBuf;

use anyhow::Result;
use clap::Args;

use crate::args::refuse;

#[derive(Args)]
pub struct ValidateArgs {
    /// Scene files (.json, or .gltf/.glb as scenes by themselves).
    #[arg(required = true)]
    pub files: Vec<PathBuf>,
}

pub fn run(a: ValidateArgs) -> Result<()> {
    let mut bad = 0;
    for f in &a.files {
        match scenes::load_scene(f) {
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
            "{bad} of {} scene files have problems",
            a.files.len()
        ));
    }
    Ok(())
}
