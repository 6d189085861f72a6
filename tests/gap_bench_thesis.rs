//! The thesis' real data (`fixtures/real/thesis`) on the bench: trained on UMBmark
//! experiment 1, the bench fits Borenstein's pair (Ed, the wheels' diameter ratio, and Eb,
//! the wheelbase) jointly, as the forward selection of `hil gap --bench` does, from the
//! nominal robot and from the kinematic surrogate's values, and predicts the held-out
//! experiments (UMBmark 2 and 3, run with the thesis' corrections, and both triangle
//! experiments). The held-out gap must be cut at least as far as the kinematic diagnosis'
//! pair cuts it, as that diagnosis of the same split computes it here (92.2 %, 240.2 ->
//! 18.6 cm; the bench measured 93.1 %, 202.0 -> 14.0 cm). The bench needs no second
//! effect: its nominal robot already has the firmware's own turn errors, which the
//! kinematic pair's second effect stood for, so Eb is fitted within two standard errors of
//! 1 (not determined: the forward selection keeps Ed alone) while Ed is determined. Only
//! the pair is fitted (231 bench runs): the whole diagnosis of these data takes far longer.

#[path = "support/mod.rs"]
mod support;

use gap::effects::{WHEELBASE_RATIO, WHEEL_DIAMETER_RATIO};
use gap::{EffectParams, Scorer, SplitRule};
use hil::runs::gap_bench::{fit_effects_jointly, kinematic_shortlist, BenchModel, SelectOptions};
use plant_model::RobotConfig;

#[test]
fn the_thesis_held_out_gap_is_cut_as_far_as_the_kinematic_pair_cuts_it() {
    let root = hil::paths::workspace_root();
    let manifests = gap::load_dir(root.join("fixtures/real/thesis")).unwrap();
    let with_endpoints: Vec<_> = manifests
        .iter()
        .filter(|m| m.manifest.endpoints.is_some())
        .cloned()
        .collect();
    let (data, _) = gap::load_dataset(&with_endpoints).unwrap();
    let (train, held) = data.split(&SplitRule::thesis_default(&manifests)).unwrap();
    let nominal = RobotConfig::load(root.join("fixtures/robots/henrytwo-ideal.toml")).unwrap();
    let bench = BenchModel::new(support::firmware("robust"), nominal, 2);
    let opts = SelectOptions::default();
    let effects = [WHEEL_DIAMETER_RATIO, WHEELBASE_RATIO];
    let surrogate = kinematic_shortlist(&train, &held, &gap::DiagnoseOptions::default()).unwrap();
    // The bar: the kinematic diagnosis' own cut of the systematic gap, its winner's (a pair).
    let kin = gap::diagnose(
        &gap::KinematicModel,
        &train,
        &held,
        &gap::DiagnoseOptions::default(),
    )
    .unwrap();
    assert_eq!(kin.shrink.winner.len(), 2, "{:?}", kin.shrink.winner);
    let kinematic_cut = 100.0 * kin.shrink.reduction_systematic;
    let mut starts = vec![vec![1.0, 1.0]];
    for (e, v) in &surrogate.fits {
        if e.iter().map(String::as_str).eq(effects) {
            starts.push(v.clone());
        }
    }
    let f = fit_effects_jointly(&bench, &train, &held, &opts, &effects, &starts).unwrap();
    let before = Scorer::new(&bench, &train, &opts.fit)
        .gap(&EffectParams::new(), held.groups())
        .unwrap();
    // As the kinematic diagnosis counts its 92 % (240 -> 20 cm): the centroid distance.
    let cut = 100.0 * (1.0 - f.heldout.systematic_cm / before.systematic_cm);
    let groups: Vec<String> = f
        .heldout
        .groups
        .iter()
        .map(|g| format!("{} {:.1} cm", g.group, g.systematic_cm))
        .collect();
    let report = format!(
        "{} = {:?} ± {:?} from {starts:?}: training χ² {:.1}, held-out gap {:.1} -> {:.1} cm, \
         beyond noise {:.1} -> {:.1} cm (cut {cut:.1} %, the kinematic pair's {kinematic_cut:.1} %); \
         {}; {} bench runs",
        f.label(),
        f.values,
        f.std_err,
        f.train_chi2,
        before.systematic_cm,
        f.heldout.systematic_cm,
        before.systematic_excess_cm,
        f.heldout.systematic_excess_cm,
        groups.join(", "),
        f.bench_runs
    );
    eprintln!("{report}");
    assert!(cut >= kinematic_cut, "{report}");
    let (ed, eb) = (f.values[0], f.values[1]);
    let (ed_se, eb_se) = (f.std_err[0].unwrap(), f.std_err[1].unwrap());
    assert!(
        (ed - 1.0).abs() > 2.0 * ed_se,
        "Ed not determined: {report}"
    );
    assert!(
        (eb - 1.0).abs() <= 2.0 * eb_se && !f.determined,
        "Eb determined: {report}"
    );
}
