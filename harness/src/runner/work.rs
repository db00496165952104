//! The run's work list — scenes × methods × parameter sets, in the order records are written —
//! and running it whole ([`run`]) or one shard of it ([`run_shard`], `crate::shard`).

use scenes::Scene;

use super::config::{Event, RunConfig};
use super::items::{WorkItem, run_items};
use crate::gpu::Gpu;
use crate::method::{Method, param_sets};
use crate::results::Results;
use crate::shard::Shard;

/// Runs every scene × method × parameter set of `cfg` (ARCHITECTURE §4).
pub fn run(
    gpu: &Gpu,
    scenes: &[Scene],
    methods: &[&dyn Method],
    cfg: &RunConfig,
    on_event: &mut dyn FnMut(Event),
) -> Result<Results, String> {
    run_shard(gpu, scenes, methods, cfg, Shard::WHOLE, on_event)
}

/// The run's work list in the order records are written: scenes, then methods, then
/// parameter sets. Sharding slices this list (see [`crate::shard`]).
pub fn work_list<'a>(
    scenes: &[Scene],
    methods: &[&'a dyn Method],
    cfg: &RunConfig,
) -> Result<Vec<WorkItem<'a>>, String> {
    // Parameter sets depend only on the method, so they are resolved once per method.
    let mut sets = Vec::with_capacity(methods.len());
    for entry in methods {
        let overrides = cfg.overrides.get(entry.id()).cloned().unwrap_or_default();
        sets.push(param_sets(*entry, &overrides, cfg.sweep).map_err(|e| format!("--param {e}"))?);
    }
    let mut out = Vec::new();
    for scene in 0..scenes.len() {
        for (&entry, sets) in methods.iter().zip(&sets) {
            for params in sets {
                out.push(WorkItem {
                    scene,
                    entry,
                    params: params.clone(),
                });
            }
        }
    }
    Ok(out)
}

/// Like [`run`], restricted to one shard of the work list; the shard is recorded in
/// `run.shard` so `merge` can reassemble the shards in order.
pub fn run_shard(
    gpu: &Gpu,
    scenes: &[Scene],
    methods: &[&dyn Method],
    cfg: &RunConfig,
    shard: Shard,
    on_event: &mut dyn FnMut(Event),
) -> Result<Results, String> {
    let work = work_list(scenes, methods, cfg)?;
    let shard_info = (!shard.is_whole()).then_some(shard);
    run_items(
        gpu,
        scenes,
        &work[shard.range(work.len())],
        cfg,
        shard_info,
        on_event,
    )
}
