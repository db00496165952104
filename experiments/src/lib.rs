//! scatterbench experiments: the runs that are more than "scenes × methods" (ARCHITECTURE
//! §9.5, §9.6), as library code the CLI calls and tests can drive.
//!
//! - [`papers`]: the papers' headline tables as data — which scenes, which configurations,
//!   what each paper claims. One module for all of them rather than one beside each method:
//!   a table compares several methods (Wyman & Ramsey's hybrid against the brute-force
//!   march, Umenhoffer's blocks against the per-particle splat), and it is data about the
//!   papers, not part of any method's contract.
//! - [`reproduce`]: runs those tables as one results run and writes the claim-vs-measured
//!   text and the equal-error table.
//! - [`scaling`]: frame time vs caster triangles and vs pixels (scene variants from
//!   `scenes::variants`), a results run plus `scaling.json`.
//! - [`stress`]: the stability table of a `scatterbench stress` run as text.

pub mod papers;
pub mod reproduce;
pub mod scaling;
pub mod stress;

use harness::isolate::Isolation;
use harness::method::{Method, Params, find};
use harness::record::RecordSettings;
use harness::runner::RunConfig;

/// The knobs of `params` that differ from the defaults of `method` (looked up in `registry`;
/// every knob when it is not there), `k=v …`, or "defaults".
pub fn params_text(registry: &[&dyn Method], method: &str, params: &Params) -> String {
    let defaults: Params = find(registry, method)
        .map(|e| {
            e.knobs()
                .into_iter()
                .map(|s| (s.name.to_string(), s.default))
                .collect()
        })
        .unwrap_or_default();
    report::format::knobs_or_defaults(params.iter().filter(|(k, v)| defaults.get(*k) != Some(*v)))
}

/// The runner configuration of an experiment: its records measured as `record` says, run
/// `run_id`, with `isolation`; explicit work items (no sweep, no overrides), not resumed.
pub fn run_config(record: &RecordSettings, run_id: &str, isolation: &Isolation) -> RunConfig {
    RunConfig {
        isolation: isolation.clone(),
        ..RunConfig::new(record.clone(), run_id)
    }
}
