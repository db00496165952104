//! The in-flight marker: `<run dir>/in-flight.json` names the record being run (and its phase
//! and worker pid) from just before it starts until it is saved in `results.json`. When the
//! parent itself dies — a driver crash with `--isolate off`, a SIGKILL, a power cut — the
//! marker survives, and `--resume` records that record as failed ("interrupted") instead of
//! running the crashing pair again; `--retry-failed` runs failed records again on request.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use crate::method::Params;
use crate::record::{Phase, failed};
use crate::results::{Results, Status};

pub const FILE: &str = "in-flight.json";

#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct InFlight {
    pub scene: String,
    pub method: String,
    pub params: Params,
    pub phase: Phase,
    /// The worker process running it (None: in-process).
    pub pid: Option<u32>,
}

pub fn path(run_dir: &Path) -> PathBuf {
    run_dir.join(FILE)
}

/// Writes the marker: a sibling temporary file renamed over the old one, so a reader never
/// sees half a marker. Not synced to disk: it guards against the process dying, and a
/// phase change must stay cheap.
pub fn write(run_dir: &Path, m: &InFlight) -> Result<(), String> {
    let p = path(run_dir);
    let tmp = run_dir.join(format!(".{FILE}.{}.tmp", std::process::id()));
    let text = serde_json::to_vec_pretty(m).map_err(|e| e.to_string())?;
    std::fs::write(&tmp, text)
        .and_then(|()| std::fs::rename(&tmp, &p))
        .map_err(|e| format!("{}: cannot write the in-flight marker: {e}", p.display()))
}

pub fn read(run_dir: &Path) -> Result<Option<InFlight>, String> {
    let p = path(run_dir);
    match std::fs::read_to_string(&p) {
        Ok(text) => serde_json::from_str(&text)
            .map(Some)
            .map_err(|e| format!("{}: unreadable in-flight marker: {e}", p.display())),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(None),
        Err(e) => Err(format!("{}: {e}", p.display())),
    }
}

pub fn clear(run_dir: &Path) -> Result<(), String> {
    match std::fs::remove_file(path(run_dir)) {
        Ok(()) => Ok(()),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(()),
        Err(e) => Err(format!("{}: {e}", path(run_dir).display())),
    }
}

/// What a resumed run must still do.
pub struct Resume {
    /// Keys of records to keep as they are.
    pub done: BTreeSet<String>,
    /// Keys of failed records to run again (`--retry-failed`), with their index in
    /// `results.records`, where the new record replaces the old one.
    pub retry: BTreeMap<String, usize>,
}

/// Turns a leftover marker into a failed "interrupted" record (unless that record was saved
/// after all), clears the marker, and lists what to keep and what to run again.
pub fn resume(results: &mut Results, run_dir: &Path, retry_failed: bool) -> Result<Resume, String> {
    if let Some(m) = read(run_dir)? {
        let key = crate::results::record_key(&m.scene, &m.method, &m.params);
        if !results.records.iter().any(|r| r.key() == key) {
            let pid = m
                .pid
                .map(|p| format!(" (worker pid {p})"))
                .unwrap_or_default();
            results.records.push(failed(&m.scene, &m.method, &m.params, format!(
                "interrupted: the run stopped while this record was in {}{pid}; not run again — \
                 pass --retry-failed with --resume to run it again",
                m.phase
            )));
        }
        clear(run_dir)?;
    }
    let mut out = Resume {
        done: BTreeSet::new(),
        retry: BTreeMap::new(),
    };
    for (i, r) in results.records.iter().enumerate() {
        if retry_failed && r.status == Status::Failed {
            out.retry.insert(r.key(), i);
        } else {
            out.done.insert(r.key());
        }
    }
    Ok(out)
}
