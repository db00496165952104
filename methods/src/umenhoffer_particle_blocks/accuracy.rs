//! The accuracy knobs `slices`, `chord_steps` and `eye_slices` and their default `auto` (issue
//! 32's close-out, a modernisation): the value resolves per scene, the way engines raise a
//! volume's quality when the camera enters it.
//!
//! Where some frame has the eye or a local light inside a particle ([`viewer_among_particles`];
//! a huge sphere around the whole scene does not count: it is a dominant sphere, exact on every
//! leg, and the profile's eye slices only blur it — `particle-radii-1e-4-to-1e3`, the eye inside
//! a 1 km sphere: the splat's total 0.0008 plain, 0.0029 with the profile), `auto` is the
//! accurate profile ([`PROFILE`]: 32 slices, an 8-node quadrature per interval,
//! the eye's slices); elsewhere it is the paper's compositing at 8 slices ([`PLAIN`], the
//! defaults before). Why all three together: on `particles-inside-deep-light` (a light deep in
//! a dense particle of a dense, overlapping cloud) the splat's in-scatter headline at 48² was
//! 0.196 at 8 slices, and with one or two of them 0.188 (eye's slices + quadrature at 8
//! slices), 0.074 (the same at 16), 0.115 (32 eye slices, closed form), 0.233 (32 slices +
//! quadrature, centre-ordered "over"), 0.108 (32 eye slices, 4 nodes); only all three reach
//! 0.043 against the bound 3 × 0.025 (README "Viewers inside particles"). The library's clouds
//! hold no viewer: they keep [`PLAIN`] to the last digit. An explicit value is always used as
//! given.
//!
//! Limits: `auto` slices fall back to 16, then 8, where 32 would need more slice-texture layers
//! than the adapter allows (many lights); an explicit value past the limit is refused (state.rs).

use anyhow::Result;
use harness::knobs::Auto;
use harness::{KnobRead, Params};
use scenes::Scene;
use scenes::particles::Particle;

use super::dominant;

/// The values of the three accuracy knobs one prepared state uses.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Accuracy {
    /// Light-pass depth slices (4, 8, 16, 32).
    pub slices: u32,
    /// Quadrature nodes per primitive interval in the gathering (0: the closed form).
    pub chord_steps: u32,
    /// The eye's own slices attenuate the gathering.
    pub eye_slices: bool,
}

/// `auto` with no viewer inside a particle: the paper's "over" compositing and closed form at 8
/// slices (the defaults before `auto`).
pub const PLAIN: Accuracy = Accuracy {
    slices: 8,
    chord_steps: 0,
    eye_slices: false,
};

/// `auto` with the eye or a light inside a particle: the accurate profile.
pub const PROFILE: Accuracy = Accuracy {
    slices: 32,
    chord_steps: 8,
    eye_slices: true,
};

/// The slice counts `auto` tries with a viewer inside, most first, down to [`PLAIN`]'s.
const AUTO_SLICES: [u32; 3] = [32, 16, 8];

/// Whether in some frame of `scene` the eye or a local light lies inside one of `ps` that is
/// not huge for the cloud (dominant.rs `huge`).
pub fn viewer_among_particles(scene: &Scene, ps: &[Particle]) -> bool {
    let extent = dominant::extent(ps);
    dominant::viewer_inside(scene, ps, |p| !dominant::huge(p.radius, extent))
}

/// The three knobs of `params` resolved: explicit values as given, `auto` as [`PLAIN`] or, with
/// `viewer_inside`, [`PROFILE`] — its slices the most of [`AUTO_SLICES`] that `fits` (the
/// adapter's slice-texture layers).
pub fn resolve(
    params: &Params,
    viewer_inside: bool,
    fits: impl Fn(u32) -> bool,
) -> Result<Accuracy> {
    let want = if viewer_inside { PROFILE } else { PLAIN };
    let slices = params.knob::<Auto<u32>>("slices")?.or_else(|| {
        AUTO_SLICES
            .into_iter()
            .filter(|&s| s <= want.slices)
            .find(|&s| fits(s))
            .unwrap_or(PLAIN.slices)
    });
    Ok(Accuracy {
        slices,
        chord_steps: params
            .knob::<Auto<u32>>("chord_steps")?
            .or_else(|| want.chord_steps),
        eye_slices: params
            .knob::<Auto<bool>>("eye_slices")?
            .or_else(|| want.eye_slices),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use harness::ParamValue;

    fn params(slices: ParamValue, steps: ParamValue, eye: ParamValue) -> Params {
        [
            ("slices", slices),
            ("chord_steps", steps),
            ("eye_slices", eye),
        ]
        .into_iter()
        .map(|(k, v)| (k.to_string(), v))
        .collect()
    }

    /// `auto` is the plain defaults without a viewer inside, the profile with one (its slices
    /// shrunk to what fits), and explicit values win over both.
    #[test]
    fn auto_resolves_per_scene_and_explicit_values_win() {
        let auto = || ParamValue::from("auto");
        let all_auto = params(auto(), auto(), auto());
        assert_eq!(resolve(&all_auto, false, |_| true).unwrap(), PLAIN);
        assert_eq!(resolve(&all_auto, true, |_| true).unwrap(), PROFILE);
        let small = resolve(&all_auto, true, |s| s <= 16).unwrap();
        assert_eq!((small.slices, small.chord_steps), (16, 8));
        assert_eq!(resolve(&all_auto, true, |_| false).unwrap().slices, 8);
        let set = params(
            ParamValue::Int(4),
            ParamValue::Int(0),
            ParamValue::Bool(false),
        );
        let fixed = Accuracy {
            slices: 4,
            chord_steps: 0,
            eye_slices: false,
        };
        assert_eq!(resolve(&set, true, |_| true).unwrap(), fixed);
        let mixed = params(ParamValue::Int(16), auto(), ParamValue::Bool(false));
        let got = resolve(&mixed, true, |_| true).unwrap();
        assert_eq!(
            (got.slices, got.chord_steps, got.eye_slices),
            (16, 8, false)
        );
    }
}
