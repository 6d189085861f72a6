//! The diagnosis of the thesis data (`fixtures/real/thesis`): fitted on experiment 1
//! (UMBmark and Triangular Path), evaluated on experiments 2 and 3, with the motor's
//! held-out PWM levels. Prints the terminal report; with a directory argument also writes
//! `gap.md`, `gap.svg` and `gap.json` there.
//!
//! ```sh
//! cargo run --release -p gap --example thesis_report [-- OUT_DIR]
//! ```

use std::path::PathBuf;

use gap::{
    diagnose_manifests, load_dir, plot_svg, render_markdown, render_text, DiagnoseOptions,
    KinematicModel, SplitRule,
};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../fixtures/real/thesis");
    let manifests = load_dir(&dir)?;
    let rule = SplitRule::TrainOnExperiments(vec!["umbmark-1".into(), "triangle-1".into()]);
    let d = diagnose_manifests(
        &KinematicModel,
        &manifests,
        &rule,
        &DiagnoseOptions::default(),
    )?;
    print!("{}", render_text(&d));
    if let Some(out) = std::env::args().nth(1) {
        let out = PathBuf::from(out);
        std::fs::create_dir_all(&out)?;
        std::fs::write(out.join("gap.svg"), plot_svg(&d)?)?;
        std::fs::write(out.join("gap.md"), render_markdown(&d, Some("gap.svg")))?;
        std::fs::write(out.join("gap.json"), serde_json::to_string_pretty(&d)?)?;
        eprintln!("wrote gap.md, gap.svg and gap.json to {}", out.display());
    }
    Ok(())
}
