//! Property tests: the B-rep of random solids against facts computed independently in
//! the test (prism counts, reflex corners by cross products, shoelace areas), and its
//! invariance under re-ordering, re-indexing and refinement of the input mesh.

use acsg::examples::refine_midpoints;
use acsg::io::MeshSoup;
use acsg::model::Part;
use glam::{DMat3, DVec2, DVec3};
use proptest::prelude::*;

/// A prism over a star-shaped polygon (counter-clockwise), from z = 0 to z = height.
fn prism(outline: &[DVec2], height: f64) -> MeshSoup {
    let n = outline.len() as u32;
    let mut positions: Vec<DVec3> = outline.iter().map(|p| p.extend(0.0)).collect();
    positions.extend(outline.iter().map(|p| p.extend(height)));
    let mut polygons = vec![(0..n).rev().collect::<Vec<_>>(), (n..2 * n).collect()];
    for i in 0..n {
        let j = (i + 1) % n;
        polygons.push(vec![i, j, n + j, n + i]);
    }
    MeshSoup {
        positions,
        polygons,
        polygon_lines: Vec::new(),
        polygon_noun: "face",
    }
}

/// Star-shaped polygons whose corners all turn clearly (no near-collinear corners).
fn star_polygon() -> impl Strategy<Value = Vec<DVec2>> {
    (4usize..12)
        .prop_flat_map(|n| proptest::collection::vec((0.0f64..1.0, 0.3f64..1.0), n))
        .prop_map(|raw| {
            let n = raw.len() as f64;
            // Angles spread around the circle, each jittered inside its own sector.
            raw.iter()
                .enumerate()
                .map(|(i, &(jitter, r))| {
                    let angle = (i as f64 + 0.1 + 0.8 * jitter) / n * std::f64::consts::TAU;
                    DVec2::new(r * angle.cos(), r * angle.sin()) * 50.0
                })
                .collect::<Vec<_>>()
        })
        .prop_filter("corners must turn clearly", |pts| {
            let n = pts.len();
            (0..n).all(|i| {
                let (a, b, c) = (pts[(i + n - 1) % n], pts[i], pts[(i + 1) % n]);
                (b - a).perp_dot(c - b).abs() > 1e-3 * (b - a).length() * (c - b).length()
            })
        })
}

fn reflex_corners(pts: &[DVec2]) -> usize {
    let n = pts.len();
    (0..n)
        .filter(|&i| (pts[i] - pts[(i + n - 1) % n]).perp_dot(pts[(i + 1) % n] - pts[i]) < 0.0)
        .count()
}

fn shoelace(pts: &[DVec2]) -> f64 {
    0.5 * pts
        .iter()
        .zip(pts.iter().cycle().skip(1))
        .map(|(p, q)| p.perp_dot(*q))
        .sum::<f64>()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(128))]

    #[test]
    fn star_prisms_have_the_counts_and_volume_of_their_outline(outline in star_polygon(), height in 1.0f64..80.0) {
        let part = Part::try_new(&prism(&outline, height), "prism").expect("a valid prism");
        let n = outline.len();
        let reflex = reflex_corners(&outline);
        prop_assert_eq!(part.faces().len(), n + 2);
        prop_assert_eq!(part.vertices().len(), 2 * n);
        prop_assert_eq!(part.edges().len(), 3 * n);
        prop_assert_eq!(part.edges().len() - part.convex_edges().count(), reflex);
        prop_assert_eq!(part.convex_vertices().count(), 2 * (n - reflex));
        let volume = shoelace(&outline) * height;
        prop_assert!((part.volume() - volume).abs() <= 1e-9 * volume);
        // The convex pieces tile the part exactly.
        let pieces = part.convex_pieces();
        let total: f64 = pieces.iter().map(|p| p.volume()).sum();
        prop_assert!((total - volume).abs() <= 1e-8 * volume, "pieces {} vs {}", total, volume);
        if reflex == 0 {
            prop_assert_eq!(pieces.len(), 1);
        }
        let tol = 1e-9 * part.bounds().diagonal();
        for piece in pieces {
            prop_assert!(piece.vertices().iter().all(|&v| piece.outside_distance(v) <= tol));
            let w = part.winding_number(piece.center());
            prop_assert!((w - 1.0).abs() < 1e-6, "piece centre has winding number {}", w);
        }
    }

    #[test]
    fn the_brep_ignores_polygon_order_indexing_and_refinement(
        outline in star_polygon(),
        (rx, ry, rz) in (-3.2f64..3.2, -3.2f64..3.2, -3.2f64..3.2),
        shift in proptest::array::uniform3(-100.0f64..100.0),
        seed in any::<u64>(),
        levels in 0usize..3,
    ) {
        let rotation = DMat3::from_euler(glam::EulerRot::ZYX, rz, ry, rx);
        let mut soup = prism(&outline, 20.0);
        for p in &mut soup.positions {
            *p = rotation * *p + DVec3::from_array(shift);
        }
        let reference = Part::try_new(&soup, "reference").expect("valid");

        // Shuffle polygons, rotate each polygon's start corner, renumber the points.
        let mut rng = seed;
        let mut next = move || { rng ^= rng << 13; rng ^= rng >> 7; rng ^= rng << 17; rng };
        let m = soup.positions.len();
        let mut perm: Vec<u32> = (0..m as u32).collect();
        for i in (1..m).rev() { perm.swap(i, (next() % (i as u64 + 1)) as usize); }
        let mut positions = vec![DVec3::ZERO; m];
        for (old, &new) in perm.iter().enumerate() { positions[new as usize] = soup.positions[old]; }
        let mut polygons: Vec<Vec<u32>> = soup.polygons.iter().map(|poly| {
            let mut q: Vec<u32> = poly.iter().map(|&v| perm[v as usize]).collect();
            let k = (next() % q.len() as u64) as usize;
            q.rotate_left(k);
            q
        }).collect();
        for i in (1..polygons.len()).rev() { polygons.swap(i, (next() % (i as u64 + 1)) as usize); }
        let shuffled = MeshSoup { positions, polygons, ..soup.clone() };
        let part = Part::try_new(&shuffled, "shuffled").expect("valid");
        prop_assert_eq!(part.vertices(), reference.vertices());
        prop_assert_eq!(part.edges(), reference.edges());

        // Refinement adds coplanar triangles and points on straight edges only.
        let mut fine = acsg::examples::triangle_soup(&reference);
        for _ in 0..levels { fine = refine_midpoints(&fine); }
        let refined = Part::try_new(&fine, "refined").expect("valid");
        prop_assert_eq!(refined.faces().len(), reference.faces().len());
        prop_assert_eq!(refined.edges(), reference.edges());
        prop_assert_eq!(refined.vertices().len(), reference.vertices().len());
        for (a, b) in refined.vertices().iter().zip(reference.vertices()) {
            prop_assert!(a.position.distance(b.position) < 1e-9 * reference.bounds().diagonal());
            prop_assert_eq!(a.convex, b.convex);
        }
    }
}
