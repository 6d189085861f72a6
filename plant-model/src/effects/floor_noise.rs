//! `floor_noise`: floor irregularities (joints, dust, bumps) as random, non-systematic error
//! per metre travelled: a heading random walk and a lateral random walk.
//!
//! Each pose step's wheel travel splits into a rolling part (the mean of the two wheels'
//! arcs, `|d_L + d_R| / 2`) and a turning part (half their difference, `|d_R - d_L| / 2`,
//! each wheel's travel in a spin on the spot). Each part is cut into stretches of
//! `stretch_mm`. A rolling stretch draws, in order, a heading change `N(0, sigma_h^2 l)`
//! and a lateral shift `N(0, sigma_y^2 l)` (`l` the stretch in metres); a turning stretch a
//! heading change `N(0, sigma_t^2 l)`: a tyre that scrubs round on the spot feels the floor
//! more than one that rolls. Each draw is spread evenly along its stretch. Over a distance
//! `L` the heading therefore wanders with variance `sigma_h^2 L` and the lateral shift it adds
//! directly with `sigma_y^2 L` (the heading's own effect on position comes on top, growing as
//! `L^3 / 3`); a spin of angle `A` adds heading variance `sigma_t^2 A b / 2`.
//!
//! The draws come from the robot's seed (SplitMix64 streams of their own, rolling and
//! turning), one draw per stretch in the order the stretches are reached: the same seed gives
//! the same floor however often the bench advances the plant. Ground only: the encoders do
//! not see the floor.
//!
//! # Signature
//!
//! Zero mean, a spread that grows with distance: the end points of repeated runs scatter
//! around the systematic end point (the thesis' five runs per direction scatter by a few
//! cm; its straight lines by a few mm sideways).
//!
//! # Keys
//!
//! | key | unit | meaning |
//! |---|---|---|
//! | `heading_deg_per_sqrt_m` | deg / sqrt(m) | sigma_h: heading standard deviation after 1 m of rolling |
//! | `lateral_mm_per_sqrt_m` | mm / sqrt(m) | sigma_y: lateral standard deviation after 1 m of rolling |
//! | `turn_heading_deg_per_sqrt_m` | deg / sqrt(m) | optional, default sigma_h: sigma_t, heading standard deviation after 1 m of wheel travel turning on the spot |
//! | `stretch_mm` | mm | optional, default 20: floor per draw (the size of a floor feature) |

use serde::{Deserialize, Serialize};

use crate::check::{check_physical, Bounds};
use crate::effects::key;
use crate::rng::{stream, SplitMix64};
use crate::Error;

/// Default of `stretch_mm`.
pub const DEFAULT_STRETCH_MM: f64 = 20.0;

/// Parameters of `[effects.floor_noise]` (see the module docs).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FloorNoise {
    /// Heading standard deviation after 1 m, degrees per sqrt(metre).
    pub heading_deg_per_sqrt_m: f64,
    /// Lateral standard deviation after 1 m, mm per sqrt(metre).
    pub lateral_mm_per_sqrt_m: f64,
    /// Heading standard deviation after 1 m of wheel travel turning on the spot, degrees per
    /// sqrt(metre); `heading_deg_per_sqrt_m` when absent.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub turn_heading_deg_per_sqrt_m: Option<f64>,
    /// Floor travelled per draw, mm.
    #[serde(default = "default_stretch")]
    pub stretch_mm: f64,
}

fn default_stretch() -> f64 {
    DEFAULT_STRETCH_MM
}

impl FloorNoise {
    /// Checks the parameters; `prefix` is `effects.floor_noise`.
    pub fn validate(&self, prefix: &str) -> Result<(), Error> {
        let heading = Bounds {
            low: 0.0,
            high: 90.0,
            unit: "deg",
        };
        check_physical(
            &key(prefix, "heading_deg_per_sqrt_m"),
            self.heading_deg_per_sqrt_m,
            heading,
            "heading standard deviation after 1 m",
        )?;
        check_physical(
            &key(prefix, "lateral_mm_per_sqrt_m"),
            self.lateral_mm_per_sqrt_m,
            Bounds {
                low: 0.0,
                high: 1000.0,
                unit: "mm",
            },
            "lateral standard deviation after 1 m",
        )?;
        if let Some(sigma) = self.turn_heading_deg_per_sqrt_m {
            check_physical(
                &key(prefix, "turn_heading_deg_per_sqrt_m"),
                sigma,
                heading,
                "heading standard deviation after 1 m turning on the spot",
            )?;
        }
        check_physical(
            &key(prefix, "stretch_mm"),
            self.stretch_mm,
            Bounds {
                low: 0.1,
                high: 10_000.0,
                unit: "mm",
            },
            "floor travelled per random draw",
        )?;
        Ok(())
    }
}

/// One kind of travel cut into stretches, each with its own draws.
#[derive(Debug, Clone, PartialEq)]
struct Stretches {
    rng: SplitMix64,
    stretch_mm: f64,
    /// Standard deviations per stretch: heading (rad) and lateral (mm).
    sigma: (f64, f64),
    /// Travel into the current stretch, mm.
    into_mm: f64,
    /// Heading and lateral change per mm of the current stretch.
    rate: (f64, f64),
}

impl Stretches {
    fn new(rng: SplitMix64, stretch_mm: f64, sigma: (f64, f64)) -> Self {
        let mut stretches = Stretches {
            rng,
            stretch_mm,
            sigma,
            into_mm: 0.0,
            rate: (0.0, 0.0),
        };
        stretches.draw();
        stretches
    }

    fn draw(&mut self) {
        let heading = self.sigma.0 * self.rng.next_standard_normal();
        let lateral = if self.sigma.1 == 0.0 {
            0.0
        } else {
            self.sigma.1 * self.rng.next_standard_normal()
        };
        self.rate = (heading / self.stretch_mm, lateral / self.stretch_mm);
        self.into_mm = 0.0;
    }

    /// Heading change (rad) and lateral shift (mm) over `travel_mm` more of this travel.
    fn advance(&mut self, travel_mm: f64) -> (f64, f64) {
        let mut left = travel_mm;
        let (mut heading, mut lateral) = (0.0, 0.0);
        while left > 0.0 {
            let take = left.min(self.stretch_mm - self.into_mm);
            heading += self.rate.0 * take;
            lateral += self.rate.1 * take;
            self.into_mm += take;
            left -= take;
            if self.into_mm >= self.stretch_mm {
                self.draw();
            }
        }
        (heading, lateral)
    }
}

/// The floor under one run: the rolling and the turning stretches being crossed.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct FloorState {
    rolling: Stretches,
    turning: Stretches,
}

impl FloorState {
    pub(crate) fn new(params: &FloorNoise, seed: u64) -> Self {
        let metres = (params.stretch_mm / 1000.0).sqrt();
        let turn_deg = params
            .turn_heading_deg_per_sqrt_m
            .unwrap_or(params.heading_deg_per_sqrt_m);
        FloorState {
            rolling: Stretches::new(
                SplitMix64::new(seed, stream::FLOOR_NOISE),
                params.stretch_mm,
                (
                    params.heading_deg_per_sqrt_m.to_radians() * metres,
                    params.lateral_mm_per_sqrt_m * metres,
                ),
            ),
            turning: Stretches::new(
                SplitMix64::new(seed, stream::FLOOR_NOISE_TURNING),
                params.stretch_mm,
                (turn_deg.to_radians() * metres, 0.0),
            ),
        }
    }

    /// Heading change (rad) and lateral shift (mm) over `rolling_mm` more rolling and
    /// `turning_mm` more turning on the spot.
    pub(crate) fn advance(&mut self, rolling_mm: f64, turning_mm: f64) -> (f64, f64) {
        let (h1, lateral) = self.rolling.advance(rolling_mm);
        let (h2, _) = self.turning.advance(turning_mm);
        (h1 + h2, lateral)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::effects::test_support::{drive, symmetric};
    use crate::units::Seconds;
    use crate::Robot;

    fn noisy() -> crate::RobotConfig {
        symmetric(|c| {
            c.effects.floor_noise = Some(FloorNoise {
                heading_deg_per_sqrt_m: 1.0,
                lateral_mm_per_sqrt_m: 3.0,
                turn_heading_deg_per_sqrt_m: Some(4.0),
                stretch_mm: 20.0,
            })
        })
    }

    /// Drives straight until each wheel has rolled `metres` (1.8 s per metre at 0.9 duty,
    /// near enough); returns heading (deg) and the lateral position (mm) for each seed.
    fn ends(config: &crate::RobotConfig, seeds: u64, seconds: f64) -> Vec<(f64, f64, f64)> {
        (0..seeds)
            .map(|seed| {
                let mut robot = Robot::new(config, seed).unwrap();
                drive(&mut robot, 0.9, 0.9);
                robot.advance_to(Seconds(seconds)).unwrap();
                let p = robot.pose();
                (p.theta().0.to_degrees(), p.y().0, p.x().0)
            })
            .collect()
    }

    fn mean_var(xs: impl Iterator<Item = f64> + Clone) -> (f64, f64) {
        let n = xs.clone().count() as f64;
        let mean = xs.clone().sum::<f64>() / n;
        let var = xs.map(|x| (x - mean).powi(2)).sum::<f64>() / (n - 1.0);
        (mean, var)
    }

    /// Signature: over many seeds the heading error has zero mean and a variance that grows
    /// linearly with the distance (sigma_h^2 per metre), and the noise does not move the
    /// encoders.
    #[test]
    fn zero_mean_and_variance_growing_with_distance() {
        let config = noisy();
        let seeds = 1000;
        let short = ends(&config, seeds, 1.0);
        let long = ends(&config, seeds, 2.0);
        let metres =
            |e: &[(f64, f64, f64)]| e.iter().map(|p| p.2).sum::<f64>() / e.len() as f64 / 1000.0;
        let (l1, l2) = (metres(&short), metres(&long));
        let (m1, v1) = mean_var(short.iter().map(|p| p.0));
        let (m2, v2) = mean_var(long.iter().map(|p| p.0));
        // Standard error of the mean: sqrt(var / n).
        assert!(m1.abs() < 3.0 * (v1 / seeds as f64).sqrt(), "mean {m1}");
        assert!(m2.abs() < 3.0 * (v2 / seeds as f64).sqrt(), "mean {m2}");
        // Variance per metre near sigma_h^2 = 1 deg^2/m (sampling error 4.5 % at n = 1000).
        assert!(
            (v1 / l1 - 1.0).abs() < 0.15,
            "var/m {} over {l1} m",
            v1 / l1
        );
        assert!(
            (v2 / l2 - 1.0).abs() < 0.15,
            "var/m {} over {l2} m",
            v2 / l2
        );
        assert!(v2 > 1.5 * v1, "variance grows with distance: {v1} -> {v2}");
        // The lateral spread grows too.
        let (_, y1) = mean_var(short.iter().map(|p| p.1));
        let (_, y2) = mean_var(long.iter().map(|p| p.1));
        assert!(y2 > 2.0 * y1, "lateral variance {y1} -> {y2}");
        // Encoders see nothing of the floor.
        let mut plain = Robot::new(&symmetric(|_| {}), 0).unwrap();
        let mut rough = Robot::new(&config, 0).unwrap();
        for robot in [&mut plain, &mut rough] {
            drive(robot, 0.9, 0.9);
            robot.advance_to(Seconds(1.0)).unwrap();
        }
        assert_eq!(
            plain.a_edges(crate::Side::Left),
            rough.a_edges(crate::Side::Left)
        );
        assert_ne!(plain.pose(), rough.pose());
    }

    /// Spins on the spot draw from the turning sigma: after the same wheel travel, the
    /// heading spreads `sigma_t / sigma_h` = 4 times as far as rolling straight.
    #[test]
    fn spins_feel_the_turning_sigma() {
        let config = noisy();
        let spread = |left: f64, right: f64| {
            let ends: Vec<f64> = (0..400)
                .map(|seed| {
                    let mut robot = Robot::new(&config, seed).unwrap();
                    drive(&mut robot, left, right);
                    robot.advance_to(Seconds(1.0)).unwrap();
                    let plain = (robot.distance_travelled(crate::Side::Right).0
                        - robot.distance_travelled(crate::Side::Left).0)
                        / 130.0;
                    robot.pose().theta().0 - plain
                })
                .collect();
            mean_var(ends.iter().copied()).1.sqrt()
        };
        let ratio = spread(-0.9, 0.9) / spread(0.9, 0.9);
        assert!((ratio - 4.0).abs() < 0.6, "ratio {ratio}");
    }

    /// The same seed gives the same floor however the plant is stepped (to rounding in the
    /// pose arcs); another seed gives another.
    #[test]
    fn same_seed_same_floor_whatever_the_stepping() {
        let config = noisy();
        let run = |seed: u64, times: &[f64]| {
            let mut robot = Robot::new(&config, seed).unwrap();
            drive(&mut robot, 0.9, 0.6);
            for &t in times {
                robot.advance_to(Seconds(t)).unwrap();
            }
            robot.pose()
        };
        let one = run(5, &[2.0]);
        let many: Vec<f64> = (1..=2000).map(|k| f64::from(k) * 1e-3).collect();
        let fine = run(5, &many);
        // As without noise: the pose arcs differ only in where the 1 ms steps fall.
        assert!((one.x().0 - fine.x().0).abs() < 1e-4, "{one} vs {fine}");
        assert!((one.y().0 - fine.y().0).abs() < 1e-4, "{one} vs {fine}");
        assert!((one.theta().0 - fine.theta().0).abs() < 1e-9);
        let other = run(6, &[2.0]);
        assert!((one.theta().0 - other.theta().0).abs() > 1e-6);
    }
}
