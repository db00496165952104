//! One record from start to end ([`run_one`]): measured (`measure.rs`), then scored against the
//! reference — headline, light core, per-frame errors and the temporal figure — with its
//! images and error maps written beside results.json (ARCHITECTURE §4.3–4.4).

use std::panic::AssertUnwindSafe;
use std::time::Instant;

use rayon::prelude::*;
use scenes::Scene;

use super::failure::{failed, settle};
use super::images::{error_scale, params_slug, write_aovs};
use super::measure::measure;
use super::phase::{self, Phase};
use super::settings::RecordSettings;
use super::validation::add_validation;
use crate::gpu::Gpu;
use crate::image::colormap::error_map;
use crate::image::headline::masked_relative;
use crate::image::metrics::{ToneMap, compare};
use crate::image::{Image, io};
use crate::method::{Method, Params};
use crate::reference::ReferenceImages;
use crate::results::{Record, Status};
use crate::sequence::{AOV_NAMES, FrameScorer, finite, shown_frames};
use crate::verdict::light_core_mask;

/// Measures and scores one record of `entry` with `params` on `scene` against `reference`
/// (frame 0's, tone-mapped with `tone`); with `floor` (`--paired-floor`), times the floor
/// after it ([`super::measure`]). Never fails: what goes wrong — a panic, the method's
/// error, a wgpu error, non-finite pixels, an image that cannot be written — is the record's
/// `failed` status and reason. Announces its phases ([`phase::enter`]). Under validation the
/// layer's messages go into the record ([`super::validation`]).
pub fn run_one(
    gpu: &Gpu,
    scene: &Scene,
    entry: &dyn Method,
    params: &Params,
    settings: &RecordSettings,
    (reference, tone): (&ReferenceImages, &ToneMap),
    floor: Option<&dyn Method>,
) -> Record {
    let _ = gpu.take_validation();
    let mut rec = measure_and_score(
        gpu,
        scene,
        (entry, floor),
        params,
        settings,
        reference,
        tone,
    );
    if gpu.choice.validate {
        add_validation(&mut rec, gpu.take_validation());
    }
    rec
}

/// `entry` measured with `params`, and the paired floor (if any) after it.
fn measure_and_score(
    gpu: &Gpu,
    scene: &Scene,
    (entry, floor): (&dyn Method, Option<&dyn Method>),
    params: &Params,
    settings: &RecordSettings,
    reference: &ReferenceImages,
    tone: &ToneMap,
) -> Record {
    let _ = gpu.take_errors();
    let mut scorer = match FrameScorer::new(
        scene,
        tone,
        reference,
        settings.reference,
        settings.cache_dir.as_deref(),
        shown_frames(scene, settings.warmup, settings.frames),
    ) {
        Ok(s) => s,
        Err(e) => {
            return failed(
                &scene.name,
                entry.id(),
                params,
                format!("per-frame references: {e}"),
            );
        }
    };
    let outcome = std::panic::catch_unwind(AssertUnwindSafe(|| {
        measure(gpu, scene, entry, params, settings, &mut scorer, floor)
    }));
    let errors = gpu.take_errors();
    phase::enter(Phase::Score);
    settle(outcome, errors)
        .and_then(|(rec, images)| score(rec, &images, scene, settings, reference, tone, scorer))
        .unwrap_or_else(|why| failed(&scene.name, entry.id(), params, why))
}

/// Scores a measured record's frame-0 images against the reference and writes its images and
/// error maps; the scorer holds its timed frames. Err: why the record failed.
fn score(
    mut rec: Record,
    images: &[Image; 3],
    scene: &Scene,
    settings: &RecordSettings,
    reference: &ReferenceImages,
    tone: &ToneMap,
    scorer: FrameScorer,
) -> Result<Record, String> {
    let [inscatter, surface, total] = images;
    let dir = format!("{}/{}/{}", scene.name, rec.method, params_slug(&rec.params));
    // Scoring and writing images are independent CPU work while the GPU idles: spread them over
    // the cores (FLIP at 512² is most of a record's overhead on a 2-core machine).
    let score_start = Instant::now();
    // The light core of the scored frame (frame 0), judged beside the headline.
    let core = light_core_mask(
        &scene.frame(0),
        settings.width,
        settings.height,
        &reference.distance,
    );
    let scored = [
        ("inscatter", inscatter, &reference.inscatter),
        ("total", total, &reference.total),
        ("surface", surface, &reference.surface),
    ];
    let mapped = [
        ("inscatter", inscatter, &reference.inscatter),
        ("total", total, &reference.total),
    ];
    let (scores, (written, maps)) = rayon::join(
        || {
            scored
                .par_iter()
                .map(|(name, img, refimg)| {
                    let m = compare(img, refimg, tone).map(|mut m| {
                        m.light_core = core
                            .as_ref()
                            .and_then(|c| masked_relative(&finite(img), refimg, c));
                        m
                    });
                    (*name, m)
                })
                .collect::<Vec<_>>()
        },
        || {
            let written = write_aovs(&settings.out_dir, &dir, inscatter, surface, total, tone);
            // Error maps: |method − reference| on a shared scale per AOV (the reference's
            // 99th percentile / 10); after write_aovs, which creates the directory.
            let maps = mapped
                .par_iter()
                .map(|(name, img, refimg)| {
                    let scale = error_scale(refimg);
                    let path = format!("{dir}/{name}.error.png");
                    io::write_png_ldr(
                        &settings.out_dir.join(&path),
                        &error_map(img, refimg, scale),
                    )
                    .map(|()| (*name, path, scale))
                })
                .collect::<Vec<_>>();
            (written, maps)
        },
    );
    let mut nonfinite = 0;
    let score_seconds = scorer.seconds;
    let (per_frame, temporal) = scorer.finish();
    rec.counters.insert(
        "light_core_pixels".into(),
        core.as_ref()
            .map_or(0, |m| m.iter().filter(|&&c| c).count()) as f64,
    );
    for (name, m) in scores {
        match m {
            Ok(mut m) => {
                nonfinite = nonfinite.max(m.nonfinite);
                let k = AOV_NAMES.iter().position(|a| *a == name).expect("an AOV");
                temporal[k].write(&mut m);
                rec.errors.insert(name.to_string(), m);
            }
            Err(e) => return Err(format!("cannot score {name}: {e}")),
        }
    }
    rec.errors_per_frame = per_frame;
    rec.images = written?;
    for map in maps {
        let (name, path, scale) = map?;
        rec.images.insert(format!("{name}_error"), path);
        rec.counters
            .insert(format!("{name}_error_scale"), scale as f64);
    }
    if let Some(t) = rec.timing.as_mut() {
        t.score_ms = (score_start.elapsed().as_secs_f64() + score_seconds) * 1e3;
    }
    if nonfinite > 0 {
        rec.status = Status::Failed;
        rec.reason = Some(format!("{nonfinite} non-finite pixels in the output"));
    }
    Ok(rec)
}
