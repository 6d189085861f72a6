//! The progress watchdog: a wheel driven hard enough must advance, and not
//! the wrong way.
//!
//! Judged once per control period from the count (the encoder handlers do
//! nothing for it), after a grace of [`STALL_GRACE_TICKS`] periods from the
//! segment start, and only in periods driven at or above the stall duty:
//! - no net progress of [`STALL_PROGRESS_COUNTS`] in the commanded direction
//!   within the stall time is a stall, or an encoder fault when the count
//!   moved back and forth ([`ENCODER_TRAVEL_COUNTS`]) meanwhile;
//! - more than [`WRONG_WAY_COUNTS`] against the commanded direction since
//!   the segment start is a wrong-direction fault (judged every period).

use henrytwo_protocol::Fault;

use super::drive::Wheel;

/// A wheel that goes more than this many counts against its commanded
/// direction within a segment is a fault: the factory `wrong_way_counts`.
pub const WRONG_WAY_COUNTS: i16 = 64;
/// Stall watchdog: net progress, in counts in the commanded direction, that
/// a wheel driven at or above the stall duty must make within the stall
/// time: the factory `stall_progress_counts`. At the set-points a wheel makes about 13 counts per tick; a wheel
/// that turns while its count does not advance (the 2x decoder with channel
/// B stuck counts +1, -1, +1 ...) or that creeps a count or two is stopped.
pub const STALL_PROGRESS_COUNTS: i16 = 3;
/// ... and counts moved within that time (each tick's change, either way,
/// added up) that make it an encoder fault rather than a stall: the progress
/// asked (this at the factory settings). Movement in
/// the commanded direction alone adds up to at most 2 under the net progress
/// above (a wheel coasting to a stop), so 3 means the count went back and
/// forth: edges arrive but do not add up. Sampled once per tick, the count
/// shows only the parity of each tick's edges (channel B stuck: about half
/// the ticks change it by one; 5 in the 14 ticks on the bench), so an
/// encoder whose edges come in even numbers per tick looks like a stall.
pub const ENCODER_TRAVEL_COUNTS: u16 = 3;

// The travel that makes an encoder fault is the progress asked.
const _: () = assert!(ENCODER_TRAVEL_COUNTS == STALL_PROGRESS_COUNTS as u16);
/// Ticks after a segment start the stall watchdog leaves alone (the first
/// runs at the start duty, below any sensible stall duty; then the wheels
/// spin up from rest).
pub const STALL_GRACE_TICKS: u8 = 3;

/// The progress watchdog's count thresholds. The factory ones
/// ([`Factory`]) are compile-time constants: the tick a robot told nothing
/// runs is the code it ran when they were compiled in, to the cycle (the
/// bench's results depend on the tick's timing); a robot given others runs
/// a second copy of the tick ([`Tuned`]).
pub trait Thresholds: Copy {
    /// Net progress, counts, that restarts the stall window.
    fn progress(self) -> i16;
    /// Counts against the commanded direction that are a fault.
    fn wrong_way(self) -> i32;
}

/// The factory thresholds, [`STALL_PROGRESS_COUNTS`] and [`WRONG_WAY_COUNTS`].
#[derive(Clone, Copy, Debug)]
pub struct Factory;

impl Thresholds for Factory {
    #[inline(always)]
    fn progress(self) -> i16 {
        STALL_PROGRESS_COUNTS
    }
    #[inline(always)]
    fn wrong_way(self) -> i32 {
        WRONG_WAY_COUNTS as i32
    }
}

/// Thresholds from the settings (`stall_progress_counts`, `wrong_way_counts`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Tuned {
    /// Net progress, counts.
    pub progress: i16,
    /// Counts against the commanded direction.
    pub wrong_way: i16,
}

impl Thresholds for Tuned {
    #[inline(always)]
    fn progress(self) -> i16 {
        self.progress
    }
    #[inline(always)]
    fn wrong_way(self) -> i32 {
        self.wrong_way as i32
    }
}

impl Tuned {
    /// `None` for the factory thresholds (the tick's [`Factory`] copy runs).
    pub const fn of(progress: i16, wrong_way: i16) -> Option<Tuned> {
        if progress == STALL_PROGRESS_COUNTS && wrong_way == WRONG_WAY_COUNTS {
            None
        } else {
            Some(Tuned { progress, wrong_way })
        }
    }
}

/// What the watchdogs found on one wheel.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum Check {
    /// Nothing wrong.
    Ok,
    /// Driven at or above the stall duty without net progress, the count
    /// (nearly) still.
    Stall,
    /// Likewise, but the count moved back and forth.
    EncoderInconsistent,
    /// Too far against the commanded direction.
    WrongWay,
}

/// The stall watchdog's judgement of one period driven at or above the
/// stall duty (`count` at its end, `counts` moved during it, `n` periods
/// long). Out of line: one copy for both wheels, and a wheel under normal
/// control (below the stall duty) does not call it.
///
/// Once the count has advanced `progress` ([`STALL_PROGRESS_COUNTS`] at the
/// factory settings) in the commanded
/// direction from the window's mark, the window starts again (as it does on
/// any period not judged). `ticks` judged periods without that progress are
/// a fault: an encoder fault if the count moved `progress` counts (either
/// way, [`ENCODER_TRAVEL_COUNTS`] at the factory settings) or more in that window (edges arrive, the count does not advance), a stall
/// otherwise.
#[inline(never)]
pub(crate) fn judge_progress<T: Thresholds>(w: &mut Wheel, count: i16, counts: u16, n: u16, ticks: u16, t: T) -> Check {
    let progress = t.progress();
    if w.still == 0 {
        w.travel = 0;
    }
    let net = count.wrapping_sub(w.mark);
    let net = if w.forward { net } else { net.wrapping_neg() };
    if net >= progress {
        w.mark = count;
        w.still = 0;
        return Check::Ok;
    }
    w.still = w.still.saturating_add(n);
    w.travel = w.travel.saturating_add(counts);
    if w.still < ticks {
        Check::Ok
    } else if w.travel >= progress as u16 {
        Check::EncoderInconsistent
    } else {
        Check::Stall
    }
}

/// The fault code of a wheel's check.
#[inline(always)]
pub(crate) fn fault_of(check: Check, stall: Fault, wrong_way: Fault) -> Fault {
    match check {
        Check::Ok => Fault::None,
        Check::Stall => stall,
        Check::EncoderInconsistent => Fault::EncoderInconsistent,
        Check::WrongWay => wrong_way,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Stall time of the tests, in periods.
    const TICKS: u16 = 14;

    fn wheel(forward: bool) -> Wheel {
        let mut w = Wheel::new();
        w.forward = forward;
        w
    }

    /// Judges one-period steps to the counts `path`; the checks in order.
    fn judge_path(w: &mut Wheel, path: &[i16]) -> std::vec::Vec<Check> {
        let mut last = w.mark;
        path.iter()
            .map(|&c| {
                let moved = c.wrapping_sub(last).unsigned_abs();
                last = c;
                judge_progress(w, c, moved, 1, TICKS, Factory)
            })
            .collect()
    }

    #[test]
    fn a_still_wheel_stalls_after_the_stall_time() {
        let mut w = wheel(true);
        let checks = judge_path(&mut w, &[0; TICKS as usize]);
        assert!(checks[..TICKS as usize - 1].iter().all(|&c| c == Check::Ok), "{checks:?}");
        assert_eq!(checks[TICKS as usize - 1], Check::Stall);
    }

    #[test]
    fn three_counts_of_progress_restart_the_window() {
        let mut w = wheel(true);
        // Three counts every thirteen periods, for far longer than the stall time.
        let path: std::vec::Vec<i16> = (1..=100).map(|i| (i / 13 * 3) as i16).collect();
        assert!(judge_path(&mut w, &path).iter().all(|&c| c == Check::Ok));
    }

    #[test]
    fn creeping_two_counts_is_a_stall() {
        let mut w = wheel(true);
        let mut path = [0i16; TICKS as usize];
        path[5..].fill(2);
        let checks = judge_path(&mut w, &path);
        assert_eq!(checks[TICKS as usize - 1], Check::Stall, "{checks:?}");
    }

    #[test]
    fn a_count_going_back_and_forth_is_an_encoder_fault() {
        let mut w = wheel(true);
        let path: std::vec::Vec<i16> = (0..TICKS).map(|i| (i % 2) as i16).collect();
        let checks = judge_path(&mut w, &path);
        assert!(checks[..TICKS as usize - 1].iter().all(|&c| c == Check::Ok), "{checks:?}");
        assert_eq!(checks[TICKS as usize - 1], Check::EncoderInconsistent);
    }

    #[test]
    fn a_reverse_wheel_progresses_downwards() {
        let down: std::vec::Vec<i16> = (1..=40).map(|i| -3 * i as i16).collect();
        assert!(judge_path(&mut wheel(false), &down).iter().all(|&c| c == Check::Ok));
        // The same counts are no progress for a forward wheel.
        assert!(judge_path(&mut wheel(true), &down).contains(&Check::EncoderInconsistent));
    }

    /// The progress asked is the one passed: creeping six counts forward
    /// within the stall time is a stall when eight are asked (a robot with
    /// finer encoders), not an encoder fault, and progress at the factory 3.
    #[test]
    fn the_progress_asked_is_the_one_passed() {
        let judge = |t: Tuned| {
            let mut w = wheel(true);
            let mut last = 0i16;
            let mut checks = std::vec::Vec::new();
            for i in 1..=TICKS as i16 {
                let c = i / 5 * 3;
                checks.push(judge_progress(&mut w, c, c.wrapping_sub(last).unsigned_abs(), 1, TICKS, t));
                last = c;
            }
            checks
        };
        let asked = |progress| Tuned { progress, wrong_way: WRONG_WAY_COUNTS };
        assert_eq!(judge(asked(8))[TICKS as usize - 1], Check::Stall);
        assert!(judge(asked(STALL_PROGRESS_COUNTS)).iter().all(|&c| c == Check::Ok));
    }

    #[test]
    fn missed_periods_count_towards_the_stall_time() {
        let mut w = wheel(true);
        assert_eq!(judge_progress(&mut w, 0, 0, TICKS - 1, TICKS, Factory), Check::Ok);
        assert_eq!(judge_progress(&mut w, 0, 0, 1, TICKS, Factory), Check::Stall);
    }

    #[test]
    fn each_check_has_its_fault() {
        let f = |c| fault_of(c, Fault::StallLeft, Fault::WrongWayLeft);
        assert_eq!(f(Check::Ok), Fault::None);
        assert_eq!(f(Check::Stall), Fault::StallLeft);
        assert_eq!(f(Check::EncoderInconsistent), Fault::EncoderInconsistent);
        assert_eq!(f(Check::WrongWay), Fault::WrongWayLeft);
    }
}
