//! Support for the test suites of every crate (GPU tests, CLI tests, benches): one definition of
//! "get an adapter or skip", of a scratch directory and of a small run configuration.

use std::collections::BTreeMap;
use std::path::PathBuf;

use crate::gpu::Gpu;
use crate::method::{ParamValue, Params};
use crate::reference::Settings;
use crate::runner::RunConfig;

/// The GPU, or None with a message when there is no adapter — except when `CI` is set, where a
/// missing adapter panics: a CI machine that cannot run the GPU tests must not pass silently.
pub fn gpu_or_skip() -> Option<Gpu> {
    match Gpu::new() {
        Ok(g) => Some(g),
        Err(e) if std::env::var_os("CI").is_some() => {
            panic!("CI is set and there is no GPU adapter: {e}")
        }
        Err(e) => {
            eprintln!("skipping GPU test: {e}");
            None
        }
    }
}

/// A fresh, empty directory under the system temp dir, unique to this process and `name`.
pub fn temp_dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("scatterbench-test-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    d
}

/// A square `res`² run of `frames` timed frames, no warm-up, no cache, no overrides.
pub fn run_config(out: PathBuf, res: u32, frames: u32) -> RunConfig {
    RunConfig {
        out_dir: out,
        width: res,
        height: res,
        frames,
        warmup: 0,
        no_skip: false,
        resume: false,
        sweep: false,
        overrides: BTreeMap::new(),
        reference: Settings::default(),
        cache_dir: None,
        run_id: "test".into(),
        budget_ms: None,
    }
}

/// Knob overrides from (name, value) pairs.
pub fn knobs(list: &[(&str, ParamValue)]) -> Params {
    list.iter()
        .map(|(k, v)| (k.to_string(), v.clone()))
        .collect()
}
