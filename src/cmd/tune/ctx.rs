//! What every scene of a tune shares (the GPU, the floor, the methods, the budgets, the
//! record settings, the start): its own module so that the phases (`screen`, `timing`) and the
//! command that runs them all import it, and none imports the command.

use std::time::Instant;

use harness::method::{Method, Params};
use harness::record::RecordSettings;

/// What every scene's work shares.
pub struct Ctx<'a> {
    pub gpu: &'a harness::Gpu,
    pub floor: &'static dyn Method,
    pub methods: Vec<&'static dyn Method>,
    pub overrides: std::collections::BTreeMap<String, Params>,
    pub budgets: Vec<f64>,
    pub settings: RecordSettings,
    pub start: Instant,
}
