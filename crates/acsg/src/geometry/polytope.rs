//! Bounded convex polytopes: as planes with their face polygons and as corners, with
//! clipping by a half-space (the step of the exact convex decomposition).

use glam::DVec3;

use super::weld::weld;

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
        ConvexPolytope::from_faces(faces, 0.0)
    }

    /// The polytope bounded by `faces` (the faces of a convex solid, each with its
    /// corners); corners closer than `eps` are one vertex.
    #[must_use]
    pub fn from_faces(faces: Vec<ConvexFace>, eps: f64) -> ConvexPolytope {
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
            let kept = clip_polygon(&face.points, side, |p| cap.push(p));
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
/// the plane (kept corners and new crossings) are also passed to `on_plane`.
pub(crate) fn clip_polygon(
    points: &[DVec3],
    side: impl Fn(DVec3) -> f64,
    mut on_plane: impl FnMut(DVec3),
) -> Vec<DVec3> {
    let mut out = Vec::with_capacity(points.len() + 1);
    for (i, &p) in points.iter().enumerate() {
        let q = points[(i + 1) % points.len()];
        let (sp, sq) = (side(p), side(q));
        if sp <= 0.0 {
            out.push(p);
            if sp == 0.0 {
                on_plane(p);
            }
        }
        if (sp < 0.0 && sq > 0.0) || (sp > 0.0 && sq < 0.0) {
            let x = p + (q - p) * (sp / (sp - sq));
            out.push(x);
            on_plane(x);
        }
    }
    out
}

/// The part of a convex polygon where `n · p <= d`.
pub(crate) fn clip_convex(poly: &[DVec3], n: DVec3, d: f64) -> Vec<DVec3> {
    clip_polygon(poly, |p| n.dot(p) - d, |_| {})
}

/// The points with those closer than `eps` merged.
fn dedup_points(points: Vec<DVec3>, eps: f64) -> Vec<DVec3> {
    weld(&points, eps).0
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
