//! The papers' headline tables as data for `scatterbench reproduce` (ARCHITECTURE §9.6):
//! which scenes, which method configurations, and what the paper claims about them. A claim is a speed ratio
//! between two configurations of the same scene (time of the slower / time of the faster),
//! so it compares across machines; the paper's side is derived from its own table.

/// `--paper` values, in the order `all` runs them.
pub const PAPERS: &[&str] = &[
    "wyman",
    "dobashi",
    "biri2006",
    "biri2003",
    "biri-poly",
    "umenhoffer",
    "yusov",
];

/// How `reproduce` prints an experiment.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Section {
    /// Per scene: every configuration's time, speed vs the first, error; then the claims.
    Configs,
    /// One row per scene (variants with more triangles): triangles, silhouette edges, shadow
    /// planes, time, and the fitted exponent of time vs triangles next to the paper's.
    Triangles,
    /// One row per scene: the method's phase counters as a share of the frame time.
    Breakdown,
}

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
    /// Methods the table needs; without them it is skipped with a message. Configurations of
    /// other methods that are not registered are left out (listed as not implemented).
    pub needs: &'static [&'static str],
    pub section: Section,
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
        wyman(),
        dobashi(),
        biri2006(),
        biri2003(),
        biri_poly(),
        umenhoffer(),
        yusov(),
    ]
}

/// Wyman & Ramsey 2008, Table 1.
fn wyman() -> Experiment {
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
        section: Section::Configs,
    }
}

/// Dobashi et al. 2000, Figs. 5 and 6.
fn dobashi() -> Experiment {
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
        section: Section::Configs,
    }
}

/// Biri et al. 2006, Table II.
fn biri2006() -> Experiment {
    Experiment {
        paper: "biri2006",
        title: "Biri et al. 2006, Table II: frame rate vs triangle count (and silhouette edges)",
        note: "Paper: GeForce-class GPU, three different scenes of 14 785, 110 014 and 136 266 \
               triangles at 31 / 10.5 / 7.6 fps (direct scattering and shadows; 30 / 10.2 / 7 \
               with indirect scattering), i.e. time ∝ triangles^0.63. Here: the same method on \
               one scene tessellated further and further (midpoint subdivision of the casters, \
               the surface unchanged), so only the triangle count and its silhouette change. \
               This is also issue 5's cost vs silhouette-edge count.",
        scenes: &[
            "sphere-point-sub0",
            "sphere-point-sub1",
            "sphere-point-sub2",
            "sphere-point-sub3",
            "spring-point-sub0",
            "spring-point-sub1",
            "spring-point-sub2",
            "spring-point-sub3",
            "pen-orbit",
        ],
        configs: vec![c("defaults", "biri-shadow-volumes", &[])],
        claims: vec![],
        qualitative: &[
            "Table II: 14 785 → 136 266 triangles (9.2×) costs 4.1× the time without indirect scattering (31 → 7.6 fps), 4.3× with it (30 → 7 fps)",
            "§V: the pen of Fig. 11a (here pen-orbit) renders at more than 30 fps with two lights",
        ],
        needs: &["biri-shadow-volumes"],
        section: Section::Triangles,
    }
}

/// Biri et al. 2003, Table 1: the work load of each stage.
fn biri2003() -> Experiment {
    Experiment {
        paper: "biri2003",
        title: "Biri et al. 2003, Table 1: work load of each stage",
        note: "Paper: GeForce 2 + 550 MHz CPU, the 35 000-triangle scene of its Fig. 12, shadow \
               planes meshed with 30 (10) triangles each: silhouettes 1 % (1.7 %), first pass \
               8.7 % (14 %), ordering of shadow planes 9.6 % (16 %), second pass surfaces 21.7 % \
               (33.6 %), second pass volumes 59 % (34.7 %). Here: biri-shadow-volumes' per-frame \
               counters as a share of the median wall time (CPU counters: silhouette_ms, \
               sort_ms; GPU phases: gpu_ms_* where the method reports them). The silhouettes \
               are recomputed only when a light or caster moves, so static scenes show ~0.",
        scenes: &["desk-pencils", "pen-orbit", "spring-point-sub2"],
        configs: vec![c("defaults", "biri-shadow-volumes", &[])],
        claims: vec![],
        qualitative: &[],
        needs: &["biri-shadow-volumes"],
        section: Section::Breakdown,
    }
}

/// Biri et al. 2003: the polynomial kernel's error vs its order.
fn biri_poly() -> Experiment {
    Experiment {
        paper: "biri-poly",
        title: "Biri et al. 2003: error of the polynomial kernel vs its order",
        note: "Paper: Λ(θ) expanded as a polynomial (Taylor series around θ = 0, annex), 'in \
               practice we use superior orders' than 2; no error figures in the text. Here: \
               orders 2…8 with the paper's Taylor fit and with Chebyshev interpolation over each \
               segment's own θ range, on an unshadowed (clear-fog) and a shadowed \
               (sphere-point) scene; a scene the method cannot handle is listed with its reason.",
        scenes: &["clear-fog", "sphere-point"],
        configs: vec![
            c(
                "taylor 4",
                "biri-polynomial",
                &[("order", "4"), ("fit", "taylor")],
            ),
            c(
                "taylor 2",
                "biri-polynomial",
                &[("order", "2"), ("fit", "taylor")],
            ),
            c(
                "taylor 3",
                "biri-polynomial",
                &[("order", "3"), ("fit", "taylor")],
            ),
            c(
                "taylor 5",
                "biri-polynomial",
                &[("order", "5"), ("fit", "taylor")],
            ),
            c(
                "taylor 6",
                "biri-polynomial",
                &[("order", "6"), ("fit", "taylor")],
            ),
            c(
                "taylor 7",
                "biri-polynomial",
                &[("order", "7"), ("fit", "taylor")],
            ),
            c(
                "taylor 8",
                "biri-polynomial",
                &[("order", "8"), ("fit", "taylor")],
            ),
            c(
                "chebyshev 2",
                "biri-polynomial",
                &[("order", "2"), ("fit", "chebyshev")],
            ),
            c(
                "chebyshev 3",
                "biri-polynomial",
                &[("order", "3"), ("fit", "chebyshev")],
            ),
            c(
                "chebyshev 4",
                "biri-polynomial",
                &[("order", "4"), ("fit", "chebyshev")],
            ),
            c(
                "chebyshev 5",
                "biri-polynomial",
                &[("order", "5"), ("fit", "chebyshev")],
            ),
            c(
                "chebyshev 6",
                "biri-polynomial",
                &[("order", "6"), ("fit", "chebyshev")],
            ),
            c(
                "chebyshev 7",
                "biri-polynomial",
                &[("order", "7"), ("fit", "chebyshev")],
            ),
            c(
                "chebyshev 8",
                "biri-polynomial",
                &[("order", "8"), ("fit", "chebyshev")],
            ),
        ],
        claims: vec![Claim {
            what: "order 8 costs over order 2 (constant-time evaluation: near 1×)",
            scene: None,
            faster: "taylor 2",
            slower: "taylor 8",
            paper: "not measured (the per-vertex cost grows with the order's terms only)",
        }],
        qualitative: &[
            "§3: the approximation is good except where the ray passes close to the source or the observer is far from it",
            "§3: second order is shown; 'in practice we use superior orders' — the error should fall with the order",
        ],
        needs: &["biri-polynomial"],
        section: Section::Configs,
    }
}

/// Umenhoffer et al., Fig. 5.
fn umenhoffer() -> Experiment {
    Experiment {
        paper: "umenhoffer",
        title: "Umenhoffer et al., Fig. 5: frame rate vs number of particle blocks (8000 particles)",
        note: "Paper: NV6800GT, 8000 particles, directional light: unblocked 8 fps, 1600 blocks \
               20, 800 blocks 42, 400 blocks 60, 40 blocks 200, 20 blocks 180 fps; faster with \
               more particles per block down to 40 blocks, slower beyond (block overhead). \
               'Unblocked' is particle-splat (every particle splatted and lit on its own).",
        scenes: &["cloud-8000"],
        configs: vec![
            c(
                "blocks 40",
                "umenhoffer-particle-blocks",
                &[("blocks", "40")],
            ),
            c("unblocked", "particle-splat", &[]),
            c("blocks 1", "umenhoffer-particle-blocks", &[("blocks", "1")]),
            c(
                "blocks 20",
                "umenhoffer-particle-blocks",
                &[("blocks", "20")],
            ),
            c(
                "blocks 400",
                "umenhoffer-particle-blocks",
                &[("blocks", "400")],
            ),
            c(
                "blocks 800",
                "umenhoffer-particle-blocks",
                &[("blocks", "800")],
            ),
            c(
                "blocks 1600",
                "umenhoffer-particle-blocks",
                &[("blocks", "1600")],
            ),
        ],
        claims: vec![
            Claim {
                what: "40 blocks over unblocked",
                scene: None,
                faster: "blocks 40",
                slower: "unblocked",
                paper: "25× (200 / 8 fps)",
            },
            Claim {
                what: "40 blocks over 20",
                scene: None,
                faster: "blocks 40",
                slower: "blocks 20",
                paper: "1.11× (200 / 180 fps)",
            },
            Claim {
                what: "40 blocks over 400",
                scene: None,
                faster: "blocks 40",
                slower: "blocks 400",
                paper: "3.33× (200 / 60 fps)",
            },
            Claim {
                what: "40 blocks over 800",
                scene: None,
                faster: "blocks 40",
                slower: "blocks 800",
                paper: "4.76× (200 / 42 fps)",
            },
            Claim {
                what: "40 blocks over 1600",
                scene: None,
                faster: "blocks 40",
                slower: "blocks 1600",
                paper: "10× (200 / 20 fps)",
            },
            Claim {
                what: "1600 blocks over unblocked",
                scene: None,
                faster: "blocks 1600",
                slower: "unblocked",
                paper: "2.5× (20 / 8 fps)",
            },
        ],
        qualitative: &[
            "§3: rendering speeds up with more particles per block until 40 blocks, then slows (block computation overhead)",
        ],
        needs: &["umenhoffer-particle-blocks"],
        section: Section::Configs,
    }
}

/// Yusov, "Outdoor light scattering", GPU Pro 5 (2014), Tables 2.1–2.3.
fn yusov() -> Experiment {
    Experiment {
        paper: "yusov",
        title: "Yusov 2014, Tables 2.1–2.3: epipolar sampling with 1-D min-max trees, three quality profiles vs brute-force ray marching",
        note: "Paper: GTX 680 at 2560×1600 (brute force 304 ms; high quality 2048 slices × 1024 \
               samples, 2048² shadow map, 9.14 ms; balanced 1024 × 1024, 1024², 3.45 ms; high \
               performance 1024 × 512, 1024², 2.73 ms) and Intel HD 5000 at 1280×720 (209.6 / \
               23.6 / 10.35 / 6.19 ms); initial step 16 throughout. Here the profiles keep the \
               paper's ratios at the default 128²: high quality = epipolar-minmax's defaults \
               ((W+H)/2 slices, max(W,H)/2 samples, 1024² maps), balanced halves the slices and \
               the shadow map, high performance also halves the samples; at another --res the \
               balanced and high-performance counts stay as listed. Brute force is raymarch-brute \
               at 256 steps with a 2048² map (the paper's brute force marches every pixel).",
        scenes: &["sphere-point", "fence-spot", "window-sun"],
        configs: vec![
            c(
                "brute force",
                "raymarch-brute",
                &[("steps", "256"), ("shadow_map", "2048")],
            ),
            c("high quality", "epipolar-minmax", &[]),
            c(
                "balanced",
                "epipolar-minmax",
                &[("slices", "64"), ("shadow_map", "512")],
            ),
            c(
                "high performance",
                "epipolar-minmax",
                &[("slices", "64"), ("samples", "32"), ("shadow_map", "512")],
            ),
            c(
                "high quality, no trees",
                "epipolar-minmax",
                &[("min_max", "false")],
            ),
        ],
        claims: vec![
            Claim {
                what: "high quality over brute force",
                scene: None,
                faster: "high quality",
                slower: "brute force",
                paper: "33× (304 / 9.14 ms, GTX 680); 8.9× (209.6 / 23.6 ms, HD 5000)",
            },
            Claim {
                what: "balanced over high quality",
                scene: None,
                faster: "balanced",
                slower: "high quality",
                paper: "2.6× (9.14 / 3.45 ms); 2.3× (23.6 / 10.35 ms)",
            },
            Claim {
                what: "high performance over balanced",
                scene: None,
                faster: "high performance",
                slower: "balanced",
                paper: "1.26× (3.45 / 2.73 ms); 1.67× (10.35 / 6.19 ms)",
            },
            Claim {
                what: "min-max trees, whole frame, high quality",
                scene: None,
                faster: "high quality",
                slower: "high quality, no trees",
                paper: "3.8× (GTX 680), 1.7× (HD 5000); the march alone 8.6× / 5.3× (Table 2.3)",
            },
        ],
        qualitative: &[
            "high quality is visually identical to brute force (§2.7)",
            "balanced is only slightly different from high quality (§2.7)",
            "the trees pay most with high-resolution shadow maps (longer runs per node, Table 2.3)",
        ],
        needs: &["epipolar-minmax", "raymarch-brute"],
        section: Section::Configs,
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
                let Some(entry) = methods::find(c.method) else {
                    continue; // not implemented yet: `reproduce` says so
                };
                for (k, v) in c.params {
                    harness::method::parse_knob(entry, k, v)
                        .unwrap_or_else(|err| panic!("{}: {err}", e.paper));
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
