//! The selection's own tests: folds and choices on small made-up data.

use super::*;
use gap::data::ObservedRun;
use gap::model::{Experiment, Firmware, TestKind};

fn groups(of: &[(&str, TestKind)]) -> Vec<Group> {
    let reference = gap::manifest::reference_from_config(&plant_model::RobotConfig::default());
    of.iter()
        .map(|&(name, test)| {
            let exp = Experiment {
                test,
                firmware: Firmware::nominal(&reference, 300.0),
                reference,
                runs: 1,
                seed: 1,
            };
            let run = ObservedRun {
                x_cm: 0.0,
                y_cm: Some(0.0),
                theta_rad: None,
            };
            Group::new(name, exp, vec![run]).expect("a group")
        })
        .collect()
}

/// No fold trains on a line alone: with a square in one experiment and the line in
/// another, leaving the square's experiment out would, so the folds are by group and
/// the square is never left out; experiments that each keep a turn are folds as they
/// are; three groups of one experiment are three folds.
#[test]
fn no_fold_trains_on_a_line_alone() {
    use TestKind as T;
    let (by, folds, out) = folds_of(&groups(&[("a", T::UmbmarkCw), ("b", T::Line)]));
    assert!(!by);
    assert_eq!(folds.len(), 1, "{folds:?}");
    assert!(folds[0].starts_with("b/"), "{folds:?}");
    assert_eq!(out.len(), 1);
    assert!(out[0].starts_with("a/"), "{out:?}");
    let (by, folds, out) = folds_of(&groups(&[
        ("a", T::UmbmarkCw),
        ("a", T::Line),
        ("b", T::UmbmarkCcw),
    ]));
    assert!(by && out.is_empty());
    assert_eq!(folds, vec!["a".to_owned(), "b".to_owned()]);
    let (by, folds, out) = folds_of(&groups(&[
        ("a", T::UmbmarkCw),
        ("a", T::UmbmarkCcw),
        ("a", T::Line),
    ]));
    assert!(!by && out.is_empty());
    assert_eq!(folds.len(), 3);
}
