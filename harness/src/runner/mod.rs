//! The runner: scenes × methods × parameter sets → records, written to `results.json`
//! atomically after every record (ARCHITECTURE §4, §5.1). A method that panics, raises a wgpu
//! error or renders non-finite pixels is recorded as failed and the run goes on.
//!
//! Each record is measured and scored by `crate::record::run_one` (the protocol: prepare timed
//! once, W warm-up and K timed frames under the time budget, frame 0 scored), in process or in
//! a worker process (`crate::isolate`). The runner sits on top of both; neither imports it.
//!
//! - `config.rs`: [`RunConfig`] (the run's [`RecordSettings`](crate::record::RecordSettings)
//!   plus resume, sweep, overrides, isolation) and the [`Event`]s a caller may show;
//! - `work.rs`: the work list ([`work_list`]), whole ([`run`]) or one shard ([`run_shard`],
//!   `crate::shard`);
//! - `items.rs`: running an explicit list of [`WorkItem`]s ([`run_items`], also used by
//!   `reproduce` and `scaling`): resume, references, dispatch, saving.
//!
//! The frame API (`AovTargets`, `render_frame`, …) lives in `crate::record`; it is re-exported
//! here for the tests and benches that render frames the runner's way.

mod config;
mod items;
mod work;

pub use crate::record::{
    AovTargets, FrameTiming, MIN_TIMED_FRAMES, another_frame, error_scale, params_slug,
    render_frame,
};
pub use config::{Event, RunConfig};
pub use items::{WorkItem, fresh_results, run_items};
pub use work::{run, run_shard, work_list};
