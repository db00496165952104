//! `scatterbench reproduce`: the papers' headline tables (ARCHITECTURE §9.6); the tables and
//! their text are `experiments::reproduce`.

use anyhow::Result;
use clap::Args;
use experiments::papers::PAPERS;
use experiments::reproduce::{self, Options};
use harness::record::RecordSettings;

use crate::registry::Registry;
use crate::args::{Frames, Output, Size};
use crate::progress::Progress;

#[derive(Args)]
pub struct ReproduceArgs {
    /// Which paper (or all). The papers used 1024² (Wyman) and 640×480 (Dobashi); the
    /// default --res is small so the whole set finishes in minutes on a software adapter.
    #[arg(long, default_value = "all", value_parser = paper_names())]
    pub paper: String,
    #[command(flatten)]
    pub size: Size,
    #[command(flatten)]
    pub frames: Frames,
    #[command(flatten)]
    pub output: Output,
    #[command(flatten)]
    pub paired_floor: crate::args::PairedFloor,
    #[command(flatten)]
    pub isolate: crate::args::isolate::IsolateArgs,
}

fn paper_names() -> clap::builder::PossibleValuesParser {
    clap::builder::PossibleValuesParser::new(PAPERS.iter().copied().chain(["all"]))
}

pub fn run(a: ReproduceArgs, registry: Registry) -> Result<()> {
    let papers: Vec<&str> = if a.paper == "all" {
        PAPERS.to_vec()
    } else {
        PAPERS.iter().copied().filter(|p| *p == a.paper).collect()
    };
    let plan = reproduce::plan(&papers, registry)?;
    let run_id = format!("reproduce-{}", harness::results::run_id_now());
    let opts = Options {
        record: RecordSettings {
            cache_dir: Some(a.output.cache.clone()),
            paired_floor: a.paired_floor.method(),
            ..RecordSettings::new(
                a.output.dir(&run_id),
                (a.size.res.width, a.size.res.height),
                (a.frames.frames, a.frames.warmup),
            )
        },
        run_id,
        isolation: a.isolate.isolation()?,
    };
    let gpu = a.isolate.device.open()?;
    eprintln!(
        "{} configurations at {}x{}, {} frames",
        plan.work.len(),
        opts.record.width,
        opts.record.height,
        opts.record.frames
    );
    let mut progress = Progress::new(Some(plan.work.len()), registry);
    let text = reproduce::run(&gpu, &plan, &opts, &mut |ev| progress.event(ev))?;
    print!("{text}");
    println!(
        "\nwritten: {} and {}",
        opts.record.out_dir.join("reproduce.md").display(),
        opts.record.out_dir.join("results.json").display()
    );
    super::write_report(&opts.record.out_dir);
    Ok(())
}
