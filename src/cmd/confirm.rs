//! `scatterbench confirm RUN_DIR`: re-time a run's verdicts (ARCHITECTURE §4.5). Per scene, the
//! `--top` cheapest configurations under each error budget (`report::candidates`) and the
//! floor run again at the run's resolution, with more frames and `--paired-floor`, into a run
//! of their own: its verdicts and `frontier` rest on samples that did not pick the winners.

use std::path::PathBuf;

use anyhow::{Result, anyhow};
use clap::Args;
use harness::method::{Method, Params, find, resolve_params};
use harness::record::RecordSettings;
use harness::results::Record;
use harness::runner::{RunConfig, WorkItem};
use report::analysis::FLOOR_METHOD;

use crate::registry::Registry;
use crate::args::{self, Frames, Output, Resume, refuse};
use crate::progress::Progress;

/// Configurations per scene and budget, 1..=50.
const TOP: std::ops::RangeInclusive<usize> = 1..=50;

#[derive(Args)]
pub struct ConfirmArgs {
    /// The run directory (holds results.json) whose verdicts to re-time.
    pub run_dir: PathBuf,
    /// Configurations re-timed per scene and error budget (1 %, 5 %, 10 %), 1..=50: the
    /// cheapest under each by the run's compared times.
    #[arg(long, default_value_t = report::candidates::DEFAULT_TOP, value_parser = args::int_in(TOP))]
    pub top: usize,
    #[command(flatten)]
    pub frames: Frames,
    #[command(flatten)]
    pub resume: Resume,
    #[command(flatten)]
    pub output: Output,
    #[command(flatten)]
    pub isolate: crate::args::isolate::IsolateArgs,
}

pub fn run(a: ConfirmArgs, registry: Registry) -> Result<()> {
    let source = super::frontier::load("RUN_DIR", &a.run_dir)?;
    let chosen = report::candidates::candidates(&source, a.top);
    if chosen.is_empty() {
        return refuse(format!(
            "RUN_DIR: {} has no ok, timed, scored configuration under any budget to confirm",
            a.run_dir.display()
        ));
    }
    let scenes = scenes_of(&chosen)?;
    let work = work_list(&a.run_dir, &scenes, &chosen, registry)?;
    let run_id = format!("confirm-{}", harness::results::run_id_now());
    let out = a.output.dir(&run_id);
    args::check_resume(a.resume.resume, &out)?;
    let [width, height] = source.run.resolution;
    let record = RecordSettings {
        cache_dir: Some(a.output.cache.clone()),
        paired_floor: Some(FLOOR_METHOD.to_string()),
        ..RecordSettings::new(&out, (width, height), (a.frames.frames, a.frames.warmup))
    };
    let cfg = RunConfig {
        resume: a.resume.resume,
        isolation: a.isolate.isolation()?,
        ..RunConfig::new(record, &run_id)
    };
    let gpu = a.isolate.device.open()?;
    eprintln!(
        "confirming {} configurations of {} on {} scenes at {width}x{height}, {} frames",
        chosen.len(),
        source.run.id,
        scenes.len(),
        a.frames.frames
    );
    let mut progress = Progress::new(Some(work.len()), registry);
    let results = harness::runner::run_items(&gpu, &scenes, &work, &cfg, None, &mut |ev| {
        progress.event(ev)
    })
    .map_err(|e| anyhow!(e))?;
    print!("{}", report::frontier::markdown(&results, None));
    println!("written: {}", out.join("results.json").display());
    super::write_report(&out);
    Ok(())
}

/// The scenes of `chosen`, each once in the order they appear, loaded by name.
fn scenes_of(chosen: &[&Record]) -> Result<Vec<scenes::Scene>> {
    let names = report::analysis::ordered(chosen.iter().map(|r| r.scene.as_str()));
    names.iter().map(|n| args::scene(n)).collect()
}

/// Per scene: the floor at its defaults (every record is paired with it at its own shadow-map
/// settings, §4.5), then the chosen configurations with the knobs they were run with, checked
/// against today's methods.
fn work_list(
    run_dir: &std::path::Path,
    scenes: &[scenes::Scene],
    chosen: &[&Record],
    registry: Registry,
) -> Result<Vec<WorkItem<'static>>> {
    let method = |id: &str| -> Result<&'static dyn Method> {
        find(registry, id).map_or_else(
            || {
                refuse(format!(
                    "{}: method '{id}' is not in this build's registry",
                    run_dir.display()
                ))
            },
            Ok,
        )
    };
    let floor = method(FLOOR_METHOD)?;
    let mut work = Vec::new();
    for (scene, s) in scenes.iter().enumerate() {
        work.push(WorkItem {
            scene,
            entry: floor,
            params: resolve_params(floor, &Params::new())?,
        });
        for r in chosen.iter().filter(|r| r.scene == s.name) {
            let entry = method(&r.method)?;
            let params = match resolve_params(entry, &r.params) {
                Ok(p) => p,
                Err(e) => return refuse(format!("{}: record {}: {e}", run_dir.display(), r.key())),
            };
            work.push(WorkItem {
                scene,
                entry,
                params,
            });
        }
    }
    Ok(work)
}
