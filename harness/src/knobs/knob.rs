//! One knob's declaration: type and range, default, sweep values, unit, meaning, and what its
//! values need of other knobs ([`Requirement`]); checking and parsing a value against it.

use std::ops::RangeInclusive;

use serde::Serialize;

use super::value::{AUTO, ParamValue};

/// What values a knob accepts.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(tag = "type", rename_all = "lowercase")]
pub enum Range {
    /// An integer in `min..=max`.
    Int {
        min: i64,
        max: i64,
    },
    /// One of these integers.
    IntSet {
        values: &'static [i64],
    },
    /// A finite number in `min..=max`.
    Float {
        min: f64,
        max: f64,
    },
    Bool,
    /// One of these words.
    Choice {
        choices: &'static [&'static str],
    },
}

impl std::fmt::Display for Range {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Range::Int { min, max } => write!(f, "an integer in {min}..={max}"),
            Range::IntSet { values } => {
                let v: Vec<String> = values.iter().map(i64::to_string).collect();
                write!(f, "one of {}", v.join(", "))
            }
            Range::Float { min, max } => write!(f, "a number in {min}..={max}"),
            Range::Bool => write!(f, "true or false"),
            Range::Choice { choices } => write!(f, "one of {}", choices.join(", ")),
        }
    }
}

/// One knob: type and range, default, the values `--sweep` runs, unit and meaning. Built with
/// [`Knob::int`], [`Knob::float`], [`Knob::boolean`] or [`Knob::choice`], then `.sweep(..)`,
/// `.unit(..)`, `.meaning(..)`.
#[derive(Clone, Debug, Serialize)]
pub struct Knob {
    pub name: &'static str,
    pub default: ParamValue,
    pub sweep: Vec<ParamValue>,
    pub range: Range,
    /// Unit of the value ("texels", "m", "steps"; empty for a pure switch or count).
    #[serde(skip_serializing_if = "str::is_empty")]
    pub unit: &'static str,
    pub meaning: &'static str,
    /// What some of its values need of other knobs.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub requires: Vec<Requirement>,
    /// Whether the word [`AUTO`] is a value besides the range: the method then picks the value
    /// per scene, as its meaning says ([`Knob::or_auto`]).
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    pub auto: bool,
}

/// A value of one knob that works only with a value of another, because the method refuses
/// anything else: biri-shadow-volumes' `accumulate = unorm8` (the paper's blended 8-bit
/// stencil target) needs `resolve = stencil`. [`resolve`](fn@super::resolve) refuses a set that
/// breaks it, naming both knobs; [`sweep`](fn@super::sweep) runs the value with the one it needs.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Requirement {
    /// The value of the declaring knob that needs the other.
    pub when: ParamValue,
    /// The other knob and the value it must then have.
    pub knob: &'static str,
    pub value: ParamValue,
}

impl Knob {
    fn new(name: &'static str, default: ParamValue, range: Range) -> Knob {
        Knob {
            name,
            default,
            sweep: Vec::new(),
            range,
            unit: "",
            meaning: "",
            requires: Vec::new(),
            auto: false,
        }
    }
    /// An integer knob in `range` (inclusive).
    pub fn int(name: &'static str, default: i64, range: RangeInclusive<i64>) -> Knob {
        let (min, max) = range.into_inner();
        Knob::new(name, ParamValue::Int(default), Range::Int { min, max })
    }
    /// An integer knob taking one of `values`.
    pub fn int_of(name: &'static str, default: i64, values: &'static [i64]) -> Knob {
        Knob::new(name, ParamValue::Int(default), Range::IntSet { values })
    }
    /// A real knob in `range` (inclusive).
    pub fn float(name: &'static str, default: f64, range: RangeInclusive<f64>) -> Knob {
        let (min, max) = range.into_inner();
        Knob::new(name, ParamValue::Float(default), Range::Float { min, max })
    }
    /// A switch; its sweep is the other value unless `.sweep(..)` says otherwise.
    pub fn boolean(name: &'static str, default: bool) -> Knob {
        Knob {
            sweep: vec![ParamValue::Bool(!default)],
            ..Knob::new(name, ParamValue::Bool(default), Range::Bool)
        }
    }
    /// One of `choices`.
    pub fn choice(
        name: &'static str,
        default: &'static str,
        choices: &'static [&'static str],
    ) -> Knob {
        Knob::new(name, ParamValue::from(default), Range::Choice { choices })
    }
    /// The values `--sweep` runs (besides the default).
    pub fn sweep<V: Into<ParamValue>>(mut self, values: impl IntoIterator<Item = V>) -> Knob {
        self.sweep = values.into_iter().map(Into::into).collect();
        self
    }
    pub fn unit(mut self, unit: &'static str) -> Knob {
        self.unit = unit;
        self
    }
    pub fn meaning(mut self, meaning: &'static str) -> Knob {
        self.meaning = meaning;
        self
    }
    /// The word [`AUTO`] is a value too (it may then be the default): the method resolves it
    /// per scene, as the meaning must say; read it as [`Auto`](super::Auto).
    pub fn or_auto(mut self) -> Knob {
        self.auto = true;
        self
    }
    /// [`Knob::or_auto`], with `auto` the default.
    pub fn default_auto(mut self) -> Knob {
        self.default = ParamValue::from(AUTO);
        self.or_auto()
    }
    /// What the knob accepts, for errors and listings: the range, and `auto` if declared.
    pub fn allowed(&self) -> String {
        if self.auto {
            format!("{}, or {AUTO}", self.range)
        } else {
            self.range.to_string()
        }
    }
    /// When this knob is `when`, knob `knob` must be `value` (see [`Requirement`]).
    pub fn requires(
        mut self,
        when: impl Into<ParamValue>,
        knob: &'static str,
        value: impl Into<ParamValue>,
    ) -> Knob {
        self.requires.push(Requirement {
            when: when.into(),
            knob,
            value: value.into(),
        });
        self
    }

    /// The value if it has the knob's type and lies in its range (integers are accepted for a
    /// float knob and stored as floats), else what is wrong.
    pub fn check(&self, v: &ParamValue) -> Result<ParamValue, KnobProblem> {
        if self.auto && v.as_str() == Some(AUTO) {
            return Ok(v.clone());
        }
        match (&self.range, v) {
            (Range::Int { min, max }, ParamValue::Int(i)) => {
                if (min..=max).contains(&i) {
                    Ok(v.clone())
                } else {
                    Err(KnobProblem::OutOfRange)
                }
            }
            (Range::IntSet { values }, ParamValue::Int(i)) => {
                if values.contains(i) {
                    Ok(v.clone())
                } else {
                    Err(KnobProblem::OutOfRange)
                }
            }
            (Range::Float { min, max }, ParamValue::Int(_) | ParamValue::Float(_)) => {
                let x = v.as_f64().expect("numeric");
                if x.is_finite() && (*min..=*max).contains(&x) {
                    Ok(ParamValue::Float(x))
                } else {
                    Err(KnobProblem::OutOfRange)
                }
            }
            (Range::Bool, ParamValue::Bool(_)) => Ok(v.clone()),
            (Range::Choice { choices }, ParamValue::Text(t)) => {
                if choices.contains(&t.as_str()) {
                    Ok(v.clone())
                } else {
                    Err(KnobProblem::OutOfRange)
                }
            }
            _ => Err(KnobProblem::WrongType),
        }
    }

    /// Parses a command-line value (`64`, `0.5`, `true`, `float`) and checks it.
    pub fn parse(&self, text: &str) -> Result<ParamValue, KnobProblem> {
        let t = text.trim();
        if self.auto && t == AUTO {
            return Ok(ParamValue::from(AUTO));
        }
        let v = match self.range {
            Range::Int { .. } | Range::IntSet { .. } => t.parse().map(ParamValue::Int).ok(),
            Range::Float { .. } => t.parse().map(ParamValue::Float).ok(),
            Range::Bool => t.parse().map(ParamValue::Bool).ok(),
            Range::Choice { .. } => Some(ParamValue::Text(t.to_string())),
        };
        self.check(&v.ok_or(KnobProblem::WrongType)?)
    }
}

/// Why a knob value was refused.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum KnobProblem {
    /// The method declares no knob of that name.
    Unknown,
    /// Not of the knob's type (text for an integer knob, …).
    WrongType,
    /// Of the right type but outside the declared range or choices.
    OutOfRange,
    /// Allowed alone, but it needs another knob's value, which the set does not have
    /// ([`Requirement`]).
    Conflict,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn check_refuses_out_of_range_and_wrong_types() {
        let k = Knob::int("steps", 128, 1..=65536);
        assert_eq!(k.check(&ParamValue::Int(0)), Err(KnobProblem::OutOfRange));
        assert_eq!(
            k.check(&ParamValue::Int(65537)),
            Err(KnobProblem::OutOfRange)
        );
        assert_eq!(k.check(&ParamValue::Int(1)), Ok(ParamValue::Int(1)));
        assert_eq!(
            k.check(&ParamValue::Float(2.0)),
            Err(KnobProblem::WrongType)
        );
        assert_eq!(k.parse("x"), Err(KnobProblem::WrongType));
        let f = Knob::float("scale", 1.0, 0.001..=1000.0);
        assert_eq!(f.check(&ParamValue::Int(2)), Ok(ParamValue::Float(2.0)));
        assert_eq!(
            f.check(&ParamValue::Float(f64::NAN)),
            Err(KnobProblem::OutOfRange)
        );
        assert_eq!(f.parse("0"), Err(KnobProblem::OutOfRange));
        let c = Knob::choice("mode", "a", &["a", "b"]);
        assert_eq!(c.parse("c"), Err(KnobProblem::OutOfRange));
        assert_eq!(c.parse("b"), Ok(ParamValue::from("b")));
        assert_eq!(
            Knob::boolean("on", true).sweep,
            vec![ParamValue::Bool(false)]
        );
    }

    /// `auto` only where declared, and spelt exactly; the range still holds beside it.
    #[test]
    fn auto_is_a_value_only_where_declared() {
        let k = Knob::int_of("n", 8, &[4, 8]).or_auto();
        assert_eq!(k.parse("auto"), Ok(ParamValue::from("auto")));
        assert_eq!(
            k.check(&ParamValue::from("auto")),
            Ok(ParamValue::from("auto"))
        );
        assert_eq!(k.parse("4"), Ok(ParamValue::Int(4)));
        assert_eq!(k.parse("5"), Err(KnobProblem::OutOfRange));
        assert_eq!(k.parse("Auto"), Err(KnobProblem::WrongType));
        assert_eq!(k.allowed(), "one of 4, 8, or auto");
        let b = Knob::boolean("on", false).or_auto();
        assert_eq!(b.parse("auto"), Ok(ParamValue::from("auto")));
        assert_eq!(b.parse("yes"), Err(KnobProblem::WrongType));
        assert_eq!(b.default, ParamValue::Bool(false));
        assert_eq!(
            Knob::int("m", 1, 0..=2).default_auto().default,
            ParamValue::from("auto")
        );
        let plain = Knob::boolean("on", false);
        assert_eq!(plain.parse("auto"), Err(KnobProblem::WrongType));
        assert_eq!(plain.allowed(), "true or false");
    }
}
