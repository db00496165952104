//! The bundle (issue 30): `scripts/bundle.sh` writes a directory that runs the benchmark on
//! another machine without a Rust toolchain. Here: a small bundle (two scenes at 64², this
//! test's own release binary) is built, moved to another directory (the original deleted, so
//! nothing can reach back into the build tree), and its `run.sh` runs there on lavapipe. The
//! records must be ok for every method that supports the scene, the references must come from
//! the bundle's cache (none rendered), and the report must be written.
//!
//! Without an adapter the run part skips with a message — except when `CI` is set.

use std::path::Path;
use std::process::Command;

use harness::results::{Results, Status};

const SCENES: &str = "sphere-point,clear-fog";

fn sh(cmd: &mut Command) -> std::process::Output {
    let out = cmd.output().expect("the command starts");
    assert!(
        out.status.success(),
        "{cmd:?} failed ({}):\n{}\n{}",
        out.status,
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    out
}

fn size_bytes(dir: &Path) -> u64 {
    std::fs::read_dir(dir)
        .unwrap()
        .map(|e| {
            let e = e.unwrap();
            let m = e.metadata().unwrap();
            if m.is_dir() {
                size_bytes(&e.path())
            } else {
                m.len()
            }
        })
        .sum()
}

#[test]
fn a_bundle_moved_elsewhere_runs_from_its_own_cache() {
    if harness::testing::gpu_or_skip().is_none() {
        return;
    }
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let built = harness::testing::temp_dir("bundle-built");
    sh(Command::new(root.join("scripts/bundle.sh"))
        .arg(&built)
        .args(["--res", "64", "--scenes", SCENES, "--max-mb", "60"])
        .arg("--binary")
        .arg(env!("CARGO_BIN_EXE_scatterbench"))
        .arg("--cache-from")
        .arg(harness::testing::temp_dir("bundle-no-source-cache")));
    assert!(
        size_bytes(&built) <= 60_000_000,
        "the bundle is at most 60 MB"
    );

    let moved = harness::testing::temp_dir("bundle-moved");
    sh(Command::new("cp").arg("-a").arg(&built).arg(&moved));
    std::fs::remove_dir_all(&built).unwrap();
    for needed in [
        "bin/scatterbench",
        "run.sh",
        "README.md",
        "scenes/sphere-point.json",
    ] {
        assert!(moved.join(needed).is_file(), "{needed} in the bundle");
    }

    let out = moved.join("results/test");
    let run = sh(Command::new(moved.join("run.sh"))
        .args(["--adapter", "llvmpipe", "--res", "64", "--out"])
        .arg(&out)
        .args(["--scenes", SCENES, "--frames", "1", "--warmup", "0"])
        .env("NODEVICE_SELECT", "1")
        .env_remove("CARGO_MANIFEST_DIR"));
    let stderr = String::from_utf8_lossy(&run.stderr);
    for scene in SCENES.split(',') {
        assert!(
            stderr.contains(&format!("reference {scene}: cached")),
            "{scene}'s reference comes from the bundle:\n{stderr}"
        );
    }
    let results = Results::load(&out.join("results.json")).unwrap();
    assert!(results.run.machine.adapter.contains("llvmpipe"));
    let ok = results
        .records
        .iter()
        .filter(|r| r.status == Status::Ok)
        .count();
    let failed: Vec<_> = results
        .records
        .iter()
        .filter(|r| r.status == Status::Failed)
        .map(|r| format!("{} × {}: {:?}", r.scene, r.method, r.reason))
        .collect();
    assert!(failed.is_empty(), "{failed:?}");
    assert!(
        ok >= 2 * 8,
        "every homogeneous method on both scenes: {ok} ok"
    );
    assert!(out.join("report/index.html").is_file(), "report written");
}
