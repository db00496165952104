//! `scatterbench tune` as a library (ARCHITECTURE §4.6): per scene and error budget, the
//! cheapest configuration of each method that meets the budget, found by a joint search over
//! the knobs and confirmed by paired, interleaved timing with 95 % intervals.
//!
//! The error is deterministic, so one scoring of a configuration decides it; only the cost
//! is noisy. A tune therefore runs in two phases per scene:
//! 1. **screening** ([`search`]): every method's joint knob space is searched on the exact
//!    headline and a one-pair floor ratio, walking from each budget's incumbent and from the
//!    cheap configurations just over it;
//! 2. **timing** ([`verdict::open`]): the few configurations near each budget's front are kept
//!    prepared beside the floor and timed in rounds of interleaved pairs, round-robin, until
//!    each open verdict's intervals ([`interval`]) are within ±5 % or the time is up.
//!
//! - [`space`]: a method's searched knobs, their values, the moves between configurations;
//! - [`search`]: the screening search, over any [`search::Evaluator`] (the benchmark, or a
//!   synthetic function in the tests);
//! - [`model`]: the separable surrogate of a method's cost and error that proposes
//!   combinations of measured moves;
//! - [`interval`]: the ratio's estimate and interval from its rounds of pairs;
//! - [`verdict`]: winner, runner-up, tie, which candidates are open, the summary count;
//! - [`drift`]: the floor's trend and jumps within the run;
//! - [`results`](mod@results): tune.json.
//!
//! The command itself (the time split, the GPU work) is `src/cmd/tune.rs`; a configuration
//! kept prepared with its floor is `crate::record::Contender`.

pub mod drift;
pub mod interval;
pub mod model;
pub mod results;
pub mod search;
pub mod space;
pub mod verdict;

pub use interval::Interval;
pub use results::{MethodSearch, SceneTune, Screened, TUNE_FILE, TuneResults};
pub use space::Space;
pub use verdict::{BudgetVerdict, Count, Timed};
