//! `scatterbench stress`: the robustness suite (ARCHITECTURE §6) — every stress case × every method,
//! records in results.json (scene = case name), a stability table on stdout and in the HTML
//! report (`OUT/report/index.html`). Exit 1 when any case × method fails a criterion.

use std::path::PathBuf;

use anyhow::{Result, anyhow, bail};
use clap::Args;
use harness::reference::Settings;
use harness::results::Status;
use harness::runner::Event;
use harness::stress::{self, StressConfig};

#[derive(Args)]
pub struct StressArgs {
    /// Comma-separated method ids, or "all".
    #[arg(long, default_value = "all")]
    pub methods: String,
    /// Comma-separated case names, or "all".
    #[arg(long, default_value = "all")]
    pub cases: String,
    /// N (square) or WxH.
    #[arg(long, default_value = "64")]
    pub res: String,
    /// Triangles in the many-triangles case.
    #[arg(long, default_value_t = 1_000_000)]
    pub triangles: usize,
    /// Continue the run in --out, skipping finished records.
    #[arg(long)]
    pub resume: bool,
    /// Output directory (default results/stress-<run-id>).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Reference cache directory.
    #[arg(long, default_value = "results/cache")]
    pub cache: PathBuf,
    #[command(flatten)]
    pub isolate: super::worker::IsolateArgs,
}

fn pick_cases(spec: &str) -> Result<Vec<&'static stress::Case>> {
    if spec == "all" {
        return Ok(stress::CASES.iter().collect());
    }
    spec.split(',')
        .map(|n| {
            stress::find(n.trim()).ok_or_else(|| {
                anyhow!(
                    "unknown stress case '{n}': valid cases are {}",
                    stress::names().join(", ")
                )
            })
        })
        .collect()
}

pub fn run(a: StressArgs) -> Result<()> {
    let (width, height) = super::parse_res(&a.res)?;
    let chosen = super::run::pick_methods(&a.methods)?;
    let cases = pick_cases(&a.cases)?;
    let run_id = harness::results::run_id_now();
    let out = a
        .out
        .clone()
        .unwrap_or_else(|| PathBuf::from("results").join(format!("stress-{run_id}")));
    if a.resume && !out.join("results.json").exists() {
        bail!(
            "--resume: {} has no results.json to continue",
            out.display()
        );
    }
    let mut gpu = harness::Gpu::new().map_err(|e| anyhow!(e))?;
    eprintln!("adapter: {} ({})", gpu.summary.adapter, gpu.summary.backend);
    let cfg = StressConfig {
        out_dir: out.clone(),
        width,
        height,
        cases,
        triangles: a.triangles,
        resume: a.resume,
        reference: Settings::default(),
        cache_dir: Some(a.cache.clone()),
        run_id,
        isolation: a.isolate.isolation()?,
    };
    let results = stress::run(&mut gpu, &chosen, &cfg, &mut |ev| match ev {
        Event::Reference {
            scene,
            cached,
            seconds,
        } => eprintln!(
            "reference {scene}: {}",
            if cached {
                "cached".to_string()
            } else {
                format!("{seconds:.1} s")
            }
        ),
        Event::Resumed(key) => eprintln!("resume: kept {key}"),
        Event::Record(r) => eprintln!(
            "  {:<8} {:<22} {:<16} {}",
            verdict(r.status),
            r.scene,
            r.method,
            line(r)
        ),
    })
    .map_err(|e| anyhow!(e))?;
    println!(
        "{:<24} {:<18} {:<12} {:>12} {:>10}  reason",
        "case", "method", "verdict", "total rRMSE", "bound"
    );
    for r in &results.records {
        let bound = r
            .counters
            .get(stress::BOUND_COUNTER)
            .map(|b| format!("{b}"))
            .unwrap_or_else(|| "-".into());
        let e = r
            .errors
            .get("total")
            .map(|m| format!("{:.3e}", m.rel_rmse))
            .unwrap_or_else(|| "-".into());
        println!(
            "{:<24} {:<18} {:<12} {:>12} {:>10}  {}",
            r.scene,
            r.method,
            verdict(r.status),
            e,
            bound,
            r.reason.as_deref().unwrap_or("")
        );
    }
    let (pass, unsupported, fail) = stress::tally(&results);
    println!(
        "{pass} pass, {unsupported} unsupported, {fail} fail — {}",
        out.join("results.json").display()
    );
    // As in `run`: the report is a view of results.json, already written, so a report problem
    // is a warning, and it is written before the exit status reports failures.
    match report::generate(&out) {
        Ok(index) => println!("report: {}", index.display()),
        Err(e) => eprintln!("warning: the report was not written: {e:#}"),
    }
    if fail > 0 {
        bail!("{fail} stress case × method pairs failed");
    }
    Ok(())
}

fn verdict(s: Status) -> &'static str {
    match s {
        Status::Ok => "pass",
        Status::Skipped => "unsupported",
        Status::Failed => "FAIL",
    }
}

fn line(r: &harness::results::Record) -> String {
    match (&r.reason, r.errors.get("total")) {
        (Some(why), _) => why.clone(),
        (None, Some(m)) => format!("total rel RMSE {:.3e}", m.rel_rmse),
        _ => String::new(),
    }
}
