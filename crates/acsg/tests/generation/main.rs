//! The generator's end-to-end tests, in one binary so that the built-in example's
//! graph (the longest run they share) is generated once:
//!
//! - `generator`: hand-derived state sets, witnesses re-verified, neighbours, the same
//!   bytes for any thread count, the same states whatever the file;
//! - `recall`: recall against the independent rotation-slice oracle;
//! - `strategies`: the paper's algorithm as a baseline against the default search;
//! - `work_limit`: a run cut short by its work limit.

#[path = "../common/mod.rs"]
mod common;
mod generator;
mod recall;
mod strategies;
mod work_limit;

use std::sync::OnceLock;

use acsg::contact::ContactScene;
use acsg::graph::{Graph, Options, generate};
use acsg::model::Part;
use acsg::pose::Bounds;
use acsg::tolerance::{CONTACT_REL, SEPARATION_REL};
use glam::DAffine3;

/// The built-in example's graph with the default options, generated once for every
/// test that reads it (its stage times zeroed).
fn built_in_example() -> &'static Graph {
    static RUN: OnceLock<Graph> = OnceLock::new();
    RUN.get_or_init(|| {
        let (l_block, box_part) = acsg::examples::l_block_and_box();
        let mut graph = generate(
            &l_block,
            &box_part,
            &acsg::examples::paper_bounds(),
            &Options::default(),
        );
        graph.stats.stage1_seconds = 0.0;
        graph.stats.stage2_seconds = 0.0;
        graph
    })
}

/// Every state's witness shows exactly that state at the contact tolerance, inside the
/// bounds, with no penetration and every other pair at least the separation apart, and
/// no rule of the prover excludes it.
fn verify_witnesses(fixed: &Part, moving: &Part, bounds: &Bounds, graph: &Graph) {
    let scene = ContactScene::new(fixed, moving);
    let problem = acsg::feasibility::Problem::new(fixed, moving, *bounds, DAffine3::IDENTITY);
    for state in &graph.states[1..] {
        let pose = state.witness.expect("every contact state has a witness");
        assert!(bounds.contains(&pose, 1e-9, 1e-12), "{pose:?} outside the bounds");
        let report = scene.evaluate(&pose.to_affine(&DAffine3::IDENTITY), CONTACT_REL);
        assert_eq!(report.contacts, state.contacts, "state {} at {pose:?}", state.id);
        assert_eq!(report.penetration, 0.0, "state {} penetrates", state.id);
        if let Some(gap) = report.min_gap {
            assert!(gap >= SEPARATION_REL * scene.scale(), "a pair only {gap} apart");
        }
        // No rule of the prover excludes the pose that shows the state: the rules are
        // sound on the generator's own witnesses too.
        let at = Bounds::try_new(pose.to_array(), pose.to_array()).unwrap();
        let rule = problem
            .exclusion(&state.contacts, &at)
            .or_else(|| problem.last_exclusion(&state.contacts, &at));
        assert_eq!(rule, None, "state {} {:?} at {pose:?}", state.id, state.contacts);
    }
}
