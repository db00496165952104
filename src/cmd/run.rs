//! The benchmark commands: `run` (scenes × methods → results.json + images).

use std::collections::BTreeMap;
use std::path::PathBuf;

use anyhow::{Result, anyhow, bail};
use clap::{Args, Subcommand};
use harness::method::{Method, Params, parse_knob};
use harness::reference::Settings;
use harness::results::Status;
use harness::runner::{Event, RunConfig};

#[derive(Subcommand)]
pub enum BenchCommand {
    /// Run methods on scenes, score them against the reference, write results.json and images.
    Run(RunArgs),
}

#[derive(Args)]
pub struct RunArgs {
    /// Comma-separated scene names or .json paths, or "all".
    #[arg(long, default_value = "all")]
    pub scenes: String,
    /// Comma-separated method ids, or "all".
    #[arg(long, default_value = "all")]
    pub methods: String,
    /// N (square) or WxH.
    #[arg(long, default_value = "512")]
    pub res: String,
    /// Timed frames per record.
    #[arg(long, default_value_t = 10)]
    pub frames: u32,
    /// Warm-up frames per record.
    #[arg(long, default_value_t = 3)]
    pub warmup: u32,
    /// Per-record time budget in seconds (0 = none): warm-up stops after its first frame once
    /// it has used a quarter of it, timing once 3 frames are timed and they have used it, so
    /// slow methods on a software adapter get 1 + 3 frames and fast ones the full W + K. The
    /// counts are recorded in each record's counters (warmup_frames, timed_frames).
    #[arg(long, default_value_t = 8.0)]
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
    /// Continue the run in --out, skipping finished records.
    #[arg(long)]
    pub resume: bool,
    /// Output directory (default results/<run-id>).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Reference cache directory.
    #[arg(long, default_value = "results/cache")]
    pub cache: PathBuf,
    /// Run only the I-th of N contiguous slices (1-based) of the scene × method × params
    /// work list, for batch schedulers; reassemble with `scatterbench merge`.
    #[arg(long, value_name = "I/N", value_parser = parse_shard)]
    pub shard: Option<harness::shard::Shard>,
    #[command(flatten)]
    pub isolate: super::worker::IsolateArgs,
}

fn parse_shard(s: &str) -> std::result::Result<harness::shard::Shard, String> {
    harness::shard::Shard::parse(s)
}

pub fn dispatch(c: BenchCommand) -> Result<()> {
    match c {
        BenchCommand::Run(a) => run(a),
    }
}

/// Registry entries named by a comma-separated list, or all of them; unknown ids are refused
/// with the valid ones.
pub fn pick_methods(spec: &str) -> Result<Vec<&'static dyn Method>> {
    if spec == "all" {
        return Ok(methods::REGISTRY.to_vec());
    }
    spec.split(',')
        .map(|id| {
            methods::find(id.trim()).ok_or_else(|| {
                anyhow!(
                    "unknown method '{id}': valid methods are {}",
                    methods::REGISTRY
                        .iter()
                        .map(|e| e.id())
                        .collect::<Vec<_>>()
                        .join(", ")
                )
            })
        })
        .collect()
}

fn pick_scenes(spec: &str) -> Result<Vec<scenes::Scene>> {
    let names: Vec<String> = if spec == "all" {
        scenes::library::names()
            .into_iter()
            .map(String::from)
            .collect()
    } else {
        spec.split(',').map(|s| s.trim().to_string()).collect()
    };
    names
        .iter()
        .map(|n| scenes::library::resolve(n).map_err(|e| anyhow!(e)))
        .collect()
}

fn parse_overrides(items: &[String], chosen: &[&dyn Method]) -> Result<BTreeMap<String, Params>> {
    let mut out: BTreeMap<String, Params> = BTreeMap::new();
    for item in items {
        let (lhs, value) = item
            .split_once('=')
            .ok_or_else(|| anyhow!("--param '{item}': expected METHOD.KNOB=VALUE"))?;
        let (method, knob) = lhs
            .split_once('.')
            .ok_or_else(|| anyhow!("--param '{item}': expected METHOD.KNOB=VALUE"))?;
        let entry = methods::find(method)
            .ok_or_else(|| anyhow!("--param '{item}': unknown method '{method}'"))?;
        if !chosen.iter().any(|e| e.id() == entry.id()) {
            bail!("--param '{item}': method '{method}' is not in --methods");
        }
        // A refused value is a harness::KnobError (names the knob and its range; exit 2).
        let v = parse_knob(entry, knob, value)?;
        out.entry(entry.id().to_string())
            .or_default()
            .insert(knob.to_string(), v);
    }
    Ok(out)
}

pub fn run(a: RunArgs) -> Result<()> {
    let (width, height) = super::parse_res(&a.res)?;
    if !a.time_budget.is_finite() || a.time_budget < 0.0 {
        bail!(
            "--time-budget: {} is not a number of seconds ≥ 0",
            a.time_budget
        );
    }
    let chosen = pick_methods(&a.methods)?;
    let scenes = pick_scenes(&a.scenes)?;
    let overrides = parse_overrides(&a.params, &chosen)?;
    let run_id = harness::results::run_id_now();
    let shard = a.shard.unwrap_or(harness::shard::Shard::WHOLE);
    let out = a.out.clone().unwrap_or_else(|| {
        PathBuf::from("results").join(if shard.is_whole() {
            run_id.clone()
        } else {
            format!("{run_id}-shard-{}-of-{}", shard.index, shard.count)
        })
    });
    if a.resume && !out.join("results.json").exists() {
        bail!(
            "--resume: {} has no results.json to continue",
            out.display()
        );
    }
    let gpu = harness::Gpu::new().map_err(|e| anyhow!(e))?;
    eprintln!(
        "adapter: {} ({}, {})",
        gpu.summary.adapter, gpu.summary.backend, gpu.summary.driver_info
    );
    if gpu.summary.software {
        eprintln!("note: software adapter — timings compare only as ratios within this run");
    }
    let cfg = RunConfig {
        out_dir: out.clone(),
        width,
        height,
        frames: a.frames,
        warmup: a.warmup,
        no_skip: a.no_skip,
        resume: a.resume,
        sweep: a.sweep,
        overrides,
        reference: Settings::default(),
        cache_dir: Some(a.cache.clone()),
        run_id,
        budget_ms: (a.time_budget > 0.0).then_some(a.time_budget * 1e3),
        isolation: a.isolate.isolation()?,
    };
    let mut counts = [0usize; 3];
    let results = harness::runner::run_shard(&gpu, &scenes, &chosen, &cfg, shard, &mut |ev| match ev {
        Event::Reference { scene, cached, seconds } => eprintln!("reference {scene}: {}", if cached { "cached".to_string() } else { format!("{seconds:.1} s") }),
        Event::Resumed(key) => eprintln!("resume: kept {key}"),
        Event::Record(r) => {
            counts[r.status as usize] += 1;
            let p: Vec<String> = r.params.iter().map(|(k, v)| format!("{k}={v}")).collect();
            match r.status {
                Status::Ok => {
                    let t = r.timing.as_ref().map(|t| t.wall_ms.median).unwrap_or(0.0);
                    let g = r.timing.as_ref().and_then(|t| t.gpu_ms).map(|g| format!(", gpu {:.2} ms", g.median)).unwrap_or_default();
                    let e = r.errors.get("inscatter").map(|m| m.rel_rmse).unwrap_or(f64::NAN);
                    eprintln!("  ok      {:<16} {:<20} {:<40} wall {t:.2} ms{g}, in-scatter rel RMSE {e:.4}", r.scene, r.method, p.join(" "));
                }
                _ => eprintln!("  {:<7} {:<16} {:<20} {}: {}", format!("{:?}", r.status).to_lowercase(), r.scene, r.method, p.join(" "), r.reason.as_deref().unwrap_or("")),
            }
        }
    })
    .map_err(|e| anyhow!(e))?;
    println!(
        "{} records ({} ok, {} skipped, {} failed) in {}",
        results.records.len(),
        counts[Status::Ok as usize],
        counts[Status::Skipped as usize],
        counts[Status::Failed as usize],
        out.join("results.json").display()
    );
    // The report is a view of results.json, which is already written: a report problem
    // must not turn a finished run into a failed one.
    match report::generate(&out) {
        Ok(index) => println!("report: {}", index.display()),
        Err(e) => eprintln!("warning: the report was not written: {e:#}"),
    }
    Ok(())
}

pub fn methods_json() -> serde_json::Value {
    serde_json::Value::Array(
        methods::REGISTRY
            .iter()
            .map(|m| {
                let info = m.info();
                let support: BTreeMap<String, serde_json::Value> = scenes::library::names()
                    .into_iter()
                    .filter_map(|n| scenes::library::resolve(n).ok())
                    .map(|s| (s.name.clone(), serde_json::to_value(m.support(&s.features(), wgpu::Features::all())).unwrap_or_default()))
                    .collect();
                serde_json::json!({"id": info.id, "paper": info.paper, "summary": info.summary, "params": m.knobs(), "support": support})
            })
            .collect(),
    )
}

pub fn print_methods() {
    println!("methods:");
    for m in methods::REGISTRY {
        let info = m.info();
        println!("  {:<20} {}", info.id, info.summary);
        for p in m.knobs() {
            let sweep: Vec<String> = p.sweep.iter().map(|v| v.to_string()).collect();
            println!(
                "  {:<20}   {} = {} ({}; sweep: {}) — {}",
                "",
                p.name,
                p.default,
                p.range,
                if sweep.is_empty() {
                    "-".into()
                } else {
                    sweep.join(", ")
                },
                p.meaning
            );
        }
    }
}
