//! The paired floor takes the record's value of every knob it shares with the method (its
//! shadow-map size and budget; `harness::record::matched_params`, ARCHITECTURE §4.5). A value
//! the floor refused would drop the record's pairing, so every registered method's parameter
//! sets — its defaults and every sweep value — must give the floor valid knobs, carried over
//! unchanged.

use harness::method::{Params, param_sets};
use harness::record::matched_params;

#[test]
fn every_methods_parameter_sets_give_the_floor_its_shadow_map_settings() {
    let floor = methods::find("no-scatter").expect("the floor is registered");
    let mut shared = 0;
    for method in methods::REGISTRY {
        let sets = param_sets(*method, &Params::new(), true).expect("declared sweep resolves");
        for params in sets {
            let matched = matched_params(floor, &params)
                .unwrap_or_else(|e| panic!("{}: {params:?}: the floor refused: {e}", method.id()));
            for knob in floor.knobs() {
                if let Some(value) = params.get(knob.name) {
                    shared += 1;
                    assert_eq!(
                        matched.get(knob.name),
                        Some(value),
                        "{}: the floor's {}",
                        method.id(),
                        knob.name
                    );
                }
            }
        }
    }
    // The property is vacuous unless methods do share the floor's knobs.
    assert!(shared > 0, "no method shares a knob with the floor");
}
