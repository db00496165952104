//! Typed knobs (ARCHITECTURE/DESIGN §2): a method declares each knob once — its type, default,
//! allowed range or choices, sweep values, unit and meaning — and reads the resolved value
//! through one typed accessor ([`KnobRead::knob`]). [`resolve_params`] fills in defaults and
//! refuses an unknown knob, a value of the wrong type or one outside the declared range with a
//! [`KnobError`] naming the method, the knob, the value and what is allowed; the CLI maps that
//! error to exit code 2. Methods never clamp or re-default a knob.

use std::collections::BTreeMap;
use std::ops::RangeInclusive;

use serde::{Deserialize, Serialize};

use crate::method::Method;

/// A knob value. Untagged in JSON: 64, 0.5, true, "float".
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq, PartialOrd)]
#[serde(untagged)]
pub enum ParamValue {
    Bool(bool),
    Int(i64),
    Float(f64),
    Text(String),
}

impl ParamValue {
    pub fn as_i64(&self) -> Option<i64> {
        match self {
            ParamValue::Int(i) => Some(*i),
            ParamValue::Float(f) if f.fract() == 0.0 => Some(*f as i64),
            _ => None,
        }
    }
    pub fn as_f64(&self) -> Option<f64> {
        match self {
            ParamValue::Int(i) => Some(*i as f64),
            ParamValue::Float(f) => Some(*f),
            _ => None,
        }
    }
    pub fn as_bool(&self) -> Option<bool> {
        match self {
            ParamValue::Bool(b) => Some(*b),
            _ => None,
        }
    }
    pub fn as_str(&self) -> Option<&str> {
        match self {
            ParamValue::Text(s) => Some(s),
            _ => None,
        }
    }
}

impl From<i64> for ParamValue {
    fn from(v: i64) -> Self {
        ParamValue::Int(v)
    }
}
impl From<i32> for ParamValue {
    fn from(v: i32) -> Self {
        ParamValue::Int(v as i64)
    }
}
impl From<f64> for ParamValue {
    fn from(v: f64) -> Self {
        ParamValue::Float(v)
    }
}
impl From<bool> for ParamValue {
    fn from(v: bool) -> Self {
        ParamValue::Bool(v)
    }
}
impl From<&str> for ParamValue {
    fn from(v: &str) -> Self {
        ParamValue::Text(v.to_string())
    }
}

impl std::fmt::Display for ParamValue {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            ParamValue::Bool(b) => write!(f, "{b}"),
            ParamValue::Int(i) => write!(f, "{i}"),
            ParamValue::Float(x) => write!(f, "{x}"),
            ParamValue::Text(s) => write!(f, "{s}"),
        }
    }
}

/// Knob name → value; a full set (defaults filled in) is what a record carries.
pub type Params = BTreeMap<String, ParamValue>;

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

    /// The value if it has the knob's type and lies in its range (integers are accepted for a
    /// float knob and stored as floats), else what is wrong.
    pub fn check(&self, v: &ParamValue) -> Result<ParamValue, KnobProblem> {
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
}

/// A refused knob value: which method, knob and value, and what is allowed. The CLI maps it to
/// exit code 2 (`anyhow::Error::downcast_ref::<KnobError>()`).
#[derive(Clone, Debug, PartialEq)]
pub struct KnobError {
    pub method: String,
    pub knob: String,
    pub value: String,
    pub problem: KnobProblem,
    /// The declared range ("an integer in 1..=65536"), or for an unknown knob the knobs there are.
    pub allowed: String,
}

impl std::fmt::Display for KnobError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let (m, k, v, a) = (&self.method, &self.knob, &self.value, &self.allowed);
        match self.problem {
            KnobProblem::Unknown => write!(f, "{m} has no knob '{k}' (= {v}); its knobs are: {a}"),
            KnobProblem::WrongType => write!(f, "{m}.{k} = {v} has the wrong type: allowed is {a}"),
            KnobProblem::OutOfRange => write!(f, "{m}.{k} = {v} is out of range: allowed is {a}"),
        }
    }
}

impl std::error::Error for KnobError {}

fn knob_error(
    method: &dyn Method,
    knobs: &[Knob],
    name: &str,
    value: &str,
    problem: KnobProblem,
) -> KnobError {
    let allowed = match knobs.iter().find(|k| k.name == name) {
        Some(k) => k.range.to_string(),
        None if knobs.is_empty() => "(none)".to_string(),
        None => knobs.iter().map(|k| k.name).collect::<Vec<_>>().join(", "),
    };
    KnobError {
        method: method.id().to_string(),
        knob: name.to_string(),
        value: value.to_string(),
        problem,
        allowed,
    }
}

/// Parses `name=text` for `method` as given on the command line, checked against its range.
pub fn parse_knob(method: &dyn Method, name: &str, text: &str) -> Result<ParamValue, KnobError> {
    let knobs = method.knobs();
    let knob = knobs
        .iter()
        .find(|k| k.name == name)
        .ok_or_else(|| knob_error(method, &knobs, name, text, KnobProblem::Unknown))?;
    knob.parse(text)
        .map_err(|p| knob_error(method, &knobs, name, text, p))
}

/// The full parameter set: every declared knob at its default, with `overrides` applied after
/// checking their names, types and ranges.
pub fn resolve_params(method: &dyn Method, overrides: &Params) -> Result<Params, KnobError> {
    let knobs = method.knobs();
    let mut p: Params = knobs
        .iter()
        .map(|k| (k.name.to_string(), k.default.clone()))
        .collect();
    for (name, v) in overrides {
        let fail = |problem| knob_error(method, &knobs, name, &v.to_string(), problem);
        let knob = knobs
            .iter()
            .find(|k| k.name == name)
            .ok_or_else(|| fail(KnobProblem::Unknown))?;
        p.insert(name.clone(), knob.check(v).map_err(fail)?);
    }
    Ok(p)
}

/// A type a knob can be read as ([`KnobRead::knob`]).
pub trait KnobType: Sized {
    fn from_value(v: &ParamValue) -> Option<Self>;
}
impl KnobType for i64 {
    fn from_value(v: &ParamValue) -> Option<Self> {
        v.as_i64()
    }
}
impl KnobType for u32 {
    fn from_value(v: &ParamValue) -> Option<Self> {
        v.as_i64().and_then(|i| u32::try_from(i).ok())
    }
}
impl KnobType for usize {
    fn from_value(v: &ParamValue) -> Option<Self> {
        v.as_i64().and_then(|i| usize::try_from(i).ok())
    }
}
impl KnobType for f64 {
    fn from_value(v: &ParamValue) -> Option<Self> {
        v.as_f64()
    }
}
impl KnobType for f32 {
    fn from_value(v: &ParamValue) -> Option<Self> {
        v.as_f64().map(|x| x as f32)
    }
}
impl KnobType for bool {
    fn from_value(v: &ParamValue) -> Option<Self> {
        v.as_bool()
    }
}
impl KnobType for String {
    fn from_value(v: &ParamValue) -> Option<Self> {
        v.as_str().map(str::to_string)
    }
}

/// The one way a method reads a knob from a resolved parameter set: `params.knob::<u32>("steps")`.
/// Resolution already checked type and range, so an error here means the method reads a knob it
/// does not declare, or as a type that cannot hold its range — a bug in the method, reported as
/// an error rather than a panic or a default.
pub trait KnobRead {
    fn knob<T: KnobType>(&self, name: &str) -> anyhow::Result<T>;
}

impl KnobRead for Params {
    fn knob<T: KnobType>(&self, name: &str) -> anyhow::Result<T> {
        let v = self.get(name).ok_or_else(|| {
            anyhow::anyhow!("knob '{name}' is not in the resolved parameters (is it declared?)")
        })?;
        T::from_value(v).ok_or_else(|| {
            anyhow::anyhow!(
                "knob '{name}' = {v} cannot be read as {}",
                std::any::type_name::<T>()
            )
        })
    }
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

    #[test]
    fn knob_read_is_typed() {
        let p: Params = [("n".to_string(), ParamValue::Int(-1))]
            .into_iter()
            .collect();
        assert_eq!(p.knob::<i64>("n").unwrap(), -1);
        assert!(p.knob::<u32>("n").is_err());
        assert!(p.knob::<bool>("n").is_err());
        assert!(p.knob::<i64>("missing").is_err());
    }
}
