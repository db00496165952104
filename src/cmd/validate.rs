//! `scatterbench validate FILE...`: every problem of every file, exit 2 if any.

use std::path::PathBuf;
use std::process::ExitCode;

pub fn run(files: &[PathBuf]) -> ExitCode {
    let mut bad = 0;
    for f in files {
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
        eprintln!("{bad} of {} scene files have problems", files.len());
        ExitCode::from(2)
    } else {
        ExitCode::SUCCESS
    }
}
