//! A UMBmark split into shards and merged is exactly what one machine
//! produces; runs in parallel give the same result as runs in series.

#[path = "support/mod.rs"]
mod support;

use support::hil;

use hil::bench::BenchOptions;
use hil::runs::odometry::{execute, merge, report, Plan, RunSet, Shard};

fn run(plan: &Plan, shard: Option<Shard>, threads: usize) -> RunSet {
    let fw = support::firmware("robust");
    let robot = support::robot("henrytwo-ideal");
    let specs = match shard {
        Some(s) => plan.shard(s),
        None => plan.runs(),
    };
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    let runs = pool
        .install(|| {
            execute(
                &fw,
                &robot,
                plan,
                &specs,
                BenchOptions::default(),
                &|_, _| {},
            )
        })
        .unwrap();
    RunSet {
        kind: "umbmark-partial".into(),
        plan: plan.clone(),
        shard,
        runs,
    }
}

#[test]
fn shards_merge_into_the_single_machine_result() {
    let fw = support::firmware("robust");
    let plan = Plan::new(
        300.0,
        42,
        &support::robot("henrytwo-ideal"),
        &Default::default(),
        &fw,
        Default::default(),
    );
    let whole = run(&plan, None, 2);
    let serial = run(&plan, None, 1);
    let a = run(&plan, Some(Shard { k: 1, n: 2 }), 2);
    let b = run(&plan, Some(Shard { k: 2, n: 2 }), 2);
    assert!(!a.runs.is_empty() && !b.runs.is_empty());
    // Through JSON, as shards travel between machines.
    let a: RunSet = serde_json::from_str(&serde_json::to_string(&a).unwrap()).unwrap();
    let b: RunSet = serde_json::from_str(&serde_json::to_string(&b).unwrap()).unwrap();
    let merged = merge(vec![b, a]).unwrap();
    let json = |p: &RunSet| {
        serde_json::to_string(&report(p, 130.0, calib::Solution::FirstOrder).unwrap()).unwrap()
    };
    assert_eq!(json(&merged), json(&whole));
    assert_eq!(json(&serial), json(&whole));
    // A shard missing is an error that names the runs.
    let only_a = run(&plan, Some(Shard { k: 1, n: 2 }), 2);
    let err = merge(vec![only_a]).unwrap_err().to_string();
    assert!(err.contains("missing"), "{err}");
}

/// `hil merge --json` of the shards prints the bytes `hil umbmark --json
/// --deterministic` prints for the same work (before, its keys came in
/// another order). A shard given twice is merged once; two different copies
/// of one run are refused (exit 2), on one line naming the run and both files,
/// whichever comes first.
#[test]
fn the_merge_command_prints_the_single_machine_bytes_and_refuses_conflicts() {
    let dir = std::env::temp_dir().join(format!("hil-merge-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let d = dir.display().to_string();
    let common = ["--leg-mm", "300", "--seed", "5", "--deterministic"];
    let whole = hil(&[&["umbmark", "--json"][..], &common].concat());
    assert!(
        whole.status.success(),
        "{}",
        String::from_utf8_lossy(&whole.stderr)
    );
    for k in ["1/2", "2/2"] {
        let out = hil(&[&["umbmark", "--shard", k, "--out", &d][..], &common].concat());
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
    }
    let a = dir.join("umbmark-shard-1-of-2.json").display().to_string();
    let b = dir.join("umbmark-shard-2-of-2.json").display().to_string();
    let merged = hil(&["merge", &b, &a, "--json"]);
    assert!(
        merged.status.success(),
        "{}",
        String::from_utf8_lossy(&merged.stderr)
    );
    assert!(
        merged.stdout == whole.stdout,
        "merged:\n{}\nsingle machine:\n{}",
        String::from_utf8_lossy(&merged.stdout),
        String::from_utf8_lossy(&whole.stdout)
    );
    let again = hil(&["merge", &a, &b, &a, "--json"]);
    assert!(
        again.status.success(),
        "{}",
        String::from_utf8_lossy(&again.stderr)
    );
    assert!(
        again.stdout == whole.stdout,
        "a shard given twice changed the result"
    );

    // The same shard with run 2's end point changed.
    let mut v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&a).unwrap()).unwrap();
    let run = v["runs"]
        .as_array_mut()
        .unwrap()
        .iter_mut()
        .find(|r| r["spec"]["index"] == 2)
        .unwrap();
    run["x_cm"] = serde_json::json!(run["x_cm"].as_f64().unwrap() + 1.0);
    let edited = dir.join("edited.json").display().to_string();
    std::fs::write(&edited, serde_json::to_string(&v).unwrap()).unwrap();
    for order in [[&a, &edited, &b], [&edited, &b, &a]] {
        let out = hil(&["merge", order[0], order[1], order[2]]);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{err}");
        assert_eq!(err.trim_end().lines().count(), 1, "{err}");
        assert!(
            err.contains("run 2") && err.contains(&a) && err.contains(&edited),
            "{err}"
        );
        assert!(
            out.stdout.is_empty(),
            "printed a result: {}",
            String::from_utf8_lossy(&out.stdout)
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}
