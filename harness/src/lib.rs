//! scatterbench harness: the CPU reference, image metrics and files, the GPU context, the
//! Method contract, timing, the runner and the results schema.

pub mod fsutil;
pub mod gpu;
pub mod image;
pub mod merge;
pub mod method;
pub mod reference;
pub mod results;
pub mod runner;
pub mod shard;
pub mod stress;
pub mod testing;

pub use gpu::Gpu;
pub use method::{
    Entry, FrameReport, Method, MethodInfo, ParamSpec, ParamValue, Params, PrepareContext, Support,
    Targets,
};
