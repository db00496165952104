//! Scoring a record's timed frames as a sequence (ARCHITECTURE §4.1, §4.4; issue 17): every
//! timed frame of an animated scene is scored against its own frame's reference
//! (`errors_per_frame`), and every record with two or more timed frames gets the
//! temporal-stability figure
//! (`errors.<aov>.temporal`, [`crate::image::headline::Temporal`]) — on a static scene too,
//! where it measures flicker of the method alone.
//!
//! Per-frame references come from the reference cache (`--cache`); the frames of the scene
//! being run are also kept in memory for the records that follow (one scene at a time), so a
//! run without a cache directory renders each frame's reference once, not once per record.
//! **Only the frames a record can show are referenced**: a record of W warm-up and K timed
//! frames shows scene frames 0 … W + K − 1 (modulo the frame count), so its scorer loads the
//! references of frames 0 … min(W + K, N) − 1 ([`shown_frames`]) — 13 of a 60-frame scene in
//! the default run, not 60 (ARCHITECTURE §4.1, "Which frames are scored").

use std::sync::{Arc, Mutex};

use rayon::prelude::*;
use scenes::Scene;

use crate::image::Image;
use crate::image::headline::{Temporal, masked_relative};
use crate::image::lag::{LagFigures, LagFlicker};
use crate::image::metrics::{ToneMap, compare};
use crate::reference::{self, ReferenceImages, Settings};
use crate::results::{ErrorsPerFrame, FrameErrors};
use crate::verdict::light_core_mask;

/// The AOVs in the order the runner reads them back.
pub const AOV_NAMES: [&str; 3] = ["inscatter", "surface", "total"];

/// The per-frame references of the scene last asked for: (cache key of its frame 0, the
/// frames loaded so far, a prefix 0 … n − 1).
type Memo = Option<(String, Vec<Arc<ReferenceImages>>)>;
static FRAME_REFERENCES: Mutex<Memo> = Mutex::new(None);

/// How many scene frames a record of `warmup` + `timed` frames can show: frames cycle through
/// the scene's N frames from frame 0 (`record::measure`), so min(W + K, N), at least 1.
pub fn shown_frames(scene: &Scene, warmup: u32, timed: u32) -> u32 {
    warmup
        .saturating_add(timed)
        .clamp(1, scene.frame_count().max(1))
}

/// The references of frames 0 … `count` − 1 of `scene` (index = frame; at most its frame
/// count), frame 0 being `frame0`. Renders (through the cache) the ones not in memory.
pub fn frame_references(
    scene: &Scene,
    frame0: &ReferenceImages,
    settings: Settings,
    cache_dir: Option<&std::path::Path>,
    count: u32,
) -> Result<Vec<Arc<ReferenceImages>>, String> {
    let (w, h) = (frame0.total.width, frame0.total.height);
    let count = count.clamp(1, scene.frame_count()) as usize;
    let key = reference::cache::key(scene, 0, w, h, &settings);
    let mut memo = FRAME_REFERENCES.lock().unwrap_or_else(|e| e.into_inner());
    let mut refs = match memo.take() {
        Some((k, refs)) if k == key => refs,
        _ => vec![Arc::new(frame0.clone())],
    };
    let rendered = (refs.len()..count).try_for_each(|f| {
        let (r, _) =
            reference::cache::render_cached(cache_dir, scene, f as u32, w, h, settings, &|_| {})?;
        refs.push(Arc::new(r));
        Ok::<_, String>(())
    });
    let out = refs[..count.min(refs.len())].to_vec();
    *memo = Some((key, refs));
    rendered.map(|()| out)
}

/// Collects the timed frames of one record.
pub struct FrameScorer<'a> {
    scene: &'a Scene,
    tone: &'a ToneMap,
    /// Frame 0's reference (the only one of a static scene).
    frame0: &'a ReferenceImages,
    /// Animated scenes: the references of the frames loaded so far, a prefix 0 … n − 1
    /// ([`frame_references`]); empty when static.
    references: Vec<Arc<ReferenceImages>>,
    /// Where further frames' references come from, should a frame past the prefix be shown.
    settings: Settings,
    cache_dir: Option<&'a std::path::Path>,
    temporal: [Temporal; 3],
    /// Lag and flicker per AOV, fed the same frames in the order they were shown (animated
    /// scenes only).
    lag: [LagFlicker; 3],
    frames: Vec<FrameErrors>,
    /// Time spent scoring, s (the harness's work, reported in `timing.score_ms`).
    pub seconds: f64,
}

impl<'a> FrameScorer<'a> {
    /// A scorer for `scene` whose records show `shown` frames (warm-up + timed,
    /// [`shown_frames`]); for an animated scene, loads the references of the frames they can
    /// show (through the cache directory when given), before any frame is timed.
    pub fn new(
        scene: &'a Scene,
        tone: &'a ToneMap,
        frame0: &'a ReferenceImages,
        settings: Settings,
        cache_dir: Option<&'a std::path::Path>,
        shown: u32,
    ) -> Result<FrameScorer<'a>, String> {
        let references = if scene.frame_count() > 1 {
            frame_references(scene, frame0, settings, cache_dir, shown)?
        } else {
            Vec::new()
        };
        Ok(FrameScorer {
            scene,
            tone,
            frame0,
            references,
            settings,
            cache_dir,
            temporal: Default::default(),
            lag: Default::default(),
            frames: Vec::new(),
            seconds: 0.0,
        })
    }

    fn animated(&self) -> bool {
        !self.references.is_empty()
    }

    /// Adds a timed frame: the scene frame `index` (any value; taken modulo the frame count) and
    /// the three AOVs read back, in [`AOV_NAMES`] order.
    pub fn timed_frame(&mut self, index: u32, images: &[Image; 3]) -> Result<(), String> {
        let start = std::time::Instant::now();
        let result = self.score(index, images);
        self.seconds += start.elapsed().as_secs_f64();
        result
    }

    /// Records the time of the frame [`Self::timed_frame`] scored last (its per-frame plot in
    /// the report); nothing on a static scene, whose frames are not kept one by one.
    pub fn time_last_frame(&mut self, wall_ms: f64, gpu_ms: Option<f64>) {
        if let Some(last) = self.frames.last_mut() {
            (last.wall_ms, last.gpu_ms) = (Some(wall_ms), gpu_ms);
        }
    }

    fn score(&mut self, index: u32, images: &[Image; 3]) -> Result<(), String> {
        let f = (index % self.scene.frame_count().max(1)) as usize;
        if self.animated() && f >= self.references.len() {
            // Past the frames loaded up front (not in the runner's own use): load up to f.
            self.references = frame_references(
                self.scene,
                self.frame0,
                self.settings,
                self.cache_dir,
                f as u32 + 1,
            )?;
        }
        let r = self.references.get(f).cloned();
        let r: &ReferenceImages = r.as_deref().unwrap_or(self.frame0);
        let refs = [&r.inscatter, &r.surface, &r.total];
        let clean: Vec<Image> = images.iter().map(finite).collect();
        let animated = self.animated();
        for (k, (img, refimg)) in clean.iter().zip(refs).enumerate() {
            self.temporal[k].push(img, refimg);
            // A static scene's references are all one image: every lag matches alike, so lag is
            // 0 and flicker the temporal figure by definition (`finish`), without the lag grid.
            if animated {
                self.lag[k].push(img, refimg);
            }
        }
        if !self.animated() {
            return Ok(());
        }
        let frame = self.scene.frame(f as u32);
        let mask = light_core_mask(&frame, r.total.width, r.total.height, &r.distance);
        let scores: Vec<_> = (0..3)
            .into_par_iter()
            .map(|k| {
                let mut m = compare(&images[k], refs[k], self.tone)?;
                m.light_core = mask
                    .as_ref()
                    .and_then(|m| masked_relative(&clean[k], refs[k], m));
                Ok::<_, String>((AOV_NAMES[k].to_string(), m))
            })
            .collect();
        let errors = scores.into_iter().collect::<Result<_, _>>()?;
        self.frames.push(FrameErrors {
            frame: f as u32,
            errors,
            wall_ms: None,
            gpu_ms: None,
        });
        Ok(())
    }

    /// The per-frame errors (animated scenes only) and the temporal figures per AOV.
    pub fn finish(self) -> (Option<ErrorsPerFrame>, [TemporalFigures; 3]) {
        let animated = self.animated();
        let figures = [0, 1, 2].map(|k| {
            let temporal = self.temporal[k].value();
            let lag = if animated {
                self.lag[k].value()
            } else {
                temporal.map(|t| LagFigures {
                    lag_frames: 0.0,
                    flicker: Some(t),
                })
            };
            TemporalFigures { temporal, lag }
        });
        let per_frame = (!self.frames.is_empty()).then(|| ErrorsPerFrame::new(self.frames));
        (per_frame, figures)
    }
}

/// An AOV's figures over a record's shown frames (None with fewer than two).
#[derive(Clone, Copy, Debug, Default)]
pub struct TemporalFigures {
    /// The temporal-stability figure ([`Temporal`]).
    pub temporal: Option<f64>,
    /// Lag and flicker ([`LagFlicker`]).
    pub lag: Option<LagFigures>,
}

impl TemporalFigures {
    /// Writes the figures into an AOV's error entry.
    pub fn write(&self, m: &mut crate::image::metrics::ErrorMetrics) {
        m.temporal = self.temporal;
        m.lag_frames = self.lag.map(|l| l.lag_frames);
        m.flicker = self.lag.and_then(|l| l.flicker);
    }
}

/// The image with non-finite channels replaced by 0 (as `compare` treats them).
pub fn finite(img: &Image) -> Image {
    Image {
        pixels: img
            .pixels
            .iter()
            .map(|p| p.map(|c| if c.is_finite() { c } else { 0.0 }))
            .collect(),
        ..img.clone()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::reference::ReferenceStats;

    /// A synthetic static reference (values 0.05–1.1, a plain distance buffer).
    fn synthetic(w: u32, h: u32) -> ReferenceImages {
        let mut img = Image::new(w, h);
        for y in 0..h {
            for x in 0..w {
                let (u, v) = (x as f32 / w as f32, y as f32 / h as f32);
                img.set(x, y, [0.05 + u, 0.3 + 0.5 * v, 0.6 + 0.5 * (u * 9.0).sin()]);
            }
        }
        ReferenceImages {
            inscatter: img.clone(),
            surface: Image::new(w, h),
            total: img,
            distance: vec![10.0; (w * h) as usize],
            stats: ReferenceStats::default(),
        }
    }

    /// A test-only "method" on a static scene: 10 % too dark, plus (when `noise` > 0) fresh
    /// noise of that amplitude every frame. Its frames go through the runner's own scorer.
    fn temporal_of(noise: f32) -> [Option<f64>; 3] {
        let scene = scenes::library::resolve("sphere-point").expect("library scene");
        let r = synthetic(48, 40);
        let tone = ToneMap::auto(&r.total);
        let mut scorer = FrameScorer::new(&scene, &tone, &r, Settings::default(), None, 9).unwrap();
        let mut rng = crate::testing::Lcg(99);
        for f in 0..6 {
            let frame = [&r.inscatter, &r.surface, &r.total].map(|img| Image {
                pixels: img
                    .pixels
                    .iter()
                    .map(|p| p.map(|c| 0.9 * c + noise * (rng.uniform() as f32 - 0.5)))
                    .collect(),
                ..img.clone()
            });
            scorer.timed_frame(f, &frame).unwrap();
        }
        let (per_frame, figures) = scorer.finish();
        assert!(
            per_frame.is_none(),
            "a static scene has no per-frame errors"
        );
        // A static scene: nothing to lag behind.
        assert!(figures.iter().all(|f| f.lag.unwrap().lag_frames == 0.0));
        figures.map(|f| f.temporal)
    }

    #[test]
    fn per_frame_noise_scores_worse_on_the_temporal_figure() {
        let steady = temporal_of(0.0);
        let noisy = temporal_of(0.05);
        // Without noise the error is the same every frame: exactly 0, though 10 % off.
        assert_eq!(steady[0], Some(0.0));
        assert_eq!(steady[2], Some(0.0));
        for k in [0, 2] {
            let n = noisy[k].unwrap();
            assert!(n > 0.01, "{} temporal {n}", AOV_NAMES[k]);
        }
    }

    /// pen-orbit at 20×16: a method that shows frame 0 for every frame is exact on frame 0 and
    /// wrong elsewhere; one that shows each frame's own reference is exact everywhere.
    #[test]
    fn animated_frames_are_scored_against_their_own_reference() {
        let scene = scenes::library::resolve("pen-orbit").expect("library scene");
        let (w, h) = (20, 16);
        let r0 = reference::render(&scene, 0, w, h, Settings::default(), &|_| {}).unwrap();
        let tone = ToneMap::auto(&r0.total);
        let refs = frame_references(&scene, &r0, Settings::default(), None, 8).unwrap();
        assert_eq!(refs.len(), scene.frame_count() as usize);
        let new = |shown| FrameScorer::new(&scene, &tone, &r0, Settings::default(), None, shown);
        // `exact` loads every frame up front; the others only frames 0 … 4 and must load the
        // rest when shown.
        let mut exact = new(11).unwrap();
        assert_eq!(exact.references.len(), 8, "min(W + K, N) frames");
        let mut frozen = new(5).unwrap();
        assert_eq!(frozen.references.len(), 5);
        let mut late = new(5).unwrap();
        for f in 3..11u32 {
            let own = &refs[(f % 8) as usize];
            // Shows the frame shown before (frame 3 shows frame 2): one frame late.
            let previous = &refs[((f - 1) % 8) as usize];
            late.timed_frame(
                f,
                &[
                    previous.inscatter.clone(),
                    previous.surface.clone(),
                    previous.total.clone(),
                ],
            )
            .unwrap();
            exact
                .timed_frame(
                    f,
                    &[
                        own.inscatter.clone(),
                        own.surface.clone(),
                        own.total.clone(),
                    ],
                )
                .unwrap();
            frozen
                .timed_frame(
                    f,
                    &[r0.inscatter.clone(), r0.surface.clone(), r0.total.clone()],
                )
                .unwrap();
        }
        let (exact_frames, exact_t) = exact.finish();
        let exact_frames = exact_frames.expect("animated");
        assert_eq!(exact_frames.frames.len(), 8);
        assert_eq!(exact_frames.frames[0].frame, 3);
        assert_eq!(exact_frames.worst["total"].headline, 0.0);
        assert_eq!(exact_t[2].temporal, Some(0.0));
        let exact_lag = exact_t[2].lag.unwrap();
        assert_eq!((exact_lag.lag_frames, exact_lag.flicker), (0.0, Some(0.0)));
        let (_, late_t) = late.finish();
        let late_lag = late_t[2].lag.unwrap();
        assert!((late_lag.lag_frames - 1.0).abs() < 0.02, "{late_lag:?}");
        assert!(late_lag.flicker.unwrap() < 1e-6, "{late_lag:?}");
        // The plain temporal figure cannot tell this lag from flicker.
        assert!(late_t[2].temporal.unwrap() > 0.0);
        let (frozen_frames, frozen_t) = frozen.finish();
        let frozen_frames = frozen_frames.expect("animated");
        for fe in &frozen_frames.frames {
            let hd = fe.errors["total"].headline.unwrap();
            if fe.frame == 0 {
                assert_eq!(hd, 0.0);
            } else {
                assert!(hd > 0.0, "frame {} headline {hd}", fe.frame);
            }
        }
        assert_ne!(frozen_frames.worst["total"].frame, Some(0));
        assert!(frozen_t[2].temporal.unwrap() > 0.0);
    }
}
