//! The conformance suite over the registry (`methods::REGISTRY`): every registered method is
//! covered the moment it is registered, without an edit here. The checks are
//! `methods::conformance` (a library, so an out-of-tree crate runs them on its own methods);
//! one test per check keeps the failures of each readable. Without an adapter the GPU cases
//! skip with a message — except when `CI` is set.

use methods::REGISTRY;
use methods::conformance::{check_docs, check_gpu_cases, check_knobs, check_shaders};

#[test]
fn every_method_is_documented() {
    check_docs(REGISTRY);
}

#[test]
fn every_method_declares_valid_knobs_and_refuses_values_outside_them() {
    check_knobs(REGISTRY);
}

#[test]
fn every_shader_validates_for_every_override_combination() {
    check_shaders(REGISTRY);
}

#[test]
fn every_method_meets_its_conformance_cases() {
    check_gpu_cases(REGISTRY);
}
