//! The session's checks, evaluation, import and file round trip.

use calib::{
    triangle_correction, umbmark_correction, LineRuns, TriangleParams, TriangleResult,
    TriangleRuns, UmbmarkParams, UmbmarkRuns,
};

use super::*;

const NOMINAL: Params = Params {
    c_left: 1.0,
    c_right: 1.0,
    wheelbase_mm: 130.0,
};

fn filled() -> Session {
    let mut s = Session::new("test", NOMINAL);
    for (i, p) in s.rounds[0].cw.iter_mut().enumerate() {
        p.x = format!("{}", -10.0 - i as f64);
        p.y = format!("{}", -8.0 + 0.5 * i as f64);
    }
    for (i, p) in s.rounds[0].ccw.iter_mut().enumerate() {
        p.x = format!("{}", 4.0 + i as f64);
        p.y = format!("{}", -3.0 - 0.25 * i as f64);
    }
    s
}

#[test]
fn a_complete_round_gives_the_libraries_correction() {
    let s = filled();
    let ev = evaluate(&s);
    assert!(ev.errors.is_empty(), "{:?}", ev.errors);
    let got = ev.rounds[0].result.as_ref().unwrap();
    let cw = (0..5)
        .map(|i| Endpoint::new(-10.0 - i as f64, -8.0 + 0.5 * i as f64))
        .collect();
    let ccw = (0..5)
        .map(|i| Endpoint::new(4.0 + i as f64, -3.0 - 0.25 * i as f64))
        .collect();
    let want = umbmark_correction(
        &UmbmarkRuns::new(cw, ccw).unwrap(),
        &UmbmarkParams {
            side_cm: 200.0,
            wheelbase_mm: 130.0,
            ..Default::default()
        },
    );
    assert_eq!(got, &want);
    let send = ev.rounds[0].send.unwrap();
    assert_eq!(send.c_left, want.cl);
    assert_eq!(send.wheelbase_mm, want.wheelbase_mm);
}

#[test]
fn each_bad_field_is_named() {
    let mut s = filled();
    s.rounds[0].cw[2].x = "abc".into();
    s.rounds[0].ccw[4].y = "".into();
    s.rounds[0].line_commanded_cm = "200".into();
    s.side_cm = "-3".into();
    let ev = evaluate(&s);
    assert!(ev.errors["r0-cw-3-x"].contains("not a number"));
    assert!(ev.errors["r0-ccw-5-y"].contains("missing"));
    assert!(ev.errors["r0-line_measured_cm"].contains("give this too"));
    assert!(ev.errors["side_cm"].contains("above 0"));
    assert!(ev.rounds[0].result.is_none());
}

#[test]
fn es_scales_both_factors_and_the_rounds_compose() {
    let mut s = filled();
    s.rounds[0].line_commanded_cm = "200".into();
    s.rounds[0].line_measured_cm = "196".into();
    let ev = evaluate(&s);
    let r = ev.rounds[0].result.as_ref().unwrap();
    let send = ev.rounds[0].send.unwrap();
    assert_eq!(r.es, Some(200.0 / 196.0));
    assert_eq!(send.c_left, r.cl / (200.0 / 196.0));
    // A second round run with the sent parameters composes with them.
    let applied = Params {
        c_left: send.c_left,
        c_right: send.c_right,
        wheelbase_mm: send.wheelbase_mm,
    };
    let mut next = filled().rounds.remove(0);
    next.params = applied;
    s.rounds.push(next);
    let ev = evaluate(&s);
    let r1 = ev.rounds[1].result.as_ref().unwrap();
    assert_eq!(ev.rounds[1].send.unwrap().c_left, applied.c_left * r1.cl);
    assert_eq!(ev.table.len(), 1);
    assert_eq!(ev.table[0].row, calib::improvement(r, r1));
}

#[test]
fn csv_import_fills_the_round() {
    let mut s = Session::new("t", NOMINAL);
    let rows = |exp: u32| {
        (1..=5)
            .flat_map(|i| {
                [
                    format!("{exp},cw,{i},-1.5,{i}\n"),
                    format!("{exp},ccw,{i},3,4.25\n"),
                ]
            })
            .collect::<String>()
    };
    let text = format!("experiment,direction,run,x_cm,y_cm\n{}", rows(1));
    import_csv(&mut s, 0, &text, None).unwrap();
    assert_eq!(
        s.rounds[0].cw[1],
        PointText {
            x: "-1.5".into(),
            y: "2".into()
        }
    );
    assert_eq!(s.rounds[0].ccw.len(), 5);
    assert!(evaluate(&s).rounds[0].result.is_some());
    let two = format!("{text}{}", rows(2));
    let e = import_csv(&mut s, 0, &two, None).unwrap_err();
    assert!(e.to_string().contains("1, 2"), "{e}");
}

#[test]
fn saved_sessions_load_back() {
    let dir = std::env::temp_dir().join(format!("station-session-{}", std::process::id()));
    let path = dir.join(file_name("emulated henrytwo/ideal"));
    assert!(path.ends_with("emulated-henrytwo-ideal.json"));
    let s = filled();
    save(&path, &s).unwrap();
    assert_eq!(load(&path).unwrap(), Some(s));
    let _ = std::fs::remove_dir_all(&dir);
}

const LINE: [(f64, f64); 5] = [(5.8, 1.0), (7.1, 1.9), (3.6, 1.8), (2.5, 1.5), (4.4, 1.8)];
const TRIANGLE: [(f64, f64); 5] = [
    (3.3, 1.9),
    (-6.9, 13.2),
    (-8.8, 19.0),
    (-9.1, 22.0),
    (-6.5, 4.7),
];

fn triangle_session(solution: Solution) -> Session {
    let mut s = Session::new("t", NOMINAL);
    s.solution = solution;
    let r = &mut s.rounds[0];
    r.method = Method::Triangle;
    for (rows, points) in [(&mut r.line, LINE), (&mut r.triangle, TRIANGLE)] {
        for (row, (x, y)) in rows.iter_mut().zip(points) {
            row.x = x.to_string();
            row.y = y.to_string();
        }
    }
    s
}

fn library_triangle(solution: Solution) -> TriangleResult {
    let line = LineRuns::new(LINE.iter().map(|&(x, y)| Endpoint::new(x, y)).collect());
    let tri = TriangleRuns::complete(TRIANGLE.iter().map(|&(x, y)| Endpoint::new(x, y)).collect());
    triangle_correction(
        &line.unwrap(),
        &tri.unwrap(),
        &TriangleParams {
            side_cm: 200.0,
            wheelbase_mm: 130.0,
            line_correction_applied: false,
            solution,
            ..Default::default()
        },
    )
}

#[test]
fn ten_triangle_points_give_the_libraries_correction() {
    for solution in [Solution::FirstOrder, Solution::Exact] {
        let ev = evaluate(&triangle_session(solution));
        assert!(ev.errors.is_empty(), "{:?}", ev.errors);
        let round = &ev.rounds[0];
        assert!(round.result.is_none());
        assert_eq!((round.complete_line, round.complete_triangle), (5, 5));
        let got = round.triangle.as_ref().unwrap();
        let want = library_triangle(solution);
        assert_eq!(got, &want);
        assert_eq!(got.solution, solution);
        let send = round.send.unwrap();
        assert_eq!(send.c_left, want.cl);
        assert_eq!(send.c_right, want.cr);
        assert_eq!(send.wheelbase_mm, want.wheelbase_mm);
    }
    assert_ne!(
        library_triangle(Solution::Exact).eb,
        library_triangle(Solution::FirstOrder).eb
    );
}

#[test]
fn triangle_fields_are_checked_and_the_y_column_may_be_unmeasured() {
    let mut s = triangle_session(Solution::FirstOrder);
    s.rounds[0].line[1].x = "7,1".into();
    s.rounds[0].triangle[3].y = "".into();
    s.rounds[0].line[4].y = "x".into();
    let ev = evaluate(&s);
    assert!(ev.errors["r0-triangle-4-y"].contains("missing"));
    assert!(ev.errors["r0-line-5-y"].contains("not a number"));
    assert!(!ev.errors.contains_key("r0-line-2-x"));
    assert!(ev.rounds[0].triangle.is_none());
    // No triangle y at all: x alone, as the library allows.
    let mut s = triangle_session(Solution::FirstOrder);
    for p in &mut s.rounds[0].triangle {
        p.y.clear();
    }
    let ev = evaluate(&s);
    assert!(ev.errors.is_empty(), "{:?}", ev.errors);
    let r = ev.rounds[0].triangle.as_ref().unwrap();
    assert_eq!(r.triangle_centroid.y_cm, None);
    assert!(ev.rounds[0].send.is_some());
}

#[test]
fn triangle_csv_import_fills_the_round() {
    let mut s = Session::new("t", NOMINAL);
    s.rounds[0].method = Method::Triangle;
    let mut text = String::from("experiment,test,run,x_cm,y_cm\n");
    for (test, points) in [("line", LINE), ("triangle", TRIANGLE)] {
        for (i, (x, y)) in points.iter().enumerate() {
            text += &format!("1,{test},{},{x},{y}\n", i + 1);
            // Experiment 2 as the thesis' table has it: no triangle y.
            let y = if test == "line" {
                y.to_string()
            } else {
                String::new()
            };
            text += &format!("2,{test},{},{x},{y}\n", i + 1);
        }
    }
    let e = import_csv(&mut s, 0, &text, None).unwrap_err();
    assert!(
        e.to_string().contains("Triangular Path experiments 1, 2"),
        "{e}"
    );
    import_csv(&mut s, 0, &text, Some(1)).unwrap();
    assert_eq!(
        evaluate(&s).rounds[0].triangle,
        Some(library_triangle(Solution::FirstOrder))
    );
    import_csv(&mut s, 0, &text, Some(2)).unwrap();
    assert_eq!(s.rounds[0].triangle[2].y, "");
    let ev = evaluate(&s);
    assert!(ev.errors.is_empty(), "{:?}", ev.errors);
    assert!(ev.rounds[0].triangle.is_some());
    // The UMBmark rows were left alone.
    assert!(s.rounds[0].cw.iter().all(|p| p.x.is_empty()));
}

#[test]
fn a_session_from_before_the_triangle_loads_as_umbmark() {
    let mut old = serde_json::to_value(filled()).unwrap();
    old.as_object_mut().unwrap().remove("solution");
    for key in ["method", "line", "triangle"] {
        old["rounds"][0].as_object_mut().unwrap().remove(key);
    }
    let s: Session = serde_json::from_value(old).unwrap();
    assert_eq!(s.rounds[0].method, Method::Umbmark);
    assert_eq!(s.solution, Solution::FirstOrder);
    assert_eq!(s.rounds[0].triangle.len(), RUNS_PER_DIRECTION);
    assert_eq!(s, filled());
}

/// The leg the station's tests ran with is the side of the formulas: a
/// round recorded at 300 mm computes with L = 30 cm (the default 200 cm gave
/// a correction 6.7 times too small), refuses a side typed otherwise, keeps
/// the leg in the file, and refuses a test with another leg once it has
/// points; a line in a UMBmark round (for Es) records nothing.
#[test]
fn the_tests_leg_is_the_side_and_a_different_side_is_refused() {
    use crate::runs::experiment::Test;
    let mut s = filled();
    assert!(!record_leg(&mut s, Test::Line, 1000.0).unwrap());
    assert_eq!(s.rounds[0].leg_mm, None);
    // Points typed, no leg recorded yet: the first test records it.
    assert!(record_leg(&mut s, Test::UmbmarkCw, 300.0).unwrap());
    assert_eq!(s.rounds[0].leg_mm, Some(300.0));
    assert_eq!(s.side_cm, "30");
    assert!(!record_leg(&mut s, Test::UmbmarkCcw, 300.0).unwrap());
    let err = record_leg(&mut s, Test::UmbmarkCcw, 2000.0).unwrap_err();
    assert!(err.to_string().contains("300 mm legs"), "{err}");
    assert_eq!(s.rounds[0].leg_mm, Some(300.0));

    let ev = evaluate(&s);
    assert!(ev.errors.is_empty(), "{:?}", ev.errors);
    let got = ev.rounds[0].result.as_ref().unwrap();
    let mut at_200 = s.clone();
    at_200.rounds[0].leg_mm = None;
    at_200.side_cm = "200".into();
    let wrong = evaluate(&at_200).rounds[0].result.clone().unwrap();
    let want = umbmark_correction(
        &UmbmarkRuns::new(
            s.rounds[0]
                .cw
                .iter()
                .map(|p| Endpoint::new(p.x.parse().unwrap(), p.y.parse().unwrap()))
                .collect(),
            s.rounds[0]
                .ccw
                .iter()
                .map(|p| Endpoint::new(p.x.parse().unwrap(), p.y.parse().unwrap()))
                .collect(),
        )
        .unwrap(),
        &UmbmarkParams {
            side_cm: 30.0,
            wheelbase_mm: 130.0,
            ..Default::default()
        },
    );
    assert_eq!(got, &want);
    assert_ne!(got.wheelbase_mm, wrong.wheelbase_mm);

    // The side typed back to 200 cm: no correction to send, the side named.
    s.side_cm = "200".into();
    let ev = evaluate(&s);
    assert!(
        ev.errors["side_cm"].contains("300 mm legs"),
        "{:?}",
        ev.errors
    );
    assert!(ev.rounds[0].result.is_none() && ev.rounds[0].send.is_none());

    // The file keeps the leg; a round with no points takes a new leg.
    let text = serde_json::to_string(&s).unwrap();
    let back: Session = serde_json::from_str(&text).unwrap();
    assert_eq!(back.rounds[0].leg_mm, Some(300.0));
    let mut fresh = Session::new("t", NOMINAL);
    assert!(record_leg(&mut fresh, Test::UmbmarkCw, 300.0).unwrap());
    assert!(record_leg(&mut fresh, Test::UmbmarkCw, 500.0).unwrap());
    assert_eq!(
        (fresh.rounds[0].leg_mm, fresh.side_cm.as_str()),
        (Some(500.0), "50")
    );
}
