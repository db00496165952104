//! Knob values: the typed value a parameter set holds ([`ParamValue`], [`Params`]) and the one
//! way a method reads it ([`KnobRead::knob`]).

use std::collections::BTreeMap;

use serde::{Deserialize, Serialize};

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

/// The value of a knob declared [`Knob::or_auto`](super::Knob::or_auto) that lets the method
/// choose per scene.
pub const AUTO: &str = "auto";

/// A knob declared [`Knob::or_auto`](super::Knob::or_auto), read as such:
/// `params.knob::<Auto<u32>>("slices")` is [`Auto::Auto`] for the word `auto`, else the value.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Auto<T> {
    /// The method picks the value per scene.
    Auto,
    /// Set to this value.
    Set(T),
}

impl<T> Auto<T> {
    /// The set value, or `auto()`'s for [`Auto::Auto`].
    pub fn or_else(self, auto: impl FnOnce() -> T) -> T {
        match self {
            Auto::Auto => auto(),
            Auto::Set(v) => v,
        }
    }
}

impl<T: KnobType> KnobType for Auto<T> {
    fn from_value(v: &ParamValue) -> Option<Self> {
        if v.as_str() == Some(AUTO) {
            Some(Auto::Auto)
        } else {
            T::from_value(v).map(Auto::Set)
        }
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
    fn knob_read_is_typed() {
        let p: Params = [("n".to_string(), ParamValue::Int(-1))]
            .into_iter()
            .collect();
        assert_eq!(p.knob::<i64>("n").unwrap(), -1);
        assert!(p.knob::<u32>("n").is_err());
        assert!(p.knob::<bool>("n").is_err());
        assert!(p.knob::<i64>("missing").is_err());
        assert_eq!(p.knob::<Auto<i64>>("n").unwrap(), Auto::Set(-1));
        let a: Params = [("n".to_string(), ParamValue::from("auto"))]
            .into_iter()
            .collect();
        assert_eq!(a.knob::<Auto<u32>>("n").unwrap(), Auto::Auto);
        assert!(a.knob::<u32>("n").is_err());
    }
}
