//! No file of tests/ is left out of the suite. hil's tests are not found by cargo on its
//! own (they live outside hil/), so a file is run only if hil/Cargo.toml names it as a
//! test binary or a binary's root names it as a module (`#[path = "x.rs"] mod x;`, as
//! tests/e2e.rs does). A file that is neither would compile nowhere and fail nowhere.

use std::collections::BTreeSet;
use std::path::Path;

/// The files of `tests` (names like `line.rs`) that no test binary of `manifest` runs:
/// neither the root of a `[[test]]` nor a `#[path]` module of one.
fn left_out(manifest: &str, tests: &Path) -> Result<Vec<String>, String> {
    let manifest: toml::Table = manifest
        .parse()
        .map_err(|e| format!("hil/Cargo.toml: {e}"))?;
    let mut run = BTreeSet::new();
    let binaries = manifest
        .get("test")
        .and_then(|t| t.as_array())
        .ok_or("hil/Cargo.toml: no [[test]]")?;
    for binary in binaries {
        let path = binary
            .get("path")
            .and_then(|p| p.as_str())
            .ok_or("hil/Cargo.toml: a [[test]] without a path")?;
        let Some(file) = path.strip_prefix("../tests/") else {
            continue;
        };
        run.insert(file.to_owned());
        let root =
            std::fs::read_to_string(tests.join(file)).map_err(|e| format!("tests/{file}: {e}"))?;
        // A module file in tests/ itself (not in a folder of one file's helpers).
        for line in root.lines() {
            if let Some(module) = line
                .trim()
                .strip_prefix("#[path = \"")
                .and_then(|rest| rest.strip_suffix("\"]"))
            {
                if !module.contains('/') {
                    run.insert(module.to_owned());
                }
            }
        }
    }
    let mut missing = Vec::new();
    for entry in std::fs::read_dir(tests).map_err(|e| format!("{}: {e}", tests.display()))? {
        let name = entry
            .map_err(|e| format!("{}: {e}", tests.display()))?
            .file_name()
            .to_string_lossy()
            .into_owned();
        if name.ends_with(".rs") && !run.contains(&name) {
            missing.push(name);
        }
    }
    missing.sort();
    Ok(missing)
}

#[test]
fn every_file_of_tests_is_in_a_test_binary() {
    let hil = Path::new(env!("CARGO_MANIFEST_DIR"));
    let manifest = std::fs::read_to_string(hil.join("Cargo.toml")).expect("hil/Cargo.toml");
    let missing = left_out(&manifest, &hil.join("../tests")).unwrap();
    assert!(
        missing.is_empty(),
        "tests/{} in no test binary: add `#[path = \"x.rs\"] mod x;` to tests/e2e.rs",
        missing.join(", tests/")
    );
}

#[test]
fn a_file_named_by_no_binary_is_found() {
    let dir = std::env::temp_dir().join(format!("hil-e2e-coverage-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("all.rs"), "#[path = \"a.rs\"]\nmod a;\n").unwrap();
    for file in ["a.rs", "own.rs", "forgotten.rs"] {
        std::fs::write(dir.join(file), "").unwrap();
    }
    let manifest = "[[test]]\nname = \"all\"\npath = \"../tests/all.rs\"\n\
                    [[test]]\nname = \"own\"\npath = \"../tests/own.rs\"\n";
    let missing = left_out(manifest, &dir);
    std::fs::remove_dir_all(&dir).unwrap();
    assert_eq!(missing.unwrap(), ["forgotten.rs"]);
}
