//! The bench-backed diagnosis in shards: `hil gap --bench --shard K/N` on each machine and
//! `hil gap --merge` of the partials print what one machine prints, byte for byte; partials
//! that do not make one diagnosis are refused (exit 2, one line naming the file or shard).
//! And `hil bench --diagnosis`'s code path produces its numbers on a tiny dataset (not their
//! speed: no test is timed).

#[path = "support/mod.rs"]
mod support;

use std::path::{Path, PathBuf};
use std::process::Output;

use support::hil;

use hil::runs::gap_bench::{
    measure_diagnosis, BenchModel, SelectOptions, SpeedPlan, DEFAULT_CASES,
};
use plant_model::RobotConfig;

fn ok(out: &Output) {
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

/// compact48's bench-made "floor" data (fixtures/real/compact48) with its legs cut to
/// 100 mm, so that a diagnosis takes seconds: the numbers do not matter here, only that
/// every machine computes the same ones.
fn short_legged_data(dir: &Path) -> PathBuf {
    let src = hil::paths::workspace_root().join("fixtures/real/compact48");
    let robot = hil::paths::workspace_root().join("fixtures/robots/compact48.toml");
    let data = dir.join("data");
    std::fs::create_dir_all(&data).unwrap();
    for f in ["umbmark-1.toml", "triangle-1.toml"] {
        let text = std::fs::read_to_string(src.join(f)).unwrap();
        assert!(text.contains("leg_mm = 2000.0"), "{f}");
        let text = text.replace("leg_mm = 2000.0", "leg_mm = 100.0").replace(
            "robot_config = \"../../robots/compact48.toml\"",
            &format!("robot_config = {:?}", robot.display().to_string()),
        );
        std::fs::write(data.join(f), text).unwrap();
    }
    for f in ["umbmark_endpoints.csv", "triangular_endpoints.csv"] {
        std::fs::copy(src.join(f), data.join(f)).unwrap();
    }
    data
}

/// The error line of a refused merge: exit 2, one line, naming `what`.
fn refused(out: &Output, what: &str) {
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert_eq!(err.trim_end().lines().count(), 1, "{err}");
    assert!(err.contains(what), "{what} not named: {err}");
}

#[test]
fn shards_merge_into_the_single_machine_report_and_wrong_sets_are_refused() {
    let dir = std::env::temp_dir().join(format!("hil-gap-shard-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let data = short_legged_data(&dir);
    let real = data.display().to_string();
    let out = dir.join("shards");
    let o = out.display().to_string();
    let common = [
        "gap",
        "--real",
        &real,
        "--bench",
        "--jobs",
        "2",
        // The effects the kinematic model cannot represent only: candidates enough for
        // two shards.
        "--shortlist",
        "0",
        // Shards fit single effects only: the single-machine report to compare with too.
        "--max-effects",
        "1",
        // The coarsest search and the fewest runs: the numbers do not matter here, only
        // that every machine computes the same ones.
        "--grid",
        "3",
        "--refine",
        "1",
        // One run per centroid: a third of the runs.
        "--centroid-runs",
        "1",
    ];

    let json = hil(&[&common[..], &["--json"]].concat());
    ok(&json);
    let text = hil(&common);
    ok(&text);
    for k in ["1/2", "2/2"] {
        ok(&hil(&[&common[..], &["--shard", k, "--out", &o]].concat()));
    }
    let a = out
        .join("gap-bench-shard-1-of-2.json")
        .display()
        .to_string();
    let b = out
        .join("gap-bench-shard-2-of-2.json")
        .display()
        .to_string();
    // Both shards hold candidates: the split is real.
    for f in [&a, &b] {
        let v: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(f).unwrap()).unwrap();
        assert!(!v["candidates"].as_array().unwrap().is_empty(), "{f}");
        // The search the plan says is the one asked for.
        assert_eq!(v["plan"]["options"]["grid"], 3, "{f}");
        assert_eq!(v["plan"]["options"]["refine"], 1, "{f}");
        assert_eq!(v["plan"]["options"]["fold_refine"], 1, "{f}");
        assert_eq!(v["plan"]["options"]["fit"]["centroid_runs"], 1, "{f}");
    }

    let merged = hil(&["gap", "--merge", &b, &a, "--json"]);
    ok(&merged);
    assert!(
        merged.stdout == json.stdout,
        "merged:\n{}\none machine:\n{}",
        String::from_utf8_lossy(&merged.stdout),
        String::from_utf8_lossy(&json.stdout)
    );
    let merged = hil(&["gap", "--merge", &a, &b, &a]);
    ok(&merged);
    assert!(
        merged.stdout == text.stdout,
        "merged:\n{}\none machine:\n{}",
        String::from_utf8_lossy(&merged.stdout),
        String::from_utf8_lossy(&text.stdout)
    );

    // A shard missing.
    refused(&hil(&["gap", "--merge", &a]), "shards 2 of 2 are missing");

    // Shard 2 of other data: its dataset hash differs.
    let edit = |name: &str, change: &dyn Fn(&mut serde_json::Value)| -> String {
        let mut v: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(&b).unwrap()).unwrap();
        change(&mut v);
        let path = dir.join(name);
        std::fs::write(&path, serde_json::to_string(&v).unwrap()).unwrap();
        path.display().to_string()
    };
    let other = edit("other-data.json", &|v| {
        v["plan"]["dataset_hash"] = "0123456789abcdef".into()
    });
    let out = hil(&["gap", "--merge", &a, &other]);
    refused(&out, &other);
    refused(&out, "another plan");
    refused(&out, "dataset hash");

    // Shard 2 given twice, one copy with another fitted value.
    let changed = edit("changed.json", &|v| {
        let x = v["candidates"][0]["candidate"]["value"].as_f64().unwrap();
        v["candidates"][0]["candidate"]["value"] = (x + 0.001).into();
    });
    let out = hil(&["gap", "--merge", &a, &b, &changed]);
    refused(&out, "shard 2/2 is in");
    refused(&out, &changed);
}

/// `hil bench --diagnosis`'s measurement on a tiny dataset (one run per test, 100 mm legs,
/// a 3-point grid, one run per centroid): both job counts timed, their runs counted alike, the ratio and the
/// budget's verdict there.
#[test]
fn the_diagnosis_benchmark_produces_its_numbers() {
    let bench = BenchModel::new(support::firmware("robust"), RobotConfig::default(), 1);
    // The fewest runs that still take every kind of fit: one run per centroid, one pair
    // and one iteration of each joint fit, no regression steps (`gap_bench_joint` runs them).
    let default = SelectOptions::default();
    let opts = SelectOptions {
        shortlist: 0,
        grid: 3,
        refine: 1,
        fold_refine: 1,
        fit: gap::FitOptions {
            centroid_runs: 1,
            ..default.fit.clone()
        },
        joint_pairs: 1,
        joint_iterations: 1,
        joint_fold_iterations: 1,
        joint_regression_steps: 0,
        ..default
    };
    let speed = measure_diagnosis(&SpeedPlan {
        bench: &bench,
        hidden: &DEFAULT_CASES[..1],
        leg_mm: 100.0,
        runs_per_group: 1,
        seed: 3,
        jobs: vec![2],
        opts: &opts,
        progress: &|_| {},
    })
    .unwrap();
    let text = speed.render();
    assert_eq!(speed.data_runs, 4, "{text}");
    let jobs: Vec<usize> = speed.timed.iter().map(|t| t.jobs).collect();
    assert_eq!(jobs, [1, 2], "{text}");
    let runs = speed.timed[0].bench_runs;
    assert!(runs > 0, "{text}");
    for t in &speed.timed {
        assert_eq!(t.bench_runs, runs, "{text}");
        assert!(t.wall_s > 0.0 && t.runs_per_s.is_finite() && t.runs_per_s > 0.0);
    }
    assert_eq!(speed.speedups.len(), 1, "{text}");
    assert!(speed.speedups[0].is_finite() && speed.speedups[0] > 0.0);
    assert_eq!(speed.two_jobs_wall_s, Some(speed.timed[1].wall_s));
    assert!(speed.within_budget.is_some());
    assert!(text.contains("speed-up with 2 jobs"), "{text}");
    assert!(text.contains("joint fits: "), "{text}");
    // The cost of each kind of fit: singles, pairs, triples, their runs adding up to the
    // diagnosis' and their wall times its share of the 2-job timing.
    let kinds: Vec<&str> = speed.costs.iter().map(|c| c.kind).collect();
    assert_eq!(kinds, ["single", "pair", "triple"], "{text}");
    assert!(speed.costs[1].fits > 0, "no joint fit was measured: {text}");
    let sum: usize = speed.costs.iter().map(|c| c.bench_runs).sum();
    assert_eq!(sum, runs, "{text}");
    assert_eq!(speed.costs[1].fits + speed.costs[2].fits, speed.joint_fits);
    assert_eq!(
        speed.costs[1].bench_runs + speed.costs[2].bench_runs,
        speed.joint_runs
    );
    let wall: f64 = speed.costs.iter().map(|c| c.wall_s).sum();
    assert!(
        (wall - speed.timed[1].wall_s).abs() <= 1e-6 * wall,
        "{text}"
    );
    assert!(text.contains("runs per fit"), "{text}");
    assert!(text.contains("budget 900 s on 2 cores"), "{text}");
}
