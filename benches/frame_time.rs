//! Criterion bench: the frame time of every built-in method × library scene
//! ([`scatterbench::bench::frame_time`] over `methods::REGISTRY`; benches/README.md).

fn frame_time(c: &mut criterion::Criterion) {
    scatterbench::bench::frame_time(c, methods::REGISTRY);
}

criterion::criterion_group!(benches, frame_time);
criterion::criterion_main!(benches);
