//! Convex polytopes and the exact decomposition of a part into convex pieces.
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

use crate::model::{FaceId, Part};

/// A planar convex polygon bounding a [`ConvexPolytope`].
#[derive(Clone, Debug, PartialEq)]
pub struct ConvexFace {
    /// Outward unit normal.
    pub normal: DVec3,
    /// Points `p` on the face satisfy `normal · p = offset`.
    pub offset: f64,
    /// Corners, counter-clockwise around `normal`.
    pub points: Vec<DVec3>,
}

/// A bounded convex polytope, held both as planes (with their face polygons) and as
/// vertices.
#[derive(Clone, Debug, PartialEq)]
pub struct ConvexPolytope {
    faces: Vec<ConvexFace>,
    vertices: Vec<DVec3>,
}

impl ConvexPolytope {
    /// The box between two corners.
    #[must_use]
    pub fn cuboid(min: DVec3, max: DVec3) -> ConvexPolytope {
        let c = |x: f64, y: f64, z: f64| DVec3::new(x, y, z);
        let (a, b) = (min, max);
        let quad = |normal: DVec3, offset: f64, points: [DVec3; 4]| ConvexFace {
            normal,
            offset,
            points: points.to_vec(),
        };
        let faces = vec![
            quad(
                -DVec3::X,
                -a.x,
                [c(a.x, a.y, a.z), c(a.x, a.y, b.z), c(a.x, b.y, b.z), c(a.x, b.y, a.z)],
            ),
            quad(
                DVec3::X,
                b.x,
                [c(b.x, a.y, a.z), c(b.x, b.y, a.z), c(b.x, b.y, b.z), c(b.x, a.y, b.z)],
            ),
            quad(
                -DVec3::Y,
                -a.y,
                [c(a.x, a.y, a.z), c(b.x, a.y, a.z), c(b.x, a.y, b.z), c(a.x, a.y, b.z)],
            ),
            quad(
                DVec3::Y,
                b.y,
                [c(a.x, b.y, a.z), c(a.x, b.y, b.z), c(b.x, b.y, b.z), c(b.x, b.y, a.z)],
            ),
            quad(
                -DVec3::Z,
                -a.z,
                [c(a.x, a.y, a.z), c(a.x, b.y, a.z), c(b.x, b.y, a.z), c(b.x, a.y, a.z)],
            ),
            quad(
                DVec3::Z,
                b.z,
                [c(a.x, a.y, b.z), c(b.x, a.y, b.z), c(b.x, b.y, b.z), c(a.x, b.y, b.z)],
            ),
        ];
        let mut polytope = ConvexPolytope {
            faces,
            vertices: Vec::new(),
        };
        polytope.collect_vertices(0.0);
        polytope
    }

    /// A convex part's own faces as a polytope (the part must have no concave edge).
    fn from_part_faces(part: &Part, eps: f64) -> ConvexPolytope {
        let faces: Vec<ConvexFace> = part
            .faces()
            .iter()
            .map(|f| ConvexFace {
                normal: f.normal,
                offset: f.offset,
                points: f.outer().vertices.iter().map(|&v| part.vertex(v).position).collect(),
            })
            .collect();
        let mut polytope = ConvexPolytope {
            faces,
            vertices: Vec::new(),
        };
        polytope.collect_vertices(eps);
        polytope
    }

    /// The bounding faces.
    #[must_use]
    pub fn faces(&self) -> &[ConvexFace] {
        &self.faces
    }

    /// The corners.
    #[must_use]
    pub fn vertices(&self) -> &[DVec3] {
        &self.vertices
    }

    /// The enclosed volume.
    #[must_use]
    pub fn volume(&self) -> f64 {
        self.faces
            .iter()
            .map(|f| {
                let p0 = f.points[0];
                f.points
                    .windows(2)
                    .skip(1)
                    .map(|w| p0.dot(w[0].cross(w[1])))
                    .sum::<f64>()
            })
            .sum::<f64>()
            / 6.0
    }

    /// The mean of the corners (a point of the interior for a solid polytope).
    #[must_use]
    pub fn center(&self) -> DVec3 {
        self.vertices.iter().sum::<DVec3>() / self.vertices.len().max(1) as f64
    }

    /// Largest signed distance of `p` outside the bounding planes (negative inside).
    #[must_use]
    pub fn outside_distance(&self, p: DVec3) -> f64 {
        self.faces
            .iter()
            .map(|f| f.normal.dot(p) - f.offset)
            .fold(f64::NEG_INFINITY, f64::max)
    }

    /// The part of this polytope where `normal · p <= offset`, or `None` when that
    /// part has no volume. Points within `eps` of the plane count as on it.
    #[must_use]
    pub fn clip(&self, normal: DVec3, offset: f64, eps: f64) -> Option<ConvexPolytope> {
        let side = |p: DVec3| {
            let s = normal.dot(p) - offset;
            if s.abs() <= eps { 0.0 } else { s }
        };
        if self.vertices.iter().all(|&p| side(p) <= 0.0) {
            return Some(self.clone());
        }
        if self.vertices.iter().all(|&p| side(p) >= 0.0) {
            return None;
        }
        let mut faces = Vec::with_capacity(self.faces.len() + 1);
        let mut cap = Vec::new();
        for face in &self.faces {
            let kept = clip_polygon(&face.points, &side, &mut cap);
            if kept.len() >= 3 {
                faces.push(ConvexFace {
                    normal: face.normal,
                    offset: face.offset,
                    points: kept,
                });
            }
        }
        let cap = order_convex(dedup_points(cap, eps), normal);
        if cap.len() >= 3 {
            faces.push(ConvexFace {
                normal,
                offset,
                points: cap,
            });
        }
        // The corners: the old ones on the kept side, then the cap's that are new.
        let mut vertices: Vec<DVec3> = self.vertices.iter().copied().filter(|&p| side(p) <= 0.0).collect();
        let kept = vertices.len();
        for &p in faces
            .last()
            .filter(|f| f.normal == normal && f.offset == offset)
            .map_or(&[][..], |f| &f.points)
        {
            if !vertices[..kept].iter().any(|q| side(*q) == 0.0 && q.distance(p) <= eps) {
                vertices.push(p);
            }
        }
        let polytope = ConvexPolytope { faces, vertices };
        (polytope.faces.len() >= 4 && polytope.volume() > eps * eps * eps).then_some(polytope)
    }

    fn collect_vertices(&mut self, eps: f64) {
        let all = self.faces.iter().flat_map(|f| f.points.iter().copied()).collect();
        self.vertices = dedup_points(all, eps);
    }
}

/// Sutherland–Hodgman step: the part of a convex polygon with `side <= 0`; points on
/// the plane are also pushed to `on_plane`.
fn clip_polygon(points: &[DVec3], side: &impl Fn(DVec3) -> f64, on_plane: &mut Vec<DVec3>) -> Vec<DVec3> {
    let mut out = Vec::with_capacity(points.len() + 1);
    for (i, &p) in points.iter().enumerate() {
        let q = points[(i + 1) % points.len()];
        let (sp, sq) = (side(p), side(q));
        if sp <= 0.0 {
            out.push(p);
            if sp == 0.0 {
                on_plane.push(p);
            }
        }
        if (sp < 0.0 && sq > 0.0) || (sp > 0.0 && sq < 0.0) {
            let x = p + (q - p) * (sp / (sp - sq));
            out.push(x);
            on_plane.push(x);
        }
    }
    out
}

fn dedup_points(points: Vec<DVec3>, eps: f64) -> Vec<DVec3> {
    crate::topology::weld(&points, eps).0
}

/// Orders coplanar points of a convex polygon counter-clockwise around `normal`.
fn order_convex(points: Vec<DVec3>, normal: DVec3) -> Vec<DVec3> {
    if points.len() < 3 {
        return points;
    }
    let center = points.iter().sum::<DVec3>() / points.len() as f64;
    let u = normal.any_orthonormal_vector();
    let w = normal.cross(u);
    let mut keyed: Vec<(f64, DVec3)> = points
        .into_iter()
        .map(|p| {
            let d = p - center;
            (d.dot(w).atan2(d.dot(u)), p)
        })
        .collect();
    keyed.sort_by(|a, b| a.0.total_cmp(&b.0));
    keyed.into_iter().map(|(_, p)| p).collect()
}

/// A triangle of the part's surface, with the face it belongs to.
#[derive(Clone, Copy)]
struct SurfaceTriangle {
    face: FaceId,
    corners: [DVec3; 3],
}

/// The generalised winding number of `q` with respect to the part's closed surface:
/// 1 inside, 0 outside (Van Oosterom–Strackee solid angles).
#[must_use]
pub fn winding_number(part: &Part, q: DVec3) -> f64 {
    let total: f64 = surface_triangles(part)
        .map(|t| {
            let [a, b, c] = t.corners.map(|p| p - q);
            let (la, lb, lc) = (a.length(), b.length(), c.length());
            let numerator = a.dot(b.cross(c));
            let denominator = la * lb * lc + a.dot(b) * lc + a.dot(c) * lb + b.dot(c) * la;
            2.0 * numerator.atan2(denominator)
        })
        .sum();
    total / (4.0 * std::f64::consts::PI)
}

fn surface_triangles(part: &Part) -> impl Iterator<Item = SurfaceTriangle> + '_ {
    part.faces().iter().enumerate().flat_map(move |(i, f)| {
        f.triangles.iter().map(move |t| SurfaceTriangle {
            face: FaceId(i as u32),
            corners: t.map(|v| part.vertex(v).position),
        })
    })
}

/// The part of a triangle strictly inside a cell (deeper than `depth`): its centroid
/// and area, if any.
fn inside_part(cell: &ConvexPolytope, corners: &[DVec3; 3], depth: f64) -> Option<(DVec3, f64)> {
    let mut poly = corners.to_vec();
    let mut scratch = Vec::new();
    for f in cell.faces() {
        let side = |p: DVec3| f.normal.dot(p) - (f.offset - depth);
        poly = clip_polygon(&poly, &side, &mut scratch);
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
#[must_use]
pub fn decompose(part: &Part) -> Vec<ConvexPolytope> {
    let scale = part.bounds().diagonal();
    let eps = crate::tolerance::scaled(crate::tolerance::WELD_REL, scale);
    let depth = crate::tolerance::scaled(crate::tolerance::COPLANAR_REL, scale) * 0.1;
    let triangles: Vec<SurfaceTriangle> = surface_triangles(part).collect();
    let concave: Vec<_> = (0..part.edges().len() as u32)
        .map(crate::model::EdgeId)
        .filter(|&e| !part.edge(e).convex)
        .collect();
    if concave.is_empty() {
        // Connected and locally convex everywhere: the part is its own single piece.
        return vec![ConvexPolytope::from_part_faces(part, eps)];
    }
    let bounds = part.bounds();
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
            if winding_number(part, cell.center()) > 0.5 {
                pieces.push(cell);
            }
            continue;
        }
        let plane = |f: FaceId| (part.face(f).normal, part.face(f).offset);
        let concave_cut = concave
            .iter()
            .find(|&&e| segment_inside(&cell, part.edge_points(e), depth))
            .map(|&e| part.edge(e).faces[0]);
        let cut = match concave_cut {
            Some(face) => face,
            None => {
                // One convex component, unless a face's point lies outside another
                // face's half-space (then that face separates two components).
                let separating = crossing.iter().find_map(|(&f, &(_, p))| {
                    crossing
                        .keys()
                        .find(|&&g| g != f && part.face(g).signed_distance(p) > depth)
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

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec2;

    #[test]
    fn clipping_a_cube_through_its_diagonal_halves_it() {
        let cube = ConvexPolytope::cuboid(DVec3::ZERO, DVec3::ONE);
        crate::assert_near!(cube.volume(), 1.0, 1e-12);
        let n = DVec3::new(1.0, 1.0, 0.0).normalize();
        let half = cube
            .clip(n, n.dot(DVec3::new(0.5, 0.5, 0.0)), 1e-12)
            .expect("half remains");
        crate::assert_near!(half.volume(), 0.5, 1e-12);
        assert_eq!(half.vertices().len(), 6);
        assert!(cube.clip(DVec3::Z, -1.0, 1e-12).is_none());
    }

    #[test]
    fn order_convex_is_counter_clockwise() {
        let pts = vec![DVec3::ZERO, DVec3::Y, DVec3::X, DVec3::new(1.0, 1.0, 0.0)];
        let ordered = order_convex(pts, DVec3::Z);
        let flat: Vec<DVec2> = ordered.iter().map(|p| p.truncate()).collect();
        let area: f64 = flat
            .iter()
            .zip(flat.iter().cycle().skip(1))
            .map(|(p, q)| p.perp_dot(*q))
            .sum();
        assert!(area > 0.0);
    }
}
