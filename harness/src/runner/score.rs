//! Scoring one record: its frames against the reference (headline, light core, per-frame
//! errors), error maps and images written beside results.json (ARCHITECTURE §4.3–4.4).

use super::*;

pub(crate) fn run_one(
    gpu: &Gpu,
    scene: &Scene,
    entry: &dyn Method,
    params: &Params,
    cfg: &RunConfig,
    reference: &ReferenceImages,
    tone: &ToneMap,
) -> Record {
    let _ = gpu.take_validation();
    let mut rec = measure_and_score(gpu, scene, entry, params, cfg, reference, tone);
    if gpu.choice.validate {
        add_validation(&mut rec, gpu.take_validation());
    }
    rec
}

/// How many of a record's validation messages it keeps (all are counted).
const KEPT_VALIDATION_MESSAGES: usize = 5;

/// Counts the validation layer's messages into the record, keeps the first ones, and fails a
/// record that raised a validation error (ARCHITECTURE §6): an ok image rendered through
/// undefined behaviour proves nothing about another driver.
fn add_validation(rec: &mut Record, messages: Vec<crate::gpu::validation::Message>) {
    let (ignored, messages): (Vec<_>, Vec<_>) = messages
        .into_iter()
        .partition(|m| m.false_positive.is_some());
    rec.counters
        .insert("validation_messages".into(), messages.len() as f64);
    if !ignored.is_empty() {
        rec.counters
            .insert("validation_ignored".into(), ignored.len() as f64);
    }
    if let Some(first) = messages.iter().find(|m| m.error)
        && rec.status == Status::Ok
    {
        rec.status = Status::Failed;
        rec.reason = Some(format!(
            "validation error ({} of {} messages): {}",
            messages.iter().filter(|m| m.error).count(),
            messages.len(),
            first.text.replace("\n\t", " ")
        ));
    }
    rec.validation = messages
        .into_iter()
        .take(KEPT_VALIDATION_MESSAGES)
        .map(|m| m.text)
        .collect();
}

fn measure_and_score(
    gpu: &Gpu,
    scene: &Scene,
    entry: &dyn Method,
    params: &Params,
    cfg: &RunConfig,
    reference: &ReferenceImages,
    tone: &ToneMap,
) -> Record {
    let _ = gpu.take_errors();
    let mut scorer = match FrameScorer::new(
        scene,
        tone,
        reference,
        cfg.reference,
        cfg.cache_dir.as_deref(),
    ) {
        Ok(s) => s,
        Err(e) => {
            return failed(
                scene,
                entry.id(),
                params,
                format!("per-frame references: {e}"),
            );
        }
    };
    let outcome = std::panic::catch_unwind(AssertUnwindSafe(|| {
        measure(gpu, scene, entry, params, cfg, &mut scorer)
    }));
    let errors = gpu.take_errors();
    crate::isolate::phase::enter(crate::isolate::Phase::Score);
    let (mut rec, images) = match settle(outcome, errors) {
        Ok(measured) => measured,
        Err(why) => return failed(scene, entry.id(), params, why),
    };
    let [inscatter, surface, total] = &images;
    let dir = format!("{}/{}/{}", scene.name, entry.id(), params_slug(params));
    // Scoring and writing images are independent CPU work while the GPU idles: spread them over
    // the cores (FLIP at 512² is most of a record's overhead on a 2-core machine).
    let score_start = Instant::now();
    // The light core of the scored frame (frame 0), judged beside the headline.
    let core = light_core_mask(&scene.frame(0), cfg.width, cfg.height, &reference.distance);
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
            let written = write_aovs(&cfg.out_dir, &dir, inscatter, surface, total, tone);
            // Error maps: |method − reference| on a shared scale per AOV (the reference's
            // 99th percentile / 10); after write_aovs, which creates the directory.
            let maps = mapped
                .par_iter()
                .map(|(name, img, refimg)| {
                    let scale = error_scale(refimg);
                    let path = format!("{dir}/{name}.error.png");
                    io::write_png_ldr(&cfg.out_dir.join(&path), &error_map(img, refimg, scale))
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
                m.temporal = temporal[k];
                rec.errors.insert(name.to_string(), m);
            }
            Err(e) => {
                return failed(
                    scene,
                    entry.id(),
                    params,
                    format!("cannot score {name}: {e}"),
                );
            }
        }
    }
    rec.errors_per_frame = per_frame;
    match written {
        Ok(paths) => rec.images = paths,
        Err(e) => return failed(scene, entry.id(), params, e),
    }
    for map in maps {
        match map {
            Ok((name, path, scale)) => {
                rec.images.insert(format!("{name}_error"), path);
                rec.counters
                    .insert(format!("{name}_error_scale"), scale as f64);
            }
            Err(e) => return failed(scene, entry.id(), params, e),
        }
    }
    if let Some(t) = rec.timing.as_mut() {
        t.score_ms = (score_start.elapsed().as_secs_f64() + score_seconds) * 1e3;
    }
    if nonfinite > 0 {
        rec.status = Status::Failed;
        rec.reason = Some(format!("{nonfinite} non-finite pixels in the output"));
    }
    rec
}

/// A measurement's outcome with the wgpu errors raised meanwhile: the record and its images, or
/// why the record failed (a panic, the method's error, a wgpu error).
fn settle<T>(
    outcome: std::thread::Result<Result<T, String>>,
    errors: Vec<String>,
) -> Result<T, String> {
    match outcome {
        Err(panic) => Err(format!("panicked: {}", panic_message(panic))),
        Ok(Err(e)) if errors.is_empty() => Err(e),
        Ok(Err(e)) => Err(format!("{e}; wgpu: {}", errors.join("; "))),
        Ok(Ok(_)) if !errors.is_empty() => Err(format!("wgpu error: {}", errors.join("; "))),
        Ok(Ok(v)) => Ok(v),
    }
}

/// A caught panic's message.
pub(crate) fn panic_message(p: Box<dyn std::any::Any + Send>) -> String {
    p.downcast_ref::<String>()
        .cloned()
        .or_else(|| p.downcast_ref::<&str>().map(|s| s.to_string()))
        .unwrap_or_else(|| "unknown panic".into())
}

/// The error that maps to the top of an error map's colour bar: a tenth of the reference's
/// 99th-percentile luminance, so 10% errors saturate.
pub fn error_scale(reference: &Image) -> f32 {
    let mut l = reference.luminance();
    l.retain(|v| v.is_finite());
    if l.is_empty() {
        return 1.0;
    }
    l.sort_by(f32::total_cmp);
    let p99 = l[((l.len() as f64 * 0.99) as usize).min(l.len() - 1)];
    (0.1 * p99).max(1e-12)
}

pub(super) fn write_aovs(
    out: &Path,
    rel_dir: &str,
    inscatter: &Image,
    surface: &Image,
    total: &Image,
    tone: &ToneMap,
) -> Result<std::collections::BTreeMap<String, String>, String> {
    let mut paths = std::collections::BTreeMap::new();
    for (name, img) in [
        ("inscatter", inscatter),
        ("surface", surface),
        ("total", total),
    ] {
        let exr = format!("{rel_dir}/{name}.exr");
        let png = format!("{rel_dir}/{name}.png");
        std::fs::create_dir_all(out.join(rel_dir))
            .map_err(|e| format!("{}: {e}", out.join(rel_dir).display()))?;
        io::write_exr(&out.join(&exr), img)?;
        io::write_png(&out.join(&png), img, tone)?;
        paths.insert(name.to_string(), exr);
        paths.insert(format!("{name}_png"), png);
    }
    Ok(paths)
}

#[cfg(test)]
mod validation_tests {
    use super::*;
    use crate::gpu::validation::Message;

    fn ok_record() -> Record {
        let mut r = Record::unmeasured("s", "m", &Params::new(), Status::Ok, String::new());
        r.reason = None;
        r
    }

    #[test]
    fn a_validation_error_fails_the_record_and_every_message_is_counted() {
        let mut r = ok_record();
        let warn = |i: usize| Message {
            error: false,
            text: format!("VALIDATION [VUID-warn-{i} (0x{i})]\n\tnot fatal"),
            false_positive: None,
        };
        let mut messages: Vec<Message> = (0..7).map(warn).collect();
        messages.insert(
            2,
            Message {
                error: true,
                text: "VALIDATION [VUID-vkCmdDraw-commandBuffer-02701 (0x2)]\n\tline width".into(),
                false_positive: None,
            },
        );
        messages.push(Message {
            error: true,
            text: "VALIDATION [UNASSIGNED (0x6)]\n\tInvalid source language operand: 10".into(),
            false_positive: Some("test"),
        });
        add_validation(&mut r, messages);
        assert_eq!(r.status, Status::Failed);
        let why = r.reason.unwrap();
        assert!(why.contains("VUID-vkCmdDraw-commandBuffer-02701"), "{why}");
        assert!(why.contains("1 of 8"), "{why}");
        assert_eq!(r.counters["validation_messages"], 8.0);
        assert_eq!(
            r.counters["validation_ignored"], 1.0,
            "a false positive, counted apart"
        );
        assert_eq!(r.validation.len(), KEPT_VALIDATION_MESSAGES);
    }

    #[test]
    fn warnings_are_recorded_but_do_not_fail() {
        let mut r = ok_record();
        add_validation(
            &mut r,
            vec![Message {
                error: false,
                text: "VALIDATION [VUID-w (0x1)]".into(),
                false_positive: None,
            }],
        );
        assert_eq!(r.status, Status::Ok);
        assert_eq!(r.counters["validation_messages"], 1.0);
        let mut clean = ok_record();
        add_validation(&mut clean, Vec::new());
        assert_eq!(clean.counters["validation_messages"], 0.0);
        assert!(clean.validation.is_empty() && clean.status == Status::Ok);
    }
}
