//! A later run against its golden run: each quantity's golden and new
//! value, the difference, the tolerance and whether it holds; what was in
//! force that differs; the table people read.

use serde::Serialize;

use super::{InForce, Kind, Quantity, Tolerances};

/// One quantity compared.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Row {
    pub quantity: String,
    pub kind: Kind,
    /// None: the golden run has no such quantity (the run now has more
    /// legs, turns or timing figures).
    pub golden: Option<f64>,
    /// None: the run now has no such quantity (fewer legs, a run that did
    /// not complete).
    pub now: Option<f64>,
    pub tolerance: f64,
    /// Within the tolerance; a quantity on one side only has moved.
    pub ok: bool,
}

impl Row {
    /// Now minus golden, when both are there.
    pub fn delta(&self) -> Option<f64> {
        Some(self.now? - self.golden?)
    }
}

/// Every quantity of `golden` against `now` (in the golden file's order,
/// then those only `now` has), held to `tol`.
pub fn compare(golden: &[Quantity], now: &[Quantity], tol: &Tolerances) -> Vec<Row> {
    let find = |qs: &[Quantity], name: &str| qs.iter().find(|q| q.name == name).map(|q| q.value);
    let mut rows: Vec<Row> = golden
        .iter()
        .map(|g| {
            let n = find(now, &g.name);
            let tolerance = tol.of(g.kind);
            Row {
                quantity: g.name.clone(),
                kind: g.kind,
                golden: Some(g.value),
                now: n,
                tolerance,
                ok: n.is_some_and(|n| (n - g.value).abs() <= tolerance),
            }
        })
        .collect();
    rows.extend(
        now.iter()
            .filter(|n| find(golden, &n.name).is_none())
            .map(|n| Row {
                quantity: n.name.clone(),
                kind: n.kind,
                golden: None,
                now: Some(n.value),
                tolerance: tol.of(n.kind),
                ok: false,
            }),
    );
    rows
}

/// Something in force that is not what the golden run had.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct Difference {
    pub what: &'static str,
    pub golden: String,
    pub now: String,
}

/// What differs between the golden run's conditions and these.
pub fn differences(golden: &InForce, now: &InForce) -> Vec<Difference> {
    let opt = |o: &Option<String>, none: &str| o.clone().unwrap_or_else(|| none.into());
    let list = |v: &[String]| {
        if v.is_empty() {
            "none".to_string()
        } else {
            v.join(" ")
        }
    };
    let fields = [
        ("firmware", golden.firmware.clone(), now.firmware.clone()),
        ("elf", opt(&golden.elf, "-"), opt(&now.elf, "-")),
        ("elf hash", golden.elf_hash.clone(), now.elf_hash.clone()),
        ("robot", golden.robot.clone(), now.robot.clone()),
        (
            "robot hash",
            golden.robot_hash.clone(),
            now.robot_hash.clone(),
        ),
        (
            "board",
            opt(&golden.board, "henrytwo (built in)"),
            opt(&now.board, "henrytwo (built in)"),
        ),
        ("seed", golden.seed.to_string(), now.seed.to_string()),
        ("params", list(&golden.params), list(&now.params)),
        (
            "keep firmware params",
            golden.keep_firmware_params.to_string(),
            now.keep_firmware_params.to_string(),
        ),
        (
            "scenario",
            opt(&golden.scenario, "none"),
            opt(&now.scenario, "none"),
        ),
        ("tests", opt(&golden.tests, "none"), opt(&now.tests, "none")),
    ];
    fields
        .into_iter()
        .filter(|(_, g, n)| g != n)
        .map(|(what, golden, now)| Difference { what, golden, now })
        .collect()
}

/// The comparison as people read it: what differs in force, then one line
/// a quantity (quantity, golden, now, delta, tolerance, ok/MOVED), then how
/// many moved.
pub fn render(rows: &[Row], in_force: &[Difference]) -> String {
    use std::fmt::Write;
    let mut s = String::new();
    for d in in_force {
        let why = if d.what == "elf hash" {
            " (a different ELF: what is compared)"
        } else {
            ""
        };
        let _ = writeln!(s, "{}: golden {}, now {}{why}", d.what, d.golden, d.now);
    }
    if in_force.is_empty() {
        s.push_str("in force: as recorded (the same ELF, robot, board, seed and parameters)\n");
    }
    let width = rows
        .iter()
        .map(|r| r.quantity.len())
        .chain(["quantity".len()])
        .max()
        .unwrap_or(8);
    let num = |v: Option<f64>| v.map_or("-".to_string(), |v| format!("{v:.3}"));
    let _ = writeln!(
        s,
        "  {:<width$}  {:>12}  {:>12}  {:>10}  {:>10}  result",
        "quantity", "golden", "now", "delta", "tolerance"
    );
    for r in rows {
        let _ = writeln!(
            s,
            "  {:<width$}  {:>12}  {:>12}  {:>10}  {:>10.3}  {}",
            r.quantity,
            num(r.golden),
            num(r.now),
            r.delta().map_or("-".into(), |d| format!("{d:+.3}")),
            r.tolerance,
            if r.ok { "ok" } else { "MOVED" }
        );
    }
    let moved: Vec<&str> = rows
        .iter()
        .filter(|r| !r.ok)
        .map(|r| r.quantity.as_str())
        .collect();
    if moved.is_empty() {
        let _ = writeln!(s, "all {} quantities within tolerance", rows.len());
    } else {
        let _ = writeln!(
            s,
            "{} of {} quantities moved: {}",
            moved.len(),
            rows.len(),
            moved.join(", ")
        );
    }
    s
}
