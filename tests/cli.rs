//! The command line from the outside (ARCHITECTURE §8): every refused argument exits 2 with a
//! message naming the argument, the value and what is allowed, before any work starts; and
//! every command accepts every scene name (library name, `-sub<L>` variant, or file).

use harness::results::{Results, Status};
use harness::testing::{gpu_or_skip, temp_dir};

mod common;
use common::cli;

/// Exit 2, and stderr contains every one of `needles`.
fn refused(args: &[&str], needles: &[&str]) {
    let (code, err) = cli(args);
    assert_eq!(code, 2, "{args:?} exited {code}: {err}");
    for n in needles {
        assert!(err.contains(n), "{args:?}: '{n}' missing from: {err}");
    }
    assert!(!err.contains("panicked"), "{args:?}: {err}");
}

#[test]
fn out_of_range_numbers_exit_2_naming_the_argument_value_and_range() {
    let out = temp_dir("cli-never-written");
    let o = out.to_str().unwrap();
    refused(
        &["run", "--res", "0", "--out", o],
        &["--res", "0", "1..=16384"],
    );
    refused(
        &["run", "--res", "64x16385", "--out", o],
        &["--res", "16385", "1..=16384"],
    );
    refused(
        &["run", "--res", "big", "--out", o],
        &["--res", "big", "WxH"],
    );
    // Zero timed frames would write an ok record with a median of 0 ms.
    refused(
        &["run", "--frames", "0", "--out", o],
        &["--frames", "0", "1..=100000"],
    );
    refused(&["run", "--warmup=-1", "--out", o], &["--warmup", "-1"]);
    refused(
        &["run", "--time-budget=-1", "--out", o],
        &["--time-budget", "-1", "0..=86400"],
    );
    refused(
        &["run", "--time-budget", "NaN", "--out", o],
        &["--time-budget", "NaN"],
    );
    refused(
        &["run", "--shard", "3/2", "--out", o],
        &["--shard", "3/2", "1 ≤ i ≤ n"],
    );
    refused(
        &["reproduce", "--frames", "0", "--out", o],
        &["--frames", "0", "1..=100000"],
    );
    refused(
        &["reproduce", "--res", "0", "--out", o],
        &["--res", "1..=16384"],
    );
    refused(
        &["stress", "--res", "0", "--out", o],
        &["--res", "1..=16384"],
    );
    refused(
        &["stress", "--triangles", "0", "--out", o],
        &["--triangles", "0", "1..=100000000"],
    );
    refused(
        &["scaling", "--frames", "0", "--out", o],
        &["--frames", "1..=100000"],
    );
    refused(
        &["scaling", "--res", "64x32", "--out", o],
        &["--res", "64x32", "square"],
    );
    refused(
        &["scaling", "--triangles", "0", "--out", o],
        &["--triangles", "'0'", "1..=100M"],
    );
    refused(
        &["scaling", "--max-frame-s", "inf", "--out", o],
        &["--max-frame-s", "inf"],
    );
    refused(
        &[
            "scaling",
            "--triangles",
            "none",
            "--res",
            "none",
            "--lights",
            "none",
            "--out",
            o,
        ],
        &["nothing to do"],
    );
    refused(
        &["reference", "--scene", "sphere-point", "--res", "0"],
        &["--res", "1..=16384"],
    );
    refused(
        &[
            "reference",
            "--scene",
            "sphere-point",
            "--convergence-stride",
            "0",
        ],
        &["--convergence-stride", "1..=1024"],
    );
    // sphere-point is static: frame 0 only.
    refused(
        &["reference", "--scene", "sphere-point", "--frame", "1"],
        &["--frame", "1", "0..=0"],
    );
    assert!(!out.exists(), "a refused command wrote {}", out.display());
}

#[test]
fn unknown_names_and_bad_knobs_exit_2_with_the_valid_choices() {
    let out = temp_dir("cli-never-written-2");
    let o = out.to_str().unwrap();
    refused(
        &["reproduce", "--paper", "nobody", "--out", o],
        &["nobody", "wyman", "umenhoffer"],
    );
    refused(
        &[
            "run",
            "--methods",
            "raymarch-brute",
            "--param",
            "raymarch-brute.steps=many",
            "--out",
            o,
        ],
        &[
            "--param",
            "raymarch-brute.steps=many",
            "an integer in 1..=65536",
        ],
    );
    // Out of range: refused, never clamped (0 steps used to render 1, 10⁸ to run for minutes).
    for v in ["0", "100000000"] {
        let item = format!("raymarch-brute.steps={v}");
        refused(
            &[
                "run",
                "--methods",
                "raymarch-brute",
                "--param",
                &item,
                "--out",
                o,
            ],
            &[
                "--param",
                "raymarch-brute.steps",
                v,
                "out of range",
                "1..=65536",
            ],
        );
    }
    refused(
        &[
            "run",
            "--methods",
            "raymarch-brute",
            "--param",
            "raymarch-brute.nope=1",
            "--out",
            o,
        ],
        &["--param", "nope", "steps"],
    );
    refused(
        &[
            "run",
            "--methods",
            "raymarch-brute",
            "--param",
            "raymarch-brute",
            "--out",
            o,
        ],
        &["--param", "METHOD.KNOB=VALUE"],
    );
    refused(
        &[
            "run",
            "--methods",
            "no-scatter",
            "--param",
            "raymarch-brute.steps=8",
            "--out",
            o,
        ],
        &["--param", "not in --methods"],
    );
    refused(
        &["run", "--resume", "--out", o],
        &["--resume", "no results.json"],
    );
    refused(
        &["run", "--scenes", "sphere-point-sub9", "--out", o],
        &["sphere-point-sub9", "at most 8"],
    );
    refused(
        &["scaling", "--scene", "nowhere", "--out", o],
        &["nowhere", "sphere-point"],
    );
    refused(&["report", o], &["RUN_DIR", "no results.json"]);
    refused(&["frontier", o], &["RUN_DIR", "no results.json"]);
    refused(
        &["frontier", o, "--before", o, "--out", o],
        &["RUN_DIR", "no results.json"],
    );
    assert!(!out.exists(), "a refused command wrote {}", out.display());
}

#[test]
fn an_invalid_scene_file_exits_2_in_validate_and_in_run() {
    let dir = temp_dir("cli-bad-scene");
    std::fs::create_dir_all(&dir).unwrap();
    let bad = dir.join("bad.json");
    std::fs::write(&bad, "{\"camera\": 3}").unwrap();
    let b = bad.to_str().unwrap();
    refused(
        &["validate", b],
        &["bad.json", "1 of 1 scenes have problems"],
    );
    let out = dir.join("out");
    refused(
        &["run", "--scenes", b, "--out", out.to_str().unwrap()],
        &["bad.json"],
    );
    assert!(!out.exists());
    let _ = std::fs::remove_dir_all(dir);
}

/// `validate` takes a library name or variant like every command that takes a scene
/// (scenes/README.md): it loads the scene and reports its content; an unknown name that is no
/// file is refused with the valid names.
#[test]
fn validate_takes_library_names_and_refuses_unknown_ones() {
    let (code, out, err) = common::scatterbench(&["validate", "atrium", "sphere-point-sub1"]);
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("atrium: ok") && out.contains("sphere-point-sub1: ok"), "{out}");
    refused(
        &["validate", "no-such-scene"],
        &["no-such-scene", "sphere-point", "1 of 1 scenes have problems"],
    );
}

/// `run --scenes` takes a `-sub<L>` variant like `reproduce` does: the record carries the
/// variant's name and the reference of the variant's mesh (16× the caster triangles of
/// spring-point at L = 2, the floor unchanged), and `reference` renders it too.
#[test]
fn every_command_accepts_scene_variants() {
    if gpu_or_skip().is_none() {
        return;
    }
    let out = temp_dir("cli-variant");
    let cache = temp_dir("cli-variant-cache");
    let (code, err) = cli(&[
        "run",
        "--scenes",
        "spring-point-sub2",
        "--methods",
        "no-scatter",
        "--res",
        "16",
        "--frames",
        "1",
        "--warmup",
        "0",
        "--out",
        out.to_str().unwrap(),
        "--cache",
        cache.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    let r = Results::load(&out.join("results.json")).unwrap();
    assert_eq!(r.records.len(), 1);
    assert_eq!(r.records[0].scene, "spring-point-sub2");
    assert_eq!(r.records[0].status, Status::Ok, "{:?}", r.records[0].reason);
    // The variant is the library scene subdivided, resolved by the scenes crate for every
    // command: its casters have 4² times the triangles.
    let base = scenes::library::resolve("spring-point").unwrap();
    let sub = scenes::library::resolve("spring-point-sub2").unwrap();
    let casters = scenes::variants::caster_triangles;
    assert_eq!(casters(&sub), 16 * casters(&base));

    let ref_out = temp_dir("cli-variant-ref");
    let (code, err) = cli(&[
        "reference",
        "--scene",
        "spring-point-sub1",
        "--res",
        "8",
        "--convergence-stride",
        "8",
        "--out",
        ref_out.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(ref_out.join("reference.json")).unwrap())
            .unwrap();
    assert_eq!(json["scene"], "spring-point-sub1");
    for d in [out, cache, ref_out] {
        let _ = std::fs::remove_dir_all(d);
    }
}

/// `docs/ARCHITECTURE.md` §8, the command line's contract: from its heading to §9's.
fn section_8() -> String {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/docs/ARCHITECTURE.md");
    let doc = std::fs::read_to_string(path).expect("docs/ARCHITECTURE.md is readable");
    let start = doc.find("\n## 8.").expect("ARCHITECTURE has a §8");
    let end = doc[start..].find("\n## 9.").map_or(doc.len(), |e| start + e);
    doc[start..end].to_string()
}

/// The long flags (`--name`) an option line of `--help` declares.
fn flags_in_help(help: &str) -> Vec<String> {
    help.lines()
        .map(str::trim_start)
        .filter(|l| l.starts_with('-'))
        .flat_map(|l| {
            let decl = l.split("  ").next().unwrap_or(l);
            decl.split([' ', ',', '='])
                .filter(|w| w.starts_with("--") && w.len() > 2)
                .map(|w| w.trim_end_matches(|c: char| !c.is_ascii_alphanumeric()).to_string())
                .collect::<Vec<_>>()
        })
        .filter(|f| f != "--help" && f != "--version")
        .collect()
}

/// Whether `flag` occurs in `text` as a whole word (`--res` is not found in `--resume`).
fn mentions(text: &str, flag: &str) -> bool {
    text.match_indices(flag).any(|(i, _)| {
        !text[i + flag.len()..]
            .chars()
            .next()
            .is_some_and(|c| c.is_ascii_alphanumeric() || c == '-' || c == '_')
    })
}

/// Every command `--help` lists and every flag each one's `--help` prints is in ARCHITECTURE
/// §8: a flag added to the code and not to the contract fails here.
#[test]
fn every_commands_flags_are_in_architecture_section_8() {
    let (code, top, _) = common::scatterbench(&["--help"]);
    assert_eq!(code, 0);
    let commands: Vec<&str> = top
        .lines()
        .skip_while(|l| !l.starts_with("Commands:"))
        .skip(1)
        .take_while(|l| l.starts_with("  "))
        .filter_map(|l| l.split_whitespace().next())
        .filter(|c| *c != "help")
        .collect();
    assert!(commands.len() >= 10, "commands parsed from --help: {commands:?}");
    let contract = section_8();
    let mut missing = Vec::new();
    let mut seen = 0;
    for command in &commands {
        if !mentions(&contract, &format!("scatterbench {command}"))
            && !mentions(&contract, &format!("`{command}`"))
        {
            missing.push(format!("the command {command}"));
        }
        let (code, help, err) = common::scatterbench(&[command, "--help"]);
        assert_eq!(code, 0, "{command} --help: {err}");
        let flags = flags_in_help(&help);
        seen += flags.len();
        for flag in flags {
            if !mentions(&contract, &flag) {
                missing.push(format!("{command} {flag}"));
            }
        }
    }
    // The parser must find flags at all (`run` alone has more than twenty).
    assert!(seen > 50, "only {seen} flags parsed from the commands' --help");
    assert!(missing.is_empty(), "missing from ARCHITECTURE §8: {missing:?}");
}

/// ARCHITECTURE.md stays a contract one can read: at most 40 000 bytes, its history in
/// docs/results/ARCHITECTURE-history.md (which must exist, since it links there).
#[test]
fn architecture_is_at_most_40_kb_and_its_history_link_resolves() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let doc = std::fs::read_to_string(root.join("docs/ARCHITECTURE.md")).expect("readable");
    assert!(doc.len() <= 40_000, "docs/ARCHITECTURE.md is {} bytes (≤ 40 000)", doc.len());
    assert!(doc.contains("results/ARCHITECTURE-history.md"));
    assert!(root.join("docs/results/ARCHITECTURE-history.md").is_file());
}
