//! scatterbench harness: the CPU reference, image metrics and files, the GPU context, the
//! Method contract and its knobs, one record's measurement (`record`), process isolation
//! (`isolate`), the runner on top of both, and the results schema (ARCHITECTURE §2.1).

pub mod fsutil;
pub mod gpu;
pub mod image;
pub mod isolate;
pub mod knobs;
pub mod merge;
pub mod method;
pub mod record;
pub mod reference;
pub mod results;
pub mod runner;
pub mod sequence;
pub mod shard;
pub mod stress;
pub mod testing;
pub mod verdict;

pub use gpu::Gpu;
pub use method::{
    Aov, ConformanceCase, FrameReport, Knob, KnobError, KnobProblem, KnobRead, Method, MethodInfo,
    ParamValue, Params, PrepareContext, Prepared, ShaderCheck, Support, Targets,
};
