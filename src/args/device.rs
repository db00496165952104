//! The device flags every command that renders shares (`--adapter`, `--validate`), their check
//! before any work, and the device they open (ARCHITECTURE §7, §8).

use anyhow::{Result, anyhow};
use clap::Args;
use harness::Gpu;
use harness::gpu::{DeviceChoice, adapters};

use super::usage::refuse;

#[derive(Args, Clone, Debug, Default)]
pub struct DeviceArgs {
    /// Render on the adapter whose name contains this (case-insensitive), as `scatterbench
    /// adapters` lists them. Default: WGPU_ADAPTER_NAME, else the best adapter (hardware
    /// before software, Vulkan first, lavapipe before SwiftShader).
    #[arg(long, value_name = "NAME")]
    pub adapter: Option<String>,
    /// Run under the Khronos validation layer (also WGPU_VALIDATION=1): every message is
    /// recorded (counter validation_messages), and a validation error fails its record.
    #[arg(long)]
    pub validate: bool,
}

impl DeviceArgs {
    /// The flags, with the environment's choice where a flag is absent.
    pub fn choice(&self) -> DeviceChoice {
        let env = DeviceChoice::from_env();
        DeviceChoice {
            adapter: self.adapter.clone().or(env.adapter),
            validate: self.validate || env.validate,
        }
    }

    /// Refuses an adapter name that matches none (exit 2, listing the adapters found), then
    /// opens the device and says which adapter the numbers will come from.
    pub fn open(&self) -> Result<Gpu> {
        let choice = self.choice();
        if let Some(name) = &choice.adapter {
            let ranked = adapters::ranked(&adapters::instance(false));
            if !ranked.is_empty() && adapters::choose(ranked, Some(name)).is_err() {
                let found: Vec<String> = adapters::list()
                    .iter()
                    .map(|a| format!("{} ({}, {})", a.name, a.backend, a.device_type))
                    .collect();
                return refuse(format!(
                    "--adapter: no adapter's name contains '{name}'; found: {}",
                    found.join("; ")
                ));
            }
        }
        let gpu = Gpu::open(&choice).map_err(|e| anyhow!(e))?;
        eprintln!(
            "adapter: {} ({}, {}){}",
            gpu.summary.adapter,
            gpu.summary.backend,
            gpu.summary.driver_info,
            if choice.validate {
                ", under the Khronos validation layer"
            } else {
                ""
            }
        );
        if gpu.summary.software {
            eprintln!("note: software adapter — timings compare only as ratios within this run");
        }
        Ok(gpu)
    }
}
