//! scatterbench harness: the CPU reference, image metrics and files, the GPU context, the
//! Method contract, timing, the runner and the results schema.

pub mod fsutil;
pub mod gpu;
pub mod image;
pub mod isolate;
pub mod knobs;
pub mod merge;
pub mod method;
pub mod reference;
pub mod results;
pub mod run_methods;
pub mod runner;
pub mod sequence;
pub mod shard;
pub mod stress;
pub mod testing;
pub mod verdict;

pub use gpu::Gpu;
pub use method::{
    Aov, ConformanceCase, FrameReport, Knob, KnobError, KnobProblem, KnobRead, Medium, Method,
    MethodInfo, ParamValue, Params, PrepareContext, Prepared, ShaderCheck, Support, Targets,
};
