//! A method's knob space for the tune: the knobs it searches, each with the values it may take
//! (the default and the declared sweep values, in order for numbers), and the moves from one
//! configuration to its neighbours (one knob to an adjacent value, with what that value
//! requires of another knob), checked against the declarations (`knobs::resolve`).

use crate::knobs::{Knob, KnobError, ParamValue, Params, resolve};

/// The joint space is enumerated whole when it has at most this many configurations.
pub const EXHAUSTIVE_MAX: u128 = 16;

/// One searched knob.
#[derive(Clone, Debug)]
pub struct Axis {
    pub name: &'static str,
    /// The default and the sweep values, each once; ascending where all are numbers.
    pub values: Vec<ParamValue>,
    /// Numbers: a move goes to the next value up or down. Otherwise to any other value.
    pub ordered: bool,
}

/// The knobs of one method that a tune searches, around `base`.
#[derive(Clone, Debug)]
pub struct Space {
    pub method: String,
    knobs: Vec<Knob>,
    pub axes: Vec<Axis>,
    /// The defaults with the fixed values (`--param`) applied.
    pub base: Params,
}

impl Space {
    /// `knobs` of `method`, less those `fixed` (kept at their given value) and those
    /// `excluded` (kept at their defaults: the floor's shared knobs, §4.6).
    pub fn new(
        method: &str,
        knobs: Vec<Knob>,
        fixed: &Params,
        excluded: &[&str],
    ) -> Result<Space, KnobError> {
        let base = resolve(method, &knobs, fixed)?;
        let axes = knobs
            .iter()
            .filter(|k| !fixed.contains_key(k.name) && !excluded.contains(&k.name))
            .filter_map(axis)
            .collect();
        Ok(Space {
            method: method.to_string(),
            knobs,
            axes,
            base,
        })
    }

    /// Configurations in the joint space (the product of the axes' value counts).
    pub fn size(&self) -> u128 {
        self.axes
            .iter()
            .map(|a| a.values.len() as u128)
            .fold(1u128, |p, n| p.saturating_mul(n))
    }

    /// Every valid configuration of the joint space (use where [`Space::size`] is small).
    pub fn all(&self) -> Vec<Params> {
        let mut out = vec![self.base.clone()];
        for a in &self.axes {
            out = out
                .iter()
                .flat_map(|p| {
                    a.values.iter().map(move |v| {
                        let mut q = p.clone();
                        q.insert(a.name.to_string(), v.clone());
                        q
                    })
                })
                .collect();
        }
        out.into_iter()
            .filter_map(|p| self.valid(p))
            .fold(Vec::new(), push_new)
    }

    /// The configurations one move from `p`: one knob to the next value up or down (numbers)
    /// or to any other value, with the value another knob must then have; valid ones only.
    pub fn neighbours(&self, p: &Params) -> Vec<Params> {
        let mut out = Vec::new();
        for a in &self.axes {
            let here = p
                .get(a.name)
                .and_then(|v| a.values.iter().position(|x| x == v));
            let targets: Vec<&ParamValue> = match (a.ordered, here) {
                (true, Some(i)) => [i.checked_sub(1), Some(i + 1)]
                    .into_iter()
                    .flatten()
                    .filter_map(|j| a.values.get(j))
                    .collect(),
                (_, here) => (0..a.values.len())
                    .filter(|&j| Some(j) != here)
                    .map(|j| &a.values[j])
                    .collect(),
            };
            for v in targets {
                if let Some(q) = self.valid(self.moved(p.clone(), a.name, v)).filter(|q| q != p) {
                    out = push_new(out, q);
                }
            }
        }
        out
    }

    /// The configurations that differ from `p` on one or two axes, each at any of its values
    /// (with what those values require); valid ones only. The surrogate's proposals
    /// (`model`) are drawn from it: it holds every combination of two moves, however far.
    pub fn two_axis_ball(&self, p: &Params) -> Vec<Params> {
        let mut out = Vec::new();
        for (i, a) in self.axes.iter().enumerate() {
            for va in &a.values {
                let q = self.moved(p.clone(), a.name, va);
                out.push(q.clone());
                for b in &self.axes[i + 1..] {
                    for vb in &b.values {
                        out.push(self.moved(q.clone(), b.name, vb));
                    }
                }
            }
        }
        // Knob values are not `Ord` or `Hash`: the debug text is the configuration's identity.
        let mut seen = std::collections::HashSet::new();
        out.into_iter()
            .filter_map(|q| self.valid(q).filter(|q| q != p))
            .filter(|q| seen.insert(format!("{q:?}")))
            .collect()
    }

    /// `p` with knob `name` at `v`, and the values `v` requires of other knobs.
    fn moved(&self, mut p: Params, name: &str, v: &ParamValue) -> Params {
        p.insert(name.to_string(), v.clone());
        let knob = self
            .knobs
            .iter()
            .find(|k| k.name == name)
            .expect("an axis");
        for r in knob.requires.iter().filter(|r| r.when == *v) {
            p.insert(r.knob.to_string(), r.value.clone());
        }
        p
    }

    /// `p` resolved against the declarations, if it meets them and keeps the fixed values.
    fn valid(&self, p: Params) -> Option<Params> {
        let q = resolve(&self.method, &self.knobs, &p).ok()?;
        let moved_fixed = self
            .base
            .iter()
            .any(|(k, v)| !self.axes.iter().any(|a| a.name == k) && q.get(k) != Some(v));
        (!moved_fixed).then_some(q)
    }
}

fn push_new(mut out: Vec<Params>, p: Params) -> Vec<Params> {
    if !out.contains(&p) {
        out.push(p);
    }
    out
}

/// The knob as an axis: its default and sweep values; None where it has no other value.
fn axis(k: &Knob) -> Option<Axis> {
    let mut values = vec![k.default.clone()];
    for v in &k.sweep {
        if !values.contains(v) {
            values.push(v.clone());
        }
    }
    if values.len() < 2 {
        return None;
    }
    let ordered = values
        .iter()
        .all(|v| matches!(v, ParamValue::Int(_) | ParamValue::Float(_)));
    if ordered {
        values.sort_by(|a, b| {
            a.as_f64()
                .unwrap_or(0.0)
                .total_cmp(&b.as_f64().unwrap_or(0.0))
        });
    }
    Some(Axis {
        name: k.name,
        values,
        ordered,
    })
}
