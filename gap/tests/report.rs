//! Reports: the terminal and Markdown renderers show the three answers, the plot is an SVG,
//! and the diagnosis serialises to JSON with its three sections.

use gap::effects::{COAST, WHEEL_DIAMETER_RATIO};
use gap::{
    diagnose, plot_svg, render_markdown, render_text, Dataset, DiagnoseOptions, EffectParams,
    Experiment, Firmware, FitOptions, Group, KinematicModel, Model, ObservedRun, Reference,
    SplitRule, TestKind,
};

fn diagnosis() -> gap::Diagnosis {
    let reference = Reference {
        wheelbase_mm: 150.0,
        mm_per_count: 0.2,
    };
    let hidden = EffectParams::new().with(WHEEL_DIAMETER_RATIO, 1.008);
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
                .predict(&hidden, &exp)
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

/// The plot is a complete SVG with one panel per held-out group.
#[test]
fn svg_plot() {
    let d = diagnosis();
    let svg = plot_svg(&d).unwrap();
    assert!(svg.starts_with("<svg") && svg.trim_end().ends_with("</svg>"));
    for g in &d.heldout_groups {
        assert!(svg.contains(g.as_str()), "{g} missing");
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
