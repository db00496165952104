//! `scatterbench references`: fills a reference cache with every frame of the given scenes at
//! the given resolutions, so that runs (and a bundle, `scripts/bundle.sh`) find them there
//! (ARCHITECTURE §9.1). Entries already present are kept; `--copy-from` takes entries from
//! another cache instead of rendering them.

use std::path::PathBuf;
use std::time::Instant;

use anyhow::{Result, anyhow};
use clap::Args;
use harness::reference::{self, Settings, cache};

use crate::args::{self, Res};

#[derive(Args)]
pub struct ReferencesArgs {
    /// Comma-separated scenes (library names, variants, .json paths), or "all" (the library).
    #[arg(long, default_value = "all")]
    pub scenes: String,
    /// Comma-separated resolutions, each N or WxH (each side 1..=16384).
    #[arg(long, default_value = "256", value_delimiter = ',', value_parser = args::parse_res)]
    pub res: Vec<Res>,
    /// The cache to fill.
    #[arg(long, default_value = "results/cache")]
    pub cache: PathBuf,
    /// Another cache to take entries from before rendering (read only).
    #[arg(long, value_name = "DIR")]
    pub copy_from: Option<PathBuf>,
    /// Mantissa bits the stored values keep, 1..=23 (23: lossless). A bundle keeps 20: at most
    /// 4.8e-7 relative, under half the reference's quadrature tolerance, for a quarter less
    /// size (ARCHITECTURE §9.1).
    #[arg(long, default_value = "23", value_parser = args::int_in(1..=23u32))]
    pub mantissa_bits: u32,
}

pub fn run(a: ReferencesArgs) -> Result<()> {
    let scenes = args::pick_scenes(&a.scenes)?;
    if let Some(src) = &a.copy_from
        && !src.is_dir()
    {
        return args::refuse(format!("--copy-from: {} is not a directory", src.display()));
    }
    let settings = Settings::default();
    let (mut rendered, mut kept, mut copied) = (0, 0, 0);
    for res in &a.res {
        for scene in &scenes {
            for frame in 0..scene.frame_count() {
                let key = cache::key(scene, frame, res.width, res.height, &settings);
                let what = if cache::load(&a.cache, &key).is_some() {
                    kept += 1;
                    "cached".to_string()
                } else if let Some(hit) = a.copy_from.as_ref().and_then(|d| cache::load(d, &key)) {
                    cache::store_rounded(&a.cache, &key, &hit, a.mantissa_bits)
                        .map_err(|e| anyhow!(e))?;
                    copied += 1;
                    "copied".to_string()
                } else {
                    let t = Instant::now();
                    let images = reference::render(
                        scene,
                        frame,
                        res.width,
                        res.height,
                        settings,
                        &|_| {},
                    )
                    .map_err(|e| anyhow!("reference of {} frame {frame}: {e}", scene.name))?;
                    cache::store_rounded(&a.cache, &key, &images, a.mantissa_bits)
                        .map_err(|e| anyhow!(e))?;
                    rendered += 1;
                    format!("rendered in {:.1} s", t.elapsed().as_secs_f64())
                };
                println!(
                    "{} frame {frame} {}x{}: {what}",
                    scene.name, res.width, res.height
                );
            }
        }
    }
    println!(
        "{}: {rendered} rendered, {copied} copied, {kept} already there",
        a.cache.display()
    );
    Ok(())
}
