//! Injection points: where the bench can bend what the firmware sees.
//!
//! The bench sits between the plant and the MCU's pins and between the host
//! and the MCU's UART, so faults of the wiring, the sensors and the link are
//! applied here: encoder lines (dropout, stuck, swapped, missed edges,
//! glitches), a motor's bridge (disconnected), the Bluetooth link (loss,
//! corruption, garbage, link down), and the MCU's reset line. Faults of the
//! physics (a stalled wheel, slip) belong to the plant.
//!
//! Everything random here draws from one seeded generator, so a faulted run
//! is as deterministic as any other.

use plant_model::rng::SplitMix64;
use serde::{Deserialize, Serialize};

/// What an encoder's lines do, between the plant and the pins.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "snake_case", tag = "kind")]
pub enum EncoderFault {
    #[default]
    Healthy,
    /// Both lines hold their last level (a cable off, the sensor unpowered).
    Dropout,
    /// Channel A stuck at a level.
    StuckA { level: bool },
    /// Channel B stuck at a level (direction decoding goes wrong).
    StuckB { level: bool },
    /// A and B swapped (the count runs backwards).
    Swapped,
    /// Every `every`-th A edge and the one after it are lost (a pulse too
    /// short for the MCU to see, as at high edge rates): two counts lost.
    MissPairs { every: u32 },
}

/// One of an encoder's two channels.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Channel {
    A,
    B,
}

/// What the Bluetooth link does to bytes from the host.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, Default)]
#[serde(default, deny_unknown_fields)]
pub struct LinkFault {
    /// Probability that a byte is lost.
    pub loss: f64,
    /// Probability that a byte arrives with one bit flipped.
    pub corrupt: f64,
    /// Probability that a random byte is inserted before a byte.
    pub garbage: f64,
    /// The link is down: every byte is lost.
    pub down: bool,
}

impl LinkFault {
    pub fn is_healthy(&self) -> bool {
        self.loss == 0.0 && self.corrupt == 0.0 && self.garbage == 0.0 && !self.down
    }
}

/// The fault dice: the workspace's one SplitMix64 ([`plant_model::rng`]), seeded from a
/// bare seed, so a fault run draws the same sequence on every machine.
#[derive(Debug, Clone)]
pub struct Dice(SplitMix64);

impl Dice {
    pub fn new(seed: u64) -> Self {
        Self(SplitMix64::from_seed(seed))
    }

    pub fn next_u64(&mut self) -> u64 {
        self.0.next_u64()
    }

    /// Uniform in [0, 1).
    pub fn unit(&mut self) -> f64 {
        self.0.next_unit()
    }

    pub fn chance(&mut self, p: f64) -> bool {
        p > 0.0 && self.unit() < p
    }
}

/// The injection state the bench consults on every edge and byte.
#[derive(Debug, Clone)]
pub struct Injection {
    pub encoder: [EncoderFault; 2],
    /// Edges seen by `MissPairs`, per side.
    pub a_edges_seen: [u32; 2],
    /// `MissPairs` is holding A at its old level until the plant's A comes back.
    holding: [bool; 2],
    /// A motor's bridge outputs are disconnected: the motor coasts.
    pub motor_disconnected: [bool; 2],
    /// A glitch pulse is on an encoder's channel now: the pin shows the
    /// inverse of its level, by side and channel (A, B).
    pub glitch: [[bool; 2]; 2],
    pub link: LinkFault,
    pub dice: Dice,
}

impl Injection {
    pub fn new(seed: u64) -> Self {
        Self {
            encoder: [EncoderFault::Healthy; 2],
            a_edges_seen: [0; 2],
            holding: [false; 2],
            motor_disconnected: [false; 2],
            glitch: [[false; 2]; 2],
            link: LinkFault::default(),
            dice: Dice::new(seed),
        }
    }

    /// The levels the pins show for the plant's levels `(a, b)`, given the
    /// levels the pins showed before.
    pub fn encoder_levels(
        &mut self,
        i: usize,
        plant: (bool, bool),
        shown: (bool, bool),
    ) -> (bool, bool) {
        let (a, b) = plant;
        match self.encoder[i] {
            EncoderFault::Healthy => (a, b),
            EncoderFault::Dropout => shown,
            EncoderFault::StuckA { level } => (level, b),
            EncoderFault::StuckB { level } => (a, level),
            EncoderFault::Swapped => (b, a),
            EncoderFault::MissPairs { every } => {
                if self.holding[i] {
                    // The plant's A came back to the level held: both edges
                    // of the pulse are lost.
                    if a == shown.0 {
                        self.holding[i] = false;
                        self.a_edges_seen[i] = self.a_edges_seen[i].wrapping_add(1);
                    }
                    return (shown.0, b);
                }
                if a != shown.0 {
                    self.a_edges_seen[i] = self.a_edges_seen[i].wrapping_add(1);
                    if self.a_edges_seen[i] % every.max(2) == 0 {
                        self.holding[i] = true;
                        return (shown.0, b);
                    }
                }
                (a, b)
            }
        }
    }

    /// Bytes that reach the MCU when the host sends `byte`.
    pub fn link_bytes(&mut self, byte: u8) -> Vec<u8> {
        let l = self.link;
        if l.is_healthy() {
            return vec![byte];
        }
        if l.down {
            return Vec::new();
        }
        let mut out = Vec::with_capacity(2);
        if self.dice.chance(l.garbage) {
            out.push(self.dice.next_u64() as u8);
        }
        if self.dice.chance(l.loss) {
            return out;
        }
        let mut b = byte;
        if self.dice.chance(l.corrupt) {
            b ^= 1 << (self.dice.next_u64() % 8);
        }
        out.push(b);
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dice_are_deterministic_and_uniform_enough() {
        let mut a = Dice::new(7);
        let mut b = Dice::new(7);
        let xs: Vec<f64> = (0..10_000).map(|_| a.unit()).collect();
        let ys: Vec<f64> = (0..10_000).map(|_| b.unit()).collect();
        assert_eq!(xs, ys);
        let mean = xs.iter().sum::<f64>() / xs.len() as f64;
        assert!((mean - 0.5).abs() < 0.02, "{mean}");
    }

    #[test]
    fn miss_pairs_loses_two_counts_per_event() {
        let mut inj = Injection::new(1);
        inj.encoder[0] = EncoderFault::MissPairs { every: 4 };
        // Walk the quadrature sequence forward and decode as the firmware does.
        let seq = [(true, false), (true, true), (false, true), (false, false)];
        let mut shown = (false, false);
        let mut count = 0i64;
        // 402 quadrature steps: 201 A edges.
        for k in 0..402 {
            let plant = seq[k % 4];
            let next = inj.encoder_levels(0, plant, shown);
            if next.0 != shown.0 {
                count += crate::bench::decode_a_edge(next.0, next.1);
            }
            shown = next;
        }
        // Edges 4, 8, ..., 200 are lost together with the edge after each.
        assert_eq!(count, 201 - 2 * 50);
    }

    #[test]
    fn link_down_loses_everything_and_healthy_loses_nothing() {
        let mut inj = Injection::new(3);
        assert_eq!(inj.link_bytes(0x42), vec![0x42]);
        inj.link.down = true;
        assert!(inj.link_bytes(0x42).is_empty());
    }
}
