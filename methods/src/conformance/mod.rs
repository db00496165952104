//! The conformance checks every method passes, as a library: a registry — the built-in
//! [`crate::REGISTRY`] (methods/tests/conformance.rs) or an out-of-tree crate's own methods
//! (examples/external-method/tests/conformance.rs) — is checked with one call.
//!
//! - [`check_docs`]: unique ids, a README and a `//!` module doc, a paper and a summary, and a
//!   declared medium that agrees with `support` on the library scenes ([`docs`]).
//! - [`check_knobs`]: knob declarations in their own ranges, out-of-range and unknown values
//!   refused by name, valid conformance-case knobs ([`knobs`]).
//! - [`check_shaders`]: every WGSL module through naga for every override combination and every
//!   library scene's constants ([`shaders`]).
//! - [`check_gpu_cases`]: each conformance case within its bound of the reference renderer, and
//!   the same image with `no_skip` ([`cases`]). Without an adapter it skips with a message —
//!   except when `CI` is set, where it fails.
//!
//! Each `check_*` panics listing every failure it found (not only the first), so one run shows
//! everything to fix; [`check_registry`] runs all four and lists all of their failures.

pub mod cases;
pub mod docs;
pub mod knobs;
pub mod shaders;

use harness::method::Method;

pub use cases::{SKIP_EQUALITY, run_case, run_cases};
pub use knobs::outside;
pub use shaders::{scene_constants, validate_shaders};

/// Every check of this module on `registry`; panics with every failure of every check.
pub fn check_registry(registry: &[&dyn Method]) {
    let failures = [
        docs::problems(registry),
        knobs::problems(registry),
        shader_problems(registry),
        gpu_problems(registry),
    ]
    .concat();
    fail_with(&failures);
}

/// [`docs`]: ids, README, module doc, paper, summary, medium.
pub fn check_docs(registry: &[&dyn Method]) {
    fail_with(&docs::problems(registry));
}

/// [`knobs`]: declarations, refusals, conformance-case knobs.
pub fn check_knobs(registry: &[&dyn Method]) {
    fail_with(&knobs::problems(registry));
}

/// [`shaders`]: every method's modules and the shared ones ([`crate::common_shaders`]).
pub fn check_shaders(registry: &[&dyn Method]) {
    fail_with(&shader_problems(registry));
}

/// [`cases`]: every method's conformance cases on the GPU.
pub fn check_gpu_cases(registry: &[&dyn Method]) {
    fail_with(&gpu_problems(registry));
}

fn fail_with(failures: &[String]) {
    assert!(
        failures.is_empty(),
        "{} conformance failure(s):\n{}",
        failures.len(),
        failures.join("\n")
    );
}

fn shader_problems(registry: &[&dyn Method]) -> Vec<String> {
    let mut out = Vec::new();
    let mut checks = crate::common_shaders();
    for m in registry {
        let own = m.shaders();
        if own.is_empty() {
            out.push(format!("{}: declares no shader", m.id()));
        }
        checks.extend(own);
    }
    match validate_shaders(&checks) {
        Ok(n) => eprintln!(
            "{} module × override combinations, {n} specialisations",
            checks.len()
        ),
        Err(failures) => out.extend(failures),
    }
    out
}

fn gpu_problems(registry: &[&dyn Method]) -> Vec<String> {
    let Some(gpu) = harness::testing::gpu_or_skip() else {
        return Vec::new();
    };
    let mut out = Vec::new();
    for m in registry {
        let (ok, failed) = run_cases(&gpu, *m);
        for line in ok {
            eprintln!("ok   {line}");
        }
        for line in &failed {
            eprintln!("FAIL {line}");
        }
        out.extend(failed);
    }
    out
}
