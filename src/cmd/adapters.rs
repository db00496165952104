//! `scatterbench adapters`: every adapter wgpu can see, with the features the suite uses
//! (ARCHITECTURE §7, §8).

use anyhow::Result;
use clap::Args;
use harness::gpu::adapters;

#[derive(Args)]
pub struct AdaptersArgs {
    /// Print JSON: [{"name", "backend", "driver", "driver_info", "device_type", "software",
    /// "features": {"timestamps", "pipeline_statistics", "depth_clip_control",
    /// "float32_blending"}, "default"}], best first.
    #[arg(long, conflicts_with = "first_hardware")]
    pub json: bool,
    /// Print only the name of the best hardware (non-software) adapter; exit 1 when there is
    /// none (the bundle's run.sh uses it).
    #[arg(long)]
    pub first_hardware: bool,
}

pub fn run(a: AdaptersArgs) -> Result<()> {
    let list = adapters::list();
    if a.first_hardware {
        let Some(best) = list.iter().find(|a| !a.software) else {
            anyhow::bail!("no hardware adapter: only software ones were found");
        };
        println!("{}", best.name);
        return Ok(());
    }
    if a.json {
        println!("{}", serde_json::to_string_pretty(&list)?);
        return Ok(());
    }
    if list.is_empty() {
        anyhow::bail!(harness::gpu::NO_ADAPTER_HELP);
    }
    let yes = |b: bool| if b { "yes" } else { "no" };
    for a in &list {
        println!(
            "{}{} — {}, {}, driver {} {}{}",
            if a.default { "* " } else { "  " },
            a.name,
            a.backend,
            a.device_type,
            a.driver,
            a.driver_info,
            if a.software { " (software)" } else { "" }
        );
        let f = &a.features;
        println!(
            "    timestamps {}, pipeline statistics {}, depth clip control {}, float32 blending {}",
            yes(f.timestamps),
            yes(f.pipeline_statistics),
            yes(f.depth_clip_control),
            yes(f.float32_blending)
        );
    }
    println!("* the adapter a run uses without --adapter");
    Ok(())
}
