//! The papers' headline tables as data for `scatterbench reproduce`: which scenes, which
//! method configurations, and what the paper claims about them. A claim is a speed ratio
//! between two configurations of the same scene (time of the slower / time of the faster),
//! so it compares across machines; the paper's side is derived from its own table.

use harness::method::Params;

/// `--paper` values, in the order `all` runs them.
pub const PAPERS: &[&str] = &["wyman", "dobashi", "biri2006", "biri-poly", "umenhoffer"];

/// One row of a table: a method with knob overrides (the rest at defaults).
pub struct Config {
    pub label: &'static str,
    pub method: &'static str,
    pub params: &'static [(&'static str, &'static str)],
}

/// "`faster` is N× faster than `slower`" with the paper's N.
pub struct Claim {
    pub what: &'static str,
    /// Only for this scene (None: every scene of the experiment).
    pub scene: Option<&'static str>,
    pub faster: &'static str,
    pub slower: &'static str,
    pub paper: &'static str,
}

pub struct Experiment {
    pub paper: &'static str,
    pub title: &'static str,
    pub note: &'static str,
    pub scenes: &'static [&'static str],
    /// The first is the baseline the "speed vs" column divides by.
    pub configs: Vec<Config>,
    pub claims: Vec<Claim>,
    /// Claims the paper makes in words (printed under the table).
    pub qualitative: &'static [&'static str],
    /// Methods the table needs; with `configs` empty the table is not written yet.
    pub needs: &'static [&'static str],
}

const fn c(
    label: &'static str,
    method: &'static str,
    params: &'static [(&'static str, &'static str)],
) -> Config {
    Config {
        label,
        method,
        params,
    }
}

pub fn experiments() -> Vec<Experiment> {
    vec![
        Experiment {
            paper: "wyman",
            title: "Wyman & Ramsey 2008, Table 1: hybrid (50 samples) vs brute-force ray marching (150)",
            note: "Paper: 1024² output, GeForce 8800 GTX, fps; sphere and spring rows. Low-resolution \
                   scattering is the paper's 256² of 1024², i.e. wyman-hybrid scale=4. raymarch-brute \
                   has no low-resolution mode, so the paper's 'brute @256²' column is not reproduced. \
                   The extra hybrid and brute sample counts feed the equal-error table.",
            scenes: &["sphere-point", "spring-point"],
            configs: vec![
                c("brute 150", "raymarch-brute", &[("steps", "150")]),
                c(
                    "hybrid 50",
                    "wyman-hybrid",
                    &[("samples", "50"), ("scale", "1")],
                ),
                c(
                    "hybrid 50 @1/4",
                    "wyman-hybrid",
                    &[("samples", "50"), ("scale", "4")],
                ),
                c("brute 32", "raymarch-brute", &[("steps", "32")]),
                c("brute 64", "raymarch-brute", &[("steps", "64")]),
                c("brute 300", "raymarch-brute", &[("steps", "300")]),
                c(
                    "hybrid 10",
                    "wyman-hybrid",
                    &[("samples", "10"), ("scale", "1")],
                ),
                c(
                    "hybrid 25",
                    "wyman-hybrid",
                    &[("samples", "25"), ("scale", "1")],
                ),
                c(
                    "hybrid 100",
                    "wyman-hybrid",
                    &[("samples", "100"), ("scale", "1")],
                ),
            ],
            claims: vec![
                Claim {
                    what: "hybrid over brute force, full-resolution scattering",
                    scene: Some("sphere-point"),
                    faster: "hybrid 50",
                    slower: "brute 150",
                    paper: "6.59× (85.0 / 12.9 fps)",
                },
                Claim {
                    what: "hybrid at 1/4 resolution over brute force at full",
                    scene: Some("sphere-point"),
                    faster: "hybrid 50 @1/4",
                    slower: "brute 150",
                    paper: "7.72× (99.6 / 12.9 fps)",
                },
                Claim {
                    what: "low-resolution scattering over full, hybrid",
                    scene: Some("sphere-point"),
                    faster: "hybrid 50 @1/4",
                    slower: "hybrid 50",
                    paper: "1.17× (99.6 / 85.0 fps)",
                },
                Claim {
                    what: "hybrid over brute force, full-resolution scattering",
                    scene: Some("spring-point"),
                    faster: "hybrid 50",
                    slower: "brute 150",
                    paper: "5.26× (76.8 / 14.6 fps)",
                },
                Claim {
                    what: "hybrid at 1/4 resolution over brute force at full",
                    scene: Some("spring-point"),
                    faster: "hybrid 50 @1/4",
                    slower: "brute 150",
                    paper: "7.71× (112.5 / 14.6 fps)",
                },
                Claim {
                    what: "low-resolution scattering over full, hybrid",
                    scene: Some("spring-point"),
                    faster: "hybrid 50 @1/4",
                    slower: "hybrid 50",
                    paper: "1.46× (112.5 / 76.8 fps)",
                },
            ],
            qualitative: &[
                "hybrid 3–8× faster than brute force at 1024² and equal samples (§4)",
                "low-resolution scattering adds another 25–100 % (§4)",
                "the sphere needs > 300 brute-force samples but 75–100 hybrid samples (Fig. 6)",
            ],
            needs: &["wyman-hybrid", "raymarch-brute"],
        },
        Experiment {
            paper: "dobashi",
            title: "Dobashi et al. 2000, Figs. 5 and 6: virtual planes (lattice 40²) and lattice (75 planes)",
            note: "Paper: 640×480, Pentium III 733 MHz + GeForce256; the figures' times were lost in \
                   the text extraction, so only its words are compared: error and cost against the \
                   planes and lattice counts.",
            scenes: &["stained-glass-spot"],
            configs: vec![
                c(
                    "planes 75 lattice 40",
                    "dobashi-virtual-planes",
                    &[("planes", "75"), ("lattice", "40")],
                ),
                c(
                    "planes 15 lattice 40",
                    "dobashi-virtual-planes",
                    &[("planes", "15"), ("lattice", "40")],
                ),
                c(
                    "planes 30 lattice 40",
                    "dobashi-virtual-planes",
                    &[("planes", "30"), ("lattice", "40")],
                ),
                c(
                    "planes 150 lattice 40",
                    "dobashi-virtual-planes",
                    &[("planes", "150"), ("lattice", "40")],
                ),
                c(
                    "planes 75 lattice 5",
                    "dobashi-virtual-planes",
                    &[("planes", "75"), ("lattice", "5")],
                ),
                c(
                    "planes 75 lattice 20",
                    "dobashi-virtual-planes",
                    &[("planes", "75"), ("lattice", "20")],
                ),
                c(
                    "planes 75 lattice 80",
                    "dobashi-virtual-planes",
                    &[("planes", "75"), ("lattice", "80")],
                ),
            ],
            claims: vec![
                Claim {
                    what: "15 planes over 75 (Fig. 5a vs 5c)",
                    scene: None,
                    faster: "planes 15 lattice 40",
                    slower: "planes 75 lattice 40",
                    paper: "faster, with shadow aliasing (time not in the extraction)",
                },
                Claim {
                    what: "5² lattice over 80² (Fig. 6a vs 6c)",
                    scene: None,
                    faster: "planes 75 lattice 5",
                    slower: "planes 75 lattice 80",
                    paper: "faster (time not in the extraction)",
                },
            ],
            qualitative: &[
                "Fig. 5: 15 and 30 planes alias the shadows; 75 planes remove it at a higher cost",
                "Fig. 6: a 5×5 lattice makes the scattering much weaker (mean in-scatter / reference < 1); 20×20 ≈ 80×80",
                "§5.4: ~70 % of the time is shadow-texture generation (read-back; gone with shadow maps)",
            ],
            needs: &["dobashi-virtual-planes"],
        },
        Experiment {
            paper: "biri2006",
            title: "Biri et al. 2006, Table 2: fps vs triangles; 2003 Table 1 time breakdown",
            note: "",
            scenes: &["desk-pencils"],
            configs: vec![],
            claims: vec![],
            qualitative: &[],
            needs: &["biri-shadow-volumes"],
        },
        Experiment {
            paper: "biri-poly",
            title: "Biri et al. 2003: polynomial error vs order",
            note: "",
            scenes: &["desk-pencils"],
            configs: vec![],
            claims: vec![],
            qualitative: &[],
            needs: &["biri-polynomial"],
        },
        Experiment {
            paper: "umenhoffer",
            title: "Umenhoffer et al., Fig. 5: time vs particle blocks",
            note: "",
            scenes: &["cloud-8000"],
            configs: vec![],
            claims: vec![],
            qualitative: &[],
            needs: &["umenhoffer-particle-blocks"],
        },
    ]
}

/// The knobs of `params` that differ from `method`'s defaults, `k=v …`, or "defaults".
pub fn params_text(method: &str, params: &Params) -> String {
    let defaults: Params = methods::find(method)
        .map(|e| {
            (e.make)()
                .params()
                .into_iter()
                .map(|s| (s.name.to_string(), s.default))
                .collect()
        })
        .unwrap_or_default();
    let v: Vec<String> = params
        .iter()
        .filter(|(k, v)| defaults.get(*k) != Some(*v))
        .map(|(k, v)| format!("{k}={v}"))
        .collect();
    if v.is_empty() {
        "defaults".into()
    } else {
        v.join(" ")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The tables name real knobs with valid values (so a renamed knob fails here, not in a
    /// long run), labels are unique, and every claim compares two labels of its table.
    #[test]
    fn tables_resolve_against_the_registry() {
        let exps = experiments();
        for p in PAPERS {
            assert!(exps.iter().any(|e| e.paper == *p), "no table for {p}");
        }
        for e in &exps {
            let labels: Vec<&str> = e.configs.iter().map(|c| c.label).collect();
            let mut unique = labels.clone();
            unique.sort();
            unique.dedup();
            assert_eq!(unique.len(), labels.len(), "{}: duplicate labels", e.paper);
            for claim in &e.claims {
                assert!(labels.contains(&claim.faster) && labels.contains(&claim.slower));
                if let Some(s) = claim.scene {
                    assert!(e.scenes.contains(&s), "{}: claim on scene {s}", e.paper);
                }
            }
            for c in &e.configs {
                assert!(
                    e.needs.contains(&c.method),
                    "{}: {} not in needs",
                    e.paper,
                    c.method
                );
                let Some(entry) = methods::find(c.method) else {
                    continue; // not implemented yet: `reproduce` says so
                };
                let specs = (entry.make)().params();
                for (k, v) in c.params {
                    let spec = specs
                        .iter()
                        .find(|s| s.name == *k)
                        .unwrap_or_else(|| panic!("{}: {} has no knob {k}", e.paper, c.method));
                    harness::method::ParamValue::parse_like(v, &spec.default)
                        .unwrap_or_else(|err| panic!("{}: {}.{k}={v}: {err}", e.paper, c.method));
                }
            }
            if e.configs.iter().all(|c| methods::find(c.method).is_some()) {
                for s in e.scenes {
                    scenes::library::resolve(s).unwrap_or_else(|err| panic!("{}: {err}", e.paper));
                }
            }
        }
    }
}
