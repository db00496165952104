//! Shader validation: every WGSL module a method can build parses and validates with naga for
//! every override combination it declares, and specialised with each library scene's constants.

use std::collections::BTreeSet;

use harness::ShaderCheck;
use harness::testing::library;

use crate::common::specialize::Specialization;

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
        // The early depth test of the crossing lists' fragment entries (wgpu grants it with
        // `Features::SHADER_EARLY_DEPTH_TEST`, which the harness requests).
        naga::valid::Capabilities::default() | naga::valid::Capabilities::EARLY_DEPTH_TEST,
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
