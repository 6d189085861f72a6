//! What separates two effects the data cannot tell apart: a probe, a variation of the
//! training tests where their fits' predictions differ most, and what is known physically.

use super::rules::separation_score;
use crate::effects::EffectParams;
use crate::fit::Evaluator;
use crate::model::{Experiment, TestKind};
use crate::GapError;

/// Physical knowledge of what separates two effects.
pub fn separating_measurement(a: &str, b: &str) -> String {
    use crate::effects::*;
    let pair = |x: &str, y: &str| (a == x && b == y) || (a == y && b == x);
    let turn_scalers = [WHEELBASE_RATIO, TURN_SLIP, DISTANCE_SCALE];
    if pair(WHEELBASE_RATIO, TURN_SLIP) {
        "both scale every spin by the same factor; drive arcs with both wheels forward at a \
         known speed ratio (their curvature depends on the wheelbase, hardly on spin slip), \
         repeat the spins at another speed or on another floor (slip changes, the wheelbase \
         does not), or measure the wheelbase at the contact patches"
            .into()
    } else if (a == COAST && turn_scalers.contains(&b)) || (b == COAST && turn_scalers.contains(&a))
    {
        "coast adds a constant angle per turn, the others scale with the turn: drive turns of \
         two different angles (the triangle's 120° next to the square's 90°, or spins of 45° \
         and 180°)"
            .into()
    } else if pair(WHEEL_DIAMETER_RATIO, TOE) {
        "Ed curves the legs (the heading error carries into the next leg), toe only shifts \
         them sideways: drive a square, or measure the end heading of the straight line"
            .into()
    } else if pair(DISTANCE_SCALE, WHEELBASE_RATIO) || pair(DISTANCE_SCALE, TURN_SLIP) {
        "Es also lengthens the legs: measure the length of a straight line (the x of the line \
         test)"
            .into()
    } else if a == FLOOR_NOISE || b == FLOOR_NOISE {
        "floor noise only spreads the runs: more runs per test, or the same tests on another \
         floor"
            .into()
    } else {
        "a test on which the two fitted models predict different end points (see the probe \
         above), or a direct measurement of one of the two parameters"
            .into()
    }
}

pub(super) fn probes(template: &Experiment) -> Vec<(String, Experiment)> {
    let mut out = Vec::new();
    for kind in TestKind::ALL {
        let mut e = template.clone();
        e.test = kind;
        out.push((format!("{kind} as in the training data"), e));
    }
    for deg in [45.0, 180.0] {
        let mut e = template.clone();
        e.test = TestKind::UmbmarkCcw;
        e.firmware.turn_umbmark_deg = deg;
        out.push((format!("umbmark_ccw with {deg}° corners"), e));
    }
    for k in [0.5, 2.0] {
        let mut e = template.clone();
        e.test = TestKind::Line;
        e.firmware.leg_mm *= k;
        out.push((format!("line of {:.0} mm", e.firmware.leg_mm), e));
    }
    let mut e = template.clone();
    e.test = TestKind::UmbmarkCcw;
    e.firmware.wheelbase_mm *= 0.9;
    out.push((
        format!(
            "umbmark_ccw with the firmware wheelbase at {:.1} mm",
            e.firmware.wheelbase_mm
        ),
        e,
    ));
    out
}

pub(super) fn find_separating_test(
    ev: &Evaluator,
    template: &Experiment,
    a: &EffectParams,
    b: &EffectParams,
) -> Result<Option<String>, GapError> {
    let mut best: Option<(f64, f64, String)> = None;
    for (name, exp) in probes(template) {
        let pa = ev.predict_experiment(a, &exp, &name)?;
        let pb = ev.predict_experiment(b, &exp, &name)?;
        let d = (pa.mean_x - pb.mean_x).hypot(pa.mean_y - pb.mean_y);
        let dth = (pa.mean_theta_deg - pb.mean_theta_deg).abs();
        let score = separation_score(d, dth);
        if best.as_ref().is_none_or(|(s, _, _)| score > *s) {
            best = Some((
                score,
                d,
                format!("{name}: end points differ by {d:.2} cm, end headings by {dth:.2}°"),
            ));
        }
    }
    Ok(best.and_then(|(s, _, text)| (s >= 1.0).then_some(text)))
}
