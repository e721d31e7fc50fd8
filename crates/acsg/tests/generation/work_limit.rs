//! A run cut short by its work limit (`Options::work_limit`): it says so, keeps only
//! verified states (a subset of the complete graph's), accounts for every candidate it
//! met, gives the same graph for any thread count, and a limit the run never reaches
//! changes nothing.

use std::collections::BTreeSet;

use acsg::contact::PrincipalContact;
use acsg::graph::{Graph, Options, SEARCH_WORK, generate};
use acsg::pose::Bounds;

use crate::{built_in_example, verify_witnesses};

fn states(graph: &Graph) -> BTreeSet<Vec<PrincipalContact>> {
    graph.states.iter().map(|s| s.contacts.clone()).collect()
}

/// What a test compares between two runs (everything but the stage times): the states
/// with their DOF, the edges, the undecided candidates.
type Outcome = (
    Vec<(Vec<PrincipalContact>, u8)>,
    Vec<[usize; 2]>,
    Vec<Vec<PrincipalContact>>,
);

fn outcome(graph: &Graph) -> Outcome {
    (
        graph.states.iter().map(|s| (s.contacts.clone(), s.dof)).collect(),
        graph.edges.clone(),
        graph.undecided.iter().map(|u| u.contacts.clone()).collect(),
    )
}

#[test]
fn a_run_cut_short_by_its_work_limit_says_so_and_keeps_only_verified_states() {
    let (l_block, box_part) = acsg::examples::l_block_and_box();
    let bounds = acsg::examples::paper_bounds();
    let complete = built_in_example();
    assert!(complete.is_complete());
    let limited = |threads: usize| {
        let options = Options {
            work_limit: Some(20_000),
            threads,
            ..Options::default()
        };
        generate(&l_block, &box_part, &bounds, &options)
    };
    let graph = limited(2);
    let s = &graph.stats;
    assert!(s.work_limit_reached);
    assert!(!graph.is_complete());
    // Every candidate met is accounted for; those met after the limit got the cheap
    // proofs only, so some stay undecided.
    assert_eq!(s.witnessed + s.infeasible + s.undecided, s.candidates);
    assert_eq!(graph.undecided.len(), s.undecided);
    assert!(s.undecided > 0);
    assert_eq!(s.proved_last, 0, "the last proofs do not run past the limit");
    // The limit stops the run soon after it is reached (one batch of decisions).
    assert!(s.boxes + SEARCH_WORK as usize * (s.stage1_optimisations + s.stage2_optimisations) < 200_000);
    // What it reports is true: each witness checks out on its own, and (the complete
    // graph holding every state) each state is one of the complete graph's.
    verify_witnesses(&l_block, &box_part, &bounds, &graph);
    let extra: Vec<_> = states(&graph).difference(&states(complete)).cloned().collect();
    assert!(extra.is_empty(), "states not in the complete graph: {extra:?}");
    assert!(graph.states.len() < complete.states.len());
    // Checked between batches in a fixed order: the same graph on one thread.
    assert_eq!(outcome(&limited(1)), outcome(&graph));
}

#[test]
fn a_work_limit_the_run_never_reaches_changes_nothing() {
    let (slab, cube) = acsg::examples::cube_and_slab();
    let tilt = 10f64.to_radians();
    let pi = std::f64::consts::PI;
    let bounds = Bounds::try_new([-1.0, -1.0, 0.0, -tilt, -tilt, -pi], [1.0, 1.0, 30.0, tilt, tilt, pi]).unwrap();
    let free = generate(&slab, &cube, &bounds, &Options::default());
    let s = &free.stats;
    let work = (s.boxes + SEARCH_WORK as usize * (s.stage1_optimisations + s.stage2_optimisations)) as u64;
    let run = |limit: u64| {
        let options = Options {
            work_limit: Some(limit),
            ..Options::default()
        };
        generate(&slab, &cube, &bounds, &options)
    };
    let roomy = run(work + 1);
    assert!(!roomy.stats.work_limit_reached);
    assert_eq!(roomy.is_complete(), free.is_complete());
    assert_eq!(outcome(&roomy), outcome(&free));
    // Half the work the run needs, and it says it was cut short.
    let tight = run(work / 2);
    assert!(tight.stats.work_limit_reached && !tight.is_complete());
    verify_witnesses(&slab, &cube, &bounds, &tight);
}
