//! `run.methods` of results.json (ARCHITECTURE §5.1): each method of a run as the run described
//! it — paper, summary, whether it is a baseline, the media it renders — so a results file is
//! read (reported, merged, compared) without the registry that wrote it: a fork's or an external
//! method's results report as faithfully as the built-in ones.

use std::collections::BTreeMap;

use serde::{Deserialize, Serialize};

use crate::method::{Method, MethodInfo, Params, resolve_params};

/// One method of a run. Every field is optional so that hand-written or partial files load;
/// the runner always writes all four. Readers show "unknown" for an absent one.
#[derive(Clone, Debug, Default, Serialize, Deserialize, PartialEq)]
pub struct MethodDescription {
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub paper: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub summary: Option<String>,
    /// [`MethodInfo::baseline`].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub baseline: Option<bool>,
    /// "homogeneous", "particles" or "both" ([`crate::method::Medium::name`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub medium: Option<String>,
    /// Every knob at its default, as this build resolves them: what a record's knobs are named
    /// against (`slices=32`) where a run holds other configurations than a sweep's.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub defaults: Option<Params>,
}

impl From<&MethodInfo> for MethodDescription {
    fn from(info: &MethodInfo) -> MethodDescription {
        MethodDescription {
            paper: Some(info.paper.to_string()),
            summary: Some(info.summary.to_string()),
            baseline: Some(info.baseline),
            medium: Some(info.medium.name().to_string()),
            defaults: None,
        }
    }
}

/// `run.methods`: method id → its description.
pub type RunMethods = BTreeMap<String, MethodDescription>;

/// Adds the description of every method in `methods` (a method listed twice is described
/// once). What is already there is replaced: the run being written describes its methods as
/// they are now.
pub fn describe<'a>(into: &mut RunMethods, methods: impl IntoIterator<Item = &'a dyn Method>) {
    for m in methods {
        let info = m.info();
        let defaults = resolve_params(m, &Params::new()).ok();
        let description = MethodDescription {
            defaults,
            ..MethodDescription::from(&info)
        };
        into.insert(info.id.to_string(), description);
    }
}

/// Adds `from`'s methods to `into` (a union). A method described differently on both sides
/// keeps `into`'s description, with a warning naming the method and `source`.
pub fn union(into: &mut RunMethods, from: &RunMethods, source: &str) -> Vec<String> {
    let mut warnings = Vec::new();
    for (id, d) in from {
        match into.get(id) {
            None => {
                into.insert(id.clone(), d.clone());
            }
            Some(mine) if mine != d => warnings.push(format!(
                "{source}: method '{id}' is described differently ({}) than in the first run \
                 that has it ({}); keeping the first",
                brief(d),
                brief(mine)
            )),
            Some(_) => {}
        }
    }
    warnings
}

/// A description in one line, for messages.
fn brief(d: &MethodDescription) -> String {
    let unknown = |v: &Option<String>| v.clone().unwrap_or_else(|| "unknown".into());
    format!(
        "paper {:?}, baseline {}, medium {}",
        unknown(&d.paper),
        d.baseline.map_or("unknown".into(), |b| b.to_string()),
        unknown(&d.medium)
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    fn described(paper: &str, baseline: bool) -> MethodDescription {
        MethodDescription {
            paper: Some(paper.into()),
            summary: Some("s".into()),
            baseline: Some(baseline),
            medium: Some("homogeneous".into()),
            defaults: None,
        }
    }

    #[test]
    fn union_adds_new_methods_and_warns_on_a_different_description() {
        let mut into: RunMethods = [("a".to_string(), described("A", false))].into();
        let from: RunMethods = [
            ("a".to_string(), described("A", true)),
            ("b".to_string(), described("B", true)),
        ]
        .into();
        let warnings = union(&mut into, &from, "shard-2");
        assert_eq!(into.len(), 2);
        assert_eq!(
            into["a"],
            described("A", false),
            "the first description stays"
        );
        assert_eq!(into["b"], described("B", true));
        assert_eq!(warnings.len(), 1, "{warnings:?}");
        assert!(
            warnings[0].contains("shard-2") && warnings[0].contains("'a'"),
            "{}",
            warnings[0]
        );
        assert!(union(&mut into, &from.clone(), "again").len() == 1);
        assert!(union(&mut into.clone(), &into, "self").is_empty());
    }

    #[test]
    fn absent_fields_load_as_unknown() {
        let d: MethodDescription = serde_json::from_str(r#"{"paper": "P"}"#).unwrap();
        assert_eq!(d.paper.as_deref(), Some("P"));
        assert_eq!((d.summary, d.baseline, d.medium), (None, None, None));
        let text = serde_json::to_string(&MethodDescription::default()).unwrap();
        assert_eq!(text, "{}");
    }
}
