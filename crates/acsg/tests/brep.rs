//! B-rep construction over the fixture models, against hand-derived counts
//! (fixtures/README.md) and exact volumes.

use std::path::PathBuf;

use acsg::model::{Part, ppc_count};

/// Asserts that two numbers are within `tol` of each other, printing both if not.
macro_rules! assert_near {
    ($a:expr, $b:expr, $tol:expr $(,)?) => {{
        let (a, b, tol): (f64, f64, f64) = ($a, $b, $tol);
        assert!(
            acsg::tolerance::near(a, b, tol),
            "{} = {a}, {} = {b}: more than {tol} apart",
            stringify!($a),
            stringify!($b)
        );
    }};
}

fn fixture(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../fixtures")
        .join(name)
}

fn load(name: &str) -> Part {
    Part::from_path(&fixture(name)).unwrap_or_else(|e| panic!("{name}: {e}"))
}

/// (faces, faces with holes, vertices, convex vertices, edges, convex edges, concave edges)
fn counts(p: &Part) -> (usize, usize, usize, usize, usize, usize, usize) {
    let convex_edges = p.convex_edges().count();
    (
        p.faces().len(),
        p.faces().iter().filter(|f| f.loops.len() > 1).count(),
        p.vertices().len(),
        p.convex_vertices().count(),
        p.edges().len(),
        convex_edges,
        p.edges().len() - convex_edges,
    )
}

/// Geometry up to numbering: sorted vertex positions and sorted face planes.
fn geometry(p: &Part) -> (Vec<[i64; 3]>, Vec<[i64; 4]>) {
    let q = |x: f64| (x * 1e6).round() as i64;
    let mut vs: Vec<_> = p.vertices().iter().map(|v| v.position.to_array().map(q)).collect();
    vs.sort_unstable();
    let mut fs: Vec<_> = p
        .faces()
        .iter()
        .map(|f| [q(f.normal.x), q(f.normal.y), q(f.normal.z), q(f.offset)])
        .collect();
    fs.sort_unstable();
    (vs, fs)
}

const L_BLOCK: (usize, usize, usize, usize, usize, usize, usize) = (8, 0, 12, 10, 18, 17, 1);
const BOXLIKE: (usize, usize, usize, usize, usize, usize, usize) = (6, 0, 8, 8, 12, 12, 0);
const HOLED: (usize, usize, usize, usize, usize, usize, usize) = (10, 2, 16, 8, 24, 20, 4);

#[test]
fn l_block_and_box_give_the_papers_counts_from_every_format() {
    let boxes = ["box.off", "box.obj", "box.stl", "box_binary.stl"].map(load);
    for b in &boxes {
        assert_eq!(counts(b), BOXLIKE, "{}", b.name());
    }
    let reference = load("l_block.off");
    for name in [
        "l_block.off",
        "l_block.obj",
        "l_block.stl",
        "l_block_binary.stl",
        "l_block.ply",
    ] {
        let part = load(name);
        assert_eq!(counts(&part), L_BLOCK, "{name}");
        assert_near!(part.volume(), 1_500_000.0, 1e-6);
        assert_eq!(geometry(&part), geometry(&reference), "{name} differs in geometry");
        // Canonical numbering makes the same part identical whatever the format.
        assert_eq!(part.vertices(), reference.vertices(), "{name} numbering");
        assert_eq!(part.edges(), reference.edges(), "{name} numbering");
        for b in &boxes {
            let ppc = ppc_count(&part, b);
            assert_eq!(
                (ppc.f_v, ppc.e_e, ppc.v_f, ppc.total()),
                (64, 204, 60, 328),
                "{name} x {}",
                b.name()
            );
        }
    }
}

#[test]
fn block_with_a_through_hole_has_two_holed_faces_and_four_concave_edges() {
    for name in ["block_with_hole.off", "block_with_hole.obj", "block_with_hole.stl"] {
        let part = load(name);
        assert_eq!(counts(&part), HOLED, "{name}");
        assert_near!(part.volume(), 455_000.0, 1e-6);
        for f in part.faces().iter().filter(|f| f.loops.len() > 1) {
            assert_near!(f.area, 100.0 * 100.0 - 30.0 * 30.0, 1e-6);
            assert_eq!(f.outer().vertices.len(), 4);
            assert_eq!(f.holes()[0].vertices.len(), 4);
        }
    }
}

#[test]
fn the_plus_peg_and_its_hole_give_the_hand_derived_counts_from_every_format() {
    for (name, expected, volume) in [
        ("plus_peg", (14, 0, 24, 16, 36, 32, 4), 128_000.0),
        ("block_with_plus_hole", (18, 2, 32, 16, 48, 40, 8), 409_800.0),
    ] {
        let parts = ["off", "stl"].map(|ext| load(&format!("{name}.{ext}")));
        for part in &parts {
            assert_eq!(counts(part), expected, "{name}");
            assert_near!(part.volume(), volume, 1e-6);
        }
        assert_eq!(geometry(&parts[0]), geometry(&parts[1]), "{name}: the formats differ");
    }
}

#[test]
fn other_fixtures_are_boxes() {
    for (name, volume) in [
        ("peg.off", 62_720.0),
        ("peg.stl", 62_720.0),
        ("cube.off", 1000.0),
        ("cube.stl", 1000.0),
        ("slab.off", 400_000.0),
        ("slab.obj", 400_000.0),
    ] {
        let part = load(name);
        assert_eq!(counts(&part), BOXLIKE, "{name}");
        assert_near!(part.volume(), volume, 1e-6);
    }
}

#[test]
fn edges_and_loops_are_consistent() {
    for name in ["l_block.stl", "block_with_hole.off", "cube.obj"] {
        let part = load(name);
        // Each edge appears once in a loop of each of its faces, in opposite directions.
        for (i, e) in part.edges().iter().enumerate() {
            let runs: Vec<(u32, bool)> = part
                .faces()
                .iter()
                .enumerate()
                .flat_map(|(fi, f)| f.loops.iter().map(move |l| (fi, l)))
                .flat_map(|(fi, l)| {
                    let n = l.vertices.len();
                    (0..n).filter(move |&k| l.edges[k].index() == i).map(move |k| {
                        (
                            fi as u32,
                            l.vertices[k] == e.vertices[0] && l.vertices[(k + 1) % n] == e.vertices[1],
                        )
                    })
                })
                .collect();
            assert_eq!(
                runs,
                {
                    let mut expected = vec![(e.faces[0].0, true), (e.faces[1].0, false)];
                    expected.sort();
                    expected
                },
                "{name} edge {i}"
            );
        }
        // Euler–Poincaré: V - E + F - (L - F) = 2 (1 - genus); all fixtures have genus 0
        // except the holed block (genus 1).
        let loops: usize = part.faces().iter().map(|f| f.loops.len()).sum();
        let chi = part.vertices().len() as i64 - part.edges().len() as i64 + part.faces().len() as i64
            - (loops - part.faces().len()) as i64;
        let genus = i64::from(name.starts_with("block_with_hole"));
        assert_eq!(chi, 2 * (1 - genus), "{name}");
    }
}

#[test]
fn convex_pieces_are_exact() {
    for (name, expected_pieces) in [
        ("l_block.off", Some(2)),
        ("block_with_hole.off", Some(4)),
        ("cube.off", Some(1)),
        ("l_block.stl", Some(2)),
        ("block_with_hole.stl", Some(4)),
        ("block_with_tight_hole.off", Some(4)),
        ("block_with_chamfered_hole.off", Some(8)),
        ("block_with_round_hole.off", None),
        ("block_with_round_hole.stl", None),
    ] {
        let part = load(name);
        let pieces = part.convex_pieces();
        let total: f64 = pieces.iter().map(|p| p.volume()).sum();
        assert_near!(total, part.volume(), 1e-9 * part.volume());
        if let Some(n) = expected_pieces {
            assert_eq!(pieces.len(), n, "{name}");
        }
        for piece in pieces {
            // Convex: every corner on the inner side of every bounding plane.
            for &v in piece.vertices() {
                assert!(piece.outside_distance(v) <= 1e-9 * part.bounds().diagonal());
            }
            // Inside the part: the centre has winding number 1.
            assert_near!(part.winding_number(piece.center()), 1.0, 1e-9);
        }
    }
}

#[test]
fn each_bad_fixture_reports_its_defect_class() {
    use acsg::load::{DefectKind, ModelError};
    for (name, kind) in [
        ("bad/open_box.off", DefectKind::NotClosed),
        ("bad/nonmanifold.off", DefectKind::NotManifold),
        ("bad/flipped_face.off", DefectKind::InconsistentOrientation),
        ("bad/inward.off", DefectKind::InwardOrientation),
        ("bad/zero_area.off", DefectKind::ZeroArea),
        ("bad/nonplanar.off", DefectKind::NotPlanar),
        ("bad/two_shells.off", DefectKind::SeveralShells),
    ] {
        match Part::from_path(&fixture(name)) {
            Err(ModelError::Invalid { name: path, report }) => {
                assert!(path.ends_with(name), "{path}");
                assert!(report.defects().iter().all(|d| d.kind == kind), "{name}: {report}");
                assert!(!report.defects().is_empty());
                assert!(
                    report
                        .defects()
                        .iter()
                        .all(|d| !d.fix.is_empty() && !d.place.is_empty())
                );
            }
            other => panic!("{name}: expected a {kind:?} report, got {other:?}"),
        }
    }
    for name in [
        "bad/empty.off",
        "bad/whitespace.stl",
        "bad/nan.off",
        "bad/inf.obj",
        "bad/truncated.stl",
        "bad/bad_index.off",
        "bad/garbage.obj",
    ] {
        assert!(
            matches!(Part::from_path(&fixture(name)), Err(ModelError::Read(_))),
            "{name}"
        );
    }
}

#[test]
fn a_gap_anywhere_in_a_fine_mesh_is_reported_with_its_place() {
    let part = load("l_block.stl");
    let mut soup = acsg::examples::triangle_soup(&part);
    soup = acsg::examples::refine_midpoints(&soup);
    let removed = soup.polygons.remove(17);
    let err = Part::try_new(&soup, "holey").expect_err("a gap");
    let report = err.report().expect("a validation report");
    assert!(report.has(acsg::load::DefectKind::NotClosed));
    // The three edges of the removed triangle are the gap.
    assert_eq!(report.defects().len(), 3);
    let corner = soup.positions[removed[0] as usize];
    let text = format!("({}, {}, {})", corner.x, corner.y, corner.z);
    assert!(report.to_string().contains(&text), "{report}");
}
