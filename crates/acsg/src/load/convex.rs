//! The exact decomposition of a part's boundary representation into convex pieces.
//!
//! The decomposition is a binary space partition of the part's bounding box by planes
//! of the part's own faces, so every piece is exact (no approximation such as VHACD):
//! - while a concave edge passes through a cell's interior, the cell is cut by the
//!   plane of one of that edge's faces;
//! - a cell crossed by no concave edge holds convex components only; if the faces
//!   crossing it bound one component, that component is the cell clipped by their
//!   half-spaces (a piece); otherwise the cell is cut by the plane of a face that
//!   separates two components;
//! - a cell crossed by no face is wholly inside or wholly outside (decided by the
//!   winding number of its centroid).
//!
//! Every cut is by the plane of a face crossing the cell, which leaves that face on the
//! children's boundaries, so the recursion ends after at most one cut per face.

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

/// The part of a triangle strictly inside a cell (deeper than `depth`): its centroid
/// and area, if any.
fn inside_part(cell: &ConvexPolytope, corners: &[DVec3; 3], depth: f64) -> Option<(DVec3, f64)> {
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
    (area > depth * depth).then(|| (poly.iter().sum::<DVec3>() / poly.len() as f64, area))
}

/// Whether part of a segment lies strictly inside a cell (deeper than `depth`).
fn segment_inside(cell: &ConvexPolytope, [mut a, mut b]: [DVec3; 2], depth: f64) -> bool {
    for f in cell.faces() {
        let (sa, sb) = (
            f.normal.dot(a) - (f.offset - depth),
            f.normal.dot(b) - (f.offset - depth),
        );
        match (sa > 0.0, sb > 0.0) {
            (true, true) => return false,
            (true, false) => a += (b - a) * (sa / (sa - sb)),
            (false, true) => b = a + (b - a) * (sa / (sa - sb)),
            (false, false) => {}
        }
    }
    a.distance(b) > depth
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
        for &t in &candidates {
            if let Some((point, area)) = inside_part(&cell, &triangles[t].corners, depth) {
                inside.push(t);
                let entry = crossing.entry(triangles[t].face).or_insert((0.0, point));
                if area > entry.0 {
                    *entry = (area, point);
                }
            }
        }
        if crossing.is_empty() {
            if winding_number(triangles.iter().map(|t| t.corners), cell.center()) > 0.5 {
                pieces.push(cell);
            }
            continue;
        }
        let plane = |f: FaceId| (face(f).normal, face(f).offset);
        let concave_cut = concave
            .iter()
            .find(|&&e| segment_inside(&cell, edge_points(e), depth))
            .map(|&e| edge(e).faces[0]);
        let cut = match concave_cut {
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
    pieces
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
