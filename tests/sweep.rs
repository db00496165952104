//! `run --sweep` generates only parameter sets a method's declarations allow together
//! (ARCHITECTURE §4.3): for every registered method, every declared knob requirement is
//! well-formed, met by the defaults and by every set `param_sets` generates, refused by
//! `resolve_params` when broken (naming both knobs), and the swept sets that bring a
//! requirement into play are accepted by the method's `prepare`.

use harness::method::{
    KnobProblem, Method, ParamValue, Params, PrepareContext, Support, param_sets, resolve_params,
};
use harness::testing::gpu_or_skip;

/// (method, knob, value that needs, other knob, value it needs) for every declaration.
fn requirements() -> Vec<(
    &'static dyn Method,
    &'static str,
    ParamValue,
    &'static str,
    ParamValue,
)> {
    let mut out = Vec::new();
    for &m in methods::REGISTRY {
        for k in m.knobs() {
            for r in &k.requires {
                out.push((m, k.name, r.when.clone(), r.knob, r.value.clone()));
            }
        }
    }
    out
}

#[test]
fn the_requirements_biri_methods_refuse_in_prepare_are_declared() {
    let declared: Vec<String> = requirements()
        .iter()
        .map(|(m, k, v, o, w)| format!("{}: {k}={v} needs {o}={w}", m.id()))
        .collect();
    for expected in [
        "biri-shadow-volumes: accumulate=unorm8 needs resolve=stencil",
        "biri-polynomial: eval=vertex needs resolve=planes",
        "biri-polynomial: accumulate=unorm8 needs resolve=planes",
    ] {
        assert!(
            declared.iter().any(|d| d == expected),
            "{expected} not in {declared:?}"
        );
    }
}

#[test]
fn every_requirement_names_a_knob_and_values_in_range() {
    for (m, knob, when, other, value) in requirements() {
        let knobs = m.knobs();
        let find = |name: &str| knobs.iter().find(|k| k.name == name);
        let this = find(knob).expect("the declaring knob");
        assert!(
            this.check(&when).is_ok(),
            "{}: {knob}={when} is out of range",
            m.id()
        );
        let Some(that) = find(other) else {
            panic!(
                "{}: {knob}={when} needs an undeclared knob '{other}'",
                m.id()
            );
        };
        assert!(
            that.check(&value).is_ok(),
            "{}: {other}={value} is out of range",
            m.id()
        );
        assert_ne!(knob, other, "{}: a knob cannot need itself", m.id());
    }
}

#[test]
fn a_broken_requirement_is_refused_naming_both_knobs() {
    for (m, knob, when, other, value) in requirements() {
        let knobs = m.knobs();
        let that = knobs
            .iter()
            .find(|k| k.name == other)
            .expect("checked above");
        let wrong = [that.default.clone()]
            .into_iter()
            .chain(that.sweep.iter().cloned())
            .find(|v| *v != value)
            .unwrap_or_else(|| panic!("{}: {other} has no value but {value}", m.id()));
        let pair: Params = [(knob.to_string(), when.clone()), (other.to_string(), wrong)].into();
        let err = resolve_params(m, &pair).expect_err("a broken requirement");
        assert_eq!(err.problem, KnobProblem::Conflict, "{err}");
        let text = err.to_string();
        assert!(text.contains(knob) && text.contains(other), "{text}");
        let met: Params = [(knob.to_string(), when), (other.to_string(), value)].into();
        assert!(resolve_params(m, &met).is_ok(), "{}: {met:?}", m.id());
    }
}

/// Every set the sweep generates resolves (so it meets every requirement), and a swept value
/// that needs another knob's value is run with it rather than dropped.
#[test]
fn sweeps_meet_every_requirement() {
    for &m in methods::REGISTRY {
        let sets = param_sets(m, &Params::new(), true).unwrap_or_else(|e| panic!("{e}"));
        for p in &sets {
            resolve_params(m, p).unwrap_or_else(|e| panic!("the sweep generated {p:?}: {e}"));
        }
        for k in m.knobs() {
            for r in k.requires.iter().filter(|r| k.sweep.contains(&r.when)) {
                assert!(
                    sets.iter()
                        .any(|p| p[k.name] == r.when && p[r.knob] == r.value),
                    "{}: the sweep lost {}={}",
                    m.id(),
                    k.name,
                    r.when
                );
            }
        }
    }
}

/// The swept sets in which a requirement is in play are ones the method's `prepare` accepts
/// (on the first library scene it supports, 16²).
#[test]
fn swept_sets_with_a_requirement_prepare() {
    let Some(gpu) = gpu_or_skip() else { return };
    for (m, knob, when, _, _) in requirements() {
        let scene = scenes::library::names()
            .into_iter()
            .map(|n| scenes::library::resolve(n).expect("library scene"))
            .find(|s| matches!(m.support(&s.features(), gpu.features()), Support::Full))
            .expect("a library scene the method supports");
        let sets = param_sets(m, &Params::new(), true).unwrap();
        for p in sets.iter().filter(|p| p[knob] == when) {
            let ctx = PrepareContext {
                gpu: &gpu,
                scene: &scene,
                params: p,
                width: 16,
                height: 16,
                no_skip: false,
            };
            if let Err(e) = m.prepare(&ctx) {
                panic!(
                    "{} refuses its own sweep set {p:?} on {}: {e:#}",
                    m.id(),
                    scene.name
                );
            }
        }
    }
}
