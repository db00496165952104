//! The benchmark commands (`run`, …): filled in by the GPU harness.

use anyhow::Result;
use clap::Subcommand;

#[derive(Subcommand)]
pub enum BenchCommand {}

pub fn dispatch(c: BenchCommand) -> Result<()> {
    match c {}
}

pub fn methods_json() -> serde_json::Value {
    serde_json::json!([])
}

pub fn print_methods() {}
