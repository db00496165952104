//! The epipolar kit: the shadow map read one epipolar plane at a time.
//!
//! For the methods that rectify the shadow map into epipolar slices through the light's screen
//! position and integrate each slice's in-scatter in compute passes (Yusov's epipolar min-max;
//! Klehm et al. / Peters et al.'s prefiltered single scattering). Used by epipolar-minmax and
//! prefiltered-single-scattering.
//!
//! Contract:
//! - [`rectification`] maps a slice and a sample along it to a camera ray and to the rectified
//!   shadow-map coordinate (WGSL `epipolar_slices.wgsl`), identically for both methods.
//! - [`skeleton`] is the per-light compute skeleton both methods share: their compiled pipelines,
//!   sizes, per-light uniform slots and the render prologue.
//! - [`published`] is their resolve: each light's in-scatter summed into a buffer, published to
//!   an `rgba32float` texture, and added to the surfaces by the shared resolve.
//!
//! It builds on the framework (`common::{renderer, resolve, pipeline, layouts, wgsl}`) only.

pub mod published;
pub mod skeleton;
pub mod rectification;
