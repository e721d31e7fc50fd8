//! Recall of the generator against an independent oracle (docs/concepts.md#ground-truth,
//! "Rotation slices"): on fixed rotations the contact translations are the boundary of
//! a union of Minkowski differences of convex pieces, built exactly in test code
//! (`common::slices`); P(X) at poses sampled there is read by an evaluator of the
//! principal-contact rule that shares nothing with the library (`common::principal`).
//!
//! - The oracle is first checked against hand-derived truths (a cube on a slab, two
//!   boxes, the peg over its holes, the L-block and its box, a cube in a notch, the
//!   evaluator at hand-made poses) so a broken oracle cannot pass.
//! - For each pair, every robust state it reads is cross-checked with the library's
//!   `ContactScene` at the same pose, and must be among the generated graph's states.
//!
//! `ACSG_RECALL_DUMP=<dir> cargo test -p acsg --test generation -- --ignored dump` writes the
//! oracle's states per pair as JSON lines, to diff against the generator, and the
//! generated states whose witness the independent evaluator reads otherwise.

use std::collections::BTreeSet;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

use crate::common::principal::{Evaluator, Verdict, describe_state};
use crate::common::slices::{
    Oracle, OracleReport, SampleKind, Slice, SliceOptions, angles_of, check_pieces, checked_pieces,
    minkowski_difference, part_volume_and_moment, piece_from_points, rotation_of, rotation_slices,
};
use acsg::contact::{ContactKind, ContactScene, PrincipalContact};
use acsg::graph::{Graph, Options, generate};
use acsg::model::{EdgeId, ElementId, FaceId, Part, VertexId};
use acsg::pose::{Bounds, Pose};
use acsg::tolerance::{CONTACT_REL, SEPARATION_REL};
use glam::{DAffine3, DMat3, DVec3};
use rayon::prelude::*;

use crate::built_in_example;

fn fixtures() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures")
}

fn fixture(name: &str) -> Part {
    Part::from_path(&fixtures().join(name)).unwrap_or_else(|e| panic!("{name}: {e}"))
}

fn degrees_bounds(min: [f64; 6], max: [f64; 6]) -> Bounds {
    Bounds::from_degrees(min, max).expect("valid bounds")
}

/// Slices given by their angles in degrees.
fn slices_deg(angles: &[[f64; 3]]) -> Vec<Slice> {
    angles
        .iter()
        .map(|a| Slice {
            angles: a.map(f64::to_radians),
            why: "test".into(),
        })
        .collect()
}

fn face_where(part: &Part, normal: DVec3, offset: f64) -> ElementId {
    let i = part
        .faces()
        .iter()
        .position(|f| f.normal.distance(normal) < 1e-12 && (f.offset - offset).abs() < 1e-9)
        .unwrap_or_else(|| panic!("{}: no face with normal {normal} at {offset}", part.name()));
    ElementId::Face(FaceId(i as u32))
}

fn vertex_at(part: &Part, p: DVec3) -> ElementId {
    let i = part
        .vertices()
        .iter()
        .position(|v| v.position.distance(p) < 1e-12)
        .unwrap_or_else(|| panic!("{}: no vertex at {p}", part.name()));
    ElementId::Vertex(VertexId(i as u32))
}

fn edge_between(part: &Part, p: DVec3, q: DVec3) -> ElementId {
    let (a, b) = (vertex_at(part, p), vertex_at(part, q));
    let i = part
        .edges()
        .iter()
        .position(|e| {
            let ends = e.vertices.map(ElementId::Vertex);
            ends == [a, b] || ends == [b, a]
        })
        .unwrap_or_else(|| panic!("{}: no edge {p} - {q}", part.name()));
    ElementId::Edge(EdgeId(i as u32))
}

fn contact(fixed: ElementId, moving: ElementId, kind: ContactKind) -> PrincipalContact {
    PrincipalContact { fixed, moving, kind }
}

fn states_of(report: &OracleReport) -> BTreeSet<Vec<PrincipalContact>> {
    report.states.iter().map(|s| s.contacts.clone()).collect()
}

fn assert_consistent(report: &OracleReport) {
    assert!(
        report.inconsistencies.is_empty(),
        "the slice construction and the evaluator disagree: {:?}",
        report.inconsistencies
    );
}

fn show(states: &BTreeSet<Vec<PrincipalContact>>) -> String {
    states
        .iter()
        .map(|s| describe_state(s))
        .collect::<Vec<_>>()
        .join("\n  ")
}

// ---------------------------------------------------------------------------------
// The oracle's own pieces, against hand-derived truths
// ---------------------------------------------------------------------------------

#[test]
fn part_volumes_from_faces_match_the_fixtures_table() {
    for (name, volume) in [
        ("block_with_hole.off", 455_000.0),
        ("block_with_tight_hole.off", 460_096.875),
        ("block_with_chamfered_hole.off", 1_360_000.0 / 3.0),
        ("l_block.off", 1_500_000.0),
        ("peg.off", 62_720.0),
    ] {
        let part = fixture(name);
        let (v, m) = part_volume_and_moment(&part);
        assert!((v - volume).abs() < 1e-9 * volume, "{name}: {v} != {volume}");
        // The blocks with a hole are symmetric about x = y = 50.
        if name.starts_with("block") {
            assert!(
                (m / v - DVec3::new(50.0, 50.0, m.z / v)).length() < 1e-9,
                "{name}: centroid {}",
                m / v
            );
        }
        checked_pieces(&part).unwrap_or_else(|e| panic!("{e}"));
    }
}

#[test]
fn a_piece_hull_of_a_box_has_its_volume_moment_and_three_edge_directions() {
    let corners: Vec<DVec3> = (0..8)
        .map(|i| {
            DVec3::new(
                (i & 1) as f64 * 2.0,
                (i >> 1 & 1) as f64 * 3.0,
                (i >> 2 & 1) as f64 * 4.0,
            )
        })
        .collect();
    let piece = piece_from_points(&corners, 1e-9);
    assert!((piece.volume - 24.0).abs() < 1e-12);
    assert!((piece.moment / piece.volume - DVec3::new(1.0, 1.5, 2.0)).length() < 1e-12);
    assert_eq!(piece.normals.len(), 6);
    assert_eq!(piece.edge_directions.len(), 3);
}

#[test]
fn pieces_that_do_not_add_up_to_the_part_are_caught() {
    let part = fixture("block_with_hole.off");
    let pieces = checked_pieces(&part).expect("the block's pieces add up");
    assert!(pieces.len() >= 2);
    // One piece missing: the volume is short.
    let missing = check_pieces(&part, pieces[1..].to_vec());
    assert!(missing.is_err_and(|e| e.contains("volume")));
    // One piece moved: same volume, another first moment.
    let mut moved = pieces.clone();
    let shifted: Vec<DVec3> = moved[0].points.iter().map(|p| *p + DVec3::new(1.0, 0.0, 0.0)).collect();
    moved[0] = piece_from_points(&shifted, 1e-9);
    assert!(check_pieces(&part, moved).is_err_and(|e| e.contains("moment")));
}

#[test]
fn pose_angles_round_trip_through_rotations() {
    for angles in [[0.1, -0.2, 0.3], [0.0, 0.0, 0.0], [-0.5, 0.4, -2.5], [3.0, 1.2, -0.1]] {
        let back = angles_of(rotation_of(angles));
        assert!(
            rotation_of(back).abs_diff_eq(rotation_of(angles), 1e-14),
            "{angles:?} -> {back:?}"
        );
        if angles[1].abs() < std::f64::consts::FRAC_PI_2 && angles.iter().all(|a| a.abs() < std::f64::consts::PI) {
            assert!(
                (0..3).all(|i| (back[i] - angles[i]).abs() < 1e-14),
                "{angles:?} -> {back:?}"
            );
        }
    }
}

#[test]
fn the_difference_of_two_cubes_is_the_doubled_cube_and_turned_it_is_a_zonotope() {
    let cube = fixture("cube.off");
    let piece = piece_from_points(cube.convex_pieces()[0].vertices(), 1e-9);
    let m = minkowski_difference(&piece, &piece, DMat3::IDENTITY, 10.0).expect("closes");
    assert_eq!(m.facets.len(), 6);
    for f in &m.facets {
        assert!((f.offset - 10.0).abs() < 1e-12, "cube ⊕ −cube is [−10, 10]³: {f:?}");
        assert_eq!(f.polygon.len(), 4);
    }
    // Turned generically, box ⊕ box is a zonotope of 6 generators: 2·C(6,2) = 30 facets.
    let m = minkowski_difference(&piece, &piece, rotation_of([0.3, 0.2, 0.1]), 10.0).expect("closes");
    assert_eq!(m.facets.len(), 30);
}

#[test]
fn slices_include_identity_corners_and_aligned_rotations() {
    let (l_block, box_part) = acsg::examples::l_block_and_box();
    let bounds = acsg::examples::paper_bounds();
    let slices = rotation_slices(&l_block, &box_part, &bounds, &SliceOptions::default());
    assert_eq!(slices[0].angles, [0.0; 3]);
    let r = std::f64::consts::PI / 10.0;
    assert!(slices.iter().any(|s| s.angles == [r, r, r]));
    assert!(slices.iter().any(|s| s.angles == [-r, 0.0, 0.0]));
    // Every slice is in bounds; some aligned slices are not single-axis turns yet keep a
    // face of the box antiparallel to a face of the L (the bottom on the floor: rotations
    // about z only, so rx = ry = 0).
    let lo = bounds.min.to_array();
    let hi = bounds.max.to_array();
    for s in &slices {
        assert!(
            (0..3).all(|i| s.angles[i] >= lo[i + 3] && s.angles[i] <= hi[i + 3]),
            "{s:?}"
        );
    }
    let bottom_on_floor = slices
        .iter()
        .filter(|s| {
            let down = rotation_of(s.angles) * DVec3::NEG_Z;
            down.distance(DVec3::NEG_Z) < 1e-12 && s.angles[2] != 0.0
        })
        .count();
    assert!(
        bottom_on_floor >= 3,
        "{bottom_on_floor} slices with the bottom face flat"
    );
    // Edge-parallel-to-face slices: (R e)·n = 0 for some box edge e and L normal n,
    // away from the axes.
    let tilted_edge = slices.iter().any(|s| {
        let r = rotation_of(s.angles);
        let generic = s.angles.iter().all(|a| a.abs() > 1e-6);
        let axes = [DVec3::X, DVec3::Y, DVec3::Z];
        generic && axes.iter().any(|e| axes.iter().any(|n| (r * *e).dot(*n).abs() < 1e-12))
    });
    assert!(tilted_edge);
}

// ---------------------------------------------------------------------------------
// The evaluator, at hand-made poses
// ---------------------------------------------------------------------------------

#[test]
fn the_evaluator_reads_hand_made_poses() {
    let (l_block, box_part) = acsg::examples::l_block_and_box();
    let eval = Evaluator::new(&l_block, &box_part);
    let floor = face_where(&l_block, DVec3::Z, 50.0);
    let wall = face_where(&l_block, DVec3::NEG_X, -150.0);
    let bottom = face_where(&box_part, DVec3::NEG_Z, -50.0);
    let side = face_where(&box_part, DVec3::X, 150.0);
    let ff = ContactKind::FaceFace;
    let at = |p: [f64; 6]| eval.evaluate(&Pose::from_array(p));
    // Assembled: flat on the floor and against the wall; the bottom edge along the
    // concave edge is implied.
    let mut both = vec![contact(floor, bottom, ff), contact(wall, side, ff)];
    both.sort();
    assert_eq!(at([0.0; 6]), Verdict::State(both));
    assert_eq!(
        at([0.0, 0.0, 10.0, 0.0, 0.0, 0.0]),
        Verdict::State(vec![contact(wall, side, ff)])
    );
    assert_eq!(
        at([-3.0, 1.0, 0.0, 0.0, 0.0, 0.0]),
        Verdict::State(vec![contact(floor, bottom, ff)])
    );
    // Free space, a hair above the floor (not robust), and sunk into the floor.
    assert_eq!(at([-3.0, 0.0, 5.0, 0.0, 0.0, 0.0]), Verdict::State(vec![]));
    assert!(matches!(at([-3.0, 0.0, 1e-5, 0.0, 0.0, 0.0]), Verdict::NonRobust(_)));
    assert!(matches!(at([-3.0, 0.0, -1.0, 0.0, 0.0, 0.0]), Verdict::Penetrating(_)));
    // Turned 5° about x, it rests on its bottom edge y = 10 (f-e with the floor) and its
    // side face stays in the plane x = 150 (f-f with the wall); the edge's end on the
    // concave edge is implied by both.
    let a = 5f64.to_radians();
    // Rx(a) maps (x, 10, 50) to (x, 10 cos a − 50 sin a, 10 sin a + 50 cos a); lift it
    // back to z = 50 and keep y.
    let (y, z) = (10.0 * a.cos() - 50.0 * a.sin(), 10.0 * a.sin() + 50.0 * a.cos());
    let pose = [0.0, 10.0 - y, 50.0 - z, a, 0.0, 0.0];
    let low_edge = edge_between(&box_part, DVec3::new(50.0, 10.0, 50.0), DVec3::new(150.0, 10.0, 50.0));
    let mut expected = vec![contact(floor, low_edge, ContactKind::FaceEdge), contact(wall, side, ff)];
    expected.sort();
    assert_eq!(at(pose), Verdict::State(expected));
}

/// The peg's bottom corner on the plain hole's top corner (65, 65, 50), turned by about
/// 1e-5 rad: the corner's bottom edge along x and the rim edge along x stay within
/// 2e-9 mm of each other from the corner out, and their closest points lie just over
/// 1e-6 L from it. A checker with a tolerance near 1e-6 L reads them touching all the
/// way to the corners, the library's reads the corners alone, this one read a crossing
/// as well: the pose is not robust, and the evaluator must say so.
#[test]
fn the_evaluator_calls_nearly_parallel_edges_crossing_next_to_a_corner_not_robust() {
    let (block, peg) = (fixture("block_with_hole.off"), fixture("peg.off"));
    let eval = Evaluator::new(&block, &peg);
    let pose = Pose::from_array([
        0.9999389300078292,
        0.9998721879617135,
        40.00120891907241,
        -0.000012781726620217566,
        0.000006107618209107185,
        0.0,
    ]);
    match eval.evaluate(&pose) {
        Verdict::NonRobust(why) => assert!(why.contains("robustness gap of the other"), "{why}"),
        other => panic!("read {other:?}"),
    }
}

/// A prism over `ring` (counter-clockwise seen from +z) from z0 to z1, as a part.
fn prism(name: &str, ring: &[(f64, f64)], z0: f64, z1: f64) -> Part {
    let n = ring.len();
    let mut off = format!("OFF\n{} {} 0\n", 2 * n, n + 2);
    for z in [z0, z1] {
        for (x, y) in ring {
            writeln!(off, "{x} {y} {z}").unwrap();
        }
    }
    let bottom: Vec<String> = (0..n).rev().map(|k| k.to_string()).collect();
    let top: Vec<String> = (n..2 * n).map(|k| k.to_string()).collect();
    writeln!(off, "{n} {}", bottom.join(" ")).unwrap();
    writeln!(off, "{n} {}", top.join(" ")).unwrap();
    for k in 0..n {
        let j = (k + 1) % n;
        writeln!(off, "4 {k} {j} {} {}", n + j, n + k).unwrap();
    }
    let soup = acsg::io::off::read(off.as_bytes()).unwrap();
    Part::try_new(&soup, name).unwrap()
}

/// A wedge (a prism over a triangle) in a V-groove, tilted 3° about x, its apex edge
/// crossing the groove's end edge. The wedge's faces meet at 74° along the apex, so a
/// point behind one face near the apex may already be in front of the other: the
/// groove's edge passes behind the plane of the wedge's side over the side's outline,
/// yet is outside the wedge all along (checked here point by point against the wedge's
/// five planes). The evaluator read it as 2.15 mm of penetration, and the oracle's
/// cross-check failed on this pair.
#[test]
fn the_evaluator_reads_an_edge_behind_a_thin_wedges_face_as_outside_it() {
    let groove = prism(
        "vblock",
        &[
            (0.0, 0.0),
            (100.0, 0.0),
            (100.0, 60.0),
            (65.0, 60.0),
            (50.0, 40.0),
            (35.0, 60.0),
            (0.0, 60.0),
        ],
        0.0,
        50.0,
    );
    let wedge = prism("vwedge", &[(50.0, 42.0), (71.0, 70.0), (29.0, 70.0)], 5.0, 45.0);
    let pose = Pose::from_array([
        -0.005420457434628118,
        -2.254671558037846,
        -3.8975187557846143,
        -3f64.to_radians(),
        0.0,
        0.0,
    ]);
    // The groove's end edge from (35, 60, 0) to (50, 40, 0), in the wedge's frame, is in
    // front of one of the wedge's planes at every point.
    let to_wedge = pose.to_affine(&DAffine3::IDENTITY).inverse();
    for k in 0..=100 {
        let p = to_wedge
            .transform_point3(DVec3::new(35.0, 60.0, 0.0).lerp(DVec3::new(50.0, 40.0, 0.0), f64::from(k) / 100.0));
        let outside = wedge
            .faces()
            .iter()
            .map(|f| f.normal.dot(p) - f.offset)
            .fold(f64::MIN, f64::max);
        assert!(outside > 0.0, "point {k} of the edge is inside the wedge");
    }
    match Evaluator::new(&groove, &wedge).evaluate(&pose) {
        Verdict::Penetrating(why) => panic!("read penetration: {why}"),
        Verdict::State(_) | Verdict::NonRobust(_) => {}
    }
}

#[test]
fn the_evaluator_reads_a_vertex_on_the_slab_and_an_edge_crossing() {
    let (slab, cube) = acsg::examples::cube_and_slab();
    let eval = Evaluator::new(&slab, &cube);
    let top = face_where(&slab, DVec3::Z, 0.0);
    let angles = [0.3, 0.2, 0.1];
    let r = rotation_of(angles);
    let (low, _) = cube
        .vertices()
        .iter()
        .map(|v| v.position)
        .map(|p| (p, (r * p).z))
        .min_by(|a, b| a.1.total_cmp(&b.1))
        .unwrap();
    let pose = Pose::from_array([0.0, 0.0, -(r * low).z, angles[0], angles[1], angles[2]]);
    assert_eq!(
        eval.evaluate(&pose),
        Verdict::State(vec![contact(top, vertex_at(&cube, low), ContactKind::FaceVertex)])
    );

    // Two cubes: B's edge (0,0,0)-(10,0,0) crossing A's top edge x = 10, z = 10 at its
    // middle (10, 5, 10), descending along (1, 1, −1) so that it clears A's top and
    // right faces. The plane through both edges has normal m = (1, 0, 1)/√2, between
    // A's face normals there; B is turned so that its edge's outward bisector
    // (0, −1, −1)/√2 points along −m.
    let a = fixture("cube.off");
    let b = fixture("cube.off");
    let eval = Evaluator::new(&a, &b);
    let d = DVec3::new(1.0, 1.0, -1.0).normalize();
    let m = DVec3::new(1.0, 0.0, 1.0).normalize();
    let bisector = DVec3::new(0.0, -1.0, -1.0).normalize();
    let r = DMat3::from_cols(d, -m, d.cross(-m))
        * DMat3::from_cols(DVec3::X, bisector, DVec3::X.cross(bisector)).transpose();
    let angles = angles_of(r);
    let t = DVec3::new(10.0, 5.0, 10.0) - rotation_of(angles) * DVec3::new(5.0, 0.0, 0.0);
    let pose = Pose::from_array([t.x, t.y, t.z, angles[0], angles[1], angles[2]]);
    let edge_a = edge_between(&a, DVec3::new(10.0, 0.0, 10.0), DVec3::new(10.0, 10.0, 10.0));
    let edge_b = edge_between(&b, DVec3::new(0.0, 0.0, 0.0), DVec3::new(10.0, 0.0, 0.0));
    assert_eq!(
        eval.evaluate(&pose),
        Verdict::State(vec![contact(edge_a, edge_b, ContactKind::EdgeEdge)])
    );
}

// ---------------------------------------------------------------------------------
// The whole oracle on single slices, against hand-derived state sets
// ---------------------------------------------------------------------------------

#[test]
fn cube_on_slab_at_identity_is_face_on_face_only() {
    let (slab, cube) = acsg::examples::cube_and_slab();
    let bounds = degrees_bounds([-1.0, -1.0, -1.0, 0.0, 0.0, 0.0], [1.0, 1.0, 1.0, 0.0, 0.0, 0.0]);
    let report = Oracle::new(&slab, &cube, bounds).run(&slices_deg(&[[0.0; 3]]));
    assert_consistent(&report);
    let top = face_where(&slab, DVec3::Z, 0.0);
    let bottom = face_where(&cube, DVec3::NEG_Z, 0.0);
    let expected = BTreeSet::from([vec![contact(top, bottom, ContactKind::FaceFace)]]);
    assert_eq!(states_of(&report), expected);
}

#[test]
fn cube_on_slab_turned_about_x_rests_on_an_edge() {
    let (slab, cube) = acsg::examples::cube_and_slab();
    let bounds = degrees_bounds([-1.0, -1.0, -1.0, 10.0, 0.0, 0.0], [1.0, 1.0, 1.0, 10.0, 0.0, 0.0]);
    let report = Oracle::new(&slab, &cube, bounds).run(&slices_deg(&[[10.0, 0.0, 0.0]]));
    assert_consistent(&report);
    // Rx(+10°) lowers y = 0, z = 0 the most: the bottom edge along x at y = 0.
    let top = face_where(&slab, DVec3::Z, 0.0);
    let edge = edge_between(&cube, DVec3::ZERO, DVec3::new(10.0, 0.0, 0.0));
    let expected = BTreeSet::from([vec![contact(top, edge, ContactKind::FaceEdge)]]);
    assert_eq!(states_of(&report), expected);
}

#[test]
fn cube_on_slab_turned_generically_rests_on_its_lowest_vertex() {
    let (slab, cube) = acsg::examples::cube_and_slab();
    let d = [10.0, 7.0, 3.0];
    let bounds = degrees_bounds([-1.0, -1.0, -5.0, d[0], d[1], d[2]], [1.0, 1.0, 5.0, d[0], d[1], d[2]]);
    let report = Oracle::new(&slab, &cube, bounds).run(&slices_deg(&[d]));
    assert_consistent(&report);
    // The height of a turned point is −sin(ry) x + cos(ry) sin(rx) y + cos(ry) cos(rx) z
    // (Rz leaves it alone): with ry = 7° and rx = 10° the corner (10, 0, 0) is lowest.
    let top = face_where(&slab, DVec3::Z, 0.0);
    let corner = vertex_at(&cube, DVec3::new(10.0, 0.0, 0.0));
    let expected = BTreeSet::from([vec![contact(top, corner, ContactKind::FaceVertex)]]);
    assert_eq!(states_of(&report), expected);
}

#[test]
fn two_cubes_in_general_position_show_every_facet_of_their_zonotope() {
    // All translations around: the states are the 30 facets of cube ⊕ −R cube: 6 f-v
    // (each face of A against B's vertex lowest along its normal), 6 v-f (mirror), 18
    // e-e (one per pair of edge directions and side).
    let a = fixture("cube.off");
    let b = fixture("cube.off");
    let d = [23.0, -31.0, 17.0];
    let bounds = degrees_bounds(
        [-30.0, -30.0, -30.0, d[0], d[1], d[2]],
        [30.0, 30.0, 30.0, d[0], d[1], d[2]],
    );
    let report = Oracle::new(&a, &b, bounds).run(&slices_deg(&[d]));
    assert_consistent(&report);
    let r = rotation_of(d.map(f64::to_radians));
    let lowest = |part: &Part, dir: DVec3, turn: DMat3| {
        let p = part
            .vertices()
            .iter()
            .map(|v| v.position)
            .min_by(|p, q| dir.dot(turn * *p).total_cmp(&dir.dot(turn * *q)))
            .unwrap();
        vertex_at(part, p)
    };
    let mut expected: BTreeSet<Vec<PrincipalContact>> = BTreeSet::new();
    for (i, f) in a.faces().iter().enumerate() {
        let v = lowest(&b, f.normal, r);
        expected.insert(vec![contact(
            ElementId::Face(FaceId(i as u32)),
            v,
            ContactKind::FaceVertex,
        )]);
    }
    for (i, f) in b.faces().iter().enumerate() {
        let v = lowest(&a, r * f.normal, DMat3::IDENTITY);
        expected.insert(vec![contact(
            v,
            ElementId::Face(FaceId(i as u32)),
            ContactKind::VertexFace,
        )]);
    }
    let found = states_of(&report);
    let edge_edge: Vec<_> = found
        .iter()
        .filter(|s| s.len() == 1 && s[0].kind == ContactKind::EdgeEdge)
        .collect();
    assert_eq!(edge_edge.len(), 18, "{}", show(&found));
    assert_eq!(found.len(), 30, "{}", show(&found));
    let single: BTreeSet<_> = found
        .iter()
        .filter(|s| s[0].kind != ContactKind::EdgeEdge)
        .cloned()
        .collect();
    assert_eq!(single, expected);
}

/// The peg over a block with a square hole, rotation pinned at identity: its four sides
/// flat on the four hole walls, two at a time in the four corners of the hole, and its
/// bottom on the block's top when it sits beside the hole (z = 40, |x| or |y| beyond the
/// clearance). Nothing else: the peg never reaches the bottom, and its edge along a
/// wall's rim at z = 40 is degenerate. `clearance` is the gap per side, `reach` the
/// x, y bounds.
fn peg_over_a_hole_at_identity(block: &str, hole: f64, clearance: f64, reach: f64) {
    let block = fixture(block);
    let peg = fixture("peg.off");
    let bounds = degrees_bounds(
        [-reach, -reach, 0.0, 0.0, 0.0, 0.0],
        [reach, reach, 45.0, 0.0, 0.0, 0.0],
    );
    let report = Oracle::new(&block, &peg, bounds).run(&slices_deg(&[[0.0; 3]]));
    assert_consistent(&report);
    let ff = ContactKind::FaceFace;
    let wall = |n: DVec3, at: f64| face_where(&block, n, n.dot(DVec3::splat(at)));
    let side = |n: DVec3, at: f64| face_where(&peg, n, n.dot(DVec3::splat(at)));
    // Hole walls face into the hole: x = hole has normal +x; the peg's x = 36 face −x.
    let (lo, hi) = (hole, 100.0 - hole);
    assert_eq!(36.0 - lo, clearance);
    let pairs = [
        (wall(DVec3::X, lo), side(DVec3::NEG_X, 36.0)),
        (wall(DVec3::NEG_X, hi), side(DVec3::X, 64.0)),
        (wall(DVec3::Y, lo), side(DVec3::NEG_Y, 36.0)),
        (wall(DVec3::NEG_Y, hi), side(DVec3::Y, 64.0)),
    ];
    let mut expected: BTreeSet<Vec<PrincipalContact>> = pairs.iter().map(|&(w, s)| vec![contact(w, s, ff)]).collect();
    for (x, y) in [(0, 2), (0, 3), (1, 2), (1, 3)] {
        let mut both = vec![contact(pairs[x].0, pairs[x].1, ff), contact(pairs[y].0, pairs[y].1, ff)];
        both.sort();
        expected.insert(both);
    }
    let top = face_where(&block, DVec3::Z, 50.0);
    let bottom = face_where(&peg, DVec3::NEG_Z, -10.0);
    expected.insert(vec![contact(top, bottom, ff)]);
    assert_eq!(states_of(&report), expected, "found:\n  {}", show(&states_of(&report)));
}

#[test]
fn peg_over_the_hole_at_identity_shows_the_nine_face_states() {
    peg_over_a_hole_at_identity("block_with_hole.off", 35.0, 1.0, 2.0);
}

#[test]
fn peg_over_the_tight_hole_at_identity_shows_the_nine_face_states() {
    peg_over_a_hole_at_identity("block_with_tight_hole.off", 35.875, 0.125, 1.0);
}

/// A 40 mm cube with the corner [20, 40]³ cut away: a concave corner where three faces
/// (x = 20, y = 20, z = 20, facing into the notch) meet. Built from the 7 occupied 20 mm
/// cells' outer faces.
fn notched_cube() -> Part {
    let occupied = |c: [i32; 3]| c.iter().all(|&i| (0..2).contains(&i)) && c != [1, 1, 1];
    let index = |p: [i32; 3]| (p[0] + 3 * p[1] + 9 * p[2]) as u32;
    let positions: Vec<DVec3> = (0..27)
        .map(|i| DVec3::new((i % 3) as f64, (i / 3 % 3) as f64, (i / 9) as f64) * 20.0)
        .collect();
    let mut polygons = Vec::new();
    for cell in (0..8).map(|i| [i & 1, i >> 1 & 1, i >> 2]) {
        if !occupied(cell) {
            continue;
        }
        for axis in 0..3 {
            for side in [0, 1] {
                let mut next = cell;
                next[axis] += if side == 1 { 1 } else { -1 };
                if occupied(next) {
                    continue;
                }
                // The cell's face on this side, its corners round the other two axes.
                let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
                let mut quad: Vec<u32> = [(0, 0), (1, 0), (1, 1), (0, 1)]
                    .iter()
                    .map(|&(a, b)| {
                        let mut p = cell;
                        p[axis] += side;
                        p[u] += a;
                        p[v] += b;
                        index(p)
                    })
                    .collect();
                // (u, v, axis) is right-handed: counter-clockwise about +axis.
                if side == 0 {
                    quad.reverse();
                }
                polygons.push(quad);
            }
        }
    }
    let soup = acsg::io::MeshSoup {
        positions,
        polygons,
        polygon_lines: vec![],
        polygon_noun: "face",
    };
    Part::try_new(&soup, "notched cube").expect("the notched cube is a valid solid")
}

/// A 10 mm cube turned generically, pushed into the notch: on that slice its translations
/// touching all three notch faces are one point, where the cube's lowest vertex along
/// each face normal rests on that face (three f-v, a vertex of U where facets of three
/// different M's meet); the three pairs hold on the segments between.
#[test]
fn a_cube_in_a_notch_rests_on_three_faces_at_one_point_of_its_slice() {
    let block = notched_cube();
    assert_eq!(block.faces().len(), 9);
    let cube = fixture("cube.off");
    let d = [3.0, -4.0, 5.0];
    let bounds = degrees_bounds(
        [15.0, 15.0, 15.0, d[0], d[1], d[2]],
        [25.0, 25.0, 25.0, d[0], d[1], d[2]],
    );
    let report = Oracle::new(&block, &cube, bounds).run(&slices_deg(&[d]));
    assert_consistent(&report);
    let r = rotation_of(d.map(f64::to_radians));
    let rests = |axis: DVec3| {
        let face = face_where(&block, axis, 20.0);
        let low = cube
            .vertices()
            .iter()
            .map(|v| v.position)
            .min_by(|p, q| axis.dot(r * *p).total_cmp(&axis.dot(r * *q)))
            .unwrap();
        contact(face, vertex_at(&cube, low), ContactKind::FaceVertex)
    };
    let [x, y, z] = [DVec3::X, DVec3::Y, DVec3::Z].map(rests);
    let vertices: BTreeSet<ElementId> = [x, y, z].iter().map(|c| c.moving).collect();
    assert_eq!(vertices.len(), 3, "three different vertices rest on the three faces");
    let found = states_of(&report);
    let sorted = |mut v: Vec<PrincipalContact>| {
        v.sort();
        v
    };
    for state in [
        vec![x, y, z],
        vec![x, y],
        vec![y, z],
        vec![x, z],
        vec![x],
        vec![y],
        vec![z],
    ] {
        let state = sorted(state);
        assert!(
            found.contains(&state),
            "{} not found among\n  {}",
            describe_state(&state),
            show(&found)
        );
    }
    assert!(
        report
            .robust_samples
            .iter()
            .any(|(s, c)| c.len() == 3 && s.kind == SampleKind::Triple)
    );
}

/// The L-block and its box with the rotation pinned at identity: on the floor, against
/// the wall, both, and on top of the upright (z = 100, x > 0).
#[test]
fn l_block_and_box_at_identity_show_the_four_face_states() {
    let (l_block, box_part) = acsg::examples::l_block_and_box();
    let bounds = degrees_bounds([-5.0, -5.0, 0.0, 0.0, 0.0, 0.0], [5.0, 5.0, 240.0, 0.0, 0.0, 0.0]);
    let report = Oracle::new(&l_block, &box_part, bounds).run(&slices_deg(&[[0.0; 3]]));
    assert_consistent(&report);
    let ff = ContactKind::FaceFace;
    let floor = contact(
        face_where(&l_block, DVec3::Z, 50.0),
        face_where(&box_part, DVec3::NEG_Z, -50.0),
        ff,
    );
    let wall = contact(
        face_where(&l_block, DVec3::NEG_X, -150.0),
        face_where(&box_part, DVec3::X, 150.0),
        ff,
    );
    let upright_top = contact(
        face_where(&l_block, DVec3::Z, 150.0),
        face_where(&box_part, DVec3::NEG_Z, -50.0),
        ff,
    );
    let mut both = vec![floor, wall];
    both.sort();
    let expected = BTreeSet::from([vec![floor], vec![wall], both, vec![upright_top]]);
    assert_eq!(states_of(&report), expected, "found:\n  {}", show(&states_of(&report)));
}

// ---------------------------------------------------------------------------------
// The pairs: oracle runs (shared by the tests of one pair), cross-checks, recall
// ---------------------------------------------------------------------------------

/// One pair of parts with its bounds, the files to reproduce it with, and the oracle's
/// report on the default slices.
struct PairRun {
    name: &'static str,
    fixed: Part,
    moving: Part,
    bounds: Bounds,
    files: (&'static str, &'static str),
    report: OracleReport,
    /// Whether the pair is the built-in example, whose graph the binary shares.
    built_in: bool,
}

/// The pairs other than the built-in example: a name, the fixed and the moving part
/// (files in `fixtures/`) and bounds as the CLI takes them.
///
/// The test suite checks the holes with one turn at a time (a tilt, a yaw): with all three
/// turns free, the generator leaves hundreds of candidates undecided on these pairs and
/// spends minutes on each graph in the test build, which the CI cannot afford. The
/// built-in example keeps all three turns (±18°) in the suite; the holes with all three
/// are the `full_turns` pairs, run on demand (see `recall_on_demand` for any other), as
/// is the chamfered hole with two turns (`tilted_and_turned`).
const PAIRS: [(&str, &str, &str, &str); 13] = [
    (
        "block_with_chamfered_hole_and_peg_tilted",
        "block_with_chamfered_hole.off",
        "peg.off",
        "x=-2:2,y=-2:2,z=0:45,rx=-1:1",
    ),
    (
        "block_with_hole_and_peg_tilted",
        "block_with_hole.off",
        "peg.off",
        "x=-2:2,y=-2:2,z=0:45,rx=-1:1",
    ),
    (
        "block_with_tight_hole_and_peg",
        "block_with_tight_hole.off",
        "peg.off",
        "x=-1:1,y=-1:1,z=0:60,rx=-3:3,ry=-3:3,rz=-3:3",
    ),
    (
        "block_with_chamfered_hole_and_peg_yawed",
        "block_with_chamfered_hole.off",
        "peg.off",
        "x=-2:2,y=-2:2,z=0:45,rz=-2:2",
    ),
    (
        "block_with_chamfered_hole_and_peg_full_turns",
        "block_with_chamfered_hole.off",
        "peg.off",
        "x=-2:2,y=-2:2,z=0:45,rx=-2:2,ry=-2:2,rz=-2:2",
    ),
    (
        "block_with_hole_and_peg_full_turns",
        "block_with_hole.off",
        "peg.off",
        "x=-2:2,y=-2:2,z=0:45,rx=-2:2,ry=-2:2,rz=-2:2",
    ),
    (
        "block_with_chamfered_hole_and_peg_tilted_and_turned",
        "block_with_chamfered_hole.off",
        "peg.off",
        "x=-2:2,y=-2:2,z=0:45,ry=-2:2,rz=-1:1",
    ),
    (
        "block_with_plus_hole_and_plus_peg_yawed",
        "block_with_plus_hole.off",
        "plus_peg.off",
        "x=-1:1,y=-1:1,z=0:45,rz=-2:2",
    ),
    (
        "cube_in_the_l_blocks_corner_turned",
        "l_block.off",
        "cube.off",
        "x=135:145,y=40:50,z=50:60,rx=-10:10,ry=-10:10,rz=-10:10",
    ),
    (
        "box_on_the_slab_tilted_and_yawed",
        "slab.off",
        "box.off",
        "x=-10:10,y=-10:10,z=-65:-35,rx=-5:5,ry=-5:5,rz=-30:30",
    ),
    (
        "hex_peg_tilted_in_its_hole",
        "block_with_hex_hole.off",
        "hex_peg.off",
        "x=-1:1,y=-1:1,z=0:45,rx=-1:1,ry=-1:1",
    ),
    (
        "cube_overhanging_the_l_blocks_floor",
        "l_block.off",
        "cube.off",
        "x=-3:3,y=20:25,z=50:55,rx=-5:5,ry=-5:5,rz=-5:5",
    ),
    (
        "plus_peg_standing_on_the_l_blocks_floor",
        "l_block.off",
        "plus_peg.off",
        "x=-3:3,y=-3:3,z=40:45,rx=-4:4,ry=-4:4,rz=-4:4",
    ),
];

/// The built-in example (index 0) or `PAIRS[index - 1]`, with its oracle run once.
fn pair_run(index: usize) -> &'static PairRun {
    static RUNS: [OnceLock<PairRun>; PAIRS.len() + 1] = [const { OnceLock::new() }; PAIRS.len() + 1];
    RUNS[index].get_or_init(|| {
        if index == 0 {
            let (fixed, moving) = acsg::examples::l_block_and_box();
            let bounds = acsg::examples::paper_bounds();
            return PairRun::new(
                "l_block_and_box",
                (fixed, moving),
                ("l_block.off", "box.off"),
                bounds,
                true,
            );
        }
        let (name, fixed, moving, bounds) = PAIRS[index - 1];
        PairRun::load(name, fixed, moving, bounds)
    })
}

impl PairRun {
    /// Runs the oracle on the default slices.
    fn new(
        name: &'static str,
        (fixed, moving): (Part, Part),
        files: (&'static str, &'static str),
        bounds: Bounds,
        built_in: bool,
    ) -> PairRun {
        let oracle = Oracle::new(&fixed, &moving, bounds);
        let report = oracle.run(&oracle.default_slices());
        let s = &report.stats;
        eprintln!(
            "{name}: {} oracle states from {} slices ({} skipped) in {:.1?}: {} samples on the boundary, {} robust \
             ({} with a degenerate contact), {} not robust",
            report.states.len(),
            s.slices,
            s.skipped_slices,
            s.elapsed,
            s.samples,
            s.robust,
            s.degenerate,
            s.non_robust
        );
        PairRun {
            built_in,
            name,
            fixed,
            moving,
            bounds,
            files,
            report,
        }
    }

    /// [`PairRun::new`] on two files (relative to `fixtures/`, or absolute) and bounds as
    /// the CLI takes them.
    fn load(name: &'static str, fixed: &'static str, moving: &'static str, bounds: &str) -> PairRun {
        let part = |p: &str| {
            let path = if Path::new(p).is_absolute() {
                PathBuf::from(p)
            } else {
                fixtures().join(p)
            };
            Part::from_path(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
        };
        let bounds = acsg::task::bounds_from_spec(bounds).unwrap_or_else(|e| panic!("{name}'s bounds: {e}"));
        PairRun::new(name, (part(fixed), part(moving)), (fixed, moving), bounds, false)
    }

    /// The cross-check, the exclusions' soundness and recall, one after the other.
    fn check_all(&self) {
        self.cross_check();
        self.exclusions_are_sound();
        self.recall();
    }

    fn reproduce(&self, pose: &Pose) -> String {
        // Poses print their angles in radians.
        let path = |p: &str| {
            if Path::new(p).is_absolute() {
                p.to_owned()
            } else {
                format!("fixtures/{p}")
            }
        };
        format!(
            "acsg contacts {} {} --radians --pose={pose}",
            path(self.files.0),
            path(self.files.1)
        )
    }

    /// Every robust sample read by the library's contact scene: same state, no
    /// penetration, no pair closer than the separation.
    fn cross_check(&self) {
        assert_consistent(&self.report);
        let stats = &self.report.stats;
        assert!(
            stats.skipped_slices * 100 <= stats.slices,
            "{}: {} of {} slices skipped (a Minkowski difference whose facets do not close)",
            self.name,
            stats.skipped_slices,
            stats.slices
        );
        let scene = ContactScene::new(&self.fixed, &self.moving);
        let evaluator = Evaluator::new(&self.fixed, &self.moving);
        let least_gap = SEPARATION_REL * scene.scale();
        // Every robust sample, in parallel; the disagreements in sample order.
        let disagreements: Vec<_> = self
            .report
            .robust_samples
            .par_iter()
            .filter_map(|(sample, state)| {
                let report = scene.evaluate(&sample.pose.to_affine(&DAffine3::IDENTITY), CONTACT_REL);
                let gap_ok = report.min_gap.is_none_or(|g| g >= least_gap);
                let agree = report.contacts == *state && report.penetration == 0.0 && gap_ok;
                (!agree).then_some((sample, state, report))
            })
            .collect();
        let count = disagreements.len();
        let mut failures = String::new();
        for (k, (sample, state, report)) in disagreements.iter().take(10).enumerate() {
            let _ = writeln!(
                failures,
                "  at {} ({} sample, slice {:?}):\n    oracle  {}\n    library {} penetration {} min_gap {:?}\n    {}",
                sample.pose,
                sample.kind.label(),
                self.report.slices[sample.slice].why,
                describe_state(state),
                describe_state(&report.contacts),
                report.penetration,
                report.min_gap,
                self.reproduce(&sample.pose)
            );
            if k < 3 {
                let touching = evaluator.explain(&sample.pose).replace('\n', "\n      ");
                let _ = writeln!(failures, "    touching pairs the oracle sees:\n      {touching}");
            }
        }
        assert!(
            count == 0,
            "{}: the library's ContactScene disagrees with the oracle's evaluator at {count} of {} robust poses:\n{failures}",
            self.name,
            self.report.robust_samples.len()
        );
    }

    /// No exclusion rule of the decisions, nor of the last proofs, rules out a small
    /// box around an oracle witness (the rules are sound), nor the witness itself.
    fn exclusions_are_sound(&self) {
        let problem = acsg::feasibility::Problem::new(&self.fixed, &self.moving, self.bounds, DAffine3::IDENTITY);
        let mut wrong = String::new();
        let mut count = 0;
        for s in &self.report.states {
            let x = s.first.pose.to_array();
            let (lo, hi) = (self.bounds.min.to_array(), self.bounds.max.to_array());
            for eps in [0.0, 1e-7, 1e-4] {
                let around =
                    |sign: f64| -> [f64; 6] { std::array::from_fn(|k| (x[k] + sign * eps).clamp(lo[k], hi[k])) };
                let Ok(b) = Bounds::try_new(around(-1.0), around(1.0)) else {
                    continue;
                };
                let excluded = problem.exclusion(&s.contacts, &b);
                if let Some(rule) = excluded.or_else(|| problem.last_exclusion(&s.contacts, &b)) {
                    count += 1;
                    let _ = writeln!(
                        wrong,
                        "  {} excluded by {rule:?} within {eps} of {}\n    {}",
                        describe_state(&s.contacts),
                        s.first.pose,
                        self.reproduce(&s.first.pose)
                    );
                }
            }
        }
        assert!(
            count == 0,
            "{}: {count} boxes around oracle witnesses excluded:\n{wrong}",
            self.name
        );
    }

    /// Every oracle state must be a state of the generated graph.
    /// The generated graph with the default options (the shared one of the built-in
    /// example).
    fn graph(&self) -> std::borrow::Cow<'static, Graph> {
        if self.built_in {
            std::borrow::Cow::Borrowed(built_in_example())
        } else {
            std::borrow::Cow::Owned(generate(&self.fixed, &self.moving, &self.bounds, &Options::default()))
        }
    }

    fn recall(&self) {
        self.assert_recalls(&self.graph(), "", |contacts| contacts.to_vec());
    }

    /// Every oracle state, its moving part's elements renamed by `rename` (the identity
    /// for the plain pair), must be a state of `graph`; `how` says how it was generated.
    fn assert_recalls(&self, graph: &Graph, how: &str, rename: impl Fn(&[PrincipalContact]) -> Vec<PrincipalContact>) {
        let generated: BTreeSet<&Vec<PrincipalContact>> = graph.states.iter().map(|s| &s.contacts).collect();
        let mut message = String::new();
        let mut missing = 0;
        for s in &self.report.states {
            let renamed = rename(&s.contacts);
            if generated.contains(&renamed) {
                continue;
            }
            missing += 1;
            let _ = write!(message, "  {}", describe_state(&s.contacts));
            if renamed != s.contacts {
                let _ = write!(message, " (renamed: {})", describe_state(&renamed));
            }
            let _ = writeln!(
                message,
                "  ({} {} samples; first on slice {:?})\n    at {}\n    {}",
                s.samples,
                s.first.kind.label(),
                self.report.slices[s.first.slice].why,
                s.first.pose,
                self.reproduce(&s.first.pose)
            );
        }
        assert!(
            missing == 0,
            "{}: the generator{how} misses {missing} of the {} states the oracle found ({} generated):\n{message}",
            self.name,
            self.report.states.len(),
            graph.states.len() - 1
        );
    }

    /// Recall with the pair held another way: the moving part's model turned half round
    /// about z (its points `(x, y, z)` now at `(-x, -y, z)`) and an assembled pose
    /// G = Rz(180°) that turns it back. Since `p_A = G (R p_B' + t)` with
    /// `p_B' = Rz(180°) p_B`, the pose `(t, rx, ry, rz)` of the plain pair is the pose
    /// `(Rz(180°) t, -rx, -ry, rz)` of this one (`Rz(180°)` turns the x and y axes over
    /// and keeps the Euler order), so the bounds map to bounds and the contact states
    /// are the same, element for element once the turned part's elements are matched by
    /// their geometry. Every oracle state of the plain pair must then be in the graph
    /// generated through G: the oracle knows nothing of assembled poses, so this checks
    /// the generator's handling of G against it.
    fn recall_held_half_turned(&self) {
        let half_turn = DMat3::from_rotation_z(std::f64::consts::PI);
        let flip = |p: DVec3| DVec3::new(-p.x, -p.y, p.z);
        let mut soup = acsg::io::read_path(&fixtures().join(self.files.1)).expect("the moving part reads");
        for p in &mut soup.positions {
            *p = flip(*p);
        }
        let turned =
            Part::try_new(&soup, "the moving part turned half round").expect("the turned part is a valid part");
        // The turned part's element at the place of each element of the part: vertices
        // by position, edges by their ends, faces by normal and corners (separate faces
        // may share a plane, as the ends of a plus's arms do).
        let vertex = |v: VertexId| -> VertexId {
            let at = flip(self.moving.vertex(v).position);
            let i = turned.vertices().iter().position(|w| w.position.distance(at) < 1e-9);
            VertexId(i.expect("every vertex has its turned twin") as u32)
        };
        let corners = |part: &Part, f: FaceId, map: &dyn Fn(VertexId) -> VertexId| {
            let mut vs: Vec<VertexId> = part.closure_vertices(ElementId::Face(f)).into_iter().map(map).collect();
            vs.sort();
            vs
        };
        let turned_corners: Vec<Vec<VertexId>> = (0..turned.faces().len())
            .map(|g| corners(&turned, FaceId(g as u32), &|v| v))
            .collect();
        let twin = |e: ElementId| -> ElementId {
            match e {
                ElementId::Vertex(v) => ElementId::Vertex(vertex(v)),
                ElementId::Edge(id) => {
                    let ends = self.moving.edge(id).vertices.map(vertex);
                    let i = turned
                        .edges()
                        .iter()
                        .position(|f| f.vertices == ends || f.vertices == [ends[1], ends[0]]);
                    ElementId::Edge(EdgeId(i.expect("every edge has its turned twin") as u32))
                }
                ElementId::Face(id) => {
                    let wanted = corners(&self.moving, id, &vertex);
                    let normal = half_turn * self.moving.face(id).normal;
                    let i = (0..turned.faces().len()).position(|g| {
                        turned.face(FaceId(g as u32)).normal.distance(normal) < 1e-12 && turned_corners[g] == wanted
                    });
                    ElementId::Face(FaceId(i.expect("every face has its turned twin") as u32))
                }
            }
        };
        let twins: std::collections::BTreeMap<ElementId, ElementId> =
            self.moving.elements().into_iter().map(|e| (e, twin(e))).collect();
        let distinct: BTreeSet<&ElementId> = twins.values().collect();
        assert_eq!(
            distinct.len(),
            twins.len(),
            "{}: two elements matched one turned element",
            self.name
        );
        // The check has teeth: the oracle found states, and the loader numbers the
        // turned part's elements otherwise (so a mix-up of the two would show).
        assert!(
            !self.report.states.is_empty(),
            "{}: the oracle found no state",
            self.name
        );
        assert!(
            twins.iter().any(|(e, t)| matches!(e, ElementId::Vertex(_)) && e != t),
            "{}: the turned part kept its numbering",
            self.name
        );
        let (lo, hi) = (self.bounds.min.to_array(), self.bounds.max.to_array());
        let bounds = Bounds::try_new(
            [-hi[0], -hi[1], lo[2], -hi[3], -hi[4], lo[5]],
            [-lo[0], -lo[1], hi[2], -lo[3], -lo[4], hi[5]],
        )
        .expect("the mapped bounds are valid");
        let options = Options {
            assembled: DAffine3::from_mat3(half_turn),
            ..Options::default()
        };
        let graph = generate(&self.fixed, &turned, &bounds, &options);
        self.assert_recalls(&graph, " held through G", |contacts| {
            let mut renamed: Vec<PrincipalContact> = contacts
                .iter()
                .map(|pc| PrincipalContact {
                    moving: twins[&pc.moving],
                    ..*pc
                })
                .collect();
            renamed.sort();
            renamed
        });
    }

    /// Writes, as JSON lines (poses as x, y, z, rx, ry, rz in radians):
    /// - `<pair>.oracle.jsonl`: every oracle state with a pose showing it, how many
    ///   samples showed it and where the first one was taken, and whether the generated
    ///   graph has it;
    /// - `<pair>.witnesses.jsonl`: the generated states whose witness the independent
    ///   evaluator reads otherwise (another state, not robust, or penetrating).
    fn dump(&self, dir: &Path) -> std::io::Result<[PathBuf; 2]> {
        let graph = self.graph();
        let generated: BTreeSet<&Vec<PrincipalContact>> = graph.states.iter().map(|s| &s.contacts).collect();
        let labels = |state: &[PrincipalContact]| -> Vec<String> {
            state
                .iter()
                .map(|c| format!("{} {} {}", c.kind.label(), c.fixed, c.moving))
                .collect()
        };
        let mut oracle = String::new();
        for s in &self.report.states {
            let line = serde_json::json!({
                "contacts": labels(&s.contacts),
                "generated": generated.contains(&s.contacts),
                "pose": s.first.pose.to_array(),
                "samples": s.samples,
                "sample": s.first.kind.label(),
                "slice": self.report.slices[s.first.slice].why,
                "reproduce": self.reproduce(&s.first.pose),
            });
            let _ = writeln!(oracle, "{line}");
        }
        // Witnesses are built to the 1e-9 L of docs/concepts.md#tolerances, not to the
        // oracle's round-off.
        let evaluator = Evaluator::with_touch(&self.fixed, &self.moving, CONTACT_REL);
        let mut witnesses = String::new();
        for state in &graph.states[1..] {
            let Some(pose) = state.witness else { continue };
            let read = match evaluator.evaluate(&pose) {
                Verdict::State(contacts) if contacts == state.contacts => continue,
                Verdict::State(contacts) => serde_json::json!({ "state": labels(&contacts) }),
                Verdict::NonRobust(why) => serde_json::json!({ "not robust": why }),
                Verdict::Penetrating(why) => serde_json::json!({ "penetrating": why }),
            };
            let line = serde_json::json!({
                "contacts": labels(&state.contacts),
                "pose": pose.to_array(),
                "independent evaluator": read,
                "reproduce": self.reproduce(&pose),
            });
            let _ = writeln!(witnesses, "{line}");
        }
        let paths = [
            dir.join(format!("{}.oracle.jsonl", self.name)),
            dir.join(format!("{}.witnesses.jsonl", self.name)),
        ];
        std::fs::write(&paths[0], oracle)?;
        std::fs::write(&paths[1], witnesses)?;
        Ok(paths)
    }
}

#[test]
fn l_block_and_box_oracle_agrees_with_the_contact_scene() {
    pair_run(0).cross_check();
}

#[test]
fn l_block_and_box_oracle_witnesses_survive_every_exclusion_rule() {
    pair_run(0).exclusions_are_sound();
}

#[test]
fn l_block_and_box_generator_finds_every_oracle_state() {
    pair_run(0).recall();
}

#[test]
fn tilted_peg_in_the_chamfered_hole_oracle_agrees_with_the_contact_scene() {
    pair_run(1).cross_check();
}

#[test]
fn tilted_peg_in_the_chamfered_hole_oracle_witnesses_survive_every_exclusion_rule() {
    pair_run(1).exclusions_are_sound();
}

#[test]
fn tilted_peg_in_the_chamfered_hole_generator_finds_every_oracle_state() {
    pair_run(1).recall();
}

#[test]
fn tilted_peg_in_the_hole_oracle_agrees_with_the_contact_scene() {
    pair_run(2).cross_check();
}

#[test]
fn tilted_peg_in_the_hole_oracle_witnesses_survive_every_exclusion_rule() {
    pair_run(2).exclusions_are_sound();
}

#[test]
fn tilted_peg_in_the_hole_generator_finds_every_oracle_state() {
    pair_run(2).recall();
}

#[test]
fn tight_hole_and_peg_oracle_agrees_with_the_contact_scene() {
    pair_run(3).cross_check();
}

#[test]
fn tight_hole_and_peg_oracle_witnesses_survive_every_exclusion_rule() {
    pair_run(3).exclusions_are_sound();
}

#[test]
#[ignore = "17 minutes in release (all 434 oracle states found since the starts are probed); run on demand"]
fn tight_hole_and_peg_generator_finds_every_oracle_state() {
    pair_run(3).recall();
}

#[test]
fn yawed_peg_in_the_chamfered_hole_oracle_agrees_with_the_contact_scene() {
    pair_run(4).cross_check();
}

#[test]
fn yawed_peg_in_the_chamfered_hole_oracle_witnesses_survive_every_exclusion_rule() {
    pair_run(4).exclusions_are_sound();
}

#[test]
fn yawed_peg_in_the_chamfered_hole_generator_finds_every_oracle_state() {
    pair_run(4).recall();
}

/// `cargo test --release -p acsg --test generation -- --ignored full_turns` (minutes).
#[test]
#[ignore = "minutes per graph; run on demand"]
fn full_turns_peg_in_the_chamfered_hole_passes_every_check() {
    pair_run(5).check_all();
}

/// `cargo test --release -p acsg --test generation -- --ignored full_turns` (minutes).
#[test]
#[ignore = "minutes per graph; run on demand"]
fn full_turns_peg_in_the_hole_passes_every_check() {
    pair_run(6).check_all();
}

/// Two turns at once, about y and z: a bottom corner alone on a side wall holds only
/// with the peg pushed across the hole (found since the starts are probed on the
/// contact's plane; before, 6 of the 130 oracle states were missing). On demand: at
/// over two minutes in the test build it was the suite's largest graph, and the CI run
/// must stay within 20 minutes.
/// `cargo test --release -p acsg --test generation -- --ignored tilted_and_turned`.
#[test]
#[ignore = "two minutes in the test build; run on demand"]
fn tilted_and_turned_peg_in_the_chamfered_hole_passes_every_check() {
    pair_run(7).check_all();
}

/// The plus peg turned about z in its plus hole: at rz = 0 three parallel walls touch
/// at once and none alone, so those states are found only by searching for the states
/// holding a contact that does not hold alone (before, 8 of the 15 oracle states were
/// missing: every state with a face flat on a wall).
#[test]
fn plus_peg_yawed_in_its_plus_hole_passes_every_check() {
    pair_run(8).check_all();
}

/// A small part (the 10 mm cube, turned up to 10° about each axis about its own
/// corner) in the L-block's inner corner, next to the concave edge: parts and bounds
/// the other pairs do not have, to keep the generator from fitting the fixtures.
#[test]
fn cube_in_the_l_blocks_corner_passes_every_check() {
    pair_run(9).check_all();
}

/// The cube in the L-block's corner held another way (see
/// `PairRun::recall_held_half_turned`).
#[test]
fn cube_in_the_l_blocks_corner_held_through_an_assembled_pose_keeps_every_oracle_state() {
    pair_run(9).recall_held_half_turned();
}

/// The box on the slab held another way (see `PairRun::recall_held_half_turned`).
#[test]
fn box_on_the_slab_held_through_an_assembled_pose_keeps_every_oracle_state() {
    pair_run(10).recall_held_half_turned();
}

/// The box on the slab, tilted up to 5° and yawed up to 30° about the origin (far from
/// the box, so a turn also carries it across the slab): resting faces, edges and
/// corners in every direction.
#[test]
fn box_on_the_slab_tilted_and_yawed_passes_every_check() {
    pair_run(10).check_all();
}

/// The hexagonal peg tilted up to 1° about x and y in its hexagonal hole (1 mm clearance
/// at the corners, 0.866 across the flats). Among its states: the peg's bottom face
/// balanced on the hole's rim edge with a corner on a wall, robust only at the largest
/// offset the bounds allow, which the generator missed before its sweep went along the
/// alignments of the boxes undecided candidates left open.
#[test]
fn hex_peg_tilted_in_its_hole_oracle_agrees_with_the_contact_scene() {
    pair_run(11).cross_check();
}

#[test]
fn hex_peg_tilted_in_its_hole_oracle_witnesses_survive_every_exclusion_rule() {
    pair_run(11).exclusions_are_sound();
}

#[test]
#[ignore = "8 minutes in release (all 160 oracle states found); run on demand"]
fn hex_peg_tilted_in_its_hole_generator_finds_every_oracle_state() {
    pair_run(11).recall();
}

/// The cube on the L-block's floor across its outer rim (x = 0), turned up to 5° about
/// each axis: corners and edges over the rim and beyond it, an overhang no other pair
/// has.
#[test]
fn cube_overhanging_the_l_blocks_floor_passes_every_check() {
    pair_run(12).check_all();
}

/// The plus peg standing on the L-block's floor, turned up to 4° about each axis: a
/// non-convex moving part (concave upright edges) resting on a face by its corners
/// and edges.
#[test]
fn plus_peg_standing_on_the_l_blocks_floor_passes_every_check() {
    pair_run(13).check_all();
}

/// Writes every pair's oracle states, and the generated states whose witnesses the
/// independent evaluator reads otherwise, to `$ACSG_RECALL_DUMP` (default
/// `target/recall-dump`) as JSON lines (see `PairRun::dump`).
#[test]
#[ignore = "writes files; run on demand"]
fn dump_oracle_states() {
    let dir = std::env::var_os("ACSG_RECALL_DUMP")
        .map(PathBuf::from)
        .unwrap_or_else(|| Path::new(env!("CARGO_MANIFEST_DIR")).join("../../target/recall-dump"));
    std::fs::create_dir_all(&dir).expect("dump directory");
    for index in 0..=PAIRS.len() {
        for path in pair_run(index).dump(&dir).expect("dump written") {
            eprintln!("wrote {}", path.display());
        }
    }
}

/// Recall on any pair, on demand: `ACSG_RECALL_PAIR="FIXED;MOVING;BOUNDS"` with the two
/// parts' paths (relative to `fixtures/` or absolute) and bounds as the CLI takes them
/// (`x=-2:2,y=-2:2,z=0:45,rx=-2:2,ry=-2:2,rz=-2:2`, angles in degrees, omitted
/// components fixed at 0). Runs the cross-check, the exclusions' soundness and recall;
/// with `ACSG_RECALL_HALF_TURN=1` also recall with the pair held through an assembled
/// pose (`PairRun::recall_held_half_turned`: the x, y and rx, ry bounds are mirrored).
#[test]
#[ignore = "needs ACSG_RECALL_PAIR; run on demand"]
fn recall_on_demand() {
    let Some(spec) = std::env::var_os("ACSG_RECALL_PAIR") else {
        eprintln!("ACSG_RECALL_PAIR is not set: nothing to check");
        return;
    };
    let spec = spec.to_string_lossy().into_owned();
    let parts: Vec<&str> = spec.split(';').collect();
    assert_eq!(
        parts.len(),
        3,
        "ACSG_RECALL_PAIR wants FIXED;MOVING;BOUNDS, got {spec:?}"
    );
    let leak = |s: &str| -> &'static str { Box::leak(s.to_owned().into_boxed_str()) };
    let run = PairRun::load(leak(&spec), leak(parts[0]), leak(parts[1]), parts[2]);
    run.check_all();
    if std::env::var_os("ACSG_RECALL_HALF_TURN").is_some_and(|v| v == "1") {
        run.recall_held_half_turned();
    }
}
