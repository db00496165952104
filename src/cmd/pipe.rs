//! A closed output pipe ends a command quietly. Rust ignores SIGPIPE, so writing to a pipe
//! whose reader has gone (`scatterbench list | head -1`) makes `println!` panic with "failed
//! printing to stdout: Broken pipe". Restoring SIGPIPE's default action is not an option:
//! the runner writes to worker pipes and must survive a dead worker. Instead a panic hook
//! recognises that one panic and exits with status 0 without a message — the reader asked
//! for no more output, and every file the command writes is already written atomically.

/// Installs the hook (keeping the default hook for every other panic).
pub fn exit_quietly_on_closed_output() {
    let default = std::panic::take_hook();
    std::panic::set_hook(Box::new(move |info| {
        let msg = info
            .payload()
            .downcast_ref::<String>()
            .map(String::as_str)
            .or_else(|| info.payload().downcast_ref::<&str>().copied())
            .unwrap_or("");
        let printing = msg.starts_with("failed printing to stdout")
            || msg.starts_with("failed printing to stderr");
        if printing && msg.contains("Broken pipe") {
            std::process::exit(0);
        }
        default(info);
    }));
}
