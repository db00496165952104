//! The conformance test, driven by the registry (`methods::REGISTRY`): every registered method
//! is covered the moment it is registered, without an edit here.
//!
//! For every method: its README and `//!` module doc exist; its id is unique; every knob's
//! default and sweep values lie in the knob's declared range; every WGSL module it can build
//! (`Method::shaders`) validates with naga for every override combination it declares, and
//! specialised with the scene constants of every library scene; and on GPU, each of its
//! conformance cases (`Method::conformance`) renders finite AOVs whose error against the
//! reference renderer is within the case's bound, and the same image with `--no-skip` as
//! without (ARCHITECTURE §2.4: skipping a pass a scene does not need must not change the image; the
//! check runs on the case's scene and on `clear-fog`, where nothing casts a shadow).
//!
//! Without an adapter the GPU part skips with a message — except when `CI` is set.

use std::collections::BTreeSet;

use harness::method::{Method, resolve_params};
use harness::testing::{self, gpu_or_skip};
use methods::conformance::{outside, run_cases, validate_shaders};

#[test]
fn every_method_is_documented_and_declares_valid_knobs() {
    let mut ids = BTreeSet::new();
    for m in methods::REGISTRY {
        let info = m.info();
        assert!(ids.insert(info.id), "{}: registered twice", info.id);
        assert!(
            methods::find(info.id).is_some_and(|f| std::ptr::eq(
                f as *const dyn Method as *const (),
                *m as *const dyn Method as *const ()
            )),
            "{}: find",
            info.id
        );
        assert!(
            info.readme.trim_start().starts_with('#') && info.readme.len() > 200,
            "{}: README.md missing or empty",
            info.id
        );
        assert!(
            info.source.starts_with("//!"),
            "{}: mod.rs does not start with a //! module doc",
            info.id
        );
        assert!(
            !info.paper.is_empty() && !info.summary.is_empty(),
            "{}",
            info.id
        );
        let knobs = m.knobs();
        let mut names = BTreeSet::new();
        for k in &knobs {
            assert!(names.insert(k.name), "{}: knob {} twice", info.id, k.name);
            assert!(!k.meaning.is_empty(), "{}.{}: no meaning", info.id, k.name);
            for v in std::iter::once(&k.default).chain(&k.sweep) {
                assert!(
                    k.check(v).is_ok(),
                    "{}.{}: {v} is outside its own range ({})",
                    info.id,
                    k.name,
                    k.range
                );
            }
        }
        resolve_params(*m, &Default::default()).expect("defaults resolve");
        assert!(!m.shaders().is_empty(), "{}: declares no shader", info.id);
        assert!(
            !m.conformance().is_empty(),
            "{}: declares no conformance case",
            info.id
        );
        for case in m.conformance() {
            let list = testing::knobs(&case.knobs);
            resolve_params(*m, &list).unwrap_or_else(|e| panic!("{}: case knobs: {e}", info.id));
        }
    }
}

#[test]
fn every_shader_validates_for_every_override_combination() {
    let mut checks = methods::common_shaders();
    for m in methods::REGISTRY {
        checks.extend(m.shaders());
    }
    match validate_shaders(&checks) {
        Ok(n) => eprintln!(
            "{} module × override combinations, {n} specialisations",
            checks.len()
        ),
        Err(failures) => panic!("{}", failures.join("\n\n")),
    }
}

#[test]
fn every_method_meets_its_conformance_cases() {
    let Some(gpu) = gpu_or_skip() else { return };
    let mut failures = Vec::new();
    for m in methods::REGISTRY {
        let (ok, failed) = run_cases(&gpu, *m);
        for line in ok {
            eprintln!("ok   {line}");
        }
        for line in &failed {
            eprintln!("FAIL {line}");
        }
        failures.extend(failed);
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// Every out-of-range or wrongly typed value of every knob of every method is refused with a
/// `KnobError` that names the method, the knob, the value and the allowed range (the CLI maps it
/// to exit 2) — and no method clamps: the refusal happens before `prepare`.
#[test]
fn every_out_of_range_knob_is_refused_with_its_range() {
    let mut n = 0;
    for m in methods::REGISTRY {
        for k in m.knobs() {
            for v in outside(&k) {
                let list = testing::knobs(&[(k.name, v.clone())]);
                let err = resolve_params(*m, &list).expect_err(&format!(
                    "{}.{} = {v} accepted",
                    m.id(),
                    k.name
                ));
                assert_eq!((err.method.as_str(), err.knob.as_str()), (m.id(), k.name));
                assert_eq!(err.allowed, k.range.to_string());
                let text = err.to_string();
                assert!(
                    text.contains(m.id()) && text.contains(k.name) && text.contains(&err.allowed),
                    "{text}"
                );
                n += 1;
            }
        }
        let err = resolve_params(*m, &testing::knobs(&[("no_such_knob", 1.into())]))
            .expect_err("unknown knob accepted");
        assert_eq!(err.problem, harness::KnobProblem::Unknown);
    }
    assert!(n > 50, "{n} refusals checked");
}
