//! Bounded records: what the bench keeps of a run grows with robot time
//! (a trace sample every 10 ms, a drive event at each PWM change, each byte
//! the firmware sends), so each record has a cap, and a bench that runs
//! for days (`hil serve`, the station's emulated robots) keeps only the
//! latest of each.
//!
//! - [`Log`]: every item up to its cap, then only a count of those dropped
//!   (the first part of a run is the one its analysis reads: legs, turns,
//!   the fault's reaction); a notice says so.
//! - [`Thinned`]: the trace, which covers the whole run at any length: when
//!   full, every other sample is dropped and the interval doubled.
//!
//! The caps are far above what a test run of the bench reaches (a 5 m
//! UMBmark leg, the longest, takes under 8 minutes of robot time) and
//! bound the longest (an hour, a test description's `end.limit_s`) to tens
//! of megabytes.

/// What a record keeps.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Retention {
    /// Every item up to the record's cap (a test run).
    Run,
    /// The latest item only (a bench that runs for days, whose records no
    /// one reads).
    Latest,
}

/// A record of items in order, up to a cap (see the module docs).
#[derive(Debug, Clone)]
pub(super) struct Log<T> {
    items: Vec<T>,
    cap: usize,
    retention: Retention,
    /// Items pushed, kept or not.
    pushed: u64,
    /// Items not kept because the log was full.
    dropped: u64,
}

impl<T> Log<T> {
    pub(super) fn new(cap: usize) -> Self {
        Self {
            items: Vec::new(),
            cap,
            retention: Retention::Run,
            pushed: 0,
            dropped: 0,
        }
    }

    pub(super) fn push(&mut self, item: T) {
        self.pushed += 1;
        match self.retention {
            Retention::Run if self.items.len() >= self.cap => self.dropped += 1,
            Retention::Run => self.items.push(item),
            Retention::Latest => {
                self.items.clear();
                self.items.push(item);
            }
        }
    }

    /// Keep only the latest item from now on (and of those kept so far).
    pub(super) fn keep_latest(&mut self) {
        self.retention = Retention::Latest;
        let n = self.items.len();
        self.items.drain(..n.saturating_sub(1));
        self.items.shrink_to_fit();
    }

    pub(super) fn as_slice(&self) -> &[T] {
        &self.items
    }

    pub(super) fn as_mut_slice(&mut self) -> &mut [T] {
        &mut self.items
    }

    pub(super) fn last(&self) -> Option<&T> {
        self.items.last()
    }

    /// Items pushed since the start, kept or not.
    pub(super) fn pushed(&self) -> u64 {
        self.pushed
    }

    /// Take what was kept, leaving the log empty (its counts stay).
    pub(super) fn take(&mut self) -> Vec<T> {
        std::mem::take(&mut self.items)
    }

    /// "the drive log kept its first N events and dropped M later ones",
    /// when it did (in [`Retention::Run`]).
    pub(super) fn notice(&self, what: &str) -> Option<String> {
        (self.dropped > 0).then(|| {
            format!(
                "the {what} reached its cap: it kept the first {} and dropped {} later ones",
                self.cap, self.dropped
            )
        })
    }
}

/// The trace: samples over the whole run, thinned when full (see the
/// module docs).
#[derive(Debug, Clone)]
pub(super) struct Thinned<T> {
    items: Vec<T>,
    cap: usize,
    retention: Retention,
    /// One sample kept of every `every` offered.
    every: u64,
    offered: u64,
}

impl<T> Thinned<T> {
    /// `cap` is rounded up to an even number (thinning halves it).
    pub(super) fn new(cap: usize) -> Self {
        Self {
            items: Vec::new(),
            cap: cap.max(2).next_multiple_of(2),
            retention: Retention::Run,
            every: 1,
            offered: 0,
        }
    }

    pub(super) fn push(&mut self, item: T) {
        let k = self.offered;
        self.offered += 1;
        if self.retention == Retention::Latest {
            self.items.clear();
            self.items.push(item);
            return;
        }
        if k % self.every != 0 {
            return;
        }
        if self.items.len() == self.cap {
            // Keep the samples at even multiples of the new interval: the
            // kept ones stay evenly spaced from the first.
            let mut i = 0;
            self.items.retain(|_| {
                i += 1;
                i % 2 == 1
            });
            self.every *= 2;
            if k % self.every != 0 {
                return;
            }
        }
        self.items.push(item);
    }

    pub(super) fn keep_latest(&mut self) {
        self.retention = Retention::Latest;
        let n = self.items.len();
        self.items.drain(..n.saturating_sub(1));
        self.items.shrink_to_fit();
    }

    pub(super) fn as_slice(&self) -> &[T] {
        &self.items
    }

    /// One sample kept of every this many taken.
    pub(super) fn every(&self) -> u64 {
        self.every
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_log_keeps_its_first_items_up_to_its_cap_and_says_so() {
        let mut log = Log::new(3);
        for i in 0..3 {
            log.push(i);
        }
        assert_eq!(log.notice("drive log"), None);
        log.push(3);
        log.push(4);
        assert_eq!(log.as_slice(), &[0, 1, 2]);
        assert_eq!(log.pushed(), 5);
        assert_eq!(
            log.notice("drive log").unwrap(),
            "the drive log reached its cap: it kept the first 3 and dropped 2 later ones"
        );
    }

    #[test]
    fn a_log_keeping_the_latest_holds_one_item_however_many_come() {
        let mut log = Log::new(1000);
        log.push(0);
        log.push(1);
        log.keep_latest();
        assert_eq!(log.as_slice(), &[1]);
        for i in 2..10_000 {
            log.push(i);
        }
        assert_eq!(log.as_slice(), &[9_999]);
        assert_eq!(log.pushed(), 10_000);
        assert_eq!(log.notice("x"), None);
    }

    /// The thinned trace stays within its cap and covers the whole run,
    /// evenly spaced from the first sample.
    #[test]
    fn a_full_trace_is_thinned_not_cut() {
        let mut t = Thinned::new(8);
        for i in 0..100u64 {
            t.push(i);
            assert!(t.as_slice().len() <= 8);
        }
        assert_eq!(t.every(), 16);
        assert_eq!(t.as_slice(), &[0, 16, 32, 48, 64, 80, 96]);
        let mut short = Thinned::new(8);
        for i in 0..8u64 {
            short.push(i);
        }
        assert_eq!(
            short.as_slice(),
            &[0, 1, 2, 3, 4, 5, 6, 7],
            "untouched below the cap"
        );
        short.keep_latest();
        short.push(8);
        assert_eq!(short.as_slice(), &[8]);
    }
}
