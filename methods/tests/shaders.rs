//! Every composed WGSL module parses and validates with naga — no GPU needed.

#[test]
fn every_shader_module_validates() {
    let sources = methods::shader_sources();
    assert!(!sources.is_empty());
    for (name, src) in sources {
        let module = naga::front::wgsl::parse_str(&src)
            .unwrap_or_else(|e| panic!("{name}: {}", e.emit_to_string(&src)));
        naga::valid::Validator::new(
            naga::valid::ValidationFlags::all(),
            naga::valid::Capabilities::default(),
        )
        .validate(&module)
        .unwrap_or_else(|e| panic!("{name}: {e:?}"));
    }
}
