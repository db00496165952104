//! Every pass a method encodes is counted in the frame's pipeline statistics (ARCHITECTURE §4.1):
//! no method source begins a pass on the encoder directly. A pass begun directly would run
//! uncounted and make the method look cheaper in the work counts than it is. One-off passes
//! outside `render` (table builds, probes) are listed here with the reason.

use std::path::Path;

/// `file:line` prefixes allowed to begin an uncounted pass, with why.
const ALLOWED: &[(&str, &str)] = &[(
    "dobashi_virtual_planes/passes.rs",
    "the probe: a test-only read-out in its own encoder, not part of a frame",
)];

fn sources(dir: &Path, out: &mut Vec<std::path::PathBuf>) {
    for e in std::fs::read_dir(dir).expect("methods/src") {
        let p = e.expect("entry").path();
        if p.is_dir() {
            sources(&p, out);
        } else if p.extension().is_some_and(|x| x == "rs") {
            out.push(p);
        }
    }
}

#[test]
fn every_pass_a_method_begins_is_counted() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = Vec::new();
    sources(&root, &mut files);
    assert!(files.len() > 20, "found only {} sources", files.len());
    let mut direct = Vec::new();
    for f in &files {
        let rel = f
            .strip_prefix(&root)
            .unwrap()
            .to_string_lossy()
            .replace('\\', "/");
        let text = std::fs::read_to_string(f).unwrap();
        for (n, line) in text.lines().enumerate() {
            let code = line.split("//").next().unwrap_or("");
            if code.contains(".begin_render_pass(") || code.contains(".begin_compute_pass(") {
                let allowed = ALLOWED.iter().any(|(file, _)| rel == *file)
                    && code.contains("begin_compute_pass(&Default::default())");
                if !allowed {
                    direct.push(format!("{rel}:{}: {}", n + 1, line.trim()));
                }
            }
        }
    }
    assert!(
        direct.is_empty(),
        "passes begun on the encoder directly (use gpu.render_pass / compute_pass or a PassCounter):\n{}",
        direct.join("\n")
    );
}
