//! Property tests of the separating axis test (`acsg::contact::penetration`) against
//! facts computed independently here: interval overlaps of axis-aligned boxes, vertex
//! containment, the separating planes themselves, projections on random directions,
//! symmetry of the two roles, and translations along the reported axis.

mod common;

use std::path::Path;
use std::sync::OnceLock;

use acsg::contact::ContactScene;
use acsg::contact::{convex_separation, penetration};
use acsg::geometry::ConvexPolytope;
use acsg::model::Part;
use acsg::model::{EdgeId, ElementId, FaceId, VertexId};
use acsg::tolerance::{CONTACT_REL, GAP_SEARCH_REL};
use glam::{DAffine3, DQuat, DVec3};
use proptest::prelude::*;

fn vec3(lo: f64, hi: f64) -> impl Strategy<Value = DVec3> {
    (lo..hi, lo..hi, lo..hi).prop_map(|(x, y, z)| DVec3::new(x, y, z))
}

fn unit_vector() -> impl Strategy<Value = DVec3> {
    vec3(-1.0, 1.0).prop_map(|v| v.try_normalize().unwrap_or(DVec3::X))
}

fn rotation() -> impl Strategy<Value = DQuat> {
    (unit_vector(), 0.0..std::f64::consts::TAU).prop_map(|(axis, angle)| DQuat::from_axis_angle(axis, angle))
}

/// The box `[-h, h]`.
fn centred_box(h: DVec3) -> ConvexPolytope {
    ConvexPolytope::cuboid(-h, h)
}

/// The interval of the projections of some points onto `u`.
fn extent(points: impl Iterator<Item = DVec3>, u: DVec3) -> (f64, f64) {
    points.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| {
        (lo.min(u.dot(p)), hi.max(u.dot(p)))
    })
}

/// Hand formula for two axis-aligned boxes: the smallest interval overlap over x, y, z
/// (when the boxes are apart, minus the largest gap).
fn aabb_depth(a_min: DVec3, a_max: DVec3, b_min: DVec3, b_max: DVec3) -> f64 {
    (0..3)
        .map(|k| (a_max[k] - b_min[k]).min(b_max[k] - a_min[k]))
        .fold(f64::INFINITY, f64::min)
}

fn cube_fixture() -> &'static Part {
    static CUBE: OnceLock<Part> = OnceLock::new();
    CUBE.get_or_init(|| {
        Part::from_path(&Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures/cube.off")).expect("cube loads")
    })
}

/// The round peg and its hole (pieces with and without Gauss maps), loaded once.
fn round_peg_in_hole() -> &'static (ContactScene<'static>, f64) {
    static SCENE: OnceLock<(ContactScene<'static>, f64)> = OnceLock::new();
    SCENE.get_or_init(|| {
        let load = |name: &str| -> &'static Part {
            let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures").join(name);
            Box::leak(Box::new(Part::from_path(&path).expect("fixture loads")))
        };
        let scene = ContactScene::new(load("block_with_round_hole.off"), load("round_peg.off"));
        let scale = scene.scale();
        (scene, scale)
    })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(128))]

    /// The optimiser's fast residual (SAT with early exits) is exactly the positive
    /// part of the full penetration depth.
    #[test]
    fn penetration_excess_is_the_positive_part_of_the_depth(
        t in vec3(-3.0, 3.0),
        lift in -20.0f64..60.0,
        q in (unit_vector(), -0.3f64..0.3).prop_map(|(axis, angle)| DQuat::from_axis_angle(axis, angle)),
    ) {
        let (scene, _) = round_peg_in_hole();
        let pose = DAffine3::from_rotation_translation(q, DVec3::new(t.x, t.y, t.z + lift));
        let full = scene.penetration_depth(&pose).max(0.0);
        prop_assert_eq!(scene.penetration_excess(&pose), full);
    }

    /// Called for nearby poses, as the optimiser calls it, the fast residual starts each
    /// pair of pieces from the axis that answered for it at the last pose: still
    /// exactly the positive part of the full depth.
    #[test]
    fn penetration_excess_at_nearby_poses_is_the_positive_part_of_the_depth(
        t in vec3(-3.0, 3.0),
        lift in -5.0f64..45.0,
        q in (unit_vector(), -0.05f64..0.05).prop_map(|(axis, angle)| DQuat::from_axis_angle(axis, angle)),
        steps in proptest::collection::vec((vec3(-0.05, 0.05), unit_vector(), -0.002f64..0.002), 1..6),
    ) {
        let (scene, _) = round_peg_in_hole();
        let mut pose = DAffine3::from_rotation_translation(q, DVec3::new(t.x, t.y, t.z + lift));
        let _ = scene.penetration_excess(&pose);
        for (shift, axis, angle) in steps {
            pose = DAffine3::from_rotation_translation(DQuat::from_axis_angle(axis, angle), shift) * pose;
            let full = scene.penetration_depth(&pose).max(0.0);
            prop_assert_eq!(scene.penetration_excess(&pose), full);
        }
    }

    /// The thresholded query (pairs dropped early) answers as the full depth does.
    #[test]
    fn penetrates_beyond_agrees_with_the_depth(
        t in vec3(-3.0, 3.0),
        lift in -20.0f64..60.0,
        q in (unit_vector(), -0.3f64..0.3).prop_map(|(axis, angle)| DQuat::from_axis_angle(axis, angle)),
        threshold in prop_oneof![Just(0.0), 0.0f64..3.0],
    ) {
        let (scene, _) = round_peg_in_hole();
        let pose = DAffine3::from_rotation_translation(q, DVec3::new(t.x, t.y, t.z + lift));
        let depth = scene.penetration_depth(&pose);
        prop_assert_eq!(scene.penetrates_beyond(&pose, threshold), depth > threshold, "depth {}", depth);
    }

    #[test]
    fn axis_aligned_boxes_match_interval_overlaps(
        a_min in vec3(-2.0, 2.0),
        a_size in vec3(0.1, 3.0),
        b_size in vec3(0.1, 3.0),
        t in vec3(-5.0, 5.0),
    ) {
        let a = ConvexPolytope::cuboid(a_min, a_min + a_size);
        let b = ConvexPolytope::cuboid(DVec3::ZERO, b_size);
        let s = convex_separation(&a, &b, &DAffine3::from_translation(t));
        let expected = aabb_depth(a_min, a_min + a_size, t, t + b_size);
        let l = a_size.length().max(b_size.length());
        prop_assert!((s.depth - expected).abs() <= 1e-9 * l, "depth {} expected {}", s.depth, expected);
        // The winning axis is a coordinate axis.
        prop_assert!(s.axis.abs().max_element() > 1.0 - 1e-12);
    }

    #[test]
    fn parts_of_axis_aligned_cubes_match_interval_overlaps(t in vec3(-15.0, 15.0)) {
        // The fixture cube [0,10]^3 against itself, translated: one piece each.
        let cube = cube_fixture();
        let r = penetration(cube, cube, &DAffine3::from_translation(t));
        let expected = aabb_depth(DVec3::ZERO, DVec3::splat(10.0), t, t + 10.0);
        prop_assert!((r.depth - expected).abs() <= 1e-9 * 20.0, "depth {} expected {}", r.depth, expected);
        prop_assert_eq!(r.pieces, Some((0, 0)));
        // A pair is examined (has a plane) exactly when the boxes are within the margin.
        prop_assert_eq!(r.certificates.len(), usize::from(expected >= -1e-6 * 20.0));
    }

    #[test]
    fn rotated_boxes(
        ha in vec3(0.2, 2.0),
        hb in vec3(0.2, 2.0),
        q in rotation(),
        t in vec3(-3.0, 3.0),
        probes in proptest::collection::vec(unit_vector(), 16),
    ) {
        let (a, b) = (centred_box(ha), centred_box(hb));
        let pose = DAffine3::from_rotation_translation(q, t);
        let inverse = pose.inverse();
        let l = 2.0 * ha.length().max(hb.length());
        let eps = 1e-9 * l;
        let s = convex_separation(&a, &b, &pose);
        let b_points = || b.vertices().iter().map(|&p| pose.transform_point3(p));
        prop_assert!((s.axis.length() - 1.0).abs() < 1e-12);

        // The roles of A and B swapped: same depth.
        let swapped = convex_separation(&b, &a, &inverse);
        prop_assert!((swapped.depth - s.depth).abs() <= eps, "{} vs swapped {}", s.depth, swapped.depth);

        if s.depth < -eps {
            // No corner of either box inside the other.
            prop_assert!(b_points().all(|p| a.outside_distance(p) > 0.0));
            prop_assert!(a.vertices().iter().all(|&p| b.outside_distance(inverse.transform_point3(p)) > 0.0));
            // The plane separates them.
            prop_assert!(a.vertices().iter().all(|&p| s.axis.dot(p) <= s.offset + 1e-9));
            prop_assert!(b_points().all(|p| s.axis.dot(p) >= s.offset - 1e-9));
            // The gap along the axis is the reported one.
            let (_, max_a) = extent(a.vertices().iter().copied(), s.axis);
            let (min_b, _) = extent(b_points(), s.axis);
            prop_assert!((min_b - max_a + s.depth).abs() <= eps);
        }
        if s.depth > eps {
            // No direction is cheaper to leave along than the reported depth.
            for &u in &probes {
                let (min_a, max_a) = extent(a.vertices().iter().copied(), u);
                let (min_b, max_b) = extent(b_points(), u);
                prop_assert!((max_a - min_b).min(max_b - min_a) >= s.depth - eps);
            }
            // Moving B out along the axis by the depth (and a hair) separates it.
            let out = DAffine3::from_translation(s.axis * (s.depth * (1.0 + 1e-6) + eps)) * pose;
            let after = convex_separation(&a, &b, &out);
            prop_assert!(after.depth <= eps, "still penetrating by {}", after.depth);
            // Half-way it still penetrates, by half (the depth is 1-Lipschitz in the translation).
            let half = DAffine3::from_translation(s.axis * (0.5 * s.depth)) * pose;
            let after = convex_separation(&a, &b, &half);
            prop_assert!((after.depth - 0.5 * s.depth).abs() <= eps, "half-way {} of {}", after.depth, s.depth);
        }
    }

    #[test]
    fn face_on_face_touches(
        ha in vec3(0.2, 2.0),
        hb in vec3(0.2, 2.0),
        angle in 0.0..std::f64::consts::TAU,
        side in prop::bool::ANY,
        yz in (-0.1f64..0.1, -0.1f64..0.1),
    ) {
        // B turned about x keeps its faces x = ±hb.x; put one on A's face x = ±ha.x.
        let sign = if side { 1.0 } else { -1.0 };
        let t = DVec3::new(sign * (ha.x + hb.x), yz.0, yz.1);
        let pose = DAffine3::from_rotation_translation(DQuat::from_rotation_x(angle), t);
        let s = convex_separation(&centred_box(ha), &centred_box(hb), &pose);
        let l = 2.0 * ha.length().max(hb.length());
        prop_assert!(s.depth.abs() <= 1e-9 * l, "depth {}", s.depth);
    }

    #[test]
    fn box_inside_box_penetrates(
        ha in vec3(1.0, 2.0),
        hb in vec3(0.05, 0.2),
        q in rotation(),
        t in vec3(-0.5, 0.5),
    ) {
        // Every corner of B is within 0.5 + 0.2·√3 < 1 of the origin on each coordinate,
        // so B is wholly inside A: no surfaces meet, yet it penetrates. Along any
        // direction B's interval lies inside A's, so the overlap is at least B's width
        // there, at least its smallest width 2·min(hb).
        let (a, b) = (centred_box(ha), centred_box(hb));
        let pose = DAffine3::from_rotation_translation(q, t);
        prop_assert!(b.vertices().iter().all(|&p| a.outside_distance(pose.transform_point3(p)) < 0.0));
        let s = convex_separation(&a, &b, &pose);
        prop_assert!(s.depth >= 2.0 * hb.min_element() - 1e-9, "depth {}", s.depth);
        prop_assert!(s.depth > 0.0);
    }
}

/// A convex part with more than 24 faces (compared through its Gauss map against
/// another large piece) and one with fewer, both from the brute-force hull.
fn large_and_small_convex_parts() -> &'static (Part, Part) {
    static PARTS: OnceLock<(Part, Part)> = OnceLock::new();
    PARTS.get_or_init(|| {
        let part = |seed: u64, count: usize, radius: f64, min_faces: usize, max_faces: usize| {
            (seed..seed + 200)
                .find_map(|s| {
                    common::hull::convex_part(&common::hull::random_points(s, count, radius), "random")
                        .filter(|p| (min_faces..=max_faces).contains(&p.faces().len()))
                })
                .expect("a random hull in general position")
        };
        (part(11, 20, 1.0, 25, usize::MAX), part(97, 9, 0.7, 4, 24))
    })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    /// A piece of more than 24 faces against one of at most 24 (the mixed pair, plain
    /// SAT on the prepared hulls) gives the depth of the plain SAT on the polytopes,
    /// which tests every face normal and edge pair of both.
    #[test]
    fn large_against_small_pieces_match_the_plain_sat(
        t in vec3(-2.0, 2.0),
        q in rotation(),
        swap in prop::bool::ANY,
    ) {
        let (large, small) = large_and_small_convex_parts();
        let (a, b) = if swap { (small, large) } else { (large, small) };
        let pose = DAffine3::from_rotation_translation(q, t);
        let report = penetration(a, b, &pose);
        let plain = convex_separation(&a.convex_pieces()[0], &b.convex_pieces()[0], &pose);
        let l = 2.0;
        if plain.depth > -1e-6 * l {
            prop_assert!((report.depth - plain.depth).abs() <= 1e-9 * l, "{} vs plain {}", report.depth, plain.depth);
        } else {
            prop_assert!(report.depth < 0.0, "apart by {} yet {}", plain.depth, report.depth);
        }
        let excess = ContactScene::new(a, b).penetration_excess(&pose);
        prop_assert!((excess - plain.depth.max(0.0)).abs() <= 1e-9 * l, "excess {} vs plain {}", excess, plain.depth);
    }
}

proptest! {
    // A brute-force pass over every pair of elements: fewer cases.
    #![proptest_config(ProptestConfig::with_cases(24))]

    /// The smallest gap the contact module reports (with its cheap plane tests that skip
    /// pairs) is the brute-force minimum over every pair of elements that do not touch.
    #[test]
    fn smallest_gap_is_the_brute_force_minimum(
        t in vec3(-1.5, 1.5),
        lift in 0.0f64..40.0,
        q in (unit_vector(), -0.05f64..0.05).prop_map(|(axis, angle)| DQuat::from_axis_angle(axis, angle)),
    ) {
        let (scene, scale) = round_peg_in_hole();
        let pose = DAffine3::from_rotation_translation(q, DVec3::new(t.x, t.y, t.z + lift));
        let report = scene.evaluate(&pose, CONTACT_REL);
        let (fixed, moving) = scene.parts();
        let elements = |part: &Part| -> Vec<ElementId> {
            (0..part.faces().len() as u32).map(|i| ElementId::Face(FaceId(i)))
                .chain((0..part.edges().len() as u32).map(|i| ElementId::Edge(EdgeId(i))))
                .chain((0..part.vertices().len() as u32).map(|i| ElementId::Vertex(VertexId(i))))
                .collect()
        };
        let (tol, search) = (CONTACT_REL * scale, GAP_SEARCH_REL * scale);
        let mut brute: Option<f64> = None;
        for a in elements(fixed) {
            for b in elements(moving) {
                let d = scene.element_distance(&pose, a, b);
                if d > tol && d < brute.unwrap_or(search) {
                    brute = Some(d);
                }
            }
        }
        match (report.min_gap, brute) {
            (Some(x), Some(y)) => prop_assert!((x - y).abs() <= 1e-12 * scale, "{x} vs {y}"),
            (x, y) => prop_assert_eq!(x, y),
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    /// On the round peg in its hole (pieces of many faces, some merged from cells), the
    /// scene's depth is the deepest pair's depth by the plain SAT on the pieces, which
    /// tests every face normal and edge pair of both.
    #[test]
    fn round_pieces_depth_is_the_plain_sat_of_the_deepest_pair(
        t in vec3(-1.5, 1.5),
        z in 0.0..40.0_f64,
        q in (unit_vector(), -0.05..0.05_f64),
    ) {
        let (scene, scale) = round_peg_in_hole();
        let (fixed, moving) = scene.parts();
        let pose = DAffine3::from_rotation_translation(DQuat::from_axis_angle(q.0, q.1), t + DVec3::Z * z);
        let plain = fixed
            .convex_pieces()
            .iter()
            .flat_map(|a| moving.convex_pieces().iter().map(move |b| convex_separation(a, b, &pose).depth))
            .fold(f64::NEG_INFINITY, f64::max);
        let depth = scene.penetration_depth(&pose);
        if plain > -1e-6 * scale {
            prop_assert!((depth - plain).abs() <= 1e-9 * scale, "{} vs plain {}", depth, plain);
        } else {
            prop_assert!(depth < 0.0, "apart by {} yet {}", plain, depth);
        }
    }
}
