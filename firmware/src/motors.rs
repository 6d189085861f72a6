//! The DRV8833 dual H-bridge: each motor has a forward and a reverse input,
//! each driven by a PWM channel with `analogWrite` semantics (0 = low,
//! 255 = high, else PWM). With both inputs low the motor coasts; forward high
//! and reverse low drives forward; the reverse pin alone drives backwards.

use crate::hal::pwm::PwmChannel;
use crate::io::{Bridges, Side};

/// One motor's two bridge inputs.
pub struct HBridge<F: PwmChannel, R: PwmChannel> {
    forward: F,
    reverse: R,
}

impl<F: PwmChannel, R: PwmChannel> HBridge<F, R> {
    /// Takes the two channels and sets both to 0 (coast).
    pub fn new(mut forward: F, mut reverse: R) -> Self {
        forward.set_duty(0);
        reverse.set_duty(0);
        HBridge { forward, reverse }
    }

    /// Sets the forward input's duty.
    #[inline]
    pub fn set_forward(&mut self, duty: u8) {
        self.forward.set_duty(duty);
    }

    /// Sets the reverse input's duty.
    #[inline]
    pub fn set_reverse(&mut self, duty: u8) {
        self.reverse.set_duty(duty);
    }

    /// Both inputs: forward first, then reverse.
    #[inline]
    pub fn set(&mut self, forward: u8, reverse: u8) {
        self.forward.set_duty(forward);
        self.reverse.set_duty(reverse);
    }
}

/// Both motors.
pub struct Motors<RF: PwmChannel, RR: PwmChannel, LF: PwmChannel, LR: PwmChannel> {
    /// Right motor.
    pub right: HBridge<RF, RR>,
    /// Left motor.
    pub left: HBridge<LF, LR>,
}

impl<RF: PwmChannel, RR: PwmChannel, LF: PwmChannel, LR: PwmChannel> Motors<RF, RR, LF, LR> {
    /// All four inputs to 0, forward inputs first (right, left), then the
    /// reverse ones (right, left), like the thesis' stop routines.
    pub fn all_off(&mut self) {
        self.right.set_forward(0);
        self.left.set_forward(0);
        self.right.set_reverse(0);
        self.left.set_reverse(0);
    }
}

impl<RF: PwmChannel, RR: PwmChannel, LF: PwmChannel, LR: PwmChannel> Bridges for Motors<RF, RR, LF, LR> {
    #[inline(always)]
    fn set_forward(&mut self, side: Side, duty: u8) {
        match side {
            Side::Left => self.left.set_forward(duty),
            Side::Right => self.right.set_forward(duty),
        }
    }

    #[inline(always)]
    fn set_reverse(&mut self, side: Side, duty: u8) {
        match side {
            Side::Left => self.left.set_reverse(duty),
            Side::Right => self.right.set_reverse(duty),
        }
    }

    #[inline(always)]
    fn all_off(&mut self) {
        Motors::all_off(self)
    }
}
