//! The conformance checks fail where they should: a method that breaks every declaration rule
//! (listed twice, a stub README, no module doc, an empty paper, a medium its `support`
//! contradicts, a default outside its range, a knob declared twice, no shader, no conformance
//! case) makes each check panic, listing every one of its problems — not only the first.

use harness::method::{
    ConformanceCase, Knob, Medium, Method, MethodInfo, PrepareContext, Prepared, ShaderCheck,
    Support,
};
use methods::conformance::{check_docs, check_knobs, check_shaders};
use scenes::SceneFeatures;

/// Breaks every rule the checks without a GPU look at.
struct Broken;

impl Method for Broken {
    fn info(&self) -> MethodInfo {
        MethodInfo {
            id: "broken",
            paper: "",
            summary: "breaks every rule",
            baseline: false,
            // It renders every scene (below), homogeneous ones included.
            medium: Medium::Particles,
            readme: "a stub",
            source: "// no module doc",
        }
    }
    fn knobs(&self) -> Vec<Knob> {
        vec![
            Knob::int("steps", 0, 1..=8).meaning("a default outside its range"),
            Knob::int("steps", 4, 1..=8).meaning("declared twice"),
        ]
    }
    fn support(&self, _: &SceneFeatures, _: wgpu::Features) -> Support {
        Support::Full
    }
    fn prepare(&self, _: &PrepareContext) -> anyhow::Result<Box<dyn Prepared>> {
        anyhow::bail!("never prepared")
    }
    fn shaders(&self) -> Vec<ShaderCheck> {
        Vec::new()
    }
    fn conformance(&self) -> Vec<ConformanceCase> {
        Vec::new()
    }
}

/// The panic message of `check` on `registry`; fails the test if it does not panic.
fn failure(check: fn(&[&dyn Method]), registry: &[&dyn Method]) -> String {
    let payload = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| check(registry)))
        .expect_err("the check passed");
    payload
        .downcast_ref::<String>()
        .cloned()
        .unwrap_or_default()
}

fn assert_lists(message: &str, needles: &[&str]) {
    for n in needles {
        assert!(message.contains(n), "'{n}' missing from:\n{message}");
    }
}

#[test]
fn docs_check_lists_every_problem() {
    let m = failure(check_docs, &[&Broken, &Broken]);
    assert_lists(
        &m,
        &[
            "broken: registered twice",
            "broken: README.md missing or a stub",
            "does not start with a //! module doc",
            "broken: empty paper or summary",
            "renders sphere-point (a homogeneous medium) but declares medium = particles",
        ],
    );
}

#[test]
fn knobs_check_lists_every_problem() {
    let m = failure(check_knobs, &[&Broken]);
    assert_lists(
        &m,
        &[
            "broken.steps: 0 is outside its own range",
            "broken: knob steps declared twice",
            "broken: declares no conformance case",
        ],
    );
}

#[test]
fn shaders_check_refuses_a_method_without_shaders() {
    let m = failure(check_shaders, &[&Broken]);
    assert_lists(&m, &["broken: declares no shader"]);
}
