//! How a record fails: a record with nothing measured and its reason, and turning what a
//! measurement raised (a panic, the method's error, wgpu errors) into that reason.

use crate::method::Params;
use crate::results::{Record, Status};

/// A failed record with nothing measured.
pub fn failed(scene: &str, method: &str, params: &Params, why: String) -> Record {
    Record::unmeasured(scene, method, params, Status::Failed, why)
}

/// A measurement's outcome with the wgpu errors raised meanwhile: its value, or why the record
/// failed (a panic, the method's error, a wgpu error).
pub(super) fn settle<T>(
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
pub fn panic_message(p: Box<dyn std::any::Any + Send>) -> String {
    p.downcast_ref::<String>()
        .cloned()
        .or_else(|| p.downcast_ref::<&str>().map(|s| s.to_string()))
        .unwrap_or_else(|| "unknown panic".into())
}
