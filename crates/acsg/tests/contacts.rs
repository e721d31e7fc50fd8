//! P(X) at hand-placed poses, one for each kind of principal contact. Expected
//! elements are picked by their geometry in the test (the face with a given plane, the
//! lowest vertex after a rotation), never from the code under test.

use std::path::PathBuf;

use acsg::contact::{ContactKind, ContactReport, ContactScene, PrincipalContact};
use acsg::feasibility::Problem;
use acsg::io::MeshSoup;
use acsg::model::{EdgeId, ElementId, FaceId, Part, VertexId};
use acsg::pose::{Bounds, Pose};
use acsg::tolerance::CONTACT_REL;
use glam::{DAffine3, DMat3, DVec3};

fn load(name: &str) -> Part {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../fixtures")
        .join(name);
    Part::from_path(&path).unwrap_or_else(|e| panic!("{name}: {e}"))
}

fn evaluate(fixed: &Part, moving: &Part, placement: DAffine3) -> ContactReport {
    ContactScene::new(fixed, moving).evaluate(&placement, CONTACT_REL)
}

fn face_with(part: &Part, normal: DVec3, offset: f64) -> ElementId {
    let i = part
        .faces()
        .iter()
        .position(|f| f.normal.distance(normal) < 1e-9 && (f.offset - offset).abs() < 1e-9)
        .unwrap_or_else(|| panic!("no face with normal {normal} and offset {offset}"));
    ElementId::Face(FaceId(i as u32))
}

fn vertex_at(part: &Part, p: DVec3) -> ElementId {
    let i = part
        .vertices()
        .iter()
        .position(|v| v.position.distance(p) < 1e-9)
        .expect("a vertex there");
    ElementId::Vertex(VertexId(i as u32))
}

fn edge_between(part: &Part, p: DVec3, q: DVec3) -> ElementId {
    let i = part
        .edges()
        .iter()
        .position(|e| {
            let [a, b] = e.vertices.map(|v| part.vertex(v).position);
            (a.distance(p) < 1e-9 && b.distance(q) < 1e-9) || (a.distance(q) < 1e-9 && b.distance(p) < 1e-9)
        })
        .expect("an edge there");
    ElementId::Edge(EdgeId(i as u32))
}

fn concave_edge(part: &Part) -> ElementId {
    let i = part.edges().iter().position(|e| !e.convex).expect("a concave edge");
    ElementId::Edge(EdgeId(i as u32))
}

fn contact(kind: ContactKind, fixed: ElementId, moving: ElementId) -> PrincipalContact {
    PrincipalContact { fixed, moving, kind }
}

fn sorted(mut v: Vec<PrincipalContact>) -> Vec<PrincipalContact> {
    v.sort();
    v
}

/// Indices of the moving part's vertices sorted by `key` after the rotation.
fn extreme(part: &Part, rotation: DMat3, key: impl Fn(DVec3) -> f64) -> Vec<usize> {
    let mut idx: Vec<usize> = (0..part.vertices().len()).collect();
    idx.sort_by(|&a, &b| {
        key(rotation * part.vertices()[a].position).total_cmp(&key(rotation * part.vertices()[b].position))
    });
    idx
}

fn assert_clean(report: &ContactReport) {
    assert_eq!(report.penetration, 0.0, "{report:?}");
}

const SLAB_TOP: (DVec3, f64) = (DVec3::Z, 0.0);

#[test]
fn a_cube_vertex_on_the_floor_is_f_v() {
    let (slab, cube) = (load("slab.off"), load("cube.off"));
    let r = DMat3::from_rotation_x(0.3) * DMat3::from_rotation_y(0.2);
    let order = extreme(&cube, r, |p| p.z);
    let low = cube.vertices()[order[0]].position;
    assert!(
        (r * cube.vertices()[order[1]].position).z - (r * low).z > 1.0,
        "a unique lowest vertex"
    );
    let report = evaluate(&slab, &cube, DAffine3::from_mat3_translation(r, -(r * low)));
    let want = contact(
        ContactKind::FaceVertex,
        face_with(&slab, SLAB_TOP.0, SLAB_TOP.1),
        vertex_at(&cube, low),
    );
    assert_eq!(report.contacts, vec![want]);
    assert_eq!(want.dof(), 5);
    assert!(!want.degenerate(&slab, &cube));
    assert_clean(&report);
    // Nothing else touches; the nearest non-touching pair is the second-lowest vertex.
    let second = (r * cube.vertices()[order[1]].position).z - (r * low).z;
    assert!(
        (report.min_gap.expect("within the search radius") - second).abs() < 1e-9,
        "{report:?}"
    );
}

#[test]
fn a_cube_edge_on_the_floor_is_f_e_and_flat_is_f_f() {
    let (slab, cube) = (load("slab.off"), load("cube.off"));
    let r = DMat3::from_rotation_x(0.3);
    let order = extreme(&cube, r, |p| p.z);
    let (p, q) = (cube.vertices()[order[0]].position, cube.vertices()[order[1]].position);
    let report = evaluate(
        &slab,
        &cube,
        DAffine3::from_mat3_translation(r, -(r * p) + DVec3::new(-5.0, 0.0, 0.0)),
    );
    let top = face_with(&slab, SLAB_TOP.0, SLAB_TOP.1);
    assert_eq!(
        report.contacts,
        vec![contact(ContactKind::FaceEdge, top, edge_between(&cube, p, q))]
    );
    assert_clean(&report);

    let flat = evaluate(&slab, &cube, DAffine3::from_translation(DVec3::new(-5.0, -5.0, 0.0)));
    assert_eq!(
        flat.contacts,
        vec![contact(ContactKind::FaceFace, top, face_with(&cube, -DVec3::Z, 0.0))]
    );
    assert_eq!(flat.contacts[0].dof(), 3);
    assert_clean(&flat);
}

#[test]
fn a_box_flat_in_the_inside_corner_is_two_f_f_and_the_corner_edge_is_implied() {
    let (l_block, box_part) = (load("l_block.off"), load("box.off"));
    let report = evaluate(&l_block, &box_part, DAffine3::IDENTITY);
    let floor = face_with(&l_block, DVec3::Z, 50.0);
    let wall = face_with(&l_block, -DVec3::X, -150.0);
    let bottom = face_with(&box_part, -DVec3::Z, -50.0);
    let side = face_with(&box_part, DVec3::X, 150.0);
    assert_eq!(
        report.contacts,
        sorted(vec![
            contact(ContactKind::FaceFace, floor, bottom),
            contact(ContactKind::FaceFace, wall, side)
        ])
    );
    assert_clean(&report);
}

/// A closed solid from polygons, whatever their winding (reversed if inward).
fn solid(positions: Vec<DVec3>, mut polygons: Vec<Vec<u32>>, name: &str) -> Part {
    let soup = |polygons: &Vec<Vec<u32>>| MeshSoup {
        positions: positions.clone(),
        polygons: polygons.clone(),
        polygon_lines: vec![],
        polygon_noun: "face",
    };
    if Part::try_new(&soup(&polygons), name).is_err() {
        polygons.iter_mut().for_each(|p| p.reverse());
    }
    Part::try_new(&soup(&polygons), name).unwrap_or_else(|e| panic!("{e}"))
}

/// A tetrahedron whose apex at the origin is sharper than the 90° groove: every edge
/// from the apex points into the free quadrant x < 0, z > 0.
fn spike() -> Part {
    let apex = DVec3::ZERO;
    let base = [
        DVec3::new(-0.3, -0.5, 1.0),
        DVec3::new(-0.3, 0.5, 1.0),
        DVec3::new(-1.0, 0.0, 0.3),
    ]
    .map(|d| d * 40.0);
    solid(
        vec![apex, base[0], base[1], base[2]],
        vec![vec![0, 1, 2], vec![0, 2, 3], vec![0, 3, 1], vec![1, 3, 2]],
        "spike",
    )
}

#[test]
fn a_sharp_vertex_pushed_into_the_concave_edge_is_a_non_degenerate_e_v() {
    // A box's corner cannot do this: with orthonormal edges d_i, all d_i·x <= 0 and
    // d_i·z >= 0 force some edge to lie on a wall. A sharper corner touches the groove
    // alone.
    let (l_block, spike) = (load("l_block.off"), spike());
    let report = evaluate(
        &l_block,
        &spike,
        DAffine3::from_translation(DVec3::new(150.0, 50.0, 50.0)),
    );
    let want = contact(
        ContactKind::EdgeVertex,
        concave_edge(&l_block),
        vertex_at(&spike, DVec3::ZERO),
    );
    assert_eq!(report.contacts, vec![want]);
    assert!(!want.degenerate(&l_block, &spike), "a vertex in a groove is stable");
    assert_eq!(want.dof(), 4);
    assert_clean(&report);
}

/// A prism along y whose cross-section (in x, z) is a triangle with a 60° apex at the
/// origin opening into the quadrant x < 0, z > 0.
fn wedge() -> Part {
    let deg = std::f64::consts::PI / 180.0;
    let section = [
        (0.0, 0.0),
        (40.0 * (105.0 * deg).cos(), 40.0 * (105.0 * deg).sin()),
        (40.0 * (165.0 * deg).cos(), 40.0 * (165.0 * deg).sin()),
    ];
    let positions = [10.0, 90.0]
        .iter()
        .flat_map(|&y| section.map(|(x, z)| DVec3::new(x, y, z)))
        .collect();
    let polygons = vec![
        vec![0, 1, 2],
        vec![3, 5, 4],
        vec![0, 3, 4, 1],
        vec![1, 4, 5, 2],
        vec![2, 5, 3, 0],
    ];
    solid(positions, polygons, "wedge")
}

#[test]
fn an_edge_in_the_groove_is_a_non_degenerate_e_e_t() {
    let l_block = load("l_block.off");
    let wedge = wedge();
    let apex = edge_between(&wedge, DVec3::new(0.0, 10.0, 0.0), DVec3::new(0.0, 90.0, 0.0));
    let report = evaluate(
        &l_block,
        &wedge,
        DAffine3::from_translation(DVec3::new(150.0, 0.0, 50.0)),
    );
    let want = contact(ContactKind::EdgeEdgeTouch, concave_edge(&l_block), apex);
    assert_eq!(report.contacts, vec![want]);
    assert!(!want.degenerate(&l_block, &wedge));
    assert_eq!(want.dof(), 2);
    assert_clean(&report);
}

#[test]
fn crossing_edges_are_e_e() {
    let (slab, cube) = (load("slab.off"), load("cube.off"));
    // Lowest edge along local x, tilted down towards +x and yawed.
    let r =
        DMat3::from_rotation_z(0.4) * DMat3::from_rotation_y(0.1) * DMat3::from_rotation_x(std::f64::consts::FRAC_PI_4);
    let (p, q) = (DVec3::new(0.0, 0.0, 0.0), DVec3::new(10.0, 0.0, 0.0));
    let mid = r * ((p + q) * 0.5);
    let report = evaluate(
        &slab,
        &cube,
        DAffine3::from_mat3_translation(r, DVec3::new(100.0, 20.0, 0.0) - mid),
    );
    let slab_edge = edge_between(&slab, DVec3::new(100.0, -100.0, 0.0), DVec3::new(100.0, 100.0, 0.0));
    let want = contact(ContactKind::EdgeEdge, slab_edge, edge_between(&cube, p, q));
    assert_eq!(report.contacts, vec![want]);
    assert_eq!(want.dof(), 5);
    assert_clean(&report);
}

#[test]
fn collinear_convex_edges_are_a_degenerate_e_e_t() {
    let (slab, cube) = (load("slab.off"), load("cube.off"));
    let r = DMat3::from_rotation_y(std::f64::consts::FRAC_PI_4);
    let (p, q) = (DVec3::new(10.0, 0.0, 0.0), DVec3::new(10.0, 10.0, 0.0));
    let report = evaluate(
        &slab,
        &cube,
        DAffine3::from_mat3_translation(r, DVec3::new(100.0, 20.0, 0.0) - r * p),
    );
    let slab_edge = edge_between(&slab, DVec3::new(100.0, -100.0, 0.0), DVec3::new(100.0, 100.0, 0.0));
    let want = contact(ContactKind::EdgeEdgeTouch, slab_edge, edge_between(&cube, p, q));
    assert_eq!(report.contacts, vec![want]);
    assert!(want.degenerate(&slab, &cube));
    assert_clean(&report);
}

#[test]
fn vertex_on_vertex_is_a_degenerate_v_v() {
    let (slab, cube) = (load("slab.off"), load("cube.off"));
    let r = DMat3::from_rotation_x(0.5) * DMat3::from_rotation_y(-0.4);
    let low = cube.vertices()[extreme(&cube, r, |p| p.z)[0]].position;
    let corner = DVec3::new(100.0, 100.0, 0.0);
    let report = evaluate(&slab, &cube, DAffine3::from_mat3_translation(r, corner - r * low));
    let want = contact(
        ContactKind::VertexVertex,
        vertex_at(&slab, corner),
        vertex_at(&cube, low),
    );
    assert_eq!(report.contacts, vec![want]);
    assert!(want.degenerate(&slab, &cube));
    assert_clean(&report);
}

#[test]
fn a_peg_face_flush_with_a_hole_wall_is_f_f() {
    let (block, peg) = (load("block_with_hole.off"), load("peg.off"));
    let report = evaluate(&block, &peg, DAffine3::from_translation(DVec3::X));
    let want = contact(
        ContactKind::FaceFace,
        face_with(&block, -DVec3::X, -65.0),
        face_with(&peg, DVec3::X, 64.0),
    );
    assert_eq!(report.contacts, vec![want]);
    assert_clean(&report);
    // The other walls are 1 and 2 away (y sides, -x side); the gap reported is 1.
    assert!((report.min_gap.expect("near walls") - 1.0).abs() < 1e-9, "{report:?}");

    let centred = evaluate(&block, &peg, DAffine3::IDENTITY);
    assert!(centred.contacts.is_empty());
    let pushed = evaluate(&block, &peg, DAffine3::from_translation(DVec3::new(2.0, 0.0, 0.0)));
    assert!((pushed.penetration - 1.0).abs() < 1e-9);
}

/// The spike's apex and the wedge's apex edge are extreme in this direction.
fn outward() -> DVec3 {
    DVec3::new(1.0, 0.0, -1.0).normalize()
}

/// Turns the slab so that its bottom face (normal -z) faces -outward(), i.e. towards the
/// fixed part's apex, and puts the bottom face's centre at `target`.
fn slab_against(target: DVec3) -> DAffine3 {
    let r = DMat3::from_rotation_y(135f64.to_radians());
    assert!((r * DVec3::Z).distance(outward()) < 1e-12);
    DAffine3::from_mat3_translation(r, target - r * DVec3::new(0.0, 0.0, -10.0))
}

#[test]
fn a_fixed_vertex_on_a_moving_face_is_v_f() {
    let (spike, slab) = (spike(), load("slab.off"));
    let report = evaluate(&spike, &slab, slab_against(DVec3::ZERO));
    let want = contact(
        ContactKind::VertexFace,
        vertex_at(&spike, DVec3::ZERO),
        face_with(&slab, -DVec3::Z, 10.0),
    );
    assert_eq!(report.contacts, vec![want]);
    assert_clean(&report);
}

#[test]
fn a_fixed_edge_in_a_moving_face_is_e_f() {
    let (wedge, slab) = (wedge(), load("slab.off"));
    let report = evaluate(&wedge, &slab, slab_against(DVec3::new(0.0, 50.0, 0.0)));
    let apex = edge_between(&wedge, DVec3::new(0.0, 10.0, 0.0), DVec3::new(0.0, 90.0, 0.0));
    let want = contact(ContactKind::EdgeFace, apex, face_with(&slab, -DVec3::Z, 10.0));
    assert_eq!(report.contacts, vec![want]);
    assert_eq!(want.dof(), 4);
    assert_clean(&report);
}

#[test]
fn a_fixed_vertex_inside_a_moving_edge_is_a_degenerate_v_e() {
    let (spike, cube) = (spike(), load("cube.off"));
    // The axis-aligned cube's edge at x = 0, z = 10 is its extreme towards -outward().
    let (p, q) = (DVec3::new(0.0, 0.0, 10.0), DVec3::new(0.0, 10.0, 10.0));
    let report = evaluate(&spike, &cube, DAffine3::from_translation(-(p + q) * 0.5));
    let want = contact(
        ContactKind::VertexEdge,
        vertex_at(&spike, DVec3::ZERO),
        edge_between(&cube, p, q),
    );
    assert_eq!(report.contacts, vec![want]);
    assert!(want.degenerate(&spike, &cube));
    assert_clean(&report);
}

#[test]
fn a_peg_corner_on_the_holes_chamfer_is_f_v() {
    let (block, peg) = (load("block_with_chamfered_hole.off"), load("peg.off"));
    // The +x chamfer: the plane x - z = 20 between z = 45 and 50, facing the hole.
    let normal = DVec3::new(-1.0, 0.0, 1.0).normalize();
    let chamfer = face_with(&block, normal, normal.dot(DVec3::new(65.0, 0.0, 45.0)));
    // Tilted about x, the peg's corner (64, 36, 10) is its unique extreme towards the
    // chamfer; put it at (67, 36, 47), on the chamfer, with the peg inside the opening.
    let r = DMat3::from_rotation_x(0.05);
    let order = extreme(&peg, r, |p| p.z - p.x);
    let corner = peg.vertices()[order[0]].position;
    assert_eq!(corner, DVec3::new(64.0, 36.0, 10.0));
    let report = evaluate(
        &block,
        &peg,
        DAffine3::from_mat3_translation(r, DVec3::new(67.0, 36.0, 47.0) - r * corner),
    );
    assert_eq!(
        report.contacts,
        vec![contact(ContactKind::FaceVertex, chamfer, vertex_at(&peg, corner))]
    );
    assert_clean(&report);
}

/// The box's side face flat on the L-block's wall over a strip 0.01 high below the
/// wall's top rim (z = 150), leaning away from the wall by `lean` about its bottom edge.
fn box_face_over_the_rim(lean: f64) -> DAffine3 {
    let bottom = DVec3::new(150.0, 10.0, 50.0);
    let r = DMat3::from_rotation_y(-lean);
    DAffine3::from_mat3_translation(r, DVec3::new(150.0, 10.0, 149.99) - r * bottom)
}

/// Leaning 1e-5 rad, the box's face is within the tolerance of the wall over the
/// strip where they overlap, and 1e-3 off it 100 higher, past the loose tolerance. Read
/// from end to end, the bottom edge lies in the wall and the rim in the box's face:
/// two parallel lines in both planes, which put the planes together, so read over the
/// overlap (docs/concepts.md#tolerances) the faces lie on each other. Checkers differ
/// there, so no witness may show either state; upright, every reading gives the faces
/// on each other and the pose is a witness.
#[test]
fn a_face_leaning_over_a_walls_rim_is_no_witness() {
    let (l_block, box_part) = (load("l_block.off"), load("box.off"));
    let wall = face_with(&l_block, -DVec3::X, -150.0);
    let side = face_with(&box_part, DVec3::X, 150.0);
    let bottom_edge = edge_between(&box_part, DVec3::new(150.0, 10.0, 50.0), DVec3::new(150.0, 90.0, 50.0));
    let leaning = box_face_over_the_rim(1e-5);
    let report = evaluate(&l_block, &box_part, leaning);
    assert!(
        report
            .contacts
            .contains(&contact(ContactKind::FaceEdge, wall, bottom_edge)),
        "read from end to end, the bottom edge lies in the wall: {report:?}"
    );
    assert!(
        !report.contacts.iter().any(|pc| pc.kind == ContactKind::FaceFace),
        "{report:?}"
    );
    assert_clean(&report);
    let around = |placement: &DAffine3| {
        let pose = Pose::from_affine(placement, &DAffine3::IDENTITY).expect("a rigid placement");
        let x = pose.to_array();
        let bounds = Bounds::try_new(x.map(|v| v - 1.0), x.map(|v| v + 1.0)).expect("valid bounds");
        (pose, bounds)
    };
    let (pose, bounds) = around(&leaning);
    let problem = Problem::new(&l_block, &box_part, bounds, DAffine3::IDENTITY);
    assert_eq!(problem.verify(&pose), None, "the readings differ: no witness");
    let (pose, bounds) = around(&box_face_over_the_rim(0.0));
    let problem = Problem::new(&l_block, &box_part, bounds, DAffine3::IDENTITY);
    let state = problem.verify(&pose).expect("upright, a witness");
    assert!(state.contains(&contact(ContactKind::FaceFace, wall, side)), "{state:?}");
}
