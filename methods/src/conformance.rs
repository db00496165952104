//! The conformance checks every method passes (methods/tests/conformance.rs runs them over
//! [`crate::REGISTRY`]; an out-of-tree method runs them on itself, see
//! examples/external-method): its shaders validate with naga for every override combination
//! and every library scene's constants ([`validate_shaders`]); each conformance case renders
//! finite AOVs within its error bound of the reference and the same image with `no_skip`
//! ([`run_case`]); every knob refuses values outside its range ([`outside`]).

use std::collections::BTreeSet;

use harness::method::{Method, Support};
use harness::testing::{self, library, max_rel_diff, reference, rel_rmse};
use harness::{Gpu, ShaderCheck};

use crate::common::specialize::Specialization;

/// The skip/no-skip images of a method may differ by this much, relative to the image's peak.
pub const SKIP_EQUALITY: f64 = 1e-5;

/// The distinct scene constants (`common::specialize`) of the library scenes.
pub fn scene_constants() -> Vec<Vec<(&'static str, f64)>> {
    let mut out: Vec<Vec<(&'static str, f64)>> = Vec::new();
    for name in scenes::library::names() {
        let c = Specialization::of(&library(name)).constants().to_vec();
        if !out.contains(&c) {
            out.push(c);
        }
    }
    out
}

/// Parses and validates `check`, then specialises it with its constants plus each scene's (the
/// ones the module declares) and validates each result.
fn validate(check: &ShaderCheck, scenes: &[Vec<(&'static str, f64)>]) -> Result<usize, String> {
    let module =
        naga::front::wgsl::parse_str(&check.source).map_err(|e| e.emit_to_string(&check.source))?;
    let info = naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::default(),
    )
    .validate(&module)
    .map_err(|e| format!("{e:?}"))?;
    let declared: BTreeSet<&str> = module
        .overrides
        .iter()
        .filter_map(|(_, o)| o.name.as_deref())
        .collect();
    for (k, _) in &check.constants {
        if !declared.contains(k) {
            return Err(format!(
                "sets override {k}, which the module does not declare"
            ));
        }
    }
    let mut n = 0;
    for scene in scenes {
        let mut map: naga::back::PipelineConstants = scene
            .iter()
            .filter(|(k, _)| declared.contains(k))
            .map(|(k, v)| (k.to_string(), *v))
            .collect();
        map.extend(check.constants.iter().map(|(k, v)| (k.to_string(), *v)));
        naga::back::pipeline_constants::process_overrides(&module, &info, None, &map)
            .map_err(|e| format!("specialised with {map:?}: {e:?}"))?;
        n += 1;
    }
    Ok(n)
}

/// The case's AOV error against the reference, and the skip/no-skip difference; failures as text.
pub fn run_case(
    gpu: &Gpu,
    m: &dyn Method,
    case: &harness::ConformanceCase,
) -> Result<String, String> {
    let id = m.id();
    let scene = library(case.scene);
    if let Support::No(why) = m.support(&scene.features(), gpu.features()) {
        return Err(format!("{id} on {}: unsupported ({why})", case.scene));
    }
    let render = |no_skip: bool| {
        let mut p = testing::prepare(gpu, m, &scene, case.res, &case.knobs, no_skip)
            .map_err(|e| format!("{id} on {}: prepare: {e:#}", case.scene))?;
        testing::render_prepared(gpu, p.as_mut(), &scene, case.res, 0, 1)
            .map_err(|e| format!("{id} on {}: render: {e:#}", case.scene))
    };
    let (skip, full) = (render(false)?, render(true)?);
    for img in [&skip.inscatter, &skip.surface, &skip.total] {
        if !img.pixels.iter().flatten().all(|v| v.is_finite()) {
            return Err(format!("{id} on {}: non-finite pixel", case.scene));
        }
    }
    let d = max_rel_diff(skip.aov(case.aov), full.aov(case.aov));
    if d > SKIP_EQUALITY {
        return Err(format!(
            "{id} on {}: --no-skip changes the image by {d:.2e} (skipped {:?})",
            case.scene, skip.report.skipped
        ));
    }
    let r = reference(&scene, case.res);
    let refimg = match case.aov {
        harness::Aov::Inscatter => &r.inscatter,
        harness::Aov::Surface => &r.surface,
        harness::Aov::Total => &r.total,
    };
    let e = rel_rmse(skip.aov(case.aov), refimg);
    let line = format!(
        "{id} on {} {}² {:?} {:?}: rel RMSE {e:.4} (bound {}), skip/no-skip {d:.1e}",
        case.scene, case.res, case.knobs, case.aov, case.max_rel_rmse
    );
    if e > case.max_rel_rmse {
        return Err(line);
    }
    Ok(line)
}

/// Values just outside each knob's declared range (and of the wrong type).
pub fn outside(k: &harness::Knob) -> Vec<harness::ParamValue> {
    use harness::ParamValue as V;
    use harness::knobs::Range;
    match &k.range {
        Range::Int { min, max } => vec![V::Int(min - 1), V::Int(max + 1), V::from("x")],
        Range::IntSet { values } => {
            let hi = values.iter().max().expect("values");
            vec![V::Int(hi + 1), V::Int(values.iter().min().unwrap() - 1)]
        }
        Range::Float { min, max } => vec![
            V::Float(min - min.abs().max(1e-12)),
            V::Float(max + max.abs().max(1e-12)),
            V::Float(f64::NAN),
        ],
        Range::Bool => vec![V::Int(1), V::from("yes")],
        Range::Choice { .. } => vec![V::from("no-such-choice"), V::Int(0)],
    }
}

/// Validates every check (see [`validate`]): the number of specialisations checked, or one line
/// per failure.
pub fn validate_shaders(checks: &[ShaderCheck]) -> Result<usize, Vec<String>> {
    let scenes = scene_constants();
    let mut failures = Vec::new();
    let mut specialised = 0;
    for c in checks {
        match validate(c, &scenes) {
            Ok(n) => specialised += n,
            Err(e) => failures.push(format!("{} {:?}: {e}", c.name, c.constants)),
        }
    }
    if failures.is_empty() {
        Ok(specialised)
    } else {
        Err(failures)
    }
}

/// `method`'s conformance cases, plus a skip/no-skip check on `clear-fog` where it renders
/// it; one line per case, and the failures.
pub fn run_cases(gpu: &Gpu, m: &dyn Method) -> (Vec<String>, Vec<String>) {
    let mut cases = m.conformance();
    // Skipping is exercised hardest where nothing casts a shadow (no bound on the error there).
    let fog = library("clear-fog");
    if !matches!(m.support(&fog.features(), gpu.features()), Support::No(_))
        && !cases.iter().any(|c| c.scene == "clear-fog")
        && let Some(first) = cases.first()
    {
        cases.push(harness::ConformanceCase::new(
            "clear-fog",
            32,
            first.aov,
            f64::INFINITY,
        ));
    }
    let (mut ok, mut failed) = (Vec::new(), Vec::new());
    for case in &cases {
        match run_case(gpu, m, case) {
            Ok(line) => ok.push(line),
            Err(e) => failed.push(e),
        }
    }
    (ok, failed)
}
