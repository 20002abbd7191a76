//! Issue 40: questions past double-double resolution, proven by the exact
//! stage from the decimals as written (no longer taken as zero).

use caymos::analysis::Warning;
use caymos::cayley_vector::Mirrors;

use crate::helpers::*;

/// A dyad C on the base A–B with sides 3 and 3 + ε: its Cayley space is
/// [ε, 6 + ε], closed at ε where C folds. At ε = 1e-35 (below
/// double-double's 2^-106 of 3) the sides were taken as equal, so the
/// folded end was lost (an open end at 0, a degenerate place); as written
/// they differ, and the end is there. At ε = 0 the sides are proven equal.
#[test]
fn sides_unequal_below_double_double_keep_their_folded_end() {
    for (digit, closed) in [("1", true), ("0", false)] {
        let text = format!(
            "bars = [[\"A\", \"C\", 3], [\"B\", \"C\", 3.{digit:0>35}]]\nbase = [\"A\", \"B\"]\n[joints]\nA = [0, 0]\nB = [4, 0]\nC = [2, 2.2360679775]\n"
        );
        let (_, s) = solve_text(&text, "dyad");
        assert_eq!(s.space.intervals.len(), 2, "ε digit {digit}");
        for iv in &s.space.intervals {
            assert_eq!(!iv.lower.events.is_empty(), closed, "ε digit {digit}: {:?}", iv.lower);
        }
        assert!(s.certifier.exact_decisions() > 0, "ε digit {digit}: decided exactly");
    }
}

/// A body of three joints on one line as written in decimals that no
/// binary float holds exactly ((0, 0), (0.1, 0.3), (0.2, 0.6)): proven flat,
/// so mirror images exist (before: "at resolution"); 1e-40 off the line,
/// proven bent.
#[test]
fn a_body_on_a_line_as_written_is_proven_flat() {
    for (y, mirrors) in [("0.6", Mirrors::Yes), ("0.6000000000000000000000000000000000000001", Mirrors::No)] {
        let text = format!(
            "bars = [[\"B\", \"Q\", 2], [\"P\", \"Q\", 2], [\"A\", \"B\", 3]]\nbodies = [[\"A\", \"M\", \"P\"]]\nbase = [\"P\", \"B\"]\n[joints]\nA = [0, 0]\nM = [0.1, 0.3]\nP = [0.2, {y}]\nB = [3, 0]\nQ = [1.5, 1.5]\n"
        );
        let (a, s) = solve_text(&text, "body");
        assert_eq!(s.mirrors, mirrors, "P.y = {y}");
        assert!(!a.warnings.iter().any(|w| matches!(w, Warning::EstimatedDecisions { .. })));
    }
}
