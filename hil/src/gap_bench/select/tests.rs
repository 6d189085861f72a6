//! The search grid of the bench-backed diagnosis.

use super::grid;
use crate::gap_bench::bench_parameters;

/// Every parameter's grid holds its neutral value once, each point once, in order, none a
/// hair beside another: the middle point of a signed range computed as `-0.2 + 0.4 · 3/6`
/// is 2.8e-17, not 0, and beside the added neutral value it left the search a bracket on
/// the positive side only. With an odd number of points over a range centred on the
/// neutral value, the neutral value has neighbours on both sides.
#[test]
fn each_grid_holds_the_neutral_value_once_with_neighbours_on_both_sides() {
    for s in bench_parameters() {
        for n in [3, 5, 7, 9] {
            let g = grid(&s, n);
            let range = s.upper - s.lower;
            assert_eq!(
                g.iter().filter(|&&v| v == s.neutral).count(),
                1,
                "{} {g:?}",
                s.name
            );
            assert!(
                g.windows(2).all(|w| w[1] - w[0] > 1e-6 * range),
                "{}: {g:?}",
                s.name
            );
            assert!(g.first() == Some(&s.lower) && g.last() == Some(&s.upper));
            if (s.upper - s.neutral - (s.neutral - s.lower)).abs() < 1e-12 {
                let at = g.iter().position(|&v| v == s.neutral).unwrap();
                assert!(at > 0 && at + 1 < g.len(), "{}: {g:?}", s.name);
                assert_eq!(g.len(), n, "{}: {g:?}", s.name);
            }
        }
    }
}
