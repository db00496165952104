//! scatterbench harness: the CPU reference, image metrics and files, the GPU context, the
//! Method contract, timing, the runner and the results schema.

pub mod fsutil;
pub mod image;
pub mod reference;
