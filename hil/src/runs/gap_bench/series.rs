//! The telemetry of a bench run, in the layout of `gap::series` (one row per firmware control
//! period: both wheels' speeds and duties, and the pose), and the score of a simulated
//! series against a measured one.
//!
//! # Where the rows come from
//!
//! A [`SeriesProbe`] watches the run loop's checks (every `CHECK_PERIOD_S` of robot time,
//! at the same cycles in every run whatever watches them, so a watched run is the unwatched
//! run). Row 0 starts at the first check that finds a wheel driven after the start command
//! (the firmware's first control tick of the test); row *k* ends at the first check at or
//! after `start + (k + 1) T`. At that check the plant may lag the CPU, but no input has
//! changed since the plant's own time (a change advances it to its cycle), so a copy of the
//! plant advanced to the check's cycle is the plant there, exactly. A row holds:
//!
//! - `t_s`: the row's end, robot time since row 0's start;
//! - `rpm_*`: the wheel's mean speed over the row, from the wheel angles at its two ends
//!   (signed, forward positive; thesis RPM, true wheel RPM / 6, as `Telemetry` keeps them);
//! - `pwm_*`: the duty the motor driver sees at the row's middle, forward minus reverse,
//!   × 255 (the firmware changes it at its ticks, near the rows' ends; the middle is clear of
//!   them);
//! - the pose at the row's end, in the start frame (x along the first leg, y to the left).
//!
//! The same run is also kept as a robot's firmware would log it ([`SeriesRun::counted`]):
//! the speeds from the encoder counts of each row, whose whole counts are the resolution of
//! a real robot's telemetry.

use gap::series::{series_gap, Sample, SegmentKind, SeriesGap, Telemetry};
use gap::GapError;
use plant_model::{RadPerSec, Robot, Seconds, Side};
use serde::Serialize;

use crate::bench::{Bench, Observer, Step};

/// The firmware's control period, s: the tick of the bench's firmware builds (the thesis'
/// `Muestreo`, Henrytwo's PID period; `SAMPLE_PERIOD_S` of the firmware crate). The plant's
/// configuration has no controller, so the period is the firmware's.
pub const CONTROL_PERIOD_S: f64 = 0.015;

/// The smallest noise a telemetry speed is given, thesis RPM: a floor under
/// [`series_noise`] for series smoother than any robot logs (a tenth of the speed of one
/// encoder count per period on Henrytwo).
pub const SERIES_NOISE_FLOOR_RPM: f64 = 0.1;

/// The telemetry of one run.
#[derive(Debug, Clone, PartialEq)]
pub struct SeriesRun {
    /// Speeds from the plant's wheel angles (the model's series).
    pub exact: Telemetry,
    /// Speeds from the encoder counts, as the firmware measures them (a real robot's log).
    pub counted: Telemetry,
}

/// The plant at one check.
#[derive(Debug, Clone, Copy)]
struct Look {
    t_s: f64,
    angle_rad: [f64; 2],
    counts: [i64; 2],
    pose: (f64, f64, f64),
}

impl Look {
    fn of(robot: &Robot, t: Seconds) -> Look {
        // No input changed since the plant's own time: a copy advanced to any time up to
        // the check's is the plant then (see the module docs).
        let mut r = robot.clone();
        if t > r.now() {
            r.advance_to(t).expect("forward in time");
        }
        let count = |side: Side| {
            let reversed = match side {
                Side::Left => r.config().encoder.reversed_left,
                Side::Right => r.config().encoder.reversed_right,
            };
            let n = r.a_edges(side);
            if reversed {
                -n
            } else {
                n
            }
        };
        let p = r.pose();
        Look {
            t_s: r.now().0,
            angle_rad: Side::BOTH.map(|s| r.wheel_angle(s).0),
            counts: Side::BOTH.map(count),
            pose: (p.x().0, p.y().0, p.theta().0),
        }
    }
}

/// Records the telemetry of a run (see the module docs).
pub struct SeriesProbe {
    period_s: f64,
    /// Row 0's start.
    origin: Option<Look>,
    /// The end of the last row.
    last: Option<Look>,
    /// Rows made.
    rows: u32,
    /// The duties at the current row's middle (None: not reached yet).
    duty: Option<[f64; 2]>,
    /// Wheel radians per encoder count.
    rad_per_count: f64,
    exact: Vec<Sample>,
    counted: Vec<Sample>,
}

impl SeriesProbe {
    /// A probe with rows of `period_s`.
    pub fn new(period_s: f64) -> Self {
        SeriesProbe {
            period_s,
            origin: None,
            last: None,
            rows: 0,
            duty: None,
            rad_per_count: f64::NAN,
            exact: Vec::new(),
            counted: Vec::new(),
        }
    }

    /// The series recorded.
    pub fn finish(self) -> SeriesRun {
        SeriesRun {
            exact: Telemetry {
                period_s: self.period_s,
                samples: self.exact,
            },
            counted: Telemetry {
                period_s: self.period_s,
                samples: self.counted,
            },
        }
    }

    /// The row from `a` to `b` with the duties `duty`.
    fn rows(&mut self, a: &Look, b: &Look, duty: [f64; 2]) {
        let o = self.origin.expect("rows follow the origin");
        let dt = b.t_s - a.t_s;
        let rpm = |rad: f64| RadPerSec(rad / dt).to_thesis_rpm().0;
        // The pose in the start frame.
        let (dx, dy) = (b.pose.0 - o.pose.0, b.pose.1 - o.pose.1);
        let (s, c) = o.pose.2.sin_cos();
        let pose = Some((c * dx + s * dy, -s * dx + c * dy, b.pose.2 - o.pose.2));
        let row = |l: f64, r: f64| Sample {
            t_s: b.t_s - o.t_s,
            rpm_left: rpm(l),
            rpm_right: rpm(r),
            pwm_left: 255.0 * duty[0],
            pwm_right: 255.0 * duty[1],
            pose,
        };
        self.exact.push(row(
            b.angle_rad[0] - a.angle_rad[0],
            b.angle_rad[1] - a.angle_rad[1],
        ));
        let counts = |i: usize| (b.counts[i] - a.counts[i]) as f64 * self.rad_per_count;
        self.counted.push(row(counts(0), counts(1)));
    }
}

impl Observer for SeriesProbe {
    fn step(&mut self, _step: &Step) {}

    fn wants_steps(&self) -> bool {
        false
    }

    fn check(&mut self, bench: &Bench) {
        let t = bench.clock().seconds(bench.cycle());
        let robot = bench.core().robot();
        let duty = Side::BOTH.map(|s| {
            let (fwd, rev) = robot.bridge_inputs(s);
            fwd.get() - rev.get()
        });
        let Some(origin) = self.origin else {
            if duty != [0.0, 0.0] {
                let look = Look::of(robot, t);
                let e = &robot.config().encoder;
                self.rad_per_count =
                    std::f64::consts::TAU / (f64::from(e.a_edges_per_motor_rev) * e.gear_ratio);
                self.origin = Some(look);
                self.last = Some(look);
            }
            return;
        };
        // Row k spans origin + k T .. origin + (k + 1) T (products, not sums: no drift).
        let k = f64::from(self.rows);
        if self.duty.is_none() && t.0 >= origin.t_s + (k + 0.5) * self.period_s {
            self.duty = Some(duty);
        }
        let end = origin.t_s + (k + 1.0) * self.period_s;
        if t.0 >= end {
            // The row's end itself when the plant has not passed it yet, else the plant's
            // own time (between the end and this check).
            let at = if robot.now().0 > end {
                robot.now()
            } else {
                Seconds(end)
            };
            let look = Look::of(robot, at);
            let last = self.last.expect("a row starts where the last ended");
            // A row shorter than half a period has no middle look: its end's duties.
            let d = self.duty.take().unwrap_or(duty);
            self.rows(&last, &look, d);
            self.last = Some(look);
            self.rows += 1;
        }
    }

    fn into_any(self: Box<Self>) -> Box<dyn std::any::Any> {
        self
    }
}

/// The noise of `real`'s speeds and duties as it weighs a segment's mean, from the data
/// alone: the long-run standard deviation of each wheel's speed and duty in the steady legs
/// (the σ for which a mean of n samples has the standard error σ/√n), by batch means: each
/// steady stretch is cut into blocks of [`NOISE_BLOCK`] samples, and σ² is the block length
/// times the variance of the block means about their stretch's mean. The controller's
/// ripple alternates from one period to the next, so it weighs a mean far less than its
/// sample-to-sample size; batch means measure what is left of it. Speeds not below
/// [`SERIES_NOISE_FLOOR_RPM`], duties not below [`SERIES_NOISE_FLOOR_PWM`].
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct SeriesNoise {
    /// Left and right speed, thesis RPM.
    pub rpm: [f64; 2],
    /// Left and right duty, of 255.
    pub pwm: [f64; 2],
}

/// The smallest noise a telemetry duty is given, of 255 (a tenth of one step of the 8-bit
/// command).
pub const SERIES_NOISE_FLOOR_PWM: f64 = 0.1;

/// Samples per block of [`series_noise`]'s batch means: 0.12 s at 15 ms, several periods of
/// the controller's ripple.
pub const NOISE_BLOCK: usize = 8;

/// See [`SeriesNoise`].
pub fn series_noise(real: &Telemetry) -> SeriesNoise {
    let seg = gap::series::segments(real);
    let s = &real.samples;
    // The steady stretches, as index ranges.
    let mut stretches = Vec::new();
    let mut i = 0;
    while i < s.len() {
        if seg[i] != SegmentKind::Steady {
            i += 1;
            continue;
        }
        let start = i;
        while i < s.len() && seg[i] == SegmentKind::Steady {
            i += 1;
        }
        stretches.push(start..i);
    }
    let noise = |f: &dyn Fn(&Sample) -> f64, floor: f64| {
        let (mut sq, mut dof) = (0.0, 0usize);
        for r in &stretches {
            let blocks: Vec<f64> = s[r.clone()]
                .chunks_exact(NOISE_BLOCK)
                .map(|b| b.iter().map(f).sum::<f64>() / NOISE_BLOCK as f64)
                .collect();
            if blocks.len() < 2 {
                continue;
            }
            let m = blocks.iter().sum::<f64>() / blocks.len() as f64;
            sq += blocks.iter().map(|b| (b - m).powi(2)).sum::<f64>();
            dof += blocks.len() - 1;
        }
        if dof == 0 {
            return floor;
        }
        (NOISE_BLOCK as f64 * sq / dof as f64).sqrt().max(floor)
    };
    let r = SERIES_NOISE_FLOOR_RPM;
    let p = SERIES_NOISE_FLOOR_PWM;
    SeriesNoise {
        rpm: [noise(&|x| x.rpm_left, r), noise(&|x| x.rpm_right, r)],
        pwm: [noise(&|x| x.pwm_left, p), noise(&|x| x.pwm_right, p)],
    }
}

/// `sim` as long as `real`: a simulated run shorter than the real one is taken to stand
/// still after its end (zero speed, zero duty, its last pose).
fn padded_to(sim: &Telemetry, real: &Telemetry) -> Telemetry {
    let mut sim = sim.clone();
    let pose = sim.samples.last().and_then(|s| s.pose);
    while sim.samples.len() < real.samples.len() {
        let t_s = real.samples[sim.samples.len()].t_s;
        sim.samples.push(Sample {
            t_s,
            rpm_left: 0.0,
            rpm_right: 0.0,
            pwm_left: 0.0,
            pwm_right: 0.0,
            pose,
        });
    }
    sim
}

/// One segment kind of a series comparison: the mean of real − sim of both wheels' speeds
/// and duties, each also over its standard error (the noise over √n).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SegmentFit {
    /// The segment kind (of the real series).
    pub segment: SegmentKind,
    /// Samples.
    pub n: usize,
    /// Mean of real − sim speed, left and right, thesis RPM.
    pub bias_rpm: [f64; 2],
    /// Mean of real − sim duty, left and right, of 255.
    pub bias_pwm: [f64; 2],
    /// The four means over their standard errors: speed left, right, duty left, right.
    pub z: [f64; 4],
}

/// A simulated series against a measured one.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SeriesScore {
    /// What is compared.
    pub label: String,
    /// The residuals of [`SegmentFit::z`] of every segment kind, squared and summed.
    pub chi2: f64,
    /// The sum over the same residuals of ln(v / v₀), v a residual's variance and v₀ its
    /// real series' part alone (0 for one simulated run): the Gaussian deviance's term for
    /// the variance the simulated runs' own spread adds. Without it, a candidate that made
    /// the bench's runs scatter (encoder glitches that move counts between periods) would
    /// lower the χ² by widening its own error bars and "fit" a series it does not explain.
    pub spread_penalty: f64,
    /// Residuals that sum.
    pub residuals: usize,
    /// RMS of real − sim speed over every sample and both wheels, thesis RPM.
    pub rms_rpm: f64,
    /// The real series' noise.
    pub noise: SeriesNoise,
    /// Per segment kind.
    pub segments: Vec<SegmentFit>,
    /// The speeds' comparison of `gap::series` (per segment, whiteness, input correlation).
    #[serde(skip)]
    pub gap: SeriesGap,
}

impl SeriesScore {
    /// What the diagnosis minimises: [`SeriesScore::chi2`] plus
    /// [`SeriesScore::spread_penalty`] (−2 ln of the Gaussian likelihood, less a constant
    /// that no candidate changes).
    pub fn deviance(&self) -> f64 {
        self.chi2 + self.spread_penalty
    }
}

/// Scores `sim` against `real` (`label` names the comparison): [`series_chi2_of_runs`] of
/// one simulated run.
pub fn series_chi2(
    label: &str,
    real: &Telemetry,
    sim: &Telemetry,
) -> Result<SeriesScore, GapError> {
    series_chi2_of_runs(label, real, std::slice::from_ref(sim))
}

/// Scores the simulated runs `sims` (at least one) against `real` (`label` names the
/// comparison), per segment kind of the real
/// series: for each wheel the mean of real − sim speed and of real − sim duty over the
/// segment's samples, each over its standard error σ/√n with σ the real series' own noise
/// ([`series_noise`]): four residuals per segment kind, about 1 each when the model is
/// right, and growing with the segment's length when it is off (a dead band needs more duty
/// all along a leg; a slower start lowers the start-up's speeds). The means, not the
/// sample-by-sample RMS, are scored: two runs of one robot differ in the phase of the speed
/// controller's ripple, which a mean averages out and an RMS does not (the RMS is reported,
/// [`SeriesScore::rms_rpm`]). A simulated run shorter than the real one is taken to stand
/// still after its end (zero speed, zero duty).
///
/// With several runs (each from its own start phase), the bias is that of their mean, and
/// its standard error also holds how much the runs' own segment means differ: the real run
/// is one start phase, the mean of k runs k of them, so the spread s of the k runs' biases
/// adds `s²(1 + 1/k)` to the variance (a start-up's speeds depend on the phase far more
/// than the steady legs' ripple says). One run: σ/√n alone. What that spread widens is
/// charged back in [`SeriesScore::spread_penalty`]; the score a search minimises is
/// [`SeriesScore::deviance`].
pub fn series_chi2_of_runs(
    label: &str,
    real: &Telemetry,
    sims: &[Telemetry],
) -> Result<SeriesScore, GapError> {
    let padded: Vec<Telemetry> = sims.iter().map(|s| padded_to(s, real)).collect();
    let first = padded
        .first()
        .ok_or_else(|| GapError::Fit(format!("{label}: no simulated run to score")))?;
    let gap = series_gap(label, real, first)?;
    let noise = series_noise(real);
    let seg = gap::series::segments(real);
    let n = gap.n;
    let k = padded.len() as f64;
    let mut segments = Vec::new();
    let mut spread_penalty = 0.0;
    for kind in SegmentKind::ALL {
        let idx: Vec<usize> = (0..n).filter(|&i| seg[i] == kind).collect();
        if idx.is_empty() {
            continue;
        }
        let m = idx.len() as f64;
        // Each run's mean of real − sim over the segment kind, for each of the four series.
        let of = |f: &dyn Fn(&Sample) -> f64| -> Vec<f64> {
            padded
                .iter()
                .map(|sim| {
                    idx.iter()
                        .map(|&i| f(&real.samples[i]) - f(&sim.samples[i]))
                        .sum::<f64>()
                        / m
                })
                .collect()
        };
        let series: [Vec<f64>; 4] = [
            of(&|s| s.rpm_left),
            of(&|s| s.rpm_right),
            of(&|s| s.pwm_left),
            of(&|s| s.pwm_right),
        ];
        let mean = |v: &[f64]| v.iter().sum::<f64>() / k;
        let spread2 = |v: &[f64]| {
            if v.len() < 2 {
                return 0.0;
            }
            let c = mean(v);
            v.iter().map(|x| (x - c).powi(2)).sum::<f64>() / (k - 1.0)
        };
        let sigma = [noise.rpm[0], noise.rpm[1], noise.pwm[0], noise.pwm[1]];
        let real2: [f64; 4] = std::array::from_fn(|c| sigma[c].powi(2) / m);
        let se2: [f64; 4] =
            std::array::from_fn(|c| real2[c] + spread2(&series[c]) * (1.0 + 1.0 / k));
        let z: [f64; 4] = std::array::from_fn(|c| mean(&series[c]) / se2[c].sqrt());
        spread_penalty += (0..4).map(|c| (se2[c] / real2[c]).ln()).sum::<f64>();
        segments.push(SegmentFit {
            segment: kind,
            n: idx.len(),
            z,
            bias_rpm: [mean(&series[0]), mean(&series[1])],
            bias_pwm: [mean(&series[2]), mean(&series[3])],
        });
    }
    let chi2 = segments
        .iter()
        .flat_map(|s| s.z)
        .map(|z| z * z)
        .sum::<f64>();
    let sq: f64 = gap
        .segments
        .iter()
        .map(|s| s.n as f64 * (s.rms_left.powi(2) + s.rms_right.powi(2)))
        .sum();
    Ok(SeriesScore {
        label: label.to_owned(),
        chi2,
        spread_penalty,
        residuals: 4 * segments.len(),
        rms_rpm: (sq / (2 * n).max(1) as f64).sqrt(),
        noise,
        segments,
        gap,
    })
}
