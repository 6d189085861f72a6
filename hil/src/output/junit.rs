//! JUnit XML, as CI systems read it (GitLab, Jenkins, GitHub's test
//! reporters), valid against Jenkins' `junit-10.xsd` (kept in
//! `tests/schemas/`, every report checked against it with xmllint):
//! `<testsuites>`, a `<testsuite>` per run with its `<properties>` (the same
//! names from every command: [`run_properties`]), a `<testcase>` with `time`
//! in wall-clock seconds (what CI compares with its job's time; the robot
//! time is the `robot_time_s` property), a `<failure message=...>` when it
//! failed, a `<skipped>` when it ran but was not judged, and `<system-out>`
//! naming what was saved for triage as `[[ATTACHMENT|path]]` lines, the
//! paths relative to the report's folder (GitLab and Jenkins' attachment
//! readers take that form; an absolute runner path means nothing once the
//! report is a CI artifact).

use std::fmt::Write;
use std::path::{Component, Path, PathBuf};

/// One test case.
#[derive(Debug, Clone, Default)]
pub struct Case {
    pub name: String,
    /// The group CI shows it under (`hil.test.FILE`, `hil.faults`).
    pub classname: String,
    /// Wall-clock seconds the case took, measured around the run (never
    /// inside it: the simulation does not read the host clock).
    pub time_s: f64,
    pub failure: Option<Failure>,
    /// Run, not judged: the reason.
    pub skipped: Option<String>,
    /// Other text for `<system-out>`, before the attachments.
    pub system_out: Option<String>,
    /// Files saved for the case, relative to the report's folder
    /// ([`relative_to_report`]): `[[ATTACHMENT|path]]` lines.
    pub attachments: Vec<String>,
}

#[derive(Debug, Clone)]
pub struct Failure {
    /// One line: which expectation, when, what was seen.
    pub message: String,
    /// What kind of failure (`expectation`, `incomplete`, `not_fired`).
    pub kind: String,
    /// The details (every expectation's verdict).
    pub text: String,
}

/// A suite: cases run with the same properties.
#[derive(Debug, Clone, Default)]
pub struct Suite {
    pub name: String,
    pub properties: Vec<(String, String)>,
    pub cases: Vec<Case>,
}

/// The properties every command gives each suite, in this order: the bench
/// version, the command, the firmware by its build name (the ELF's stem, as
/// `--firmware` names it), the plant's seed and the robot seconds the run
/// simulated. A command's own properties follow these.
pub fn run_properties(
    command: &str,
    firmware: &str,
    seed: u64,
    robot_time_s: f64,
) -> Vec<(String, String)> {
    vec![
        ("hil".into(), env!("CARGO_PKG_VERSION").into()),
        ("command".into(), command.into()),
        ("firmware".into(), firmware.into()),
        ("seed".into(), seed.to_string()),
        ("robot_time_s".into(), format!("{robot_time_s:.6}")),
    ]
}

/// `file` as a path from the folder of `report` (both made absolute
/// against the working directory first), `/`-separated, for an
/// `[[ATTACHMENT|...]]` line that still holds when the report and its
/// artifacts are moved together.
pub fn relative_to_report(report: &Path, file: &Path) -> String {
    let abs = |p: &Path| std::path::absolute(p).unwrap_or_else(|_| p.to_path_buf());
    let base = abs(report)
        .parent()
        .map(Path::to_path_buf)
        .unwrap_or_default();
    let rel = relative(&normal(&base), &normal(&abs(file)));
    rel.components()
        .map(|c| c.as_os_str().to_string_lossy())
        .collect::<Vec<_>>()
        .join("/")
}

/// `p` with `.` dropped and `..` taken back, as written (no links followed:
/// the files may not exist yet).
fn normal(p: &Path) -> PathBuf {
    let mut out = PathBuf::new();
    for c in p.components() {
        match c {
            Component::CurDir => {}
            Component::ParentDir => {
                out.pop();
            }
            c => out.push(c),
        }
    }
    out
}

/// `to` from `from`, both absolute and normal.
fn relative(from: &Path, to: &Path) -> PathBuf {
    let a: Vec<_> = from.components().collect();
    let b: Vec<_> = to.components().collect();
    let common = a.iter().zip(&b).take_while(|(x, y)| x == y).count();
    let mut out = PathBuf::new();
    for _ in common..a.len() {
        out.push("..");
    }
    for c in &b[common..] {
        out.push(c);
    }
    out
}

/// `s` with what XML does not allow dropped (control characters but tab
/// and newline) and its markup characters escaped, for text and attributes.
fn escape(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&apos;"),
            '\t' | '\n' | '\r' => out.push(c),
            c if (c as u32) < 0x20 || matches!(c, '\u{FFFE}' | '\u{FFFF}') => {}
            c => out.push(c),
        }
    }
    out
}

/// Seconds as JUnit writes them.
fn secs(t: f64) -> String {
    format!("{:.3}", if t.is_finite() { t.max(0.0) } else { 0.0 })
}

/// The document: `<testsuites name=...>` holding `suites`.
pub fn render(name: &str, suites: &[Suite]) -> String {
    let count = |f: &dyn Fn(&Case) -> bool| -> usize {
        suites
            .iter()
            .map(|s| s.cases.iter().filter(|c| f(c)).count())
            .sum()
    };
    let tests = count(&|_| true);
    let failures = count(&|c| c.failure.is_some());
    let time: f64 = suites.iter().flat_map(|s| &s.cases).map(|c| c.time_s).sum();
    let mut x = String::from("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n");
    // junit-10.xsd allows no `skipped` here (only on a testsuite).
    let _ = writeln!(
        x,
        "<testsuites name=\"{}\" tests=\"{tests}\" failures=\"{failures}\" errors=\"0\" time=\"{}\">",
        escape(name),
        secs(time)
    );
    for s in suites {
        let failures = s.cases.iter().filter(|c| c.failure.is_some()).count();
        let skipped = s.cases.iter().filter(|c| c.skipped.is_some()).count();
        let time: f64 = s.cases.iter().map(|c| c.time_s).sum();
        let _ = writeln!(
            x,
            "  <testsuite name=\"{}\" tests=\"{}\" failures=\"{failures}\" errors=\"0\" skipped=\"{skipped}\" time=\"{}\">",
            escape(&s.name),
            s.cases.len(),
            secs(time)
        );
        if !s.properties.is_empty() {
            x.push_str("    <properties>\n");
            for (k, v) in &s.properties {
                let _ = writeln!(
                    x,
                    "      <property name=\"{}\" value=\"{}\"/>",
                    escape(k),
                    escape(v)
                );
            }
            x.push_str("    </properties>\n");
        }
        for c in &s.cases {
            let _ = write!(
                x,
                "    <testcase name=\"{}\" classname=\"{}\" time=\"{}\"",
                escape(&c.name),
                escape(&c.classname),
                secs(c.time_s)
            );
            let out: Vec<String> = c
                .system_out
                .iter()
                .cloned()
                .chain(c.attachments.iter().map(|a| format!("[[ATTACHMENT|{a}]]")))
                .collect();
            if c.failure.is_none() && c.skipped.is_none() && out.is_empty() {
                x.push_str("/>\n");
                continue;
            }
            x.push_str(">\n");
            if let Some(f) = &c.failure {
                let _ = writeln!(
                    x,
                    "      <failure message=\"{}\" type=\"{}\">{}</failure>",
                    escape(&f.message),
                    escape(&f.kind),
                    escape(&f.text)
                );
            }
            if let Some(why) = &c.skipped {
                let _ = writeln!(x, "      <skipped message=\"{}\"/>", escape(why));
            }
            if !out.is_empty() {
                let _ = writeln!(
                    x,
                    "      <system-out>{}</system-out>",
                    escape(&out.join("\n"))
                );
            }
            x.push_str("    </testcase>\n");
        }
        x.push_str("  </testsuite>\n");
    }
    x.push_str("</testsuites>\n");
    x
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn markup_and_control_characters_are_escaped_or_dropped() {
        assert_eq!(
            escape("a<b & \"c\" 'd'>\u{1}\n"),
            "a&lt;b &amp; &quot;c&quot; &apos;d&apos;&gt;\n"
        );
    }

    #[test]
    fn counts_add_up_and_a_passing_case_is_empty() {
        let suite = Suite {
            name: "s".into(),
            properties: vec![("seed".into(), "0".into())],
            cases: vec![
                Case {
                    name: "ok".into(),
                    classname: "hil.test".into(),
                    time_s: 1.5,
                    ..Default::default()
                },
                Case {
                    name: "bad".into(),
                    classname: "hil.test".into(),
                    time_s: 2.0,
                    failure: Some(Failure {
                        message: "m".into(),
                        kind: "expectation".into(),
                        text: "t".into(),
                    }),
                    attachments: vec!["r-artifacts/x.vcd".into()],
                    ..Default::default()
                },
            ],
        };
        let x = render("hil test", &[suite]);
        assert!(
            x.contains("tests=\"2\" failures=\"1\" errors=\"0\" skipped=\"0\" time=\"3.500\""),
            "{x}"
        );
        assert!(x.contains("<testcase name=\"ok\" classname=\"hil.test\" time=\"1.500\"/>"));
        assert!(x.contains("<failure message=\"m\" type=\"expectation\">t</failure>"));
        assert!(x.contains("<property name=\"seed\" value=\"0\"/>"));
        assert!(x.contains("<system-out>[[ATTACHMENT|r-artifacts/x.vcd]]</system-out>"));
        // junit-10.xsd: a testsuite may say how many were skipped, the
        // testsuites element may not.
        let top = x.lines().find(|l| l.starts_with("<testsuites")).unwrap();
        assert!(!top.contains("skipped="), "{top}");
    }

    #[test]
    fn attachments_are_relative_to_the_reports_folder() {
        let r = |report: &str, file: &str| relative_to_report(Path::new(report), Path::new(file));
        assert_eq!(
            r("out/report.xml", "out/report-artifacts/a.vcd"),
            "report-artifacts/a.vcd"
        );
        assert_eq!(r("report.xml", "./arts/a.vcd"), "arts/a.vcd");
        assert_eq!(r("ci/junit/report.xml", "ci/arts/a.vcd"), "../arts/a.vcd");
        assert_eq!(r("/a/b/report.xml", "/a/c/../b/x/a.vcd"), "x/a.vcd");
    }

    #[test]
    fn every_command_gives_the_same_property_names() {
        let names = |p: Vec<(String, String)>| p.into_iter().map(|(k, _)| k).collect::<Vec<_>>();
        assert_eq!(
            names(run_properties("test", "robust", 0, 1.0)),
            names(run_properties("faults", "thesis", 7, 2.0))
        );
        let p = run_properties("test", "robust", 3, 34.25);
        assert!(
            p.contains(&("robot_time_s".into(), "34.250000".into())),
            "{p:?}"
        );
    }
}
