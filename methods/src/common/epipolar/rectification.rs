//! Epipolar slices and the rectified shadow-map coordinate, shared by the methods that read the
//! shadow map one epipolar plane at a time (epipolar-minmax, prefiltered-single-scattering).
//!
//! `EPIPOLAR_SLICES` (WGSL, needs `wgsl::PRELUDE`): the epipole of a light (`epipole_uv`, also
//! behind the camera or at infinity), slices from it to evenly spaced points of the screen
//! border (`epipolar_slice`: entry, exit, the epipolar plane's axes e1, e2 and the rectified
//! extent u_max), a screen point's continuous slice coordinate (`slice_coordinate`) and the world
//! point at rectified coordinate u of a slice (`rectified_point`: the angle about a local light
//! from its axis toward the eye, the distance across a directional light's rays). Papers:
//! Engelhardt & Dachsbacher, I3D 2010 (epipolar slices); Chen, Baran, Kavan & Durand, I3D 2011
//! (rectification: one shadow-map row per slice); Yusov, GPU Pro 5, 2014 (slices on the border).

/// The shared WGSL: `Slice` and the functions above.
pub const EPIPOLAR_SLICES: &str = include_str!("epipolar_slices.wgsl");

/// Bytes of one WGSL `Slice` (three vec4s) in a storage buffer.
pub const SLICE_BYTES: u64 = 48;
