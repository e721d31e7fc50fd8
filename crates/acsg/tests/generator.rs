//! The generator against hand-derived state sets, every witness re-verified through the
//! contact module.

use acsg::contact::{ContactKind, ContactScene};
use acsg::graph::{Graph, Options, generate};
use acsg::model::Part;
use acsg::pose::Bounds;
use acsg::tolerance::{CONTACT_REL, SEPARATION_REL};
use glam::DAffine3;

/// Every state's witness shows exactly that state, inside the bounds, with no
/// penetration and every other pair clear.
fn verify_witnesses(fixed: &Part, moving: &Part, bounds: &Bounds, graph: &Graph) {
    let scene = ContactScene::new(fixed, moving);
    for state in &graph.states[1..] {
        let pose = state.witness.expect("every contact state has a witness");
        assert!(bounds.contains(&pose, 1e-9, 1e-12), "{pose:?} outside the bounds");
        let report = scene.evaluate(&pose.to_affine(&DAffine3::IDENTITY), CONTACT_REL);
        assert_eq!(report.contacts, state.contacts, "state {} at {pose:?}", state.id);
        assert_eq!(report.penetration, 0.0);
        if let Some(gap) = report.min_gap {
            assert!(gap >= SEPARATION_REL * scene.scale(), "a pair only {gap} apart");
        }
    }
}

fn kinds(graph: &Graph) -> Vec<Vec<ContactKind>> {
    let mut out: Vec<Vec<ContactKind>> = graph.states[1..]
        .iter()
        .map(|s| s.contacts.iter().map(|c| c.kind).collect())
        .collect();
    out.sort();
    out
}

#[test]
fn a_cube_free_to_turn_on_a_slab_has_26_states() {
    let (slab, cube) = acsg::examples::cube_and_slab();
    let pi = std::f64::consts::PI;
    let bounds = Bounds::try_new([-1.0, -1.0, 0.0, -pi, -pi, -pi], [1.0, 1.0, 30.0, pi, pi, pi]).unwrap();
    let graph = generate(&slab, &cube, &bounds, &Options::default());
    eprintln!("{:#?}", graph.stats);
    let k = kinds(&graph);
    let count = |kind: ContactKind| k.iter().filter(|s| **s == [kind]).count();
    assert_eq!(
        (count(ContactKind::FaceVertex), count(ContactKind::FaceEdge), count(ContactKind::FaceFace)),
        (8, 12, 6)
    );
    assert_eq!(k.len(), 26);
    verify_witnesses(&slab, &cube, &bounds, &graph);
}

#[test]
fn a_cube_tilting_10_degrees_on_a_slab_has_9_states() {
    let (slab, cube) = acsg::examples::cube_and_slab();
    let (tilt, pi) = (10f64.to_radians(), std::f64::consts::PI);
    let bounds = Bounds::try_new([-1.0, -1.0, 0.0, -tilt, -tilt, -pi], [1.0, 1.0, 30.0, tilt, tilt, pi]).unwrap();
    let graph = generate(&slab, &cube, &bounds, &Options::default());
    let k = kinds(&graph);
    let count = |kind: ContactKind| k.iter().filter(|s| **s == [kind]).count();
    assert_eq!(
        (count(ContactKind::FaceVertex), count(ContactKind::FaceEdge), count(ContactKind::FaceFace)),
        (4, 4, 1)
    );
    assert_eq!(k.len(), 9);
    verify_witnesses(&slab, &cube, &bounds, &graph);
}

#[test]
fn the_papers_example() {
    let (l_block, box_part) = acsg::examples::l_block_and_box();
    let bounds = acsg::examples::paper_bounds();
    let started = std::time::Instant::now();
    let graph = generate(&l_block, &box_part, &bounds, &Options::default());
    eprintln!("{:#?} in {:?}", graph.stats, started.elapsed());
    for s in &graph.states {
        eprintln!("{} {:?} dof {}", s.id, s.contacts.iter().map(|c| format!("{}-{}", c.fixed, c.moving)).collect::<Vec<_>>(), s.dof);
    }
    verify_witnesses(&l_block, &box_part, &bounds, &graph);
}
