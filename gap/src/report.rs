//! Renderers of a [`Diagnosis`]: plain text for the terminal, Markdown, and an SVG plot of
//! the held-out groups (runs, measured centroid, model before and after).

use std::fmt::Write as _;
use std::sync::Once;

use plotters::prelude::*;
use plotters::style::FontStyle;

use crate::breakdown::Component;
use crate::diagnose::{Diagnosis, RankedFit};
use crate::fit::{Estimate, Gap};
use crate::GapError;

fn opt(v: Option<f64>, prec: usize) -> String {
    v.map_or("—".to_owned(), |v| format!("{v:.prec$}"))
}

fn comp(c: &Component, prec: usize) -> String {
    match (c.value, c.std_err) {
        (Some(v), Some(s)) => format!("{v:+.prec$} ± {s:.prec$}"),
        (Some(v), None) => format!("{v:+.prec$}"),
        _ => "not determined".to_owned(),
    }
}

fn estimate(e: &Estimate) -> String {
    let unit = if e.unit == "1" {
        String::new()
    } else {
        format!(" {}", e.unit)
    };
    let mut s = format!("{} = {:.5}", e.symbol, e.value);
    if let Some(se) = e.std_err {
        let _ = write!(s, " ± {se:.5}");
    } else {
        s.push_str(" (undetermined)");
    }
    s.push_str(&unit);
    if let Some(b) = e.bootstrap_sd {
        let _ = write!(s, " [bootstrap sd {b:.5}]");
    }
    if e.at_bound {
        s.push_str(" [at bound]");
    }
    s
}

fn estimates(r: &RankedFit) -> String {
    if r.fit.estimates.is_empty() {
        return "—".into();
    }
    r.fit
        .estimates
        .iter()
        .map(estimate)
        .collect::<Vec<_>>()
        .join(", ")
}

fn gap_line(g: &Gap) -> String {
    format!(
        "systematic {:.2} cm, scatter {:.2} cm, total {:.2} cm",
        g.systematic_cm, g.scatter_cm, g.total_cm
    )
}

fn xy(x: f64, y: Option<f64>) -> String {
    format!(
        "({x:+.2}, {})",
        y.map_or("—".to_owned(), |y| format!("{y:+.2}"))
    )
}

/// Plain text for a terminal.
pub fn render_text(d: &Diagnosis) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "Sim-to-real gap diagnosis (model: {})", d.model);
    let _ = writeln!(s, "Split: {}", d.split);
    let _ = writeln!(s, "  trained on: {}", d.train_groups.join(", "));
    let _ = writeln!(s, "  held out:   {}", d.heldout_groups.join(", "));

    let _ = writeln!(
        s,
        "\n1. WHERE: residual real − model as it is (cm, x along the first leg, y left)"
    );
    let _ = writeln!(
        s,
        "  {:<26} {:>3} {:>18} {:>18} {:>18} {:>7} {:>15}",
        "group", "n", "real x̄, ȳ", "model x̄, ȳ", "residual", "|res|", "sd x, y"
    );
    for (tag, gap) in [("train", &d.where_.train), ("held", &d.where_.heldout)] {
        for g in &gap.groups {
            let _ = writeln!(
                s,
                "  {:<26} {:>3} {:>18} {:>18} {:>18} {:>7.2} {:>15}",
                format!("{} [{tag}]", g.group),
                g.observed.n,
                xy(g.observed.mean_x, g.observed.mean_y),
                xy(g.predicted.mean_x, Some(g.predicted.mean_y)),
                xy(g.residual_x_cm, g.residual_y_cm),
                g.systematic_cm,
                format!("{:.2}, {}", g.observed.sd_x, opt(g.observed.sd_y, 2)),
            );
        }
    }
    let _ = writeln!(
        s,
        "\n  First-order decomposition of the residual (α: under-rotation per corner, β: heading \
         change per leg, left +):"
    );
    let _ = writeln!(
        s,
        "  {:<24} {:>18} {:>18} {:>16} {:>10} {:>10}",
        "experiment [against]",
        "α (deg/corner)",
        "β (deg/leg)",
        "scale (%)",
        "residual",
        "remainder"
    );
    let rows = d.where_.decomposition.iter().map(|x| ("as is", x)).chain(
        d.where_
            .decomposition_after_winner
            .iter()
            .map(|x| ("winner", x)),
    );
    for (tag, dc) in rows {
        let _ = writeln!(
            s,
            "  {:<24} {:>18} {:>18} {:>16} {:>7.2} cm {:>7.2} cm",
            format!("{} [{tag}]", dc.experiment),
            comp(&dc.alpha_deg, 3),
            comp(&dc.beta_deg, 3),
            comp(&dc.scale_pct, 3),
            dc.residual_cm,
            dc.remainder_cm
        );
        for n in dc.notes.iter().filter(|_| tag == "as is") {
            let _ = writeln!(s, "  {:<24} note: {n}", "");
        }
    }
    let _ = writeln!(s, "\n  Scatter (non-systematic), variance between runs:");
    for dc in &d.where_.decomposition {
        for sc in &dc.scatter {
            let _ = writeln!(
                s,
                "  {:<26} var x {:>7.2} cm², var y {:>7} cm², cov {:>7} cm², centroid se {:.2} cm",
                sc.group,
                sc.var_x_cm2,
                opt(sc.var_y_cm2, 2),
                opt(sc.cov_xy_cm2, 2),
                sc.centroid_se_cm
            );
        }
    }

    let _ = writeln!(s, "\n2. WHICH EFFECT (fitted on the training groups)");
    let _ = writeln!(
        s,
        "  model as it is: χ² {:.1} over {} residuals, BIC {:.1}",
        d.which.baseline.chi2, d.which.baseline.n_residuals, d.which.baseline.bic
    );
    let table = |s: &mut String, title: &str, rows: &[RankedFit], max: usize| {
        let _ = writeln!(s, "  {title}");
        let _ = writeln!(
            s,
            "  {:>4} {:<40} {:>10} {:>10} {:>7} {:>11} {:>6}  value",
            "BIC#", "effect(s)", "χ²", "BIC", "share", "held-out", "HO#"
        );
        for r in rows.iter().take(max) {
            let _ = writeln!(
                s,
                "  {:>4} {:<40} {:>10.1} {:>10.1} {:>6.1}% {:>8.2} cm {:>6}  {}",
                r.rank_bic,
                r.fit.label(),
                r.fit.chi2,
                r.fit.bic,
                100.0 * r.fit.share_explained,
                r.fit.heldout.as_ref().map_or(f64::NAN, |g| g.total_cm),
                r.rank_heldout,
                estimates(r)
            );
        }
    };
    table(&mut s, "Single effects:", &d.which.singles, usize::MAX);
    if !d.which.pairs.is_empty() {
        table(&mut s, "Pairs (best 10 by BIC):", &d.which.pairs, 10);
    }
    for f in &d.which.extended {
        let _ = writeln!(
            s,
            "  Extended: {:<40} χ² {:.1}, BIC {:.1}, held-out {:.2} cm: {}",
            f.label(),
            f.chi2,
            f.bic,
            f.heldout.as_ref().map_or(f64::NAN, |g| g.total_cm),
            f.estimates
                .iter()
                .map(estimate)
                .collect::<Vec<_>>()
                .join(", ")
        );
    }
    let _ = writeln!(
        s,
        "  Winner: {} — {}",
        d.which.winner.join(" + "),
        d.which.winner_reason
    );
    if d.which.indistinguishable.is_empty() {
        let _ = writeln!(
            s,
            "  No pair of effects found indistinguishable by these data."
        );
    }
    for c in &d.which.indistinguishable {
        let _ = writeln!(
            s,
            "  Cannot be told apart: {}{}",
            c.effects.join(" vs "),
            if c.given.is_empty() {
                String::new()
            } else {
                format!(" (given {})", c.given.join(" + "))
            }
        );
        for e in &c.evidence {
            let _ = writeln!(s, "    - {e}");
        }
        let _ = writeln!(
            s,
            "    - best probe test: {}",
            c.separating_test
                .as_deref()
                .unwrap_or("none of the probe tests separates them by end points")
        );
        let _ = writeln!(s, "    - to separate them: {}", c.suggestion);
    }
    if !d.which.unsupported.is_empty() {
        let _ = writeln!(s, "  Not representable by this model:");
        for u in &d.which.unsupported {
            let _ = writeln!(s, "    - {}: {}", u.name, u.reason);
        }
    }

    let sh = &d.shrink;
    let _ = writeln!(
        s,
        "\n3. HOW FAR IT SHRINKS on the held-out groups (winner: {})",
        sh.winner.join(" + ")
    );
    let _ = writeln!(s, "  before: {}", gap_line(&sh.before));
    let _ = writeln!(s, "  after:  {}", gap_line(&sh.after));
    let _ = writeln!(
        s,
        "  removed: {:.1} % of the total, {:.1} % of the systematic, {:.1} % of the scatter gap",
        100.0 * sh.reduction_total,
        100.0 * sh.reduction_systematic,
        100.0 * sh.reduction_scatter
    );
    for p in &sh.path {
        let _ = writeln!(
            s,
            "  step {:<40} systematic {:>7.2} cm, total {:>7.2} cm",
            if p.effects.is_empty() {
                "(model as it is)".to_owned()
            } else {
                p.effects.join(" + ")
            },
            p.systematic_cm,
            p.total_cm
        );
    }
    for (b, a) in sh.before.groups.iter().zip(&sh.after.groups) {
        let _ = writeln!(
            s,
            "  {:<26} centroid gap {:>7.2} → {:>6.2} cm   real {} model {} → {}",
            b.group,
            b.systematic_cm,
            a.systematic_cm,
            xy(b.observed.mean_x, b.observed.mean_y),
            xy(b.predicted.mean_x, Some(b.predicted.mean_y)),
            xy(a.predicted.mean_x, Some(a.predicted.mean_y)),
        );
    }

    for m in &d.motor {
        let _ = writeln!(
            s,
            "\nMotor ({}), trained on PWM {:?}, held out {:?}: held-out RMS {:.2} → {:.2} thesis RPM \
             ({:.1} % removed) by adding Coulomb friction (dead band PWM {:.1}); before: speed ∝ \
             duty, gain {:.2}/duty, tau {:.4} s; after: tau {:.4} s",
            m.side,
            m.train,
            m.held_out,
            m.heldout_rms_before,
            m.heldout_rms_after,
            100.0 * m.reduction,
            m.after_dead_band_pwm,
            m.before_gain_rpm_per_duty,
            m.before_tau_s,
            m.after_tau_s
        );
        for l in &m.levels {
            let _ = writeln!(
                s,
                "  PWM {:>3} {:<9} steady {:>6.2} | before {:>6.2} (rms {:>5.2}) | after {:>6.2} (rms {:>5.2}: rise {:>5.2}, steady {:>5.2}) | {}",
                l.pwm,
                if l.held_out { "held out" } else { "fitted" },
                l.measured_steady_rpm,
                l.before_steady_rpm,
                l.before_rms_rpm,
                l.after_steady_rpm,
                l.after_rms_rpm,
                l.after_rise_rms_rpm,
                l.after_steady_rms_rpm,
                l.after_tests.verdict
            );
        }
    }
    for g in &d.series {
        let _ = writeln!(s, "\nTime series: {} ({} samples)", g.label, g.n);
        for seg in &g.segments {
            let _ = writeln!(
                s,
                "  {:<10?} n {:>5}  bias L {:+.2} R {:+.2}  rms L {:.2} R {:.2} (thesis RPM)",
                seg.segment, seg.n, seg.bias_left, seg.bias_right, seg.rms_left, seg.rms_right
            );
        }
        for w in &g.wheels {
            let _ = writeln!(s, "  {}: {}", w.side, w.verdict);
        }
        for n in &g.notes {
            let _ = writeln!(s, "  note: {n}");
        }
    }
    if !d.notes.is_empty() {
        let _ = writeln!(s, "\nNotes:");
        for n in &d.notes {
            let _ = writeln!(s, "  - {n}");
        }
    }
    s
}

/// Markdown; `svg` names the plot file to link (from [`plot_svg`]) when there is one.
pub fn render_markdown(d: &Diagnosis, svg: Option<&str>) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "# Sim-to-real gap diagnosis\n");
    let _ = writeln!(s, "Model: `{}`. Split: {}.\n", d.model, d.split);
    let _ = writeln!(s, "- Trained on: {}", d.train_groups.join(", "));
    let _ = writeln!(s, "- Held out: {}\n", d.heldout_groups.join(", "));
    let _ = writeln!(s, "## 1. Where the gap lies\n");
    let _ = writeln!(s, "Residual real − model as it is, cm (default frame: x along the first leg, y to the left).\n");
    let _ = writeln!(
        s,
        "| group | set | n | real x̄, ȳ | model x̄, ȳ | residual | \\|res\\| | sd x, y |"
    );
    let _ = writeln!(s, "|---|---|---:|---|---|---|---:|---|");
    for (tag, gap) in [("train", &d.where_.train), ("held out", &d.where_.heldout)] {
        for g in &gap.groups {
            let _ = writeln!(
                s,
                "| {} | {tag} | {} | {} | {} | {} | {:.2} | {:.2}, {} |",
                g.group,
                g.observed.n,
                xy(g.observed.mean_x, g.observed.mean_y),
                xy(g.predicted.mean_x, Some(g.predicted.mean_y)),
                xy(g.residual_x_cm, g.residual_y_cm),
                g.systematic_cm,
                g.observed.sd_x,
                opt(g.observed.sd_y, 2)
            );
        }
    }
    let _ = writeln!(s, "\nFirst-order decomposition (α: under-rotation per corner; β: heading change per leg, left +), against the model as it is and against the winner:\n");
    let _ = writeln!(s, "| experiment | against | α (deg/corner) | β (deg/leg) | scale (%) | residual (cm) | remainder (cm) |");
    let _ = writeln!(s, "|---|---|---|---|---|---:|---:|");
    let rows = d
        .where_
        .decomposition
        .iter()
        .map(|x| ("model as it is", x))
        .chain(
            d.where_
                .decomposition_after_winner
                .iter()
                .map(|x| ("winner", x)),
        );
    for (tag, dc) in rows {
        let _ = writeln!(
            s,
            "| {} | {tag} | {} | {} | {} | {:.2} | {:.2} |",
            dc.experiment,
            comp(&dc.alpha_deg, 3),
            comp(&dc.beta_deg, 3),
            comp(&dc.scale_pct, 3),
            dc.residual_cm,
            dc.remainder_cm
        );
    }
    let _ = writeln!(s, "\n## 2. Which effect\n");
    let _ = writeln!(
        s,
        "Model as it is: χ² {:.1} over {} residuals, BIC {:.1}.\n",
        d.which.baseline.chi2, d.which.baseline.n_residuals, d.which.baseline.bic
    );
    let table = |s: &mut String, rows: &[RankedFit], max: usize| {
        let _ = writeln!(s, "| BIC rank | effect(s) | χ² | AIC | BIC | share of gap | held-out gap (cm) | held-out rank | values |");
        let _ = writeln!(s, "|---:|---|---:|---:|---:|---:|---:|---:|---|");
        for r in rows.iter().take(max) {
            let _ = writeln!(
                s,
                "| {} | {} | {:.1} | {:.1} | {:.1} | {:.1} % | {:.2} | {} | {} |",
                r.rank_bic,
                r.fit.label(),
                r.fit.chi2,
                r.fit.aic,
                r.fit.bic,
                100.0 * r.fit.share_explained,
                r.fit.heldout.as_ref().map_or(f64::NAN, |g| g.total_cm),
                r.rank_heldout,
                estimates(r)
            );
        }
    };
    table(&mut s, &d.which.singles, usize::MAX);
    if !d.which.pairs.is_empty() {
        let _ = writeln!(s, "\nPairs (best 10 by BIC):\n");
        table(&mut s, &d.which.pairs, 10);
    }
    for f in &d.which.extended {
        let _ = writeln!(
            s,
            "\nExtended by forward selection: {} (χ² {:.1}, BIC {:.1}, held-out {:.2} cm): {}.",
            f.label(),
            f.chi2,
            f.bic,
            f.heldout.as_ref().map_or(f64::NAN, |g| g.total_cm),
            f.estimates
                .iter()
                .map(estimate)
                .collect::<Vec<_>>()
                .join(", ")
        );
    }
    let _ = writeln!(
        s,
        "\n**Winner: {}** — {}.\n",
        d.which.winner.join(" + "),
        d.which.winner_reason
    );
    for c in &d.which.indistinguishable {
        let _ = writeln!(
            s,
            "**Cannot be told apart: {}**{}",
            c.effects.join(" vs "),
            if c.given.is_empty() {
                String::new()
            } else {
                format!(" (given {})", c.given.join(" + "))
            }
        );
        for e in &c.evidence {
            let _ = writeln!(s, "- {e}");
        }
        let _ = writeln!(
            s,
            "- best probe test: {}",
            c.separating_test
                .as_deref()
                .unwrap_or("none of the probe tests separates them by end points")
        );
        let _ = writeln!(s, "- to separate them: {}\n", c.suggestion);
    }
    if !d.which.unsupported.is_empty() {
        let _ = writeln!(s, "Not representable by this model:\n");
        for u in &d.which.unsupported {
            let _ = writeln!(s, "- `{}`: {}", u.name, u.reason);
        }
    }
    let sh = &d.shrink;
    let _ = writeln!(s, "\n## 3. How far it shrinks (held out)\n");
    let _ = writeln!(s, "| | systematic (cm) | scatter (cm) | total (cm) |");
    let _ = writeln!(s, "|---|---:|---:|---:|");
    let _ = writeln!(
        s,
        "| model as it is | {:.2} | {:.2} | {:.2} |",
        sh.before.systematic_cm, sh.before.scatter_cm, sh.before.total_cm
    );
    let _ = writeln!(
        s,
        "| with {} | {:.2} | {:.2} | {:.2} |",
        sh.winner.join(" + "),
        sh.after.systematic_cm,
        sh.after.scatter_cm,
        sh.after.total_cm
    );
    let _ = writeln!(
        s,
        "| removed | {:.1} % | {:.1} % | {:.1} % |",
        100.0 * sh.reduction_systematic,
        100.0 * sh.reduction_scatter,
        100.0 * sh.reduction_total
    );
    let _ = writeln!(
        s,
        "\nStep by step (held-out total gap): {}.",
        sh.path
            .iter()
            .map(|p| format!(
                "{} {:.2} cm",
                if p.effects.is_empty() {
                    "model as it is".to_owned()
                } else {
                    p.effects.join(" + ")
                },
                p.total_cm
            ))
            .collect::<Vec<_>>()
            .join(" → ")
    );
    if let Some(svg) = svg {
        let _ = writeln!(
            s,
            "\n![held-out groups: runs, measured centroid, model before and after]({svg})"
        );
    }
    for m in &d.motor {
        let _ = writeln!(
            s,
            "\n### Motor {} (train PWM {:?}, hold out {:?})\n\nHeld-out RMS {:.2} → {:.2} thesis RPM ({:.1} % removed) by adding Coulomb friction (dead band PWM {:.1}).\n",
            m.side, m.train, m.held_out, m.heldout_rms_before, m.heldout_rms_after, 100.0 * m.reduction, m.after_dead_band_pwm
        );
        let _ = writeln!(
            s,
            "| PWM | role | measured | before | after | rms before | rms after | residual tests |"
        );
        let _ = writeln!(s, "|---:|---|---:|---:|---:|---:|---:|---|");
        for l in &m.levels {
            let _ = writeln!(
                s,
                "| {} | {} | {:.2} | {:.2} | {:.2} | {:.2} | {:.2} | {} |",
                l.pwm,
                if l.held_out { "held out" } else { "fitted" },
                l.measured_steady_rpm,
                l.before_steady_rpm,
                l.after_steady_rpm,
                l.before_rms_rpm,
                l.after_rms_rpm,
                l.after_tests.verdict
            );
        }
    }
    for g in &d.series {
        let _ = writeln!(s, "\n### Time series: {}\n", g.label);
        let _ = writeln!(s, "| segment | n | bias L | bias R | rms L | rms R |");
        let _ = writeln!(s, "|---|---:|---:|---:|---:|---:|");
        for seg in &g.segments {
            let _ = writeln!(
                s,
                "| {:?} | {} | {:+.2} | {:+.2} | {:.2} | {:.2} |",
                seg.segment, seg.n, seg.bias_left, seg.bias_right, seg.rms_left, seg.rms_right
            );
        }
        for w in &g.wheels {
            let _ = writeln!(s, "\n- {}: {}", w.side, w.verdict);
        }
    }
    if !d.notes.is_empty() {
        let _ = writeln!(s, "\n## Notes\n");
        for n in &d.notes {
            let _ = writeln!(s, "- {n}");
        }
    }
    s
}

const FONT: &str = "sans-serif";
static FONTS: Once = Once::new();

fn register_fonts() {
    FONTS.call_once(|| {
        // DejaVu Sans is a valid TrueType font; registration cannot fail for it.
        let _ = plotters::style::register_font(FONT, FontStyle::Normal, dejavu::sans::regular());
    });
}

/// An SVG of the held-out groups: one panel each with the measured runs (grey dots), their
/// centroid (black circle), the model as it is (red cross) and with the winner (blue
/// triangle).
pub fn plot_svg(d: &Diagnosis) -> Result<String, GapError> {
    register_fonts();
    let before = &d.shrink.before.groups;
    let after = &d.shrink.after.groups;
    let n = before.len().max(1);
    let cols = n.min(3);
    let rows = n.div_ceil(cols);
    let (w, h) = (380 * cols as u32, 360 * rows as u32);
    let mut out = String::new();
    {
        let root = SVGBackend::with_string(&mut out, (w, h)).into_drawing_area();
        let e = |x: &dyn std::fmt::Display| GapError::Plot(x.to_string());
        root.fill(&WHITE).map_err(|x| e(&x))?;
        let panels = root.split_evenly((rows, cols));
        for ((b, a), area) in before.iter().zip(after).zip(panels.iter()) {
            let mut pts = vec![
                (b.observed.mean_x, b.observed.mean_y.unwrap_or(0.0)),
                (b.predicted.mean_x, b.predicted.mean_y),
                (a.predicted.mean_x, a.predicted.mean_y),
                (0.0, 0.0),
            ];
            // Runs are not in the gap; draw ±2 sd around the centroid instead.
            let (sx, sy) = (b.observed.sd_x, b.observed.sd_y.unwrap_or(0.0));
            pts.push((
                b.observed.mean_x - 2.0 * sx,
                b.observed.mean_y.unwrap_or(0.0) - 2.0 * sy,
            ));
            pts.push((
                b.observed.mean_x + 2.0 * sx,
                b.observed.mean_y.unwrap_or(0.0) + 2.0 * sy,
            ));
            let (x0, x1) = pts
                .iter()
                .fold((f64::MAX, f64::MIN), |(a, b), p| (a.min(p.0), b.max(p.0)));
            let (y0, y1) = pts
                .iter()
                .fold((f64::MAX, f64::MIN), |(a, b), p| (a.min(p.1), b.max(p.1)));
            let pad = 0.15 * (x1 - x0).max(y1 - y0).max(2.0);
            let mut chart = ChartBuilder::on(area)
                .caption(&b.group, (FONT, 15))
                .margin(8)
                .x_label_area_size(28)
                .y_label_area_size(40)
                .build_cartesian_2d((x0 - pad)..(x1 + pad), (y0 - pad)..(y1 + pad))
                .map_err(|x| e(&x))?;
            chart
                .configure_mesh()
                .x_desc("x (cm)")
                .y_desc("y (cm)")
                .label_style((FONT, 11))
                .draw()
                .map_err(|x| e(&x))?;
            let grey = RGBColor(150, 150, 150);
            let (mx, my) = (b.observed.mean_x, b.observed.mean_y.unwrap_or(0.0));
            chart
                .draw_series(LineSeries::new(
                    [
                        (mx - 2.0 * sx, my - 2.0 * sy),
                        (mx + 2.0 * sx, my - 2.0 * sy),
                        (mx + 2.0 * sx, my + 2.0 * sy),
                        (mx - 2.0 * sx, my + 2.0 * sy),
                        (mx - 2.0 * sx, my - 2.0 * sy),
                    ],
                    grey,
                ))
                .map_err(|x| e(&x))?
                .label("real ±2 sd")
                .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 14, y)], grey));
            chart
                .draw_series(std::iter::once(Circle::new((mx, my), 5, BLACK.filled())))
                .map_err(|x| e(&x))?
                .label("real centroid")
                .legend(|(x, y)| Circle::new((x + 7, y), 4, BLACK.filled()));
            chart
                .draw_series(std::iter::once(Cross::new(
                    (b.predicted.mean_x, b.predicted.mean_y),
                    6,
                    RED.stroke_width(2),
                )))
                .map_err(|x| e(&x))?
                .label("model as it is")
                .legend(|(x, y)| Cross::new((x + 7, y), 4, RED.stroke_width(2)));
            chart
                .draw_series(std::iter::once(TriangleMarker::new(
                    (a.predicted.mean_x, a.predicted.mean_y),
                    7,
                    BLUE.filled(),
                )))
                .map_err(|x| e(&x))?
                .label("with the winner")
                .legend(|(x, y)| TriangleMarker::new((x + 7, y), 5, BLUE.filled()));
            chart
                .configure_series_labels()
                .label_font((FONT, 11))
                .background_style(WHITE.mix(0.8))
                .border_style(BLACK)
                .draw()
                .map_err(|x| e(&x))?;
        }
        root.present().map_err(|x| e(&x))?;
    }
    Ok(out)
}
