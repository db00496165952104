//! What the runner calls per record ([`Dispatch::run`]): the record in process, or in a worker
//! of the pool, with the in-flight marker naming it (and its phase) until it is saved.

use scenes::Scene;

use super::config::{Isolation, default_timeout};
use super::marker::{self, InFlight};
use super::parent::{Job, Pool};
use crate::gpu::Gpu;
use crate::image::metrics::ToneMap;
use crate::method::{Method, Params};
use crate::record::phase::{self, Phase};
use crate::record::{RecordSettings, failed, run_one};
use crate::reference::ReferenceImages;
use crate::results::Record;

/// Runs records for the runner, in process or in workers, keeping the in-flight marker.
pub struct Dispatch<'a> {
    gpu: &'a Gpu,
    settings: &'a RecordSettings,
    pool: Option<Pool>,
    /// The paired floor's method in process (`settings.paired_floor`); a worker finds it in
    /// its own registry by the id.
    floor: Option<&'a dyn Method>,
}

impl<'a> Dispatch<'a> {
    /// Records measured with `settings`, in workers when `isolation` names a worker command;
    /// `floor` is the method `settings.paired_floor` names, for records run in process.
    pub fn new(
        gpu: &'a Gpu,
        settings: &'a RecordSettings,
        isolation: &Isolation,
        floor: Option<&'a dyn Method>,
    ) -> Dispatch<'a> {
        let pool = isolation.worker.clone().map(|cmd| {
            let s = settings;
            let timeout = isolation
                .record_timeout
                .unwrap_or_else(|| default_timeout(s.budget_ms, s.warmup, s.frames));
            Pool::new(cmd, isolation.reuse, timeout)
        });
        Dispatch {
            gpu,
            settings,
            pool,
            floor,
        }
    }

    /// Workers started so far (0 in process).
    pub fn workers_started(&self) -> u32 {
        self.pool.as_ref().map_or(0, |p| p.spawned)
    }

    /// Runs one record; the in-flight marker names it (and its phase) until the caller has
    /// saved it and called [`marker::clear`].
    pub fn run(
        &mut self,
        scene_index: usize,
        scene: &Scene,
        entry: &dyn Method,
        params: &Params,
        reference: &ReferenceImages,
        tone: &ToneMap,
    ) -> Result<Record, String> {
        let out = self.settings.out_dir.clone();
        let mut flight = InFlight {
            scene: scene.name.clone(),
            method: entry.id().to_string(),
            params: params.clone(),
            phase: Phase::Start,
            pid: None,
        };
        marker::write(&out, &flight)?;
        let Some(pool) = self.pool.as_mut() else {
            let hook = move |p: Phase| {
                flight.phase = p;
                // Best effort: a marker one phase behind only words the reason less precisely.
                let _ = marker::write(&out, &flight);
            };
            return Ok(phase::with_hook(hook, || {
                run_one(
                    self.gpu,
                    scene,
                    entry,
                    params,
                    self.settings,
                    (reference, tone),
                    self.floor,
                )
            }));
        };
        let job = Job {
            scene_index,
            scene,
            reference,
            method: entry.id(),
            params,
            settings: self.settings,
        };
        let mut on_phase = |p: Phase, pid: u32| {
            flight.phase = p;
            flight.pid = (pid != 0).then_some(pid);
            let _ = marker::write(&out, &flight);
        };
        Ok(match pool.run(&job, &mut on_phase) {
            Ok(r) => r,
            Err(f) => failed(&scene.name, entry.id(), params, f.reason),
        })
    }
}
