//! JUnit XML, as CI systems read it (GitLab, Jenkins, GitHub's test
//! reporters): `<testsuites>`, a `<testsuite>` with its `<properties>` (the
//! seed, the firmware), a `<testcase>` per test with `time` in seconds (the
//! bench's: robot seconds), a `<failure message=...>` when it failed, a
//! `<skipped>` when it ran but was not judged, and `<system-out>` naming
//! what was saved for triage.

use std::fmt::Write;

/// One test case.
#[derive(Debug, Clone, Default)]
pub struct Case {
    pub name: String,
    /// The group CI shows it under (`hil.test.FILE`, `hil.faults`).
    pub classname: String,
    /// Robot seconds.
    pub time_s: f64,
    pub failure: Option<Failure>,
    /// Run, not judged: the reason.
    pub skipped: Option<String>,
    pub system_out: Option<String>,
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
    let skipped = count(&|c| c.skipped.is_some());
    let time: f64 = suites.iter().flat_map(|s| &s.cases).map(|c| c.time_s).sum();
    let mut x = String::from("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n");
    let _ = writeln!(
        x,
        "<testsuites name=\"{}\" tests=\"{tests}\" failures=\"{failures}\" errors=\"0\" skipped=\"{skipped}\" time=\"{}\">",
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
            if c.failure.is_none() && c.skipped.is_none() && c.system_out.is_none() {
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
            if let Some(out) = &c.system_out {
                let _ = writeln!(x, "      <system-out>{}</system-out>", escape(out));
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
                    system_out: Some("vcd: x.vcd".into()),
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
    }
}
