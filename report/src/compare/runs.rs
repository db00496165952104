//! The runs a comparison reads: each `RUN/results.json`, checked to hold the same kind of
//! work (resolution, frame counts, scored frame, run kind) so that their records compare.
//! Their adapters may differ — that is the point; `merge` is the command that refuses it.

use std::path::{Path, PathBuf};

use harness::results::{Results, RunInfo};

/// Why runs cannot be compared. The CLI maps [`CompareError::Refused`] to exit 2 (the
/// arguments name runs that do not compare) and [`CompareError::Unreadable`] to exit 1.
#[derive(Debug)]
pub enum CompareError {
    Refused(String),
    Unreadable(String),
}

impl std::fmt::Display for CompareError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            CompareError::Refused(m) | CompareError::Unreadable(m) => f.write_str(m),
        }
    }
}

impl std::error::Error for CompareError {}

/// One run of the comparison.
pub struct Run {
    pub dir: PathBuf,
    /// "A", "B", … in the order given.
    pub label: String,
    pub results: Results,
}

/// The label of the `i`-th run: A … Z, then R27, R28, ….
pub fn label(i: usize) -> String {
    match u8::try_from(i).ok().filter(|&i| i < 26) {
        Some(i) => char::from(b'A' + i).to_string(),
        None => format!("R{}", i + 1),
    }
}

/// Loads `dirs` (at least two) and refuses runs whose work differs.
pub fn load(dirs: &[PathBuf]) -> Result<Vec<Run>, CompareError> {
    if dirs.len() < 2 {
        return Err(CompareError::Refused(format!(
            "compare needs at least two run directories, got {}",
            dirs.len()
        )));
    }
    let mut runs = Vec::new();
    for (i, dir) in dirs.iter().enumerate() {
        runs.push(Run {
            dir: dir.clone(),
            label: label(i),
            results: load_one(dir)?,
        });
    }
    for r in &runs[1..] {
        check_same_work(&runs[0], r)?;
    }
    Ok(runs)
}

fn load_one(dir: &Path) -> Result<Results, CompareError> {
    let path = dir.join("results.json");
    if !path.is_file() {
        return Err(CompareError::Refused(format!(
            "RUN: {} holds no results.json (pass directories written by `scatterbench run`)",
            dir.display()
        )));
    }
    crate::load(&path)
        .map(|(results, _)| results)
        .map_err(|e| CompareError::Unreadable(format!("{e:#}")))
}

/// What must be equal for two runs to have measured the same work, as (field, value).
fn work(run: &RunInfo) -> [(&'static str, String); 4] {
    [
        (
            "resolution",
            format!("{}x{}", run.resolution[0], run.resolution[1]),
        ),
        (
            "frames/warm-up",
            format!("{} timed after {} warm-up", run.frames, run.warmup),
        ),
        ("scored frame", run.scored_frame.to_string()),
        ("run kind", run.kind.clone().unwrap_or_else(|| "run".into())),
    ]
}

fn check_same_work(first: &Run, other: &Run) -> Result<(), CompareError> {
    let (a, b) = (work(&first.results.run), work(&other.results.run));
    match a.iter().zip(&b).find(|(x, y)| x.1 != y.1) {
        None => Ok(()),
        Some(((field, va), (_, vb))) => Err(CompareError::Refused(format!(
            "cannot compare: {field} differs — {} has {va}, {} has {vb} (compare runs of the \
             same work list measured on different adapters)",
            first.dir.display(),
            other.dir.display()
        ))),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn labels_are_letters_then_numbered() {
        assert_eq!(label(0), "A");
        assert_eq!(label(25), "Z");
        assert_eq!(label(26), "R27");
    }
}
