//! The paper's algorithm as a baseline (`Strategy::Paper`) against the default search:
//! on the same input the default finds every state the baseline finds, and every
//! baseline witness passes the contact module's check on its own.

use std::collections::BTreeSet;
use std::path::PathBuf;

use acsg::contact::PrincipalContact;
use acsg::graph::{Graph, Options, Strategy, generate};
use acsg::model::Part;
use acsg::pose::Bounds;

use crate::{built_in_example, verify_witnesses};

fn fixture(name: &str) -> Part {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../fixtures")
        .join(name);
    Part::from_path(&path).unwrap_or_else(|e| panic!("{name}: {e}"))
}

fn run(fixed: &Part, moving: &Part, bounds: &Bounds, strategy: Strategy) -> Graph {
    let options = Options {
        strategy,
        ..Options::default()
    };
    generate(fixed, moving, bounds, &options)
}

fn states(graph: &Graph) -> BTreeSet<Vec<PrincipalContact>> {
    graph.states.iter().map(|s| s.contacts.clone()).collect()
}

/// Runs both strategies; checks the baseline's witnesses, its completeness record (it
/// proves nothing, so it is never complete and every candidate it did not witness is
/// undecided over the whole bounds), and that the default's states hold all of its
/// states. Both graphs (the baseline's first), for further checks.
fn compare(fixed: &Part, moving: &Part, bounds: &Bounds) -> Graph {
    compare_with(fixed, moving, bounds, &run(fixed, moving, bounds, Strategy::Full))
}

/// [`compare`] with the default's graph given.
fn compare_with(fixed: &Part, moving: &Part, bounds: &Bounds, full: &Graph) -> Graph {
    let paper = run(fixed, moving, bounds, Strategy::Paper);
    verify_witnesses(fixed, moving, bounds, &paper);
    assert_eq!(paper.strategy, Strategy::Paper);
    assert!(!paper.is_complete());
    let s = &paper.stats;
    assert_eq!(s.infeasible, 0, "the paper's algorithm proves nothing infeasible");
    assert_eq!(s.witnessed + s.undecided, s.candidates);
    assert_eq!(paper.undecided.len(), s.undecided);
    assert!(paper.undecided.iter().all(|u| u.open == *bounds));
    // Every PPC is optimised; no sound exclusion, no descent.
    assert_eq!((s.stage1_searched, s.ppc_unreachable, s.descents), (s.ppc, 0, 0));
    assert_eq!(s.stage2_searched, s.stage2_candidates);
    let missing: Vec<_> = states(&paper).difference(&states(full)).cloned().collect();
    assert!(
        missing.is_empty(),
        "the default misses {} of the baseline's {} states: {missing:?}",
        missing.len(),
        paper.states.len()
    );
    paper
}

#[test]
fn on_the_built_in_example_the_default_finds_every_state_of_the_papers_algorithm() {
    let (l_block, box_part) = acsg::examples::l_block_and_box();
    let paper = compare_with(&l_block, &box_part, &acsg::examples::paper_bounds(), built_in_example());
    assert_eq!(paper.stats.ppc, 328);
    // The four bottom corners of the box on the floor are feasible PPCs, and stage 2
    // grows states from them.
    assert!(paper.stats.feasible_ppc >= 4);
    assert!(paper.states.iter().any(|s| s.contacts.len() >= 2));
}

#[test]
fn on_a_cube_tilting_on_a_slab_the_default_finds_every_state_of_the_papers_algorithm() {
    let (slab, cube) = acsg::examples::cube_and_slab();
    let pi = std::f64::consts::PI;
    let tilt = 10f64.to_radians();
    let bounds = Bounds::try_new([-1.0, -1.0, 0.0, -tilt, -tilt, -pi], [1.0, 1.0, 30.0, tilt, tilt, pi]).unwrap();
    let paper = compare(&slab, &cube, &bounds);
    // The corners on the slab are its feasible PPCs; two of them make an edge on the
    // slab.
    assert_eq!(paper.stats.feasible_ppc, 4);
    assert!(paper.states.iter().any(|s| s.contacts.len() == 1 && s.dof == 4));
}

#[test]
fn with_the_rotation_pinned_the_papers_algorithm_finds_less_than_the_default() {
    // The square peg over the square hole, turned neither way: a corner of the peg
    // cannot touch a face alone (its bottom face comes down flat), so no PPC is
    // feasible and the paper's algorithm, which grows from PPCs only, finds nothing.
    let (block, peg) = (fixture("block_with_hole.off"), fixture("peg.off"));
    let bounds = Bounds::try_new([-2.0, -2.0, 0.0, 0.0, 0.0, 0.0], [2.0, 2.0, 45.0, 0.0, 0.0, 0.0]).unwrap();
    let full = run(&block, &peg, &bounds, Strategy::Full);
    let paper = compare_with(&block, &peg, &bounds, &full);
    assert_eq!(paper.stats.feasible_ppc, 0);
    assert_eq!(paper.states.len(), 1, "free space alone");
    assert!(full.is_complete() && full.states.len() > 1);
}
