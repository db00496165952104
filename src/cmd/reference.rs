//! `scatterbench reference --scene S`: the ground truth as EXR (linear) and PNG (tone-mapped),
//! with `reference.json` giving its time and its convergence against a 4× tighter self
//! (ARCHITECTURE §3).

use std::path::PathBuf;

use anyhow::{Result, anyhow};
use clap::Args;
use harness::image::{io, metrics::ToneMap};
use harness::reference::{self, Settings};
use indicatif::{ProgressBar, ProgressStyle};

use crate::args::{self, Size, refuse};

#[derive(Args)]
pub struct ReferenceArgs {
    /// Library name, variant <scene>-sub<L>, or path to a scene .json.
    #[arg(long)]
    pub scene: String,
    #[command(flatten)]
    pub size: Size,
    /// Frame to render, 0 ≤ F < the scene's frame count.
    #[arg(long, default_value = "0", value_parser = args::int_in(0..=u32::MAX))]
    pub frame: u32,
    /// Output directory (default results/reference/<scene>).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Convergence check on every Nth pixel in each direction, 1..=1024 (1 = every pixel).
    #[arg(long, default_value = "4", value_parser = args::int_in(1..=1024u32))]
    pub convergence_stride: u32,
}

pub fn run(a: ReferenceArgs) -> Result<()> {
    let scene = args::scene(&a.scene)?;
    let (w, h) = (a.size.res.width, a.size.res.height);
    if a.frame >= scene.frame_count() {
        return refuse(format!(
            "--frame: {} is outside 0..={} (scene '{}' has {} frames)",
            a.frame,
            scene.frame_count() - 1,
            scene.name,
            scene.frame_count()
        ));
    }
    let out = a
        .out
        .unwrap_or_else(|| PathBuf::from("results/reference").join(&scene.name));
    let settings = Settings::default();
    let bar = ProgressBar::new(w as u64 * h as u64);
    bar.set_style(
        ProgressStyle::with_template("{msg} [{bar:40}] {percent}% {elapsed}/{eta}")
            .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    bar.set_message(format!("reference {} {w}x{h}", scene.name));
    let images = reference::render(&scene, a.frame, w, h, settings, &|n| bar.inc(n))
        .map_err(|e| anyhow!(e))?;
    bar.finish_and_clear();
    let conv = reference::convergence(&scene, a.frame, &images, settings, a.convergence_stride)
        .map_err(|e| anyhow!(e))?;
    std::fs::create_dir_all(&out)
        .map_err(|e| anyhow!("{}: cannot create output directory: {e}", out.display()))?;
    let tone = ToneMap::auto(&images.total);
    for (name, img) in [
        ("inscatter", &images.inscatter),
        ("surface", &images.surface),
        ("total", &images.total),
    ] {
        io::write_exr(&out.join(format!("{name}.exr")), img).map_err(|e| anyhow!(e))?;
        io::write_png(&out.join(format!("{name}.png")), img, &tone).map_err(|e| anyhow!(e))?;
    }
    let report = serde_json::json!({
        "scene": scene.name, "frame": a.frame, "resolution": [w, h],
        "seconds": images.stats.seconds, "threads": images.stats.threads, "settings": settings,
        "convergence": conv, "tone_map_exposure": tone.exposure,
    });
    harness::fsutil::write_atomic(
        &out.join("reference.json"),
        serde_json::to_string_pretty(&report)?.as_bytes(),
    )
    .map_err(|e| anyhow!(e))?;
    println!(
        "reference {} {w}x{h}: {:.2} s on {} threads; convergence (4x tighter, {} px): rel RMSE in-scatter {:.2e}, total {:.2e}",
        scene.name,
        images.stats.seconds,
        images.stats.threads,
        conv.pixels,
        conv.rel_rmse_inscatter,
        conv.rel_rmse_total
    );
    println!("wrote {}", out.display());
    Ok(())
}
