//! The generator against hand-derived state sets, every witness re-verified through the
//! contact module.

use acsg::contact::{ContactKind, ContactScene};
use acsg::graph::{Graph, Options, generate};
use acsg::model::{ElementId, Part};
use acsg::pose::Bounds;
use acsg::tolerance::CONTACT_REL;
use glam::DAffine3;

use crate::{built_in_example, verify_witnesses};

/// The cube on the slab with x, y within ±1, z from 0 to 30, yaw free and the tilt
/// about x and y within ±`tilt`: every witness verified, then the numbers of single f-v,
/// f-e and f-f states and of all states besides free space.
fn cube_on_slab(tilt: f64) -> ((usize, usize, usize), usize) {
    let (slab, cube) = acsg::examples::cube_and_slab();
    let pi = std::f64::consts::PI;
    let bounds = Bounds::try_new([-1.0, -1.0, 0.0, -tilt, -tilt, -pi], [1.0, 1.0, 30.0, tilt, tilt, pi]).unwrap();
    let graph = generate(&slab, &cube, &bounds, &Options::default());
    verify_witnesses(&slab, &cube, &bounds, &graph);
    let states = &graph.states[1..];
    let single = |kind: ContactKind| {
        states
            .iter()
            .filter(|s| s.contacts.len() == 1 && s.contacts[0].kind == kind)
            .count()
    };
    (
        (
            single(ContactKind::FaceVertex),
            single(ContactKind::FaceEdge),
            single(ContactKind::FaceFace),
        ),
        states.len(),
    )
}

#[test]
fn a_cube_free_to_turn_on_a_slab_has_26_states() {
    assert_eq!(cube_on_slab(std::f64::consts::PI), ((8, 12, 6), 26));
}

#[test]
fn a_cube_tilting_10_degrees_on_a_slab_has_9_states() {
    assert_eq!(cube_on_slab(10f64.to_radians()), ((4, 4, 1), 9));
}

/// The vertices and edges in an element's closure, for the test's own one-PPC check.
fn closure(part: &Part, e: ElementId) -> (Vec<ElementId>, Vec<ElementId>) {
    match e {
        ElementId::Vertex(v) => (vec![ElementId::Vertex(v)], vec![]),
        ElementId::Edge(x) => (
            part.edge(x).vertices.iter().map(|&v| ElementId::Vertex(v)).collect(),
            vec![ElementId::Edge(x)],
        ),
        ElementId::Face(f) => (
            part.face(f)
                .loops
                .iter()
                .flat_map(|l| l.vertices.iter().map(|&v| ElementId::Vertex(v)))
                .collect(),
            part.face(f)
                .loops
                .iter()
                .flat_map(|l| l.edges.iter().map(|&x| ElementId::Edge(x)))
                .collect(),
        ),
    }
}

/// A graph's JSON document (the caller zeroes its stage times).
fn document(graph: &Graph, fixed: &Part, moving: &Part, bounds: &Bounds) -> String {
    acsg::graph::Document::new(graph, fixed, moving, bounds, &Options::default(), ["a", "b"]).to_json()
}

#[test]
fn the_built_in_example_has_no_redundant_state_and_a_connected_graph_of_touching_regions() {
    let (l_block, box_part) = acsg::examples::l_block_and_box();
    assert_eq!(acsg::model::ppc_count(&l_block, &box_part).total(), 328);
    let bounds = acsg::examples::paper_bounds();
    let graph = built_in_example();
    assert_eq!(graph.stats.ppc, 328);
    // Every state is P(X) at its witness (so none is a redundant description), and the
    // states are distinct.
    verify_witnesses(&l_block, &box_part, &bounds, graph);
    let distinct: std::collections::BTreeSet<_> = graph.states.iter().map(|s| s.contacts.clone()).collect();
    assert_eq!(distinct.len(), graph.states.len());
    assert!(
        graph.states.iter().all(|s| !s.degenerate),
        "degenerate states are off by default"
    );
    // The floor contacts of the box's bottom corners (found by hand in stage 1's test)
    // are there.
    assert!(graph.states.iter().filter(|s| s.contacts.len() == 1).count() >= 4);

    // Every edge joins states one PPC apart: checked at the larger state's witness, every
    // contact of the smaller one still touches there (its elements' closures meet), and
    // the larger one has one more contact or one contact of higher order.
    let scene = ContactScene::new(&l_block, &box_part);
    for &[a, b] in &graph.edges {
        let (small, large) = (&graph.states[a], &graph.states[b]);
        if a == 0 {
            // Neighbours are states whose regions touch (docs/concepts.md#the-graph): next to
            // the state's witness some pose is free (the parts apart, clean).
            let witness = large.witness.unwrap().to_array();
            let mut rng = 0x5EED_u64 ^ b as u64;
            let free = (0..2000).any(|_| {
                let pose: [f64; 6] = std::array::from_fn(|k| {
                    rng ^= rng << 13;
                    rng ^= rng >> 7;
                    rng ^= rng << 17;
                    let u = (rng >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0;
                    witness[k] + u * if k < 3 { 0.05 } else { 2e-4 }
                });
                let pose = acsg::pose::Pose::from_array(pose);
                let report = scene.evaluate(&pose.to_affine(&DAffine3::IDENTITY), CONTACT_REL);
                bounds.contains(&pose, 0.0, 0.0) && report.contacts.is_empty() && report.penetration == 0.0
            });
            assert!(
                free,
                "free space and state {b} ({:?}): no free pose next to its witness",
                large.contacts
            );
            continue;
        }
        let (small, large) = if (small.dof, large.contacts.len()) >= (large.dof, small.contacts.len()) {
            (small, large)
        } else {
            (large, small)
        };
        let pose = large.witness.unwrap().to_affine(&DAffine3::IDENTITY);
        for pc in &small.contacts {
            // The small state's contact still touches at the large state's witness: some
            // vertex or edge of one element's closure lies on the other's closure.
            let report = scene.evaluate(&pose, CONTACT_REL);
            let touching = report.contacts.iter().any(|c| {
                let (fv, fe) = closure(&l_block, c.fixed);
                let (mv, me) = closure(&box_part, c.moving);
                let fixed_ok = c.fixed == pc.fixed || fv.contains(&pc.fixed) || fe.contains(&pc.fixed) || {
                    let (pv, pe) = closure(&l_block, pc.fixed);
                    pv.contains(&c.fixed) || pe.contains(&c.fixed)
                };
                let moving_ok = c.moving == pc.moving || mv.contains(&pc.moving) || me.contains(&pc.moving) || {
                    let (pv, pe) = closure(&box_part, pc.moving);
                    pv.contains(&c.moving) || pe.contains(&c.moving)
                };
                fixed_ok && moving_ok
            });
            assert!(
                touching,
                "edge {a}-{b}: {pc:?} of the smaller state is gone at the larger one's witness"
            );
        }
        assert!(large.dof <= small.dof, "edge {a}-{b} does not constrain more");
    }
    // Connected: a search from free space reaches every state.
    let mut seen = vec![false; graph.states.len()];
    let mut stack = vec![0];
    seen[0] = true;
    while let Some(s) = stack.pop() {
        for &[a, b] in &graph.edges {
            for (x, y) in [(a, b), (b, a)] {
                if x == s && !seen[y] {
                    seen[y] = true;
                    stack.push(y);
                }
            }
        }
    }
    let unreached: Vec<usize> = (0..seen.len()).filter(|&i| !seen[i]).collect();
    assert!(
        unreached.is_empty(),
        "states not connected to free space: {unreached:?}"
    );
}

/// The peg turning about its axis in the plain hole and in the chamfered one (x, y
/// within ±2 mm, yaw within ±2°): every candidate decided (issue 12). The last four
/// left undecided in the plain hole were a vertical edge of the peg crossing a rim edge
/// of the hole alone, which cannot be: below the rim the edge lies in the wall. They
/// are proved since a convex face is tested as one polygon (before, its two triangles
/// let a vertex on their shared diagonal count as off both, along a band of poses).
/// The chamfered hole's last, a vertical edge crossing the hole's lower rim, is proved
/// since the linearised test bounds the turn met with the translation component by
/// component.
#[test]
fn the_peg_turning_in_either_hole_has_a_complete_graph() {
    let fixtures = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures");
    let peg = Part::from_path(&fixtures.join("peg.off")).unwrap();
    let bounds = acsg::task::bounds_from_spec("x=-2:2,y=-2:2,z=0:45,rz=-2:2").unwrap();
    for hole in ["block_with_hole.off", "block_with_chamfered_hole.off"] {
        let block = Part::from_path(&fixtures.join(hole)).unwrap();
        let graph = generate(&block, &peg, &bounds, &Options::default());
        assert!(graph.undecided.is_empty(), "{hole}: {:?}", graph.undecided);
        assert_eq!(graph.stats.undecided, 0, "{hole}");
        assert!(graph.states.len() > 20, "{hole}: {} states", graph.states.len());
        verify_witnesses(&block, &peg, &bounds, &graph);
    }
}

/// The box low over the L-block's step, tipping about x and y by up to 1° (x, y within
/// ±1 mm, z within 0–5 mm): a run with candidates witnessed, proved infeasible and left
/// undecided (seven), small enough to generate twice in the test build (the built-in
/// example takes minutes on one thread there). Tipping about y alone served until the
/// rule `crossing-in-a-face` decided every candidate there, and the chamfered hole with
/// the peg turning about its axis before that (see
/// `the_peg_turning_in_either_hole_has_a_complete_graph`).
#[test]
fn the_output_does_not_depend_on_the_thread_count() {
    let fixtures = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures");
    let block = Part::from_path(&fixtures.join("l_block.off")).unwrap();
    let peg = Part::from_path(&fixtures.join("box.off")).unwrap();
    let bounds = acsg::task::bounds_from_spec("x=-1:1,y=-1:1,z=0:5,rx=-1:1,ry=-1:1").unwrap();
    let on = |threads: usize| {
        let options = Options {
            threads,
            ..Options::default()
        };
        let mut graph = generate(&block, &peg, &bounds, &options);
        graph.stats.stage1_seconds = 0.0;
        graph.stats.stage2_seconds = 0.0;
        graph
    };
    let one = on(1);
    let s = &one.stats;
    assert!(s.witnessed > 0 && s.infeasible > 0 && s.undecided > 0, "{s:?}");
    // The document does not record the thread count: one thread and four give the same
    // bytes.
    assert_eq!(
        document(&one, &block, &peg, &bounds),
        document(&on(4), &block, &peg, &bounds)
    );
}

/// The same parts give the same states (issue 12): the peg read from its OFF file, with
/// every x shifted by 1e-9 L, with its faces listed in reverse order, and from the
/// IGES file in inches (read as millimetres), over the plain hole, within bounds where
/// the decisions are exact enough to settle (the rotation fixed: at identity, the graph
/// is complete; turned a little, every run leaves the same candidate undecided).
#[test]
fn the_same_parts_give_the_same_states_whatever_the_file() {
    let fixtures = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures");
    let block = Part::from_path(&fixtures.join("block_with_hole.off")).unwrap();
    let peg = Part::from_path(&fixtures.join("peg.off")).unwrap();
    let scale = acsg::model::length_scale(&block, &peg);
    // The OFF text with a change to its vertex lines or its face lines.
    let text = std::fs::read_to_string(fixtures.join("peg.off")).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    let vertices = lines[1].split_whitespace().next().unwrap().parse::<usize>().unwrap();
    let (head, rest) = lines.split_at(2);
    let (vertex_lines, face_lines) = rest.split_at(vertices);
    let shifted: Vec<String> = vertex_lines
        .iter()
        .map(|l| {
            let mut c: Vec<f64> = l.split_whitespace().map(|x| x.parse().unwrap()).collect();
            c[0] += 1e-9 * scale;
            format!("{:?} {:?} {:?}", c[0], c[1], c[2])
        })
        .collect();
    let dir = tempfile::tempdir().unwrap();
    let write = |name: &str, body: Vec<String>| {
        let path = dir.path().join(name);
        let all: Vec<String> = head.iter().map(|s| s.to_string()).chain(body).collect();
        std::fs::write(&path, all.join("\n") + "\n").unwrap();
        Part::from_path(&path).unwrap()
    };
    let shifted = write(
        "shifted.off",
        shifted
            .into_iter()
            .chain(face_lines.iter().map(|s| s.to_string()))
            .collect(),
    );
    let reordered = write(
        "reordered.off",
        vertex_lines
            .iter()
            .map(|s| s.to_string())
            .chain(face_lines.iter().rev().map(|s| s.to_string()))
            .collect(),
    );
    let inch = Part::from_path(&fixtures.join("cad/peg_inch.igs")).unwrap();
    let states = |moving: &Part, bounds: &Bounds| {
        let graph = generate(&block, moving, bounds, &Options::default());
        let set: std::collections::BTreeSet<_> = graph.states.iter().map(|s| s.contacts.clone()).collect();
        (set, graph.stats.undecided)
    };
    for (name, rotation) in [("pinned at identity", [0.0; 3]), ("turned", [0.5, -0.3, 0.2])] {
        let r = rotation.map(f64::to_radians);
        let bounds = Bounds::try_new([-2.0, -2.0, 0.0, r[0], r[1], r[2]], [2.0, 2.0, 45.0, r[0], r[1], r[2]]).unwrap();
        let (base, undecided) = states(&peg, &bounds);
        assert!(base.len() > 5, "{name}: {} states", base.len());
        if name.starts_with("pinned") {
            assert_eq!(undecided, 0, "{name}: the graph is complete");
        }
        for (variant, part) in [
            ("shifted by 1e-9 L", &shifted),
            ("faces reversed", &reordered),
            ("inches", &inch),
        ] {
            let (got, _) = states(part, &bounds);
            assert_eq!(got, base, "{name}: the peg {variant} gives other states");
        }
    }
}

/// The plus-shaped peg in its plus-shaped hole, 1 mm clearance on every side, rotation
/// pinned, x and y within ±1 mm: a wall touches only where x or y is at ±1, and there
/// three parallel walls touch at once (an arm's end and the two shoulders beside it),
/// so no single contact holds alone. By hand: free space, 4 sides of three f-f each, 4
/// corners of six (the two sides' contacts), 9 states; the sides' regions (segments of
/// the square's sides, times z) meet free space and the corners next to them, and the
/// corners' regions (points, times z) lie in free space's closure: 4 × 3 + 4 = 16 edges.
#[test]
fn a_plus_peg_pinned_in_its_plus_hole_touches_three_walls_at_once() {
    let fixtures = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures");
    let block = Part::from_path(&fixtures.join("block_with_plus_hole.off")).unwrap();
    let peg = Part::from_path(&fixtures.join("plus_peg.off")).unwrap();
    let bounds = Bounds::try_new([-1.0, -1.0, 0.0, 0.0, 0.0, 0.0], [1.0, 1.0, 45.0, 0.0, 0.0, 0.0]).unwrap();
    let graph = generate(&block, &peg, &bounds, &Options::default());
    verify_witnesses(&block, &peg, &bounds, &graph);
    // The walls each contact of a side holds, as the outward normal of the peg's face.
    let side = |contacts: &[acsg::contact::PrincipalContact]| -> Vec<[i64; 3]> {
        let mut normals: Vec<[i64; 3]> = contacts
            .iter()
            .map(|pc| {
                assert_eq!(pc.kind, ContactKind::FaceFace, "{pc:?} is not a face on a face");
                let ElementId::Face(f) = pc.moving else { unreachable!() };
                peg.face(f).normal.to_array().map(|c| c.round() as i64)
            })
            .collect();
        normals.sort_unstable();
        normals.dedup();
        normals
    };
    let mut by_size = std::collections::BTreeMap::new();
    for state in &graph.states[1..] {
        let walls = side(&state.contacts);
        assert_eq!(
            state.contacts.len(),
            3 * walls.len(),
            "state {} holds {} contacts on {} sides",
            state.id,
            state.contacts.len(),
            walls.len()
        );
        *by_size.entry(state.contacts.len()).or_insert(0) += 1;
    }
    assert_eq!(by_size, std::collections::BTreeMap::from([(3, 4), (6, 4)]));
    assert_eq!(graph.states.len(), 9);
    assert_eq!(graph.edges.len(), 16);
    // Below a corner, five of its six walls cannot touch without the sixth (its face
    // stays flush, over the wall): each such candidate is proved infeasible, none left
    // undecided.
    for u in &graph.undecided {
        let walls = u.contacts.iter().all(|pc| match pc.moving {
            ElementId::Face(f) => pc.kind == ContactKind::FaceFace && peg.face(f).normal.z.abs() < 0.5,
            _ => false,
        });
        assert!(!walls, "walls only, undecided: {:?}", u.contacts);
    }
}
