//! The screening phase of a scene: the references loaded once, and the joint search
//! (`harness::tune::search`) run on the GPU, each configuration prepared beside the floor,
//! given one timed pair, and scored on the headline.

use std::sync::Arc;
use std::time::Instant;

use anyhow::{Result, anyhow};
use harness::image::metrics::ToneMap;
use harness::method::{Method, Params, Support};
use harness::record::{Contender, write_aovs};
use harness::reference::ReferenceImages;
use harness::tune::search::{Evaluator, Log, search};
use harness::tune::{MethodSearch, Screened, Space};

use super::ctx::Ctx;

/// An animated scene is scored on its first frames, at most this many (all of pen-orbit's 8).
pub const SCORED_FRAMES: u32 = 8;
/// Untimed pairs before a screened configuration's one timed pair: a prepared method's and
/// floor's first frames run cold (measured at 512² on lavapipe: the floor 43–77 ms in its first
/// pair, 20–25 ms warm), and not by the same factor, which biased the one-pair ratio.
pub const SCREEN_WARMUP: u32 = 1;

/// Where screening's time went, s: preparing, timing, scoring.
#[derive(Clone, Copy, Debug, Default)]
pub struct Phases {
    pub prepare_s: f64,
    pub time_s: f64,
    pub score_s: f64,
}

impl Phases {
    /// Adds one configuration's phases, from the instants that bound them.
    fn add(&mut self, [t0, t1, t2, t3]: [Instant; 4]) {
        self.prepare_s += (t1 - t0).as_secs_f64();
        self.time_s += (t2 - t1).as_secs_f64();
        self.score_s += (t3 - t2).as_secs_f64();
    }
}

/// A scene's references: frame 0's tone map, and the frames a configuration is scored on.
pub struct References {
    pub frame0: ReferenceImages,
    pub tone: ToneMap,
    pub frames: Vec<Arc<ReferenceImages>>,
}

impl References {
    /// Through the cache; frame 0's images written under `<scene>/reference/` for the report.
    pub fn load(ctx: &Ctx, scene: &scenes::Scene, out: &std::path::Path) -> Result<References> {
        let s = &ctx.settings;
        let (frame0, _) = harness::reference::cache::render_cached(
            s.cache_dir.as_deref(),
            scene,
            0,
            s.width,
            s.height,
            s.reference,
            &|_| {},
        )
        .map_err(|e| anyhow!("{}: reference: {e}", scene.name))?;
        let tone = ToneMap::auto(&frame0.total);
        write_aovs(
            out,
            &format!("{}/reference", scene.name),
            &frame0.inscatter,
            &frame0.surface,
            &frame0.total,
            &tone,
        )
        .map_err(|e| anyhow!(e))?;
        let count = scene.frame_count().min(SCORED_FRAMES);
        let frames = harness::sequence::frame_references(
            scene,
            &frame0,
            s.reference,
            s.cache_dir.as_deref(),
            count,
        )
        .map_err(|e| anyhow!("{}: per-frame references: {e}", scene.name))?;
        Ok(References {
            frame0,
            tone,
            frames,
        })
    }

    pub fn scored(&self) -> Vec<&ReferenceImages> {
        self.frames.iter().map(|r| r.as_ref()).collect()
    }
}

/// What screening a scene found.
pub struct Screening {
    pub log: Log,
    pub entries: Vec<&'static dyn Method>,
    pub methods: Vec<MethodSearch>,
    pub screened: Vec<Screened>,
    /// (s since the tune started, floor ms) of every timed pair.
    pub floor_samples: Vec<(f64, f64)>,
    pub phases: Phases,
}

impl Screening {
    /// The screening's floor samples followed by `later` ones.
    pub fn floor_samples_then(&self, later: Vec<(f64, f64)>) -> Vec<(f64, f64)> {
        self.floor_samples.iter().copied().chain(later).collect()
    }
}

/// The joint search on `scene` until `deadline`.
pub fn screen(ctx: &Ctx, scene: &scenes::Scene, refs: &References, deadline: Instant) -> Screening {
    let floor_knobs: Vec<&str> = ctx.floor.knobs().iter().map(|k| k.name).collect();
    let mut entries = Vec::new();
    let mut spaces = Vec::new();
    let mut methods = Vec::new();
    // Baselines (brute force, the un-accelerated forms) last: the search evaluates every
    // method's defaults in this order, and a costly first one has no cost cap yet.
    let mut order = ctx.methods.clone();
    order.sort_by_key(|m| m.info().baseline);
    for &m in &order {
        let skip = |why: String| MethodSearch {
            method: m.id().into(),
            knobs: Vec::new(),
            joint_size: 0.0,
            evaluated: 0,
            skipped: Some(why),
        };
        if let Support::No(why) = m.support(&scene.features(), ctx.gpu.features()) {
            methods.push(skip(why));
            continue;
        }
        let fixed = ctx.overrides.get(m.id()).cloned().unwrap_or_default();
        match Space::new(m.id(), m.knobs(), &fixed, &floor_knobs) {
            Ok(s) => {
                methods.push(MethodSearch {
                    method: m.id().into(),
                    knobs: s.axes.iter().map(|a| a.name.to_string()).collect(),
                    joint_size: s.size() as f64,
                    evaluated: 0,
                    skipped: None,
                });
                entries.push(m);
                spaces.push(s);
            }
            Err(e) => methods.push(skip(e.to_string())),
        }
    }
    let mut eval = ScreenEval {
        ctx,
        scene,
        refs: refs.scored(),
        entries: &entries,
        screened: Vec::new(),
        floor_samples: Vec::new(),
        phases: Phases::default(),
        deadline,
    };
    let log = search(&spaces, &ctx.budgets, &mut eval);
    let (screened, floor_samples, phases) = (eval.screened, eval.floor_samples, eval.phases);
    for m in methods.iter_mut() {
        m.evaluated = screened.iter().filter(|s| s.method == m.method).count();
    }
    Screening {
        log,
        entries,
        methods,
        screened,
        floor_samples,
        phases,
    }
}

/// The benchmark as the search's evaluator.
struct ScreenEval<'a> {
    ctx: &'a Ctx<'a>,
    scene: &'a scenes::Scene,
    refs: Vec<&'a ReferenceImages>,
    entries: &'a [&'static dyn Method],
    screened: Vec<Screened>,
    floor_samples: Vec<(f64, f64)>,
    phases: Phases,
    deadline: Instant,
}

impl ScreenEval<'_> {
    /// (error, floor ratio) of one configuration: prepared, one pair timed after
    /// [`SCREEN_WARMUP`] untimed, scored; error +∞ (not scored) where the ratio is over
    /// `cost_cap`: scoring renders frames (8 for pen-orbit), seconds for a costly configuration.
    fn measure(
        &mut self,
        entry: &dyn Method,
        params: &Params,
        cost_cap: f64,
    ) -> Result<(f64, f64), String> {
        let (gpu, scene) = (self.ctx.gpu, self.scene);
        let t0 = Instant::now();
        let mut c = Contender::prepare(
            gpu,
            scene,
            (entry, params),
            self.ctx.floor,
            &self.ctx.settings,
        )?;
        let t1 = Instant::now();
        let pairs = c.time(gpu, scene, SCREEN_WARMUP, 1)?;
        let t2 = Instant::now();
        let pair = pairs.first().ok_or("no pair was timed")?;
        let at = self.ctx.start.elapsed().as_secs_f64();
        self.floor_samples.push((at, pair.floor_ms));
        let ratio = pair.method_ms / pair.floor_ms;
        let error = match ratio > cost_cap {
            true => f64::INFINITY,
            false => c.score(gpu, scene, &self.refs)?.inscatter,
        };
        self.phases.add([t0, t1, t2, Instant::now()]);
        Ok((error, ratio))
    }
}

impl Evaluator for ScreenEval<'_> {
    fn evaluate(&mut self, method: usize, params: &Params, cost_cap: f64) -> Option<(f64, f64)> {
        let entry = self.entries[method];
        let outcome = self.measure(entry, params, cost_cap);
        let (error, ratio, failed) = match &outcome {
            Ok((e, r)) => (Some(*e), Some(*r), None),
            Err(why) => (None, None, Some(why.clone())),
        };
        self.screened.push(Screened {
            method: entry.id().into(),
            params: params.clone(),
            error: error.filter(|e| e.is_finite()),
            ratio,
            failed,
            unscored: error.is_some_and(f64::is_infinite),
        });
        outcome.ok()
    }

    fn stop(&mut self) -> bool {
        Instant::now() >= self.deadline
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every registered method's space, as the tune builds it, has moves from its defaults
    /// (one per searched knob at least), each a valid parameter set that keeps the floor's
    /// shared knobs at their defaults.
    #[test]
    fn every_methods_space_has_valid_moves_from_its_defaults() {
        let floor = harness::method::find(methods::REGISTRY, FLOOR).unwrap();
        let floor_knobs: Vec<&str> = floor.knobs().iter().map(|k| k.name).collect();
        for m in methods::REGISTRY.iter().filter(|m| m.id() != FLOOR) {
            let s = Space::new(m.id(), m.knobs(), &Params::new(), &floor_knobs).unwrap();
            let n = s.neighbours(&s.base);
            assert!(
                n.len() >= s.axes.len(),
                "{}: {} moves for {} axes",
                m.id(),
                n.len(),
                s.axes.len()
            );
            for p in &n {
                harness::method::resolve_params(*m, p).unwrap();
                for k in &floor_knobs {
                    assert_eq!(p.get(*k), s.base.get(*k), "{}: moved {k}", m.id());
                }
            }
        }
    }

    const FLOOR: &str = report::analysis::FLOOR_METHOD;
}
