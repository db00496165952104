//! One record (ARCHITECTURE §4): a method × parameter set on a scene, measured and scored by
//! [`run_one`] — `prepare` timed once, W warm-up and K timed frames under the time budget,
//! every timed frame read back and scored, then frame 0 scored against its reference with the
//! images written beside results.json. A method that panics, raises a wgpu error or renders
//! non-finite pixels gives a failed record, never an error.
//!
//! What it needs is one [`RecordSettings`]; the runner calls [`run_one`] in process and an
//! isolated worker calls it with the settings it got over the pipe (`crate::isolate`), so the
//! two run the same code. It depends on neither: the runner sits on top of isolation, and both
//! on this module.
//!
//! - `settings.rs`: [`RecordSettings`], serialisable for the worker protocol;
//! - `phase.rs`: the phase a record is in, announced to a per-thread hook;
//! - `frame.rs`: the AOV targets and one timed frame ([`render_frame`]);
//! - `measure.rs`: prepare, the warm-up and timed frames, the time budget ([`another_frame`]);
//! - `paired.rs`: the paired floor, rendered one frame before each of the method's;
//! - `contender.rs`: a configuration kept prepared with its floor, timed in pairs and scored on
//!   the headline alone (`scatterbench tune`);
//! - `score.rs`: [`run_one`], the scoring of the measured frames;
//! - `images.rs`: the files a record writes; `failure.rs`: a failed record and its reason;
//! - `validation.rs`: the validation layer's messages in the record (under `--validate`).

mod contender;
mod failure;
mod frame;
mod images;
mod measure;
mod paired;
pub mod phase;
mod score;
mod settings;
mod validation;

pub use contender::{Contender, Pair, Scored};
pub use failure::{failed, panic_message};
pub use frame::{AovTargets, FrameTiming, render_frame};
pub use images::{error_scale, params_slug, write_aovs};
pub use measure::{MIN_TIMED_FRAMES, another_frame};
pub use paired::matched_params;
pub use phase::Phase;
pub use score::run_one;
pub use settings::RecordSettings;
