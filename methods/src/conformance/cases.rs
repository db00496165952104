//! The GPU cases: each conformance case renders finite AOVs within its error bound of the
//! reference renderer, and the same image with `no_skip` as without.

use harness::Gpu;
use harness::method::{Method, Support};
use harness::testing::{self, library, max_rel_diff, reference, rel_rmse};

/// The skip/no-skip images of a method may differ by this much, relative to the image's peak.
pub const SKIP_EQUALITY: f64 = 1e-5;

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
