//! `scatterbench run`: scenes × methods × parameter sets → results.json, images and report
//! (ARCHITECTURE §4, §5, §9.2–§9.3).

use std::path::PathBuf;

use anyhow::{Result, anyhow};
use clap::Args;
use harness::record::RecordSettings;
use harness::runner::RunConfig;
use harness::shard::Shard;

use crate::registry::Registry;
use crate::args::{self, Frames, MethodList, Output, Resume, Size};
use crate::progress::Progress;

#[derive(Args)]
pub struct RunArgs {
    /// Comma-separated scenes (library names, variants <scene>-sub<L>, or .json paths), or
    /// "all" (the library).
    #[arg(long, default_value = "all")]
    pub scenes: String,
    #[command(flatten)]
    pub methods: MethodList,
    #[command(flatten)]
    pub size: Size,
    #[command(flatten)]
    pub frames: Frames,
    /// Per-record time budget in seconds, 0..=86400 (0 = none): warm-up stops after its
    /// first frame once it has used a quarter of it, timing once a frame is timed and the timed
    /// frames have used it, and a first frame that alone uses it is the one timed frame. Fast
    /// methods get the full W + K; a 35 s/frame method on a software adapter gets 0 + 1. The
    /// counts are in each record's counters (warmup_frames, timed_frames), the budget in
    /// run.time_budget_s.
    #[arg(long, default_value = "2", value_parser = args::parse_seconds)]
    pub time_budget: f64,
    /// METHOD.KNOB=VALUE (repeatable).
    #[arg(long = "param")]
    pub params: Vec<String>,
    /// Run every declared sweep value of every knob.
    #[arg(long)]
    pub sweep: bool,
    /// Run every pass even where the scene does not need it.
    #[arg(long)]
    pub no_skip: bool,
    #[command(flatten)]
    pub paired_floor: args::PairedFloor,
    #[command(flatten)]
    pub resume: Resume,
    #[command(flatten)]
    pub output: Output,
    /// Run only the I-th of N contiguous slices (1-based) of the scene × method × params
    /// work list, for batch schedulers; reassemble with `scatterbench merge`.
    #[arg(long, value_name = "I/N", value_parser = Shard::parse)]
    pub shard: Option<Shard>,
    #[command(flatten)]
    pub isolate: crate::args::isolate::IsolateArgs,
}

pub fn run(a: RunArgs, registry: Registry) -> Result<()> {
    let chosen = args::pick_methods(&a.methods.methods, registry)?;
    let scenes = args::pick_scenes(&a.scenes)?;
    let overrides = args::parse_overrides(&a.params, &chosen, registry)?;
    let floor = report::analysis::FLOOR_METHOD;
    if a.paired_floor.paired_floor && !chosen.iter().any(|m| m.id() == floor) {
        return args::refuse(format!(
            "--paired-floor times the floor ({floor}) in every record and needs it among \
             --methods (it is also the scenes' floor record); add {floor} to --methods"
        ));
    }
    let run_id = harness::results::run_id_now();
    let shard = a.shard.unwrap_or(Shard::WHOLE);
    let out: PathBuf = a.output.dir(&if shard.is_whole() {
        run_id.clone()
    } else {
        format!("{run_id}-shard-{}-of-{}", shard.index, shard.count)
    });
    args::check_resume(a.resume.resume, &out)?;
    let gpu = a.isolate.device.open()?;
    let cfg = RunConfig {
        record: RecordSettings {
            no_skip: a.no_skip,
            cache_dir: Some(a.output.cache.clone()),
            budget_ms: (a.time_budget > 0.0).then_some(a.time_budget * 1e3),
            paired_floor: a.paired_floor.method(),
            ..RecordSettings::new(
                &out,
                (a.size.res.width, a.size.res.height),
                (a.frames.frames, a.frames.warmup),
            )
        },
        resume: a.resume.resume,
        sweep: a.sweep,
        overrides,
        run_id,
        isolation: a.isolate.isolation()?,
    };
    let mut progress = Progress::new(None, registry);
    let results = harness::runner::run_shard(&gpu, &scenes, &chosen, &cfg, shard, &mut |ev| {
        progress.event(ev)
    })
    .map_err(|e| anyhow!(e))?;
    let [ok, skipped, failed] = progress.counts();
    println!(
        "{} records ({ok} ok, {skipped} skipped, {failed} failed) in {}",
        results.records.len(),
        out.join("results.json").display()
    );
    super::write_report(&out);
    Ok(())
}
