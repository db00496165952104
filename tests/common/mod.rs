//! What the root package's integration tests share: running this package's binary.
// Each test file compiles its own copy of this module and uses part of it.
#![allow(dead_code)]

use std::process::Command;

pub const BIN: &str = env!("CARGO_BIN_EXE_scatterbench");

/// Runs `scatterbench ARGS` (Mesa's device-select layer quiet) → (exit code, stdout, stderr).
pub fn scatterbench(args: &[&str]) -> (i32, String, String) {
    let o = Command::new(BIN)
        .args(args)
        .env("NODEVICE_SELECT", "1")
        .output()
        .expect("the scatterbench binary starts");
    (
        o.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&o.stdout).into_owned(),
        String::from_utf8_lossy(&o.stderr).into_owned(),
    )
}

/// [`scatterbench`]'s exit code and stderr.
pub fn cli(args: &[&str]) -> (i32, String) {
    let (code, _, stderr) = scatterbench(args);
    (code, stderr)
}
