//! Typed knobs (ARCHITECTURE §2.3): a method declares each knob once — its type, default,
//! allowed range or choices, sweep values, unit, meaning, and what a value needs of another
//! knob — and reads the resolved value through one typed accessor ([`KnobRead::knob`]).
//! [`resolve`] fills in defaults and refuses an unknown knob, a value of the wrong type, one
//! outside the declared range, or a pair of values the declarations forbid, with a
//! [`KnobError`] naming the method, the knob, the value and what is allowed; the CLI maps that
//! error to exit code 2. Methods never clamp or re-default a knob. A knob declared
//! [`Knob::or_auto`] (or [`Knob::default_auto`]) also takes the word `auto`: the method picks
//! the value per scene as the knob's meaning says, reading it as [`Auto`].
//!
//! - [`value`]: the values ([`ParamValue`], [`Params`]) and reading them ([`KnobRead`]);
//! - [`knob`]: one declaration ([`Knob`], [`Range`], [`Requirement`]), checking one value;
//! - [`resolve`](mod@resolve): full parameter sets, the sweep's sets, [`KnobError`].
//!
//! `crate::method` applies these to a [`Method`](crate::method::Method)
//! (`resolve_params`, `parse_knob`, `param_sets`).

pub mod knob;
pub mod resolve;
pub mod value;

pub use knob::{Knob, KnobProblem, Range, Requirement};
pub use resolve::{KnobError, parse, resolve, sweep};
pub use value::{AUTO, Auto, KnobRead, KnobType, ParamValue, Params};
