//! A UMBmark split into shards and merged is exactly what one machine
//! produces; runs in parallel give the same result as runs in series.

#[path = "support/mod.rs"]
mod support;

use hil::bench::BenchOptions;
use hil::umbmark::{execute, merge, report, Partial, Plan, Shard};

fn run(plan: &Plan, shard: Option<Shard>, threads: usize) -> Partial {
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
    Partial {
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
    let a: Partial = serde_json::from_str(&serde_json::to_string(&a).unwrap()).unwrap();
    let b: Partial = serde_json::from_str(&serde_json::to_string(&b).unwrap()).unwrap();
    let merged = merge(vec![b, a]).unwrap();
    let json = |p: &Partial| {
        serde_json::to_string(&report(p, 130.0, calib::Solution::FirstOrder).unwrap()).unwrap()
    };
    assert_eq!(json(&merged), json(&whole));
    assert_eq!(json(&serial), json(&whole));
    // A shard missing is an error that names the runs.
    let only_a = run(&plan, Some(Shard { k: 1, n: 2 }), 2);
    let err = merge(vec![only_a]).unwrap_err().to_string();
    assert!(err.contains("missing"), "{err}");
}
