//! `reproduce::plan` works over the registry it is given: a table whose method that registry
//! lacks is skipped with a message, and every work item names a method of that registry.

use experiments::papers::PAPERS;
use experiments::reproduce::plan;
use harness::method::Method;

fn registered(ids: &[&str]) -> Vec<&'static dyn Method> {
    ids.iter()
        .map(|id| methods::find(id).expect("built-in"))
        .collect()
}

#[test]
fn a_table_whose_method_the_registry_lacks_is_skipped_with_a_message() {
    let registry = registered(&["raymarch-brute", "dobashi-virtual-planes"]);
    let p = plan(&["wyman", "dobashi"], &registry).unwrap();
    let papers: Vec<&str> = p.experiments.iter().map(|e| e.paper).collect();
    assert_eq!(papers, ["dobashi"]);
    assert!(
        p.notes
            .contains("skipped: method not registered yet: wyman-hybrid"),
        "{}",
        p.notes
    );
    assert!(!p.work.is_empty());
    for item in &p.work {
        assert!(
            registry.iter().any(|m| m.id() == item.entry.id()),
            "{} is not in the given registry",
            item.entry.id()
        );
    }
}

#[test]
fn the_built_in_registry_runs_every_table() {
    let p = plan(PAPERS, methods::REGISTRY).unwrap();
    assert_eq!(p.experiments.len(), PAPERS.len(), "{}", p.notes);
    assert!(!p.notes.contains("skipped"), "{}", p.notes);
}

/// Every scene of the plan gets the floor at its defaults when the registry has it, so the
/// equal-error tables can give floor ratios; without it, no floor work appears.
#[test]
fn the_plan_times_the_floor_on_every_scene_when_it_is_registered() {
    let floor = report::analysis::FLOOR_METHOD;
    let with = plan(
        &["dobashi"],
        &registered(&["dobashi-virtual-planes", floor]),
    )
    .unwrap();
    let floor_scenes: Vec<usize> = with
        .work
        .iter()
        .filter(|w| w.entry.id() == floor)
        .map(|w| w.scene)
        .collect();
    assert_eq!(floor_scenes, (0..with.scenes.len()).collect::<Vec<_>>());
    let without = plan(&["dobashi"], &registered(&["dobashi-virtual-planes"])).unwrap();
    assert!(without.work.iter().all(|w| w.entry.id() != floor));
}
