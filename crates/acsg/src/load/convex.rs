//! The exact decomposition of a part's boundary representation into convex pieces.
//!
//! The decomposition is a binary space partition of the part's bounding box by planes
//! of the part's own faces, so every piece is exact (no approximation such as VHACD):
//! - while a concave edge passes through a cell's interior, the cell is cut by the
//!   plane, among those of the faces at such edges, that splits the fewest of them
//!   (then the fewest pieces of surface in the cell);
//! - a cell crossed by no concave edge holds convex components only; if the faces
//!   crossing it bound one component, that component is the cell clipped by their
//!   half-spaces (a piece); otherwise the cell is cut by the plane of a face that
//!   separates two components;
//! - a cell crossed by no face is wholly inside or wholly outside (decided by the
//!   winding number of its centroid).
//!
//! Every cut is by the plane of a face crossing the cell, which leaves that face on the
//! children's boundaries, so the recursion ends after at most one cut per face. Then
//! neighbouring pieces whose union is convex are merged ([`merge`]).
//!
//! The count is still above the floor on a block with a chamfered n-gon hole: about
//! 2.6 n for n = 32 and 3.6 n for n = 64, where 2n pieces suffice. With `M_k` the
//! material beyond both the wall `k` and the chamfer `k` (convex), the material is the
//! union of the `M_k`, each point in a cyclic run of them, so the pieces
//! `M_k \ M_(k-1)`, split by the wall `k - 1`'s plane into two convex parts, are a
//! decomposition. It is no partition of cells, though: each plane bounds a few pieces
//! only, where a partition's cut runs through all of its cell.

mod merge;

use std::collections::BTreeMap;

use glam::DVec3;

use super::topology::Brep;
use crate::geometry::{ConvexFace, ConvexPolytope, clip_polygon, winding_number};
use crate::model::{EdgeId, FaceId};

/// A triangle of the part's surface, with the face it belongs to.
#[derive(Clone, Copy)]
struct SurfaceTriangle {
    face: FaceId,
    corners: [DVec3; 3],
}

/// The triangles of the part's surface.
fn surface_triangles(brep: &Brep) -> impl Iterator<Item = SurfaceTriangle> + '_ {
    brep.faces.iter().enumerate().flat_map(move |(i, f)| {
        f.triangles.iter().map(move |t| SurfaceTriangle {
            face: FaceId(i as u32),
            corners: t.map(|v| brep.vertices[v.index()].position),
        })
    })
}

/// The part of a triangle strictly inside a cell (deeper than `depth`), if its area
/// exceeds `depth²`.
fn inside_part(cell: &ConvexPolytope, corners: &[DVec3; 3], depth: f64) -> Option<InsidePart> {
    let mut poly = corners.to_vec();
    for f in cell.faces() {
        let side = |p: DVec3| f.normal.dot(p) - (f.offset - depth);
        poly = clip_polygon(&poly, side, |_| {});
        if poly.len() < 3 {
            return None;
        }
    }
    let normal2 = poly
        .windows(2)
        .skip(1)
        .map(|w| (w[0] - poly[0]).cross(w[1] - poly[0]))
        .sum::<DVec3>();
    let area = 0.5 * normal2.length();
    (area > depth * depth).then(|| InsidePart {
        point: poly.iter().sum::<DVec3>() / poly.len() as f64,
        area,
        polygon: poly,
    })
}

/// The part of a surface triangle inside a cell.
struct InsidePart {
    /// A point of it (the mean of its corners).
    point: DVec3,
    area: f64,
    polygon: Vec<DVec3>,
}

/// The part of a segment strictly inside a cell (deeper than `depth`), if longer than
/// `depth`.
fn segment_inside(cell: &ConvexPolytope, [mut a, mut b]: [DVec3; 2], depth: f64) -> Option<[DVec3; 2]> {
    for f in cell.faces() {
        let (sa, sb) = (
            f.normal.dot(a) - (f.offset - depth),
            f.normal.dot(b) - (f.offset - depth),
        );
        match (sa > 0.0, sb > 0.0) {
            (true, true) => return None,
            (true, false) => a += (b - a) * (sa / (sa - sb)),
            (false, true) => b = a + (b - a) * (sa / (sa - sb)),
            (false, false) => {}
        }
    }
    (a.distance(b) > depth).then_some([a, b])
}

/// Whether a plane passes strictly between some two of `points` (each farther than
/// `depth` from it).
fn splits(points: &[DVec3], (n, d): (DVec3, f64), depth: f64) -> bool {
    let (mut below, mut above) = (false, false);
    for &p in points {
        let s = n.dot(p) - d;
        below |= s < -depth;
        above |= s > depth;
    }
    below && above
}

/// Decomposes a part exactly into convex pieces with disjoint interiors whose union is
/// the part.
pub(crate) fn decompose(brep: &Brep) -> Vec<ConvexPolytope> {
    let face = |f: FaceId| &brep.faces[f.index()];
    let edge = |e: EdgeId| &brep.edges[e.index()];
    let edge_points = |e: EdgeId| edge(e).vertices.map(|v| brep.vertices[v.index()].position);
    let scale = brep.bounds.diagonal();
    let eps = crate::tolerance::scaled(crate::tolerance::WELD_REL, scale);
    let depth = crate::tolerance::scaled(crate::tolerance::COPLANAR_REL, scale) * 0.1;
    let triangles: Vec<SurfaceTriangle> = surface_triangles(brep).collect();
    let concave: Vec<_> = (0..brep.edges.len() as u32)
        .map(EdgeId)
        .filter(|&e| !edge(e).convex)
        .collect();
    if concave.is_empty() {
        // Connected and locally convex everywhere: the part is its own single piece.
        return vec![own_faces(brep, eps)];
    }
    let plane = |f: FaceId| (face(f).normal, face(f).offset);
    let bounds = brep.bounds;
    let mut pieces = Vec::new();
    let mut stack = vec![(
        ConvexPolytope::cuboid(bounds.min, bounds.max),
        (0..triangles.len()).collect::<Vec<_>>(),
    )];
    while let Some((cell, candidates)) = stack.pop() {
        // Faces crossing the cell, each with a point of it inside the cell.
        let mut crossing: BTreeMap<FaceId, (f64, DVec3)> = BTreeMap::new();
        let mut inside = Vec::new();
        let mut polygons = Vec::new();
        for &t in &candidates {
            if let Some(part) = inside_part(&cell, &triangles[t].corners, depth) {
                inside.push(t);
                let entry = crossing.entry(triangles[t].face).or_insert((0.0, part.point));
                if part.area > entry.0 {
                    *entry = (part.area, part.point);
                }
                polygons.push(part.polygon);
            }
        }
        if crossing.is_empty() {
            if winding_number(triangles.iter().map(|t| t.corners), cell.center()) > 0.5 {
                pieces.push(cell);
            }
            continue;
        }
        let concave_inside: Vec<(EdgeId, [DVec3; 2])> = concave
            .iter()
            .filter_map(|&e| segment_inside(&cell, edge_points(e), depth).map(|s| (e, s)))
            .collect();
        let cut = match least_splitting_cut(brep, &concave_inside, &polygons, depth) {
            Some(face) => face,
            None => {
                // One convex component, unless a face's point lies outside another
                // face's half-space (then that face separates two components).
                let separating = crossing.iter().find_map(|(&f, &(_, p))| {
                    crossing
                        .keys()
                        .find(|&&g| g != f && face(g).signed_distance(p) > depth)
                        .copied()
                });
                match separating {
                    Some(face) => face,
                    None => {
                        let piece = crossing.keys().try_fold(cell.clone(), |c, &f| {
                            let (n, d) = plane(f);
                            c.clip(n, d, eps)
                        });
                        pieces.extend(piece);
                        continue;
                    }
                }
            }
        };
        let (n, d) = plane(cut);
        for child in [cell.clip(n, d, eps), cell.clip(-n, -d, eps)].into_iter().flatten() {
            stack.push((child, inside.clone()));
        }
    }
    let roundoff = crate::tolerance::scaled(crate::tolerance::ROUNDOFF_REL, scale);
    merge::merge_convex_unions(pieces, roundoff, eps)
}

/// Among the planes of the faces at the concave edges crossing a cell, the one that
/// splits the fewest of those edges, then the fewest pieces of surface in the cell
/// (the usual autopartition rule: every split edge or polygon must be cut again on
/// both sides, so each avoided split saves pieces). Ties go to the first candidate.
/// `None` when no concave edge crosses the cell.
fn least_splitting_cut(
    brep: &Brep,
    concave_inside: &[(EdgeId, [DVec3; 2])],
    polygons: &[Vec<DVec3>],
    depth: f64,
) -> Option<FaceId> {
    let mut best: Option<((usize, usize), FaceId)> = None;
    let mut seen = Vec::new();
    for &(e, _) in concave_inside {
        for f in brep.edges[e.index()].faces {
            if seen.contains(&f) {
                continue;
            }
            seen.push(f);
            let face = &brep.faces[f.index()];
            let cut = (face.normal, face.offset);
            let edges = concave_inside.iter().filter(|(_, s)| splits(s, cut, depth)).count();
            if best.is_some_and(|((least, _), _)| edges > least) {
                continue;
            }
            let surface = polygons.iter().filter(|p| splits(p, cut, depth)).count();
            if best.is_none_or(|(score, _)| (edges, surface) < score) {
                best = Some(((edges, surface), f));
            }
        }
    }
    best.map(|(_, f)| f)
}

/// A convex part's own faces as a polytope (the part must have no concave edge).
fn own_faces(brep: &Brep, eps: f64) -> ConvexPolytope {
    let faces: Vec<ConvexFace> = brep
        .faces
        .iter()
        .map(|f| ConvexFace {
            normal: f.normal,
            offset: f.offset,
            points: f
                .outer()
                .vertices
                .iter()
                .map(|&v| brep.vertices[v.index()].position)
                .collect(),
        })
        .collect();
    ConvexPolytope::from_faces(faces, eps)
}

#[cfg(test)]
mod tests {
    use std::path::PathBuf;

    use glam::DVec3;

    use crate::model::Part;
    use crate::testing::Numbers;

    fn fixture(name: &str) -> Part {
        let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
            .join("../../fixtures")
            .join(name);
        Part::from_path(&path).unwrap_or_else(|e| panic!("{name}: {e}"))
    }

    /// Asserts that a part's pieces are an exact convex decomposition: each convex, their
    /// volumes adding up to the part's, and sample points of the bounding box inside
    /// exactly one piece when inside the part and in none when outside (points near a
    /// piece's boundary are skipped: there both answers are right).
    fn assert_exact(name: &str, part: &Part, samples: usize) {
        let scale = part.bounds().diagonal();
        let pieces = part.convex_pieces();
        for (k, piece) in pieces.iter().enumerate() {
            for &v in piece.vertices() {
                assert!(
                    piece.outside_distance(v) <= 1e-9 * scale,
                    "{name}: piece {k} is not convex"
                );
            }
        }
        let total: f64 = pieces.iter().map(|p| p.volume()).sum();
        assert!(
            (total - part.volume()).abs() <= 1e-9 * part.volume(),
            "{name}: pieces' volume {total}, part's {}",
            part.volume()
        );
        let (lo, hi) = (part.bounds().min, part.bounds().max);
        let near = 1e-6 * scale;
        let mut numbers = Numbers(0x9e37_79b9_7f4a_7c15);
        let mut inside = 0;
        for _ in 0..samples {
            let p = lo + (hi - lo) * DVec3::new(numbers.next(), numbers.next(), numbers.next());
            let distances: Vec<f64> = pieces.iter().map(|piece| piece.outside_distance(p)).collect();
            if distances.iter().any(|d| d.abs() < near) {
                continue;
            }
            let containing = distances.iter().filter(|&&d| d < 0.0).count();
            if part.winding_number(p) > 0.5 {
                assert_eq!(
                    containing, 1,
                    "{name}: {p} is inside the part and in {containing} pieces"
                );
                inside += 1;
            } else {
                assert_eq!(
                    containing, 0,
                    "{name}: {p} is outside the part and in {containing} pieces"
                );
            }
        }
        assert!(inside > samples / 4, "{name}: too few samples inside");
    }

    #[test]
    fn the_fixtures_pieces_are_exact_and_few() {
        // Bounds on the piece count, as found by this decomposition (the former one,
        // which cut by the first concave edge's face, found 2, 4, 9, 4 and 238): the
        // square hole's four walls need four pieces (a pinwheel of the walls' planes),
        // the L needs two.
        for (name, most) in [
            ("l_block.off", 2),
            ("block_with_hole.off", 4),
            ("block_with_tight_hole.off", 4),
            ("block_with_chamfered_hole.off", 8),
            ("block_with_round_hole.off", 84),
            ("cube.off", 1),
        ] {
            let part = fixture(name);
            assert!(
                part.convex_pieces().len() <= most,
                "{name}: {} pieces",
                part.convex_pieces().len()
            );
            assert_exact(name, &part, 2000);
        }
    }

    #[test]
    fn the_round_holes_pieces_are_exact_and_grow_slowly() {
        // The former decomposition made 25, 77 and 238 pieces here. These bounds are
        // what this one finds (they regress if a change makes more); an exact
        // decomposition with 2n pieces exists (see the module's docs), so they are not
        // the floor.
        for (n, most) in [(8, 16), (16, 37), (32, 84)] {
            let name = format!("scale/block_with_round_hole_{n}.off");
            let part = fixture(&name);
            assert!(
                part.convex_pieces().len() <= most,
                "{name}: {} pieces",
                part.convex_pieces().len()
            );
            assert_exact(&name, &part, 1000);
        }
    }

    #[test]
    fn a_convex_part_is_one_piece() {
        let part = fixture("peg.off");
        assert_eq!(part.convex_pieces().len(), 1);
        assert_exact("peg.off", &part, 500);
    }
}
