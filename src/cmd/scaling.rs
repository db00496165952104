//! `scatterbench scaling`: frame time vs caster triangles, vs pixels and vs local lights
//! (ARCHITECTURE §9.5);
//! the sweeps are `experiments::scaling`.

use anyhow::Result;
use clap::Args;
use experiments::scaling::{self, Options};
use harness::record::RecordSettings;

use crate::registry::Registry;
use crate::args::{self, Frames, MethodList, Output, Res, refuse};
use crate::progress::Progress;

#[derive(Args)]
pub struct ScalingArgs {
    #[command(flatten)]
    pub methods: MethodList,
    /// The scene the variants are made from (a library name, variant or .json path).
    #[arg(long, default_value = "sphere-point")]
    pub scene: String,
    /// Caster triangle targets (k = 1000, M = 1000000), comma-separated, each 1..=100M;
    /// "none" skips the sweep.
    #[arg(long, default_value = "1k,4k,16k,64k,256k,1M", value_parser = args::parse_counts)]
    pub triangles: Counts,
    /// Resolution of the triangle sweep (N or WxH, each side 1..=16384).
    #[arg(long, default_value = "128", value_parser = args::parse_res)]
    pub triangles_res: Res,
    /// Square resolutions of the pixel sweep, comma-separated, each 1..=16384; "none" skips
    /// the sweep.
    #[arg(long, default_value = "128,256,512,1024", value_parser = args::parse_sizes)]
    pub res: Sizes,
    /// Local-light counts of the light sweep, comma-separated, each 1..=64 (torches on the
    /// atrium's columns); "none" skips the sweep.
    #[arg(long, default_value = "1,4,16,64", value_parser = args::parse_counts)]
    pub lights: Counts,
    /// The scene of the light sweep: one with atrium stonework (a library name or .json path).
    #[arg(long, default_value = "atrium")]
    pub lights_scene: String,
    /// Resolution of the light sweep (N or WxH, each side 1..=16384).
    #[arg(long, default_value = "128", value_parser = args::parse_res)]
    pub lights_res: Res,
    /// Pixel sweep: a method is not run at a resolution where its frame time, extrapolated
    /// ∝ pixels from the previous resolution, would exceed this many seconds, 0..=86400
    /// (0 = no cap), so the big resolutions are measured for the methods that are cheap
    /// enough.
    #[arg(long, default_value = "5", value_parser = args::parse_seconds)]
    pub max_frame_s: f64,
    #[command(flatten)]
    pub frames: Frames,
    #[command(flatten)]
    pub output: Output,
    #[command(flatten)]
    pub isolate: crate::args::isolate::IsolateArgs,
}

/// Parsed `--triangles` (an alias: clap would take a field spelled `Vec<…>` as a repeated
/// argument, this is one comma-separated value).
pub type Counts = Vec<usize>;
/// Parsed `--res` of the pixel sweep.
pub type Sizes = Vec<u32>;

pub fn run(a: ScalingArgs, registry: Registry) -> Result<()> {
    let run_id = format!("scaling-{}", harness::results::run_id_now());
    let opts = Options {
        methods: args::pick_methods(&a.methods.methods, registry)?,
        base: args::scene(&a.scene)?,
        triangles: a.triangles,
        resolutions: a.res,
        lights_scene: if a.lights.is_empty() {
            None
        } else {
            Some(args::scene(&a.lights_scene)?)
        },
        lights: a.lights,
        lights_res: (a.lights_res.width, a.lights_res.height),
        max_frame_s: a.max_frame_s,
        record: RecordSettings {
            cache_dir: Some(a.output.cache.clone()),
            ..RecordSettings::new(
                a.output.dir(&run_id),
                (a.triangles_res.width, a.triangles_res.height),
                (a.frames.frames, a.frames.warmup),
            )
        },
        run_id,
        isolation: a.isolate.isolation()?,
    };
    if let Err(why) = opts.check() {
        return refuse(why);
    }
    let plan = scaling::plan(&opts)?;
    let gpu = a.isolate.device.open()?;
    eprintln!(
        "{} methods × ({} triangle variants at {}x{} + {} light variants at {}x{} + {} resolutions), {} frames",
        opts.methods.len(),
        plan.triangles.len(),
        opts.record.width,
        opts.record.height,
        plan.lights.len(),
        opts.lights_res.0,
        opts.lights_res.1,
        plan.pixels.len(),
        opts.record.frames
    );
    let mut progress = Progress::new(None, registry);
    let outcome = scaling::run(&gpu, &plan, &opts, &mut |ev| progress.event(ev))?;
    if !outcome.capped.is_empty() {
        eprintln!(
            "not run (over --max-frame-s {}): {}",
            opts.max_frame_s,
            outcome.capped.join(", ")
        );
    }
    print!("{}", scaling::summary_text(&outcome.spec, &outcome.results));
    println!(
        "written: {}",
        opts.record.out_dir.join("results.json").display()
    );
    super::write_report(&opts.record.out_dir);
    Ok(())
}
