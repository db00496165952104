//! The Khronos validation layer's messages, kept for the record they belong to (issue 30).
//!
//! wgpu-hal's Vulkan debug messenger passes every message of the layer to the `log` crate
//! (target `wgpu_hal::vulkan::instance`), formatted `"{type:?} [{VUID} (0x{id:x})]\n\t{text}"`
//! at `Error` or `Warn` level by severity. [`install`] sets a logger that keeps the messages of
//! type VALIDATION and nothing else; the runner takes them per record ([`take`]): the count is
//! counter `validation_messages`, the first ones go into the record, and under `--validate` an
//! error-severity message fails the record (ARCHITECTURE §6).
//!
//! The logger also notices wgpu's note that the layer was asked for but is not installed, so
//! `--validate` can refuse to run silently unvalidated ([`layer_missing`]). wgpu logs that note
//! at debug level while it creates the instance, so the log level is raised to debug for that
//! moment only ([`while_creating_instance`]).

use std::sync::Mutex;
use std::sync::atomic::{AtomicBool, Ordering};

/// One message of the validation layer.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Message {
    /// Error severity (a VUID violated), as opposed to a warning.
    pub error: bool,
    /// The message as wgpu logged it: type, VUID and id, then the layer's text.
    pub text: String,
    /// Why the message is a known false positive ([`FALSE_POSITIVES`]), if it is one: such a
    /// message is counted apart (counter `validation_ignored`) and fails nothing.
    pub false_positive: Option<&'static str>,
}

/// Messages that are wrong about valid input, each with the reason: (text they contain, why).
/// Keep this list short and every entry explained; anything else is our bug until shown
/// otherwise.
pub const FALSE_POSITIVES: &[(&str, &str)] = &[(
    "Invalid source language operand: 10",
    "SPIR-V's SourceLanguage WGSL (10) is newer than the spirv-tools inside older layers \
     (Debian 12's 1.3.239); naga writes it in OpSource only because validation turns on wgpu's \
     DEBUG flag, which the layer needs to report through wgpu's messenger",
)];

static MESSAGES: Mutex<Vec<Message>> = Mutex::new(Vec::new());
static LAYER_MISSING: AtomicBool = AtomicBool::new(false);
static LOGGER: Logger = Logger;

struct Logger;

const TARGET: &str = "wgpu_hal::vulkan";

impl log::Log for Logger {
    fn enabled(&self, meta: &log::Metadata) -> bool {
        meta.level() <= log::Level::Debug && meta.target().starts_with(TARGET)
    }

    fn log(&self, record: &log::Record) {
        if !self.enabled(record.metadata()) {
            return;
        }
        let text = record.args().to_string();
        if text.contains("VALIDATION requested, but unable to find layer") {
            LAYER_MISSING.store(true, Ordering::Relaxed);
        } else if record.level() <= log::Level::Warn
            && text.starts_with("VALIDATION [")
            && let Ok(mut m) = MESSAGES.lock()
        {
            let false_positive = FALSE_POSITIVES
                .iter()
                .find(|(needle, _)| text.contains(needle))
                .map(|(_, why)| *why);
            m.push(Message {
                error: record.level() == log::Level::Error,
                text,
                false_positive,
            });
        }
    }

    fn flush(&self) {}
}

/// Installs the logger (once; later calls do nothing). Fails when the process already has
/// another logger, whose messages would then be lost.
pub fn install() -> Result<(), String> {
    static DONE: Mutex<bool> = Mutex::new(false);
    let mut done = DONE.lock().map_err(|e| e.to_string())?;
    if !*done {
        log::set_logger(&LOGGER)
            .map_err(|_| "another logger is installed: validation messages would be lost")?;
        log::set_max_level(log::LevelFilter::Warn);
        *done = true;
    }
    Ok(())
}

/// Runs `create` (the instance's creation) with the log level at debug, where wgpu says
/// whether it found the layer, then back at warn: the messenger's severities are fixed at
/// creation (warn and error are all that is kept), and later debug lines cost nothing.
pub fn while_creating_instance<T>(create: impl FnOnce() -> T) -> T {
    log::set_max_level(log::LevelFilter::Debug);
    let made = create();
    log::set_max_level(log::LevelFilter::Warn);
    made
}

/// The messages logged since the last call.
pub fn take() -> Vec<Message> {
    MESSAGES
        .lock()
        .map(|mut m| std::mem::take(&mut *m))
        .unwrap_or_default()
}

/// Whether wgpu said the validation layer was asked for and not found.
pub fn layer_missing() -> bool {
    LAYER_MISSING.load(Ordering::Relaxed)
}

/// The message's VUID (`VUID-vkCmdDraw-commandBuffer-02701`), when it has one.
pub fn vuid(text: &str) -> Option<&str> {
    let start = text.find('[')? + 1;
    let rest = &text[start..];
    Some(rest[..rest.find(' ')?].trim()).filter(|v| !v.is_empty())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn keeps_validation_messages_of_wgpu_hal_only() {
        install().unwrap();
        install().unwrap(); // idempotent
        take();
        let vk = "wgpu_hal::vulkan::instance";
        log::warn!(target: vk, "VALIDATION [VUID-x-y-1 (0x1)]\n\tsomething odd");
        log::error!(target: vk, "VALIDATION [UNASSIGNED-x (0x6)]\n\tInvalid source language operand: 10");
        log::error!(target: vk, "VALIDATION [VUID-vkCmdDraw-commandBuffer-02701 (0x2)]\n\tline width");
        log::error!(target: vk, "GENERAL [Loader Message (0x0)]\n\tnot the layer");
        log::error!(target: "naga::front", "VALIDATION [not wgpu-hal]");
        log::set_max_level(log::LevelFilter::Debug);
        log::debug!(target: vk, "VALIDATION [VUID-info (0x3)]\n\tbelow warn");
        log::set_max_level(log::LevelFilter::Warn);
        let got = take();
        assert_eq!(got.len(), 3, "{got:?}");
        assert!(!got[0].error && got[1].error && got[2].error);
        assert!(got[0].false_positive.is_none() && got[2].false_positive.is_none());
        assert!(
            got[1].false_positive.is_some(),
            "the known false positive is marked"
        );
        assert_eq!(
            vuid(&got[2].text),
            Some("VUID-vkCmdDraw-commandBuffer-02701")
        );
        assert!(take().is_empty(), "taken once");
    }
}
