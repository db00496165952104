//! The Khronos validation layer's messages in a record (ARCHITECTURE §6): counted, the first
//! ones kept, and an error fails the record.

use crate::gpu::validation::Message;
use crate::results::{Record, Status};

/// How many of a record's validation messages it keeps (all are counted).
const KEPT_VALIDATION_MESSAGES: usize = 5;

/// Counts the validation layer's messages into the record, keeps the first ones, and fails a
/// record that raised a validation error (ARCHITECTURE §6): an ok image rendered through
/// undefined behaviour proves nothing about another driver.
pub(super) fn add_validation(rec: &mut Record, messages: Vec<Message>) {
    let (ignored, messages): (Vec<_>, Vec<_>) = messages
        .into_iter()
        .partition(|m| m.false_positive.is_some());
    rec.counters
        .insert("validation_messages".into(), messages.len() as f64);
    if !ignored.is_empty() {
        rec.counters
            .insert("validation_ignored".into(), ignored.len() as f64);
    }
    if let Some(first) = messages.iter().find(|m| m.error)
        && rec.status == Status::Ok
    {
        rec.status = Status::Failed;
        rec.reason = Some(format!(
            "validation error ({} of {} messages): {}",
            messages.iter().filter(|m| m.error).count(),
            messages.len(),
            first.text.replace("\n\t", " ")
        ));
    }
    rec.validation = messages
        .into_iter()
        .take(KEPT_VALIDATION_MESSAGES)
        .map(|m| m.text)
        .collect();
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::method::Params;

    fn ok_record() -> Record {
        let mut r = Record::unmeasured("s", "m", &Params::new(), Status::Ok, String::new());
        r.reason = None;
        r
    }

    #[test]
    fn a_validation_error_fails_the_record_and_every_message_is_counted() {
        let mut r = ok_record();
        let warn = |i: usize| Message {
            error: false,
            text: format!("VALIDATION [VUID-warn-{i} (0x{i})]\n\tnot fatal"),
            false_positive: None,
        };
        let mut messages: Vec<Message> = (0..7).map(warn).collect();
        messages.insert(
            2,
            Message {
                error: true,
                text: "VALIDATION [VUID-vkCmdDraw-commandBuffer-02701 (0x2)]\n\tline width".into(),
                false_positive: None,
            },
        );
        messages.push(Message {
            error: true,
            text: "VALIDATION [UNASSIGNED (0x6)]\n\tInvalid source language operand: 10".into(),
            false_positive: Some("test"),
        });
        add_validation(&mut r, messages);
        assert_eq!(r.status, Status::Failed);
        let why = r.reason.unwrap();
        assert!(why.contains("VUID-vkCmdDraw-commandBuffer-02701"), "{why}");
        assert!(why.contains("1 of 8"), "{why}");
        assert_eq!(r.counters["validation_messages"], 8.0);
        assert_eq!(
            r.counters["validation_ignored"], 1.0,
            "a false positive, counted apart"
        );
        assert_eq!(r.validation.len(), KEPT_VALIDATION_MESSAGES);
    }

    #[test]
    fn warnings_are_recorded_but_do_not_fail() {
        let mut r = ok_record();
        add_validation(
            &mut r,
            vec![Message {
                error: false,
                text: "VALIDATION [VUID-w (0x1)]".into(),
                false_positive: None,
            }],
        );
        assert_eq!(r.status, Status::Ok);
        assert_eq!(r.counters["validation_messages"], 1.0);
        let mut clean = ok_record();
        add_validation(&mut clean, Vec::new());
        assert_eq!(clean.counters["validation_messages"], 0.0);
        assert!(clean.validation.is_empty() && clean.status == Status::Ok);
    }
}
