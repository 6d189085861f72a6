//! Each test's selector byte, name and shape (legs, turns, turn angle, ideal end), as the
//! protocol's README and the thesis define them, and the names parsed back.

use henrytwo_protocol::test_kind::{Test, UnknownTest};

#[test]
fn each_test_its_byte_name_and_shape() {
    let table = [
        (Test::UmbmarkCw, 2, "umbmark-cw", 4, 4, -90.0),
        (Test::UmbmarkCcw, 3, "umbmark-ccw", 4, 4, 90.0),
        (Test::Line, 4, "line", 1, 0, 0.0),
        (Test::Triangle, 5, "triangle", 3, 3, 120.0),
    ];
    for (t, byte, name, legs, turns, deg) in table {
        assert_eq!(t.command_byte(), byte, "{t:?}");
        assert_eq!(t.name(), name, "{t:?}");
        assert_eq!(
            (t.legs(), t.turns(), t.turn_deg()),
            (legs, turns, deg),
            "{t:?}"
        );
        assert_eq!(t.shape(), (legs, turns, deg), "{t:?}");
        assert_eq!(Test::from_name(name), Some(t));
        assert_eq!(name.parse::<Test>(), Ok(t));
    }
}

/// Polygons close; the line ends one leg ahead.
#[test]
fn ideal_end_points() {
    for t in [Test::UmbmarkCw, Test::UmbmarkCcw, Test::Triangle] {
        assert_eq!(t.ideal_end(2.5), (0.0, 0.0), "{t:?}");
    }
    assert_eq!(Test::Line.ideal_end(2.5), (2.5, 0.0));
}

/// Any other name is refused with the list of the right ones.
#[test]
fn unknown_names_are_refused_with_the_known_ones() {
    for name in ["", "square", "Line", "umbmark_cw"] {
        assert_eq!(Test::from_name(name), None, "{name}");
        assert_eq!(name.parse::<Test>(), Err(UnknownTest), "{name}");
    }
    assert_eq!(
        UnknownTest.to_string(),
        "unknown test: use umbmark-cw, umbmark-ccw, line or triangle"
    );
}
