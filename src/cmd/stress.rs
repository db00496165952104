//! `scatterbench stress`: the robustness suite (ARCHITECTURE §6) — every stress case × every
//! method, records in results.json (scene = case name), a stability table on stdout and in
//! the HTML report (`OUT/report/index.html`). Exit 1 when any case × method fails a criterion.

use anyhow::{Result, anyhow, bail};
use clap::Args;
use harness::record::RecordSettings;
use harness::stress::{self, StressConfig};

use crate::registry::Registry;
use crate::args::{self, MethodList, Output, Resume, Size, refuse};
use crate::progress::Progress;

#[derive(Args)]
pub struct StressArgs {
    #[command(flatten)]
    pub methods: MethodList,
    /// Comma-separated case names, or "all".
    #[arg(long, default_value = "all")]
    pub cases: String,
    #[command(flatten)]
    pub size: Size,
    /// Triangles in the many-triangles case, 1..=100000000.
    #[arg(long, default_value = "1000000", value_parser = args::int_in(1..=100_000_000usize))]
    pub triangles: usize,
    /// Particles in the particle-million case, 1..=1000000 (the scene format's most).
    #[arg(long, default_value = "1000000", value_parser = args::int_in(1..=1_000_000usize))]
    pub particles: usize,
    #[command(flatten)]
    pub resume: Resume,
    #[command(flatten)]
    pub output: Output,
    #[command(flatten)]
    pub isolate: crate::args::isolate::IsolateArgs,
}

fn pick_cases(spec: &str) -> Result<Vec<&'static stress::Case>> {
    if spec == "all" {
        return Ok(stress::CASES.iter().collect());
    }
    spec.split(',')
        .map(|n| match stress::find(n.trim()) {
            Some(c) => Ok(c),
            None => refuse(format!(
                "--cases: unknown stress case '{n}'; valid cases are {}, all",
                stress::names().join(", ")
            )),
        })
        .collect()
}

pub fn run(a: StressArgs, registry: Registry) -> Result<()> {
    let chosen = args::pick_methods(&a.methods.methods, registry)?;
    let cases = pick_cases(&a.cases)?;
    let run_id = harness::results::run_id_now();
    let out = a.output.dir(&format!("stress-{run_id}"));
    args::check_resume(a.resume.resume, &out)?;
    let mut gpu = a.isolate.device.open()?;
    let cfg = StressConfig {
        record: RecordSettings {
            cache_dir: Some(a.output.cache.clone()),
            ..stress::one_frame(&out, (a.size.res.width, a.size.res.height))
        },
        cases,
        triangles: a.triangles,
        particles: a.particles,
        resume: a.resume.resume,
        run_id,
        isolation: a.isolate.isolation()?,
    };
    let mut progress = Progress::stress(registry);
    let results = stress::run(&mut gpu, &chosen, &cfg, &mut |ev| progress.event(ev))
        .map_err(|e| anyhow!(e))?;
    println!(
        "{} — {}",
        experiments::stress::table_text(&results),
        out.join("results.json").display()
    );
    // The report is written before the exit status reports failures.
    super::write_report(&out);
    let (_, _, fail) = stress::tally(&results);
    if fail > 0 {
        bail!("{fail} stress case × method pairs failed");
    }
    Ok(())
}
