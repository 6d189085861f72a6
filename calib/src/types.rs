//! Measured data and the conventions they are expressed in.

use serde::{Deserialize, Serialize};

use crate::Error;

/// End-position error of one run: where the robot stopped minus where it should have stopped,
/// in centimetres, in the frame the data were recorded in (see [`Frame`]).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Endpoint {
    /// Error along the frame's x axis, cm.
    pub x_cm: f64,
    /// Error along the frame's y axis, cm.
    pub y_cm: f64,
}

impl Endpoint {
    /// A new end point.
    pub const fn new(x_cm: f64, y_cm: f64) -> Self {
        Self { x_cm, y_cm }
    }

    /// Distance from the origin, cm.
    pub fn norm(self) -> f64 {
        self.x_cm.hypot(self.y_cm)
    }
}

/// An end point whose y value may be unknown. Only the triangle runs of the Triangular Path
/// test accept a missing y (the thesis' experiment 2 lost its y column in transcription):
/// the turn error is computed from x, and everything that needs y is reported as unknown.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct PartialEndpoint {
    /// Error along x, cm.
    pub x_cm: f64,
    /// Error along y, cm, when it was recorded.
    pub y_cm: Option<f64>,
}

impl PartialEndpoint {
    /// A new end point, y possibly unknown.
    pub const fn new(x_cm: f64, y_cm: Option<f64>) -> Self {
        Self { x_cm, y_cm }
    }

    /// The complete end point, when y is known.
    pub fn complete(self) -> Option<Endpoint> {
        self.y_cm.map(|y_cm| Endpoint::new(self.x_cm, y_cm))
    }
}

impl From<Endpoint> for PartialEndpoint {
    fn from(p: Endpoint) -> Self {
        Self::new(p.x_cm, Some(p.y_cm))
    }
}

/// Sense of travel around the square (or triangle), seen from above.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Direction {
    /// Clockwise: every turn is a right turn.
    Cw,
    /// Counter-clockwise: every turn is a left turn.
    Ccw,
}

impl Direction {
    /// `"cw"` or `"ccw"`, as in the CSV files.
    pub fn as_str(self) -> &'static str {
        match self {
            Self::Cw => "cw",
            Self::Ccw => "ccw",
        }
    }

    /// The other direction.
    pub fn reversed(self) -> Self {
        match self {
            Self::Cw => Self::Ccw,
            Self::Ccw => Self::Cw,
        }
    }
}

/// The coordinate frame end-point errors are recorded in.
///
/// All formulas of this crate are written in [`Frame::Default`]; data recorded in another
/// frame are converted first. A frame is never guessed: it is declared by the caller, and the
/// analysis only *warns* when the x- and y-based estimates disagree the way a mirrored or
/// rotated axis would explain (see [`crate::umbmark::Agreement`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Frame {
    /// Borenstein & Feng's geometry: origin at the start point, x along the first leg
    /// (the robot's initial heading), y to the robot's left, error = end minus start.
    /// A counter-clockwise square turns left, towards +y.
    #[default]
    Default,
    /// The convention of the thesis' calibration GUI as the team reads its UMBmark tables:
    /// the same as [`Frame::Default`] with the x axis mirrored (x_gui = −x). Evidence: on the
    /// thesis' UMBmark experiment 1 the x- and y-based estimates of α and β have opposite
    /// signs in the default frame and the same signs with x mirrored, and the GUI abandoned
    /// Borenstein's x formula for α (it is commented out in ANEXO C). The thesis' triangle
    /// tables, by contrast, fit [`Frame::Default`] (there x and y give turn errors within
    /// 0.5° of each other, and 4.2° apart with x mirrored); experiments 2 and 3 of UMBmark
    /// favour neither.
    ThesisGui,
}

impl Frame {
    /// Convert a point recorded in this frame to [`Frame::Default`].
    pub fn to_default(self, p: Endpoint) -> Endpoint {
        match self {
            Self::Default => p,
            Self::ThesisGui => Endpoint::new(-p.x_cm, p.y_cm),
        }
    }

    /// Convert a point from [`Frame::Default`] to this frame.
    pub fn from_default(self, p: Endpoint) -> Endpoint {
        // Both conversions are involutions.
        self.to_default(p)
    }

    /// Convert a point recorded in this frame to `target`.
    pub fn convert(self, p: Endpoint, target: Frame) -> Endpoint {
        target.from_default(self.to_default(p))
    }
}

/// Which formulas to apply.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Mode {
    /// The published method (Borenstein & Feng 1996; Ruan, Li, Zhu 2012, with the 120° turn
    /// form derived in [`crate::triangle`]), radians where radians are due.
    #[default]
    Correct,
    /// The thesis' MATLAB GUI (ANEXO C and D) applied exactly as printed, bugs included, to
    /// the numbers as the thesis authors typed them ([`Frame::ThesisGui`]). Only for
    /// reproducing the thesis; see [`crate::thesis`] for the list of differences.
    ///
    /// The end points are converted from the declared frame into the GUI's before its
    /// formulas run, so the thesis' own tables must be declared [`Frame::ThesisGui`] (the
    /// numbers as typed), whatever physical frame they were measured in.
    ThesisCompat,
}

/// Which wheelbase enters the diameter-ratio formula Ed = (R + b/2)/(R − b/2).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum EdVariant {
    /// Borenstein & Feng (1996), eq. (11): the nominal wheelbase b.
    #[default]
    Borenstein,
    /// As in OptiOdom: the corrected wheelbase Eb·b. The curvature of a leg is set by the
    /// *actual* wheelbase, so this is the self-consistent choice; the two differ to second
    /// order (by a factor ≈ Eb on Ed − 1).
    OptiOdom,
}

/// A straight-line measurement of the linear scale error Es (Borenstein & Feng 1996):
/// the robot is told to go `commanded_cm` and actually goes `measured_cm`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ScaleError {
    /// Distance the odometry computed (the commanded length), cm.
    pub commanded_cm: f64,
    /// Distance measured on the floor, cm.
    pub measured_cm: f64,
}

impl ScaleError {
    /// Es = L_calc / L_actual.
    pub fn es(&self) -> f64 {
        self.commanded_cm / self.measured_cm
    }
}

fn check_points<'a>(
    what: &str,
    points: impl IntoIterator<Item = (f64, Option<f64>)> + 'a,
) -> Result<(), Error> {
    let mut points = points.into_iter().peekable();
    if points.peek().is_none() {
        return Err(Error::InvalidRuns(format!(
            "no {what} runs; at least one is needed (the methods ask for five)"
        )));
    }
    for (i, (x, y)) in points.enumerate() {
        if !x.is_finite() || y.is_some_and(|y| !y.is_finite()) {
            return Err(Error::InvalidRuns(format!(
                "{what} run {} is not a pair of finite numbers",
                i + 1
            )));
        }
    }
    Ok(())
}

/// The end errors of a UMBmark experiment: runs clockwise and counter-clockwise.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct UmbmarkRuns {
    cw: Vec<Endpoint>,
    ccw: Vec<Endpoint>,
}

impl UmbmarkRuns {
    /// Runs of both directions; each must be non-empty and finite.
    pub fn new(cw: Vec<Endpoint>, ccw: Vec<Endpoint>) -> Result<Self, Error> {
        check_points("cw", cw.iter().map(|p| (p.x_cm, Some(p.y_cm))))?;
        check_points("ccw", ccw.iter().map(|p| (p.x_cm, Some(p.y_cm))))?;
        Ok(Self { cw, ccw })
    }

    /// Clockwise runs.
    pub fn cw(&self) -> &[Endpoint] {
        &self.cw
    }

    /// Counter-clockwise runs.
    pub fn ccw(&self) -> &[Endpoint] {
        &self.ccw
    }

    /// The runs of one direction.
    pub fn runs(&self, direction: Direction) -> &[Endpoint] {
        match direction {
            Direction::Cw => &self.cw,
            Direction::Ccw => &self.ccw,
        }
    }

    /// The same data with the CW and CCW labels exchanged.
    pub fn swapped(&self) -> Self {
        Self {
            cw: self.ccw.clone(),
            ccw: self.cw.clone(),
        }
    }
}

/// The end errors of the straight-line runs of a Triangular Path experiment: x along the
/// commanded line (end minus commanded end), y to the left.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct LineRuns(Vec<Endpoint>);

impl LineRuns {
    /// Non-empty, finite runs.
    pub fn new(runs: Vec<Endpoint>) -> Result<Self, Error> {
        check_points("line", runs.iter().map(|p| (p.x_cm, Some(p.y_cm))))?;
        Ok(Self(runs))
    }

    /// The runs.
    pub fn runs(&self) -> &[Endpoint] {
        &self.0
    }
}

/// The end errors of the triangle runs of a Triangular Path experiment (y may be unknown).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TriangleRuns(Vec<PartialEndpoint>);

impl TriangleRuns {
    /// Non-empty runs with finite values.
    pub fn new(runs: Vec<PartialEndpoint>) -> Result<Self, Error> {
        check_points("triangle", runs.iter().map(|p| (p.x_cm, p.y_cm)))?;
        Ok(Self(runs))
    }

    /// Complete runs (y known).
    pub fn complete(runs: Vec<Endpoint>) -> Result<Self, Error> {
        Self::new(runs.into_iter().map(PartialEndpoint::from).collect())
    }

    /// The runs.
    pub fn runs(&self) -> &[PartialEndpoint] {
        &self.0
    }

    /// Whether every run has its y value.
    pub fn has_all_y(&self) -> bool {
        self.0.iter().all(|p| p.y_cm.is_some())
    }
}

/// Mean of a non-empty set of points.
pub(crate) fn centroid(points: &[Endpoint]) -> Endpoint {
    let n = points.len() as f64;
    let (sx, sy) = points
        .iter()
        .fold((0.0, 0.0), |(sx, sy), p| (sx + p.x_cm, sy + p.y_cm));
    Endpoint::new(sx / n, sy / n)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Runs must be there and finite; the error names the direction and the run (from 1).
    /// A triangle run's y may be unknown, not infinite.
    #[test]
    fn runs_are_refused_empty_or_not_finite_with_which() {
        let p = |x: f64, y: f64| Endpoint::new(x, y);
        let message = |r: Result<(), Error>| r.unwrap_err().to_string();
        let umbmark = |cw, ccw| UmbmarkRuns::new(cw, ccw).map(|_| ());
        assert!(umbmark(vec![p(1.0, 2.0)], vec![p(3.0, 4.0)]).is_ok());
        assert!(message(umbmark(vec![], vec![p(3.0, 4.0)])).contains("no cw runs"));
        let bad = message(umbmark(
            vec![p(1.0, 2.0)],
            vec![p(3.0, 4.0), p(f64::NAN, 0.0)],
        ));
        assert!(
            bad.contains("ccw run 2 is not a pair of finite numbers"),
            "{bad}"
        );
        assert!(message(LineRuns::new(vec![]).map(|_| ())).contains("no line runs"));
        let partial = |y| PartialEndpoint { x_cm: 1.0, y_cm: y };
        assert!(TriangleRuns::new(vec![partial(None), partial(Some(2.0))]).is_ok());
        let bad = message(TriangleRuns::new(vec![partial(Some(f64::INFINITY))]).map(|_| ()));
        assert!(bad.contains("triangle run 1"), "{bad}");
    }
}
