//! Full parameter sets: defaults filled in, overrides checked against the declarations
//! ([`resolve`]), the sets `--sweep` runs ([`sweep`]), and the error that names what was
//! refused ([`KnobError`]).

use super::knob::{Knob, KnobProblem};
use super::value::{ParamValue, Params};

/// A refused knob value: which method, knob and value, and what is allowed. The CLI maps it to
/// exit code 2 (`anyhow::Error::downcast_ref::<KnobError>()`).
#[derive(Clone, Debug, PartialEq)]
pub struct KnobError {
    pub method: String,
    pub knob: String,
    pub value: String,
    pub problem: KnobProblem,
    /// The declared range ("an integer in 1..=65536"); for an unknown knob the knobs there are;
    /// for a conflict what the value needs and what it got ("resolve = stencil, not per-pixel").
    pub allowed: String,
}

impl std::fmt::Display for KnobError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let (m, k, v, a) = (&self.method, &self.knob, &self.value, &self.allowed);
        match self.problem {
            KnobProblem::Unknown => write!(f, "{m} has no knob '{k}' (= {v}); its knobs are: {a}"),
            KnobProblem::WrongType => write!(f, "{m}.{k} = {v} has the wrong type: allowed is {a}"),
            KnobProblem::OutOfRange => write!(f, "{m}.{k} = {v} is out of range: allowed is {a}"),
            KnobProblem::Conflict => write!(f, "{m}.{k} = {v} needs {a}"),
        }
    }
}

impl std::error::Error for KnobError {}

fn knob_error(
    method: &str,
    knobs: &[Knob],
    name: &str,
    value: &str,
    problem: KnobProblem,
) -> KnobError {
    let allowed = match knobs.iter().find(|k| k.name == name) {
        Some(k) => k.allowed(),
        None if knobs.is_empty() => "(none)".to_string(),
        None => knobs.iter().map(|k| k.name).collect::<Vec<_>>().join(", "),
    };
    KnobError {
        method: method.to_string(),
        knob: name.to_string(),
        value: value.to_string(),
        problem,
        allowed,
    }
}

/// Parses `name=text` for `method`'s `knobs` as given on the command line, checked against its
/// range.
pub fn parse(
    method: &str,
    knobs: &[Knob],
    name: &str,
    text: &str,
) -> Result<ParamValue, KnobError> {
    let knob = knobs
        .iter()
        .find(|k| k.name == name)
        .ok_or_else(|| knob_error(method, knobs, name, text, KnobProblem::Unknown))?;
    knob.parse(text)
        .map_err(|p| knob_error(method, knobs, name, text, p))
}

/// The full parameter set of `method`: every knob in `knobs` at its default, with `overrides`
/// applied after checking their names, types and ranges, and every declared requirement met.
pub fn resolve(method: &str, knobs: &[Knob], overrides: &Params) -> Result<Params, KnobError> {
    let mut p: Params = knobs
        .iter()
        .map(|k| (k.name.to_string(), k.default.clone()))
        .collect();
    for (name, v) in overrides {
        let fail = |problem| knob_error(method, knobs, name, &v.to_string(), problem);
        let knob = knobs
            .iter()
            .find(|k| k.name == name)
            .ok_or_else(|| fail(KnobProblem::Unknown))?;
        p.insert(name.clone(), knob.check(v).map_err(fail)?);
    }
    match unmet(knobs, &p).into_iter().next() {
        Some(e) => Err(e.error(method)),
        None => Ok(p),
    }
}

/// A requirement a parameter set does not meet: knob `knob` is `value`, which needs `needs` to
/// be `wanted`, and it is `got`.
struct Unmet<'a> {
    knob: &'a str,
    value: &'a ParamValue,
    needs: &'a str,
    wanted: &'a ParamValue,
    got: Option<&'a ParamValue>,
}

impl Unmet<'_> {
    fn error(&self, method: &str) -> KnobError {
        let got = self.got.map_or("unset".to_string(), ParamValue::to_string);
        KnobError {
            method: method.to_string(),
            knob: self.knob.to_string(),
            value: self.value.to_string(),
            problem: KnobProblem::Conflict,
            allowed: format!("{} = {}, not {got}", self.needs, self.wanted),
        }
    }
}

/// Every declared requirement `params` does not meet, in declaration order.
fn unmet<'a>(knobs: &'a [Knob], params: &'a Params) -> Vec<Unmet<'a>> {
    let mut out = Vec::new();
    for k in knobs {
        let Some(value) = params.get(k.name) else {
            continue;
        };
        for r in k.requires.iter().filter(|r| r.when == *value) {
            let got = params.get(r.knob);
            if got != Some(&r.value) {
                out.push(Unmet {
                    knob: k.name,
                    value,
                    needs: r.knob,
                    wanted: &r.value,
                    got,
                });
            }
        }
    }
    out
}

/// The parameter sets `--sweep` runs for `method`: the resolved defaults with `overrides`, and
/// with `sweep` one set per declared sweep value of each knob not fixed by an override (the
/// others at their base values).
///
/// A sweep value that needs another knob's value (a [`Requirement`](super::Requirement)) is run
/// with that value set too: `accumulate = unorm8` comes with `resolve = stencil`, so the sweep
/// still measures the paper's 8-bit target instead of dropping it. When an override fixes the
/// needed knob to something else, the user's choice wins and that sweep value is left out, as
/// is any set that would still break a requirement.
pub fn sweep(
    method: &str,
    knobs: &[Knob],
    overrides: &Params,
    sweep: bool,
) -> Result<Vec<Params>, KnobError> {
    let base = resolve(method, knobs, overrides)?;
    let mut out = vec![base.clone()];
    if !sweep {
        return Ok(out);
    }
    for k in knobs.iter().filter(|k| !overrides.contains_key(k.name)) {
        for v in &k.sweep {
            let mut p = base.clone();
            p.insert(k.name.to_string(), v.clone());
            for r in k.requires.iter().filter(|r| r.when == *v) {
                if overrides.get(r.knob).is_none_or(|fixed| *fixed == r.value) {
                    p.insert(r.knob.to_string(), r.value.clone());
                }
            }
            if unmet(knobs, &p).is_empty() && !out.contains(&p) {
                out.push(p);
            }
        }
    }
    Ok(out)
}

#[cfg(test)]
#[path = "resolve_tests.rs"]
mod tests;
