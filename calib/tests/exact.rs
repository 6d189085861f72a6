//! The exact solver's edges: end points its model cannot reach give no line solution and,
//! for the squares and triangles, a fit that says how much it leaves unexplained (not a
//! silent wrong one), and nearly straight legs lose nothing to the small-angle branch.

use calib::exact::{
    line_beta, polygon_end, residual_warning, triangle_delta, umbmark_alpha_beta,
    RESIDUAL_WARNING_CM,
};
use calib::{Direction, Endpoint, Solution};

const L: f64 = 200.0;

/// A line can end at most l·(1 − cos β)/β to the side for the largest bend the solver
/// accepts (1.2 rad: 106 cm of a 200 cm line); 60 % of the length to the side is out of
/// reach, on either side. Squares and triangles that end metres away are fitted as well as
/// the model can, and the fit says it leaves metres unexplained.
#[test]
fn unreachable_end_points_are_said_to_be() {
    for y in [0.6 * L, -0.6 * L, 2.0 * L] {
        assert_eq!(line_beta(y, L), None, "y = {y}");
    }
    let far = Endpoint::new(-3.0 * L, 0.0);
    let fit = umbmark_alpha_beta(far, far, L).expect("a best fit");
    assert!(fit.rms_cm > 100.0, "{fit:?}");
    assert!(residual_warning(fit.rms_cm).is_some());
    for dir in [Direction::Cw, Direction::Ccw] {
        let fit = triangle_delta(3.0 * L, Some(0.0), L, 0.0, dir).expect("a best fit");
        assert!(fit.rms_cm > 100.0, "{dir:?}: {fit:?}");
    }
    assert!(residual_warning(RESIDUAL_WARNING_CM).is_none());
}

/// Just inside the limit the same solvers do find the model's parameters.
#[test]
fn large_but_reachable_errors_are_solved() {
    for b in [0.55, 1.15, -1.15] {
        let end = polygon_end(0.0, b, L, 0.0, Direction::Ccw, 1);
        let eb = line_beta(end.y_cm, L).expect("converges");
        assert!((eb - b).abs() < 1e-9, "{eb}");
    }
}

/// A leg bending by less than 2·10⁻⁸ rad is as long as its arc to the last bit (the exact
/// chord differs from it by less than an ulp), and it leaves at half its bend.
#[test]
fn nearly_straight_legs_keep_their_length() {
    for b in [0.0, 1e-12, 1.8e-8, -1.8e-8] {
        let end = polygon_end(0.0, b, L, 0.0, Direction::Ccw, 1);
        assert_eq!(end.x_cm, L * (b / 2.0).cos(), "beta {b}");
        assert_eq!(end.y_cm, L * (b / 2.0).sin(), "beta {b}");
    }
}

/// One leg bending uniformly by β is a circular arc of length l: it ends at
/// (l·sin β/β, l·(1 − cos β)/β), heading β; the next leg starts after the turn.
#[test]
fn a_leg_is_an_arc_of_its_length() {
    for b in [0.5f64, -0.3, 0.05] {
        let end = polygon_end(0.0, b, L, 0.0, Direction::Ccw, 1);
        assert!((end.x_cm - L * b.sin() / b).abs() < 1e-9, "{b}: {end:?}");
        assert!(
            (end.y_cm - L * (1.0 - b.cos()) / b).abs() < 1e-9,
            "{b}: {end:?}"
        );
    }
}

/// Without errors the legs close the polygon; two legs of a square end one side along and one
/// to the left (CCW) or right (CW); an under-rotating turn (positive error) turns less.
#[test]
fn error_free_paths_are_the_nominal_polygons() {
    let q = std::f64::consts::FRAC_PI_2;
    let t = 2.0 * std::f64::consts::FRAC_PI_3;
    for dir in [Direction::Cw, Direction::Ccw] {
        let square = polygon_end(0.0, 0.0, L, q, dir, 4);
        let triangle = polygon_end(0.0, 0.0, L, t, dir, 3);
        assert!(square.x_cm.hypot(square.y_cm) < 1e-9, "{dir:?} {square:?}");
        assert!(
            triangle.x_cm.hypot(triangle.y_cm) < 1e-9,
            "{dir:?} {triangle:?}"
        );
    }
    let ccw = polygon_end(0.0, 0.0, L, q, Direction::Ccw, 2);
    let cw = polygon_end(0.0, 0.0, L, q, Direction::Cw, 2);
    assert!(
        (ccw.x_cm - L).abs() < 1e-9 && (ccw.y_cm - L).abs() < 1e-9,
        "{ccw:?}"
    );
    assert!(
        (cw.x_cm - L).abs() < 1e-9 && (cw.y_cm + L).abs() < 1e-9,
        "{cw:?}"
    );
    // A 10° under-rotation: the second leg leaves at 80°.
    let e = 10f64.to_radians();
    let short = polygon_end(e, 0.0, L, q, Direction::Ccw, 2);
    let want = (L + L * (q - e).cos(), L * (q - e).sin());
    assert!((short.x_cm - want.0).abs() < 1e-9 && (short.y_cm - want.1).abs() < 1e-9);
}

/// The solution names reports print are the ones option files use.
#[test]
fn solution_names() {
    for (s, name) in [
        (Solution::FirstOrder, "first-order"),
        (Solution::Exact, "exact"),
    ] {
        assert_eq!(s.as_str(), name);
        assert_eq!(serde_json::to_string(&s).unwrap(), format!("\"{name}\""));
    }
}

/// Measured end points exactly on the axis (a rounded centroid often is) are solved like any
/// other: a straight line, a square pair with no error, a triangle whose x error vanishes.
#[test]
fn end_points_exactly_on_the_axis_are_solved() {
    let b = line_beta(0.0, L).expect("converges");
    assert!(b.abs() < 1e-12, "{b}");
    let origin = Endpoint::new(0.0, 0.0);
    let [a, b] = umbmark_alpha_beta(origin, origin, L)
        .expect("converges")
        .params;
    assert!(a.abs() < 1e-12 && b.abs() < 1e-12, "{a} {b}");
    let t = 2.0 * std::f64::consts::FRAC_PI_3;
    for dir in [Direction::Cw, Direction::Ccw] {
        let [d] = triangle_delta(0.0, None, L, 0.05, dir)
            .expect("converges")
            .params;
        let end = polygon_end(d, 0.05, L, t, dir, 3);
        assert!(end.x_cm.abs() < 1e-9, "{dir:?}: {d} gives {end:?}");
    }
}

/// The model's leg is an arc of the length driven, so its curvature is the bend over that
/// length: a quarter circle of radius 100 cm (β = π/2 over 50π cm) has 1/100 per cm, a bend
/// the other way the opposite sign. Borenstein's reads the length as the chord,
/// 2 sin(β/2)/L: the same to first order, 10 % more here.
#[test]
fn the_curvature_of_a_leg_is_its_bend_over_its_length() {
    let (b, l) = (std::f64::consts::FRAC_PI_2, 50.0 * std::f64::consts::PI);
    assert!((Solution::Exact.curvature(b, l) - 0.01).abs() < 1e-15);
    assert!((Solution::Exact.curvature(-b, l) + 0.01).abs() < 1e-15);
    let chord = 2.0 * (b / 2.0).sin() / l;
    assert!((Solution::FirstOrder.curvature(b, l) - chord).abs() < 1e-15);
}

/// Turns that miss by more than the solvers accept (0.6 rad) are fitted at the edge of that
/// range, never past it, and the fit says what it leaves unexplained.
#[test]
fn fits_stay_within_the_range_the_solvers_accept() {
    let t = 2.0 * std::f64::consts::FRAC_PI_3;
    let q = std::f64::consts::FRAC_PI_2;
    for d in [0.64, -0.64] {
        for dir in [Direction::Cw, Direction::Ccw] {
            let end = polygon_end(d, 0.0, L, t, dir, 3);
            let fit = triangle_delta(end.x_cm, Some(end.y_cm), L, 0.0, dir).expect("a best fit");
            assert!(fit.params[0].abs() <= 0.6, "{d} {dir:?}: {fit:?}");
            assert!(fit.rms_cm > 1.0, "{d} {dir:?}: {fit:?}");
        }
        let cw = polygon_end(d, 0.0, L, q, Direction::Cw, 4);
        let ccw = polygon_end(d, 0.0, L, q, Direction::Ccw, 4);
        let fit = umbmark_alpha_beta(cw, ccw, L).expect("a best fit");
        assert!(fit.params[0].abs() <= 0.6, "{d}: {fit:?}");
        assert!(fit.rms_cm > 1.0, "{d}: {fit:?}");
    }
}

/// A triangle's rms is over the components measured: x alone when y was not recorded, x
/// and y otherwise (an end point no turn error reaches, so neither is zero).
#[test]
fn a_triangle_fit_reports_the_rms_of_the_components_measured() {
    let t = 2.0 * std::f64::consts::FRAC_PI_3;
    let (x, y, beta) = (3.0 * L, 10.0, 0.05);
    for dir in [Direction::Cw, Direction::Ccw] {
        let fit = triangle_delta(x, None, L, beta, dir).expect("a best fit");
        let p = polygon_end(fit.params[0], beta, L, t, dir, 3);
        assert!(
            (fit.rms_cm - (p.x_cm - x).abs()).abs() < 1e-9,
            "{dir:?}: {fit:?}"
        );
        let fit = triangle_delta(x, Some(y), L, beta, dir).expect("a best fit");
        let p = polygon_end(fit.params[0], beta, L, t, dir, 3);
        let want = (((p.x_cm - x).powi(2) + (p.y_cm - y).powi(2)) / 2.0).sqrt();
        assert!(
            (fit.rms_cm - want).abs() < 1e-9,
            "{dir:?}: {fit:?} vs {want}"
        );
    }
}

/// UMBmark end points whose turn error lies past the range (0.7 rad), with offsets the model
/// cannot explain: the fit sits on the edge α = 0.6 and, along that edge, at the least
/// squares minimum in β (no neighbour 10⁻⁶..10⁻² rad away fits better), wherever the
/// first-order start and the grid put it.
#[test]
fn a_fit_on_the_edge_of_the_range_is_the_minimum_along_it() {
    let q = std::f64::consts::FRAC_PI_2;
    let rms = |a: f64, b: f64, cw: Endpoint, ccw: Endpoint| {
        let (pcw, pccw) = (
            polygon_end(a, b, L, q, Direction::Cw, 4),
            polygon_end(a, b, L, q, Direction::Ccw, 4),
        );
        let r = [
            pcw.x_cm - cw.x_cm,
            pcw.y_cm - cw.y_cm,
            pccw.x_cm - ccw.x_cm,
            pccw.y_cm - ccw.y_cm,
        ];
        (r.iter().map(|v| v * v).sum::<f64>() / 4.0).sqrt()
    };
    for (a, b, dx, dy) in [
        (0.7, 0.1, 12.0, -20.0),
        (-0.7, -0.05, -30.0, 8.0),
        (0.75, 0.013, 5.0, 40.0),
    ] {
        let mut cw = polygon_end(a, b, L, q, Direction::Cw, 4);
        let ccw = polygon_end(a, b, L, q, Direction::Ccw, 4);
        cw.x_cm += dx;
        cw.y_cm += dy;
        let fit = umbmark_alpha_beta(cw, ccw, L).expect("a best fit");
        let [fa, fb] = fit.params;
        assert_eq!(fa.abs(), 0.6, "{a} {b}: {fit:?}");
        assert!((fit.rms_cm - rms(fa, fb, cw, ccw)).abs() < 1e-9, "{fit:?}");
        for d in [1e-6, 1e-5, 1e-4, 1e-3, 1e-2] {
            for nb in [fb - d, fb + d] {
                let near = rms(fa, nb, cw, ccw);
                assert!(
                    near >= fit.rms_cm - 1e-9,
                    "{a} {b}: β {nb} fits better ({near} cm) than the fit's {fb} ({} cm)",
                    fit.rms_cm
                );
            }
        }
    }
}

/// Long legs (4.9 m) and a turn error past the range with offsets of decimetres: the grid's
/// best point (0.02 rad apart, 10 cm of a leg's end in β) lies in the basin of the edge
/// α = −0.6, whose minimum leaves 48.29 cm rms; the first-order start lies in the basin of
/// a better one, near (0.0884, −0.0110) with 47.08 cm. The fit is the better of the two.
#[test]
fn a_narrow_basin_the_grid_misses_is_found_from_the_first_order_start() {
    let cw = Endpoint {
        x_cm: -41.589083642838176,
        y_cm: -105.89888833097663,
    };
    let ccw = Endpoint {
        x_cm: -6.499933719274331,
        y_cm: 156.05568994150627,
    };
    let fit = umbmark_alpha_beta(cw, ccw, 488.69278805892395).expect("a best fit");
    let [a, b] = fit.params;
    assert!(
        (fit.rms_cm - 47.0829).abs() < 1e-3
            && (a - 0.08838).abs() < 1e-4
            && (b + 0.01095).abs() < 1e-4,
        "{fit:?}"
    );
}

/// More end points whose best minimum lies in a basin narrower than the grid's step, with
/// what the fit leaves there and, from a start anywhere else, in the next basin (cm rms):
/// decimetres to metres off the model, as a robot with an error the model lacks gives.
#[test]
fn the_first_order_start_finds_the_basins_the_grid_misses() {
    for (cw, ccw, l, best, next) in [
        (
            (-141.65808687070017, -383.7206833908974),
            (-22.872070297517595, 233.30748686409385),
            547.6685615522227,
            58.6390,
            59.9774,
        ),
        (
            (50.39377118043032, -124.38975435384202),
            (129.49465011981394, 209.06104382830063),
            205.0235184731403,
            44.0720,
            44.1995,
        ),
        (
            (105.725454588626, -239.35980526909518),
            (163.0548318610445, -30.239757450393064),
            220.52824432920946,
            56.8549,
            56.8853,
        ),
    ] {
        let fit = umbmark_alpha_beta(Endpoint::new(cw.0, cw.1), Endpoint::new(ccw.0, ccw.1), l)
            .expect("a best fit");
        assert!(
            (fit.rms_cm - best).abs() < 1e-4,
            "L {l}: {fit:?}, not the basin of {best} cm (the next one leaves {next} cm)"
        );
    }
}

/// End points whose first-order turn error (−0.69 rad) lies past the range, where a point
/// outside it fits better (31.84 cm rms) than any inside: the fit stays in the range, on
/// its edge α = −0.6 (32.19 cm), and the first-order solution is no start.
#[test]
fn a_first_order_solution_past_the_range_is_no_start() {
    let (cw, ccw) = (
        Endpoint::new(287.21149923718247, -67.0613303799025),
        Endpoint::new(278.42596945603805, 36.502706351402225),
    );
    let fit = umbmark_alpha_beta(cw, ccw, 233.71878750777637).expect("a best fit");
    assert_eq!(fit.params[0], -0.6, "{fit:?}");
    assert!((fit.rms_cm - 32.1908).abs() < 1e-4, "{fit:?}");
}
