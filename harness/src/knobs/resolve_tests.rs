//! Resolution and sweeps against declarations written here, so each property is checked
//! without a method.

use super::*;
use crate::knobs::knob::Knob;

/// biri-shadow-volumes' shape: an 8-bit target that needs the stencil resolve.
fn knobs() -> Vec<Knob> {
    vec![
        Knob::int("table", 256, 4..=4096).sweep([32, 64]),
        Knob::choice("resolve", "per-pixel", &["per-pixel", "stencil"]).sweep(["stencil"]),
        Knob::choice("accumulate", "float", &["float", "unorm8"])
            .sweep(["unorm8"])
            .requires("unorm8", "resolve", "stencil"),
    ]
}

fn set(list: &[(&str, &str)]) -> Params {
    list.iter()
        .map(|(k, v)| (k.to_string(), ParamValue::from(*v)))
        .collect()
}

#[test]
fn a_requirement_is_refused_naming_both_knobs() {
    let err = resolve("m", &knobs(), &set(&[("accumulate", "unorm8")])).unwrap_err();
    assert_eq!(err.problem, KnobProblem::Conflict);
    assert_eq!(
        (err.knob.as_str(), err.value.as_str()),
        ("accumulate", "unorm8")
    );
    assert_eq!(
        err.to_string(),
        "m.accumulate = unorm8 needs resolve = stencil, not per-pixel"
    );
    let both = set(&[("accumulate", "unorm8"), ("resolve", "stencil")]);
    let p = resolve("m", &knobs(), &both).expect("a met requirement resolves");
    assert_eq!(p["accumulate"], ParamValue::from("unorm8"));
    // A value without a requirement is free.
    assert!(resolve("m", &knobs(), &set(&[("resolve", "stencil")])).is_ok());
}

#[test]
fn the_sweep_sets_what_a_value_needs() {
    let sets = sweep("m", &knobs(), &Params::new(), true).unwrap();
    assert_eq!(sets.len(), 5, "{sets:?}");
    let unorm8: Vec<&Params> = sets
        .iter()
        .filter(|p| p["accumulate"] == ParamValue::from("unorm8"))
        .collect();
    assert_eq!(unorm8.len(), 1);
    assert_eq!(unorm8[0]["resolve"], ParamValue::from("stencil"));
    for p in &sets {
        let overrides = p.clone();
        assert!(resolve("m", &knobs(), &overrides).is_ok(), "{p:?}");
    }
}

#[test]
fn an_override_of_the_needed_knob_wins_over_the_sweep() {
    let per_pixel = set(&[("resolve", "per-pixel")]);
    let sets = sweep("m", &knobs(), &per_pixel, true).unwrap();
    assert!(
        sets.iter()
            .all(|p| p["accumulate"] == ParamValue::from("float")),
        "{sets:?}"
    );
    let stencil = set(&[("resolve", "stencil")]);
    let sets = sweep("m", &knobs(), &stencil, true).unwrap();
    assert!(
        sets.iter()
            .any(|p| p["accumulate"] == ParamValue::from("unorm8"))
    );
    assert!(
        sets.iter()
            .all(|p| p["resolve"] == ParamValue::from("stencil"))
    );
}

#[test]
fn without_sweep_only_the_base_set() {
    let sets = sweep("m", &knobs(), &Params::new(), false).unwrap();
    assert_eq!(sets, [resolve("m", &knobs(), &Params::new()).unwrap()]);
}
