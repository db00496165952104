//! The knobs a method declares: unique names with a meaning, defaults and sweep values inside
//! their own ranges, every value outside a range refused with a `KnobError` that names the
//! method, the knob, the value and the range (the CLI's exit 2; no method clamps), an unknown
//! knob refused, and the knobs of every conformance case valid.

use std::collections::BTreeSet;

use harness::method::{KnobProblem, Method, resolve_params};
use harness::testing;

/// One line per problem of any method in `registry`.
pub fn problems(registry: &[&dyn Method]) -> Vec<String> {
    let mut out = Vec::new();
    for m in registry {
        out.extend(declared(*m));
        out.extend(refusals(*m));
        if m.conformance().is_empty() {
            out.push(format!("{}: declares no conformance case", m.id()));
        }
        for case in m.conformance() {
            if let Err(e) = resolve_params(*m, &testing::knobs(&case.knobs)) {
                out.push(format!(
                    "{}: conformance case on {}: {e}",
                    m.id(),
                    case.scene
                ));
            }
        }
    }
    out
}

/// Names, meanings, defaults and sweeps.
fn declared(m: &dyn Method) -> Vec<String> {
    let id = m.id();
    let mut out = Vec::new();
    let mut names = BTreeSet::new();
    for k in m.knobs() {
        if !names.insert(k.name) {
            out.push(format!("{id}: knob {} declared twice", k.name));
        }
        if k.meaning.is_empty() {
            out.push(format!("{id}.{}: no meaning", k.name));
        }
        for v in std::iter::once(&k.default).chain(&k.sweep) {
            if k.check(v).is_err() {
                out.push(format!(
                    "{id}.{}: {v} is outside its own range ({})",
                    k.name,
                    k.allowed()
                ));
            }
        }
    }
    if let Err(e) = resolve_params(m, &Default::default()) {
        out.push(format!("{id}: the defaults do not resolve: {e}"));
    }
    out
}

/// Every value just outside each knob's range, and an unknown knob, must be refused by name.
fn refusals(m: &dyn Method) -> Vec<String> {
    let id = m.id();
    let mut out = Vec::new();
    for k in m.knobs() {
        for v in outside(&k) {
            let err = match resolve_params(m, &testing::knobs(&[(k.name, v.clone())])) {
                Ok(_) => {
                    out.push(format!(
                        "{id}.{} = {v} accepted (allowed: {})",
                        k.name,
                        k.allowed()
                    ));
                    continue;
                }
                Err(e) => e,
            };
            let text = err.to_string();
            let names_all =
                text.contains(id) && text.contains(k.name) && text.contains(&err.allowed);
            if (err.method.as_str(), err.knob.as_str()) != (id, k.name)
                || err.allowed != k.allowed()
                || !names_all
            {
                out.push(format!(
                    "{id}.{} = {v}: the refusal does not name the method, knob and range: {text}",
                    k.name
                ));
            }
        }
    }
    match resolve_params(m, &testing::knobs(&[("no_such_knob", 1.into())])) {
        Err(e) if e.problem == KnobProblem::Unknown => {}
        other => out.push(format!(
            "{id}: an unknown knob was not refused as unknown: {other:?}"
        )),
    }
    out
}

/// Values just outside each knob's declared range (and of the wrong type; a word near `auto`
/// where the knob takes it).
pub fn outside(k: &harness::Knob) -> Vec<harness::ParamValue> {
    use harness::ParamValue as V;
    use harness::knobs::Range;
    let near_auto = k.auto.then(|| V::from("automatic"));
    let mut out = match &k.range {
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
    };
    out.extend(near_auto);
    out
}
