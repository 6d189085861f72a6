//! Reports: the terminal and Markdown renderers show the three answers, the plot is an SVG,
//! and the diagnosis serialises to JSON with its three sections.

use gap::effects::{COAST, FLOOR_NOISE, WHEEL_DIAMETER_RATIO};
use gap::{
    diagnose, plot_svg, render_markdown, render_text, Dataset, DiagnoseOptions, EffectParams,
    Experiment, Firmware, FitOptions, Group, KinematicModel, Model, ObservedRun, Reference,
    SplitRule, TestKind,
};

fn diagnosis() -> gap::Diagnosis {
    diagnosis_of(&EffectParams::new().with(WHEEL_DIAMETER_RATIO, 1.008))
}

fn diagnosis_of(hidden: &EffectParams) -> gap::Diagnosis {
    let reference = Reference {
        wheelbase_mm: 150.0,
        mm_per_count: 0.2,
    };
    let mut d = Dataset::default();
    for (name, leg) in [("a", 2000.0), ("b", 1500.0)] {
        for test in [TestKind::UmbmarkCw, TestKind::UmbmarkCcw, TestKind::Line] {
            let exp = Experiment {
                test,
                firmware: Firmware::nominal(&reference, leg),
                reference,
                runs: 5,
                seed: 1,
            };
            let runs = KinematicModel
                .predict(hidden, &exp)
                .unwrap()
                .into_iter()
                .map(|r| ObservedRun {
                    x_cm: r.x_cm,
                    y_cm: Some(r.y_cm),
                    theta_rad: None,
                })
                .collect();
            d.push(Group::new(name, exp, runs).unwrap()).unwrap();
        }
    }
    let (t, h) = d.split(&SplitRule::LeaveOut(vec!["b".into()])).unwrap();
    let opts = DiagnoseOptions {
        fit: FitOptions {
            bootstrap: 4,
            ..FitOptions::default()
        },
        candidates: Some(vec![WHEEL_DIAMETER_RATIO.into(), COAST.into()]),
    };
    diagnose(&KinematicModel, &t, &h, &opts).unwrap()
}

/// The text and Markdown reports carry the three answers and the winner.
#[test]
fn renderers() {
    let d = diagnosis();
    let text = render_text(&d);
    for needle in [
        "1. WHERE",
        "2. WHICH EFFECT",
        "3. HOW FAR IT SHRINKS",
        "Winner: wheel_diameter_ratio",
    ] {
        assert!(text.contains(needle), "{needle} missing:\n{text}");
    }
    // Each group's row: the real and the model's centroids and their difference.
    for g in d.where_.train.groups.iter().chain(&d.where_.heldout.groups) {
        let row = text
            .lines()
            .find(|l| l.trim_start().starts_with(&format!("{} [", g.group)))
            .unwrap();
        let y = g.observed.mean_y.unwrap();
        for (x, y) in [
            (g.observed.mean_x, y),
            (g.predicted.mean_x, g.predicted.mean_y),
            (g.residual_x_cm, g.residual_y_cm.unwrap()),
        ] {
            let pair = format!("({x:+.2}, {y:+.2})");
            assert!(row.contains(&pair), "{pair} not in {row}");
        }
    }
    let md = render_markdown(&d, Some("gap.svg"));
    for needle in [
        "## 1. Where",
        "## 2. Which effect",
        "## 3. How far",
        "![held-out",
        "| BIC rank |",
    ] {
        assert!(md.contains(needle), "{needle} missing:\n{md}");
    }
}

/// The plot is a complete SVG with one panel per held-out group, each with the real
/// centroid (a black dot) inside the grey box of ±2 sd of the runs around it.
#[test]
fn svg_plot() {
    let d = diagnosis_of(
        &EffectParams::new()
            .with(WHEEL_DIAMETER_RATIO, 1.008)
            .with(FLOOR_NOISE, 1.0),
    );
    let svg = plot_svg(&d).unwrap();
    assert!(svg.starts_with("<svg") && svg.trim_end().ends_with("</svg>"));
    for g in &d.heldout_groups {
        assert!(svg.contains(g.as_str()), "{g} missing");
    }
    let attr = |tag: &str, name: &str| -> String {
        let at = tag.find(&format!(" {name}=\"")).unwrap() + name.len() + 3;
        tag[at..at + tag[at..].find('"').unwrap()].to_owned()
    };
    let tags = |start: &str| -> Vec<String> {
        svg.split('<')
            .filter(|t| t.starts_with(start))
            .map(|t| t.to_owned())
            .collect()
    };
    let boxes: Vec<Vec<(i64, i64)>> = tags("polyline")
        .iter()
        .filter(|t| attr(t, "stroke") == "#969696")
        .map(|t| {
            attr(t, "points")
                .split_whitespace()
                .map(|p| {
                    let (x, y) = p.split_once(',').unwrap();
                    (x.parse().unwrap(), y.parse().unwrap())
                })
                .collect()
        })
        .filter(|p: &Vec<(i64, i64)>| p.len() == 5)
        .collect();
    let dots: Vec<(i64, i64)> = tags("circle")
        .iter()
        .filter(|t| attr(t, "r") == "5" && attr(t, "fill") == "#000000")
        .map(|t| {
            (
                attr(t, "cx").parse().unwrap(),
                attr(t, "cy").parse().unwrap(),
            )
        })
        .collect();
    assert_eq!(boxes.len(), d.heldout_groups.len());
    assert_eq!(dots.len(), boxes.len());
    for (p, dot) in boxes.iter().zip(&dots) {
        assert_eq!(p[0], p[4], "closed: {p:?}");
        assert!(
            p[0].1 == p[1].1 && p[1].0 == p[2].0 && p[2].1 == p[3].1 && p[3].0 == p[0].0,
            "a rectangle: {p:?}"
        );
        let (w, h) = ((p[1].0 - p[0].0).abs(), (p[2].1 - p[1].1).abs());
        assert!(w > 10 && h > 10, "{p:?}");
        let centre = ((p[0].0 + p[2].0) / 2, (p[0].1 + p[2].1) / 2);
        assert!(
            (centre.0 - dot.0).abs() <= 1 && (centre.1 - dot.1).abs() <= 1,
            "{p:?} around {dot:?}"
        );
    }
}

/// The JSON has the three answers under `where`, `which` and `shrink`.
#[test]
fn json_sections() {
    let v = serde_json::to_value(diagnosis()).unwrap();
    for k in ["where", "which", "shrink", "split", "model"] {
        assert!(v.get(k).is_some(), "{k}");
    }
    assert_eq!(v["which"]["winner"][0], WHEEL_DIAMETER_RATIO);
}
