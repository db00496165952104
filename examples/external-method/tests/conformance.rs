//! The conformance suite every built-in method passes (`methods::conformance`), on this crate's.

#[test]
fn unshadowed_march_conforms() {
    methods::conformance::check_registry(&[&external_method::UnshadowedMarch]);
}
