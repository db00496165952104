//! `scatterbench merge`: several run directories (typically the shards of one `run --shard`)
//! → one run directory with one results.json and every image the records point to.
//!
//! Runs merge only when their numbers are comparable: same schema, kind, resolution, frame
//! counts and scored frame, and the same adapter (timings from different GPUs are not
//! ratios of one run; `allow_mixed_adapters` overrides that one check). Shards of one split
//! are put back in shard order, so the merged records come in the unsharded order; other
//! runs are concatenated in the order given. A record (scene, method, params) present twice
//! is refused rather than silently picking one, unless `replace` says the later run's wins
//! (it then keeps the earlier one's place, and the merge warns how many were replaced).
//! `run.methods` is the union of the runs' (a method described differently in two runs keeps
//! the first description, with a warning).

use std::collections::BTreeMap;
use std::path::{Component, Path, PathBuf};

use crate::results::{Record, Results, RunInfo};
use crate::run_methods;

#[derive(Clone, Debug, Default)]
pub struct MergeOptions {
    /// Merge runs measured on different adapters (their timings then do not compare).
    pub allow_mixed_adapters: bool,
    /// Id of the merged run (default: the first run's id with "-merged").
    pub run_id: Option<String>,
    /// A record (scene, method, params) in two runs: the later run's takes the earlier one's
    /// place (a method re-run after a fix, or a refinement sweep, folded into a sweep) instead
    /// of the merge being refused.
    pub replace: bool,
}

/// What a merge did, for the caller to print.
#[derive(Debug)]
pub struct MergeSummary {
    pub results: Results,
    pub files_copied: usize,
    /// Non-fatal problems (missing shards, different commits).
    pub warnings: Vec<String>,
}

/// Merges `dirs` into `out` (which must not already hold a results.json).
pub fn merge(dirs: &[PathBuf], out: &Path, opts: &MergeOptions) -> Result<MergeSummary, String> {
    if dirs.is_empty() {
        return Err("merge: give at least one run directory".into());
    }
    if out.join("results.json").exists() {
        return Err(format!(
            "{}: already holds a results.json; merge into a new directory",
            out.display()
        ));
    }
    let mut runs: Vec<(PathBuf, Results)> = Vec::new();
    for d in dirs {
        let r = Results::load(&d.join("results.json"))?;
        runs.push((d.clone(), r));
    }
    check_compatible(&runs, opts)?;
    let mut warnings = order_shards(&mut runs)?;
    let first = &runs[0].1.run;
    for (d, r) in &runs[1..] {
        if r.run.git_commit != first.git_commit {
            warnings.push(format!(
                "{}: git commit {} differs from {} ({})",
                d.display(),
                r.run.git_commit,
                first.git_commit,
                runs[0].0.display()
            ));
        }
    }

    let (records, replaced) = collect_records(&runs, opts.replace)?;
    if replaced > 0 {
        warnings.push(format!(
            "{replaced} records of earlier runs replaced by the same records of later runs (--replace)"
        ));
    }

    // Files: every image a record names, and the reference images of its scene.
    std::fs::create_dir_all(out).map_err(|e| format!("{}: {e}", out.display()))?;
    let mut files_copied = 0;
    for (i, rec) in &records {
        for rel in rec.images.values() {
            copy_rel(&runs[*i].0, out, rel)?;
            files_copied += 1;
        }
    }
    for (d, r) in &runs {
        let mut scenes: Vec<&str> = r.records.iter().map(|x| x.scene.as_str()).collect();
        scenes.dedup();
        for s in scenes {
            let rel = format!("{s}/reference");
            let dir = d.join(&rel);
            let Ok(entries) = std::fs::read_dir(&dir) else {
                continue; // a scene whose records were all skipped has no reference
            };
            for e in entries.flatten() {
                if e.path().is_file() {
                    copy_rel(
                        d,
                        out,
                        &format!("{rel}/{}", e.file_name().to_string_lossy()),
                    )?;
                    files_copied += 1;
                }
            }
        }
    }

    let mut run: RunInfo = first.clone();
    run.id = opts
        .run_id
        .clone()
        .unwrap_or_else(|| format!("{}-merged", first.id));
    run.shard = None;
    run.note = format!("{} (merged from {} runs)", run.note, runs.len());
    for (d, r) in &runs[1..] {
        let source = d.display().to_string();
        warnings.extend(run_methods::union(
            &mut run.methods,
            &r.run.methods,
            &source,
        ));
    }
    let results = Results {
        schema_version: runs[0].1.schema_version,
        run,
        records: records.into_iter().map(|(_, r)| r).collect(),
    };
    results.save(&out.join("results.json"))?;
    Ok(MergeSummary {
        results,
        files_copied,
        warnings,
    })
}

/// Refuses runs whose numbers do not compare.
fn check_compatible(runs: &[(PathBuf, Results)], opts: &MergeOptions) -> Result<(), String> {
    let (d0, r0) = &runs[0];
    for (d, r) in &runs[1..] {
        let mismatch = |what: &str, a: String, b: String| {
            Err(format!(
                "cannot merge: {what} differs — {} has {a}, {} has {b}",
                d0.display(),
                d.display()
            ))
        };
        let (a, b) = (&r0.run, &r.run);
        if r.schema_version != r0.schema_version {
            return mismatch(
                "schema_version",
                r0.schema_version.to_string(),
                r.schema_version.to_string(),
            );
        }
        if a.resolution != b.resolution {
            return mismatch(
                "resolution",
                format!("{}x{}", a.resolution[0], a.resolution[1]),
                format!("{}x{}", b.resolution[0], b.resolution[1]),
            );
        }
        if a.kind != b.kind {
            return mismatch("run kind", format!("{:?}", a.kind), format!("{:?}", b.kind));
        }
        if (a.frames, a.warmup) != (b.frames, b.warmup) {
            return mismatch(
                "frames/warm-up",
                format!("{}/{}", a.frames, a.warmup),
                format!("{}/{}", b.frames, b.warmup),
            );
        }
        if a.scored_frame != b.scored_frame {
            return mismatch(
                "scored frame",
                a.scored_frame.to_string(),
                b.scored_frame.to_string(),
            );
        }
        if a.machine.adapter != b.machine.adapter && !opts.allow_mixed_adapters {
            return Err(format!(
                "cannot merge: adapter differs — {} ran on '{}', {} on '{}' (timings would not \
                 compare; pass --allow-mixed-adapters to merge anyway)",
                d0.display(),
                a.machine.adapter,
                d.display(),
                b.machine.adapter
            ));
        }
    }
    Ok(())
}

/// Sorts shards of one split by index; warns about missing shards. Runs without shard
/// info keep the given order; mixing them with shards, or shards of different splits, is
/// refused (their order would be a guess).
fn order_shards(runs: &mut [(PathBuf, Results)]) -> Result<Vec<String>, String> {
    let shards: Vec<_> = runs.iter().map(|(_, r)| r.run.shard).collect();
    if shards.iter().all(Option::is_none) {
        return Ok(Vec::new());
    }
    if shards.iter().any(Option::is_none) {
        return Err("cannot merge shards with unsharded runs: merge the shards first".into());
    }
    let count = shards[0].expect("checked").count;
    if let Some((d, r)) = runs
        .iter()
        .find(|(_, r)| r.run.shard.expect("checked").count != count)
    {
        return Err(format!(
            "cannot merge shards of different splits: {} is shard {} (others are of {count})",
            d.display(),
            r.run.shard.expect("checked")
        ));
    }
    runs.sort_by_key(|(_, r)| r.run.shard.expect("checked").index);
    for w in runs.windows(2) {
        if w[0].1.run.shard == w[1].1.run.shard {
            return Err(format!(
                "{} and {} are both shard {}",
                w[0].0.display(),
                w[1].0.display(),
                w[0].1.run.shard.expect("checked")
            ));
        }
    }
    let missing: Vec<String> = (1..=count)
        .filter(|i| {
            !runs
                .iter()
                .any(|(_, r)| r.run.shard.expect("checked").index == *i)
        })
        .map(|i| format!("{i}/{count}"))
        .collect();
    Ok(if missing.is_empty() {
        Vec::new()
    } else {
        vec![format!(
            "shards missing: {} (the merged run is partial)",
            missing.join(", ")
        )]
    })
}

/// The runs' records in order, each with the index of its run. A record (scene, method, params)
/// in two runs is refused, or with `replace` the later run's takes the earlier one's place;
/// also the number of records so replaced.
fn collect_records(
    runs: &[(PathBuf, Results)],
    replace: bool,
) -> Result<(Vec<(usize, Record)>, usize), String> {
    let mut at: BTreeMap<String, usize> = BTreeMap::new();
    let mut records: Vec<(usize, Record)> = Vec::new();
    let mut replaced = 0;
    for (i, (d, r)) in runs.iter().enumerate() {
        for rec in &r.records {
            let key = rec.key();
            match at.get(&key) {
                None => {
                    at.insert(key, records.len());
                    records.push((i, rec.clone()));
                }
                Some(&k) if replace => {
                    records[k] = (i, rec.clone());
                    replaced += 1;
                }
                Some(&k) => {
                    return Err(format!(
                        "record {key} is in both {} and {}: merge each record once, or pass --replace to keep the later run's",
                        runs[records[k].0].0.display(),
                        d.display()
                    ));
                }
            }
        }
    }
    Ok((records, replaced))
}

/// Copies `from/rel` to `to/rel`; `rel` must stay inside the run directory.
fn copy_rel(from: &Path, to: &Path, rel: &str) -> Result<(), String> {
    let p = Path::new(rel);
    if !p.components().all(|c| matches!(c, Component::Normal(_))) {
        return Err(format!(
            "{}: image path '{rel}' leaves the run directory",
            from.display()
        ));
    }
    let (src, dst) = (from.join(p), to.join(p));
    if let Some(parent) = dst.parent() {
        std::fs::create_dir_all(parent).map_err(|e| format!("{}: {e}", parent.display()))?;
    }
    std::fs::copy(&src, &dst)
        .map(|_| ())
        .map_err(|e| format!("copying {}: {e}", src.display()))
}
