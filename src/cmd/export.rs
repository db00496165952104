//! `scatterbench export SCENE --gltf OUT.glb`: a scene as binary glTF for Blender or any glTF
//! viewer (`scenes::gltf::export`), written atomically (ARCHITECTURE §8.1).

use std::path::PathBuf;

use anyhow::{Result, anyhow};
use clap::Args;

use crate::args::{refuse, scene};

#[derive(Args)]
pub struct ExportArgs {
    /// The scene: a library name, a variant or a path (ARCHITECTURE §8.2).
    pub scene: String,
    /// Where to write the binary glTF (.glb).
    #[arg(long, value_name = "OUT.glb")]
    pub gltf: PathBuf,
}

pub fn run(a: ExportArgs) -> Result<()> {
    if !a
        .gltf
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("glb"))
    {
        return refuse(format!(
            "--gltf {}: the export is binary glTF; name the file .glb",
            a.gltf.display()
        ));
    }
    let s = scene(&a.scene)?;
    let bytes = scenes::gltf::export::to_glb(&s).map_err(|e| anyhow!("{}: {e}", s.name))?;
    harness::fsutil::write_atomic(&a.gltf, &bytes).map_err(|e| anyhow!(e))?;
    println!(
        "{}: {} objects, {} triangles, {} lights → {} ({} bytes)",
        s.name,
        s.desc.objects.len(),
        s.triangle_count(),
        s.desc.lights.len(),
        a.gltf.display(),
        bytes.len()
    );
    Ok(())
}
