//! Translations at a fixed rotation.
//!
//! With the rotation fixed, every point contact (f-v, v-f, e-e crossing, e-v, v-e,
//! v-v) is a set of linear equations in the translation, and where its contact point
//! sits in its elements is affine in the translation. When a target's contacts pin the
//! translation to a line or a point, the poses there that show the target are found
//! exactly: the line is cut to the bounds, to the edges' interiors and to the faces'
//! triangles; the stretches where the parts penetrate (exact, by the separating axis
//! theorem along the line) are removed; what is left is tried at its middle. A state
//! that holds only on a sliver of translations (a vertex in a concave edge between two
//! walls, a corner in a tight hole) is found this way where a local optimisation from a
//! start nearby is not. Contacts that also hold the rotation (faces on faces, edges in
//! faces, edges along edges) take part once the rotation is projected to where their
//! elements are parallel.

use glam::{DAffine3, DVec3};

use super::Problem;
use super::residual::perpendiculars;
use crate::contact::{ContactKind, PrincipalContact};
use crate::model::{ElementId, FaceId, Part};
use crate::pose::{Bounds, Pose};
use crate::tolerance::{CONTACT_REL, PARALLEL_SIN, SEPARATION_REL, scaled};

/// Sorted, disjoint closed intervals of the line parameter.
type Intervals = Vec<(f64, f64)>;

/// What a contact asks of the translation `u` (in the fixed frame) at a fixed rotation.
#[derive(Default)]
struct Linear {
    /// Equations `a · u = b`.
    rows: Vec<(DVec3, f64)>,
    /// Ranges `lo ≤ a · u + c ≤ hi` (where contact points sit in edges).
    ranges: Vec<(DVec3, f64, f64, f64)>,
    /// Sets of points `x0 + sign · u` of which one must lie in one of the triangles
    /// of `triangles[k]`: a vertex in a face is a set of one; an edge or a face lying
    /// in a face, points spread over it (one of them on the face: they overlap).
    in_faces: Vec<Vec<(DVec3, f64, usize)>>,
    /// Whether each set stands for an edge or a face overlapping a face (not a point).
    overlaps: Vec<bool>,
    /// Faces' triangles, placed.
    triangles: Vec<Vec<[DVec3; 3]>>,
}

impl Linear {
    /// A set of points of which one must lie in a face's triangles.
    fn in_face(&mut self, points: impl IntoIterator<Item = DVec3>, sign: f64, triangles: Vec<[DVec3; 3]>) {
        let k = self.triangles.len();
        self.triangles.push(triangles);
        let set: Vec<(DVec3, f64, usize)> = points.into_iter().map(|x| (x, sign, k)).collect();
        self.overlaps.push(set.len() > 1);
        self.in_faces.push(set);
    }
}

/// Points spread along an edge, its ends included.
fn along([a, b]: [DVec3; 2]) -> impl Iterator<Item = DVec3> {
    (0..=EDGE_SAMPLES).map(move |i| a.lerp(b, i as f64 / EDGE_SAMPLES as f64))
}

/// A face's triangles, placed.
fn face_triangles(part: &Part, f: FaceId, place: &DAffine3) -> Vec<[DVec3; 3]> {
    part.face(f)
        .triangles
        .iter()
        .map(|t| t.map(|v| place.transform_point3(part.vertex(v).position)))
        .collect()
}

impl Problem<'_> {
    /// A witness of `target` at the rotation `angles` (radians), with the translation
    /// within `bounds`, when the target's contacts pin the translation to a line or a
    /// point (`None` otherwise, or when no pose there shows the target). Clean poses met
    /// that show another state go to `others`.
    pub(super) fn slide(
        &self,
        target: &[PrincipalContact],
        angles: [f64; 3],
        bounds: &Bounds,
        others: &mut Vec<(Vec<PrincipalContact>, Pose)>,
    ) -> Option<Pose> {
        let line = self.line(target, angles, bounds)?;
        let depth = scaled(CONTACT_REL, self.scale);
        let longest_first = |mut list: Intervals| {
            list.sort_by(|x, y| (y.1 - y.0).total_cmp(&(x.1 - x.0)));
            list.truncate(SLIDE_TRIES);
            list
        };
        let mut free = longest_first(line.free(self, depth));
        // Then where edges or faces lie in the planes of faces but off them: the poses
        // there show other states.
        if line.loose != line.allowed {
            free.extend(longest_first(line.free_of(&line.loose, self, depth)));
        }
        let margin = scaled(SEPARATION_REL, self.scale);
        for &(a, b) in &free {
            if b - a < 2.0 * margin && line.d != DVec3::ZERO {
                continue;
            }
            let pose = line.pose(0.5 * (a + b));
            match self.clean_state(&pose) {
                Some(state) if state == target => return Some(pose),
                Some(state) if !state.is_empty() && !others.iter().any(|(known, _)| *known == state) => {
                    others.push((state, pose));
                }
                _ => {}
            }
        }
        None
    }

    /// How far the target is from holding at the rotation `angles`: minus the length
    /// of the longest free stretch of its line when one is long enough for a witness,
    /// else the mean depth of penetration over points spread along the line (within
    /// the bounds and the elements), which falls as the rotation nears one where the
    /// target holds. `None` when the contacts do not pin the translation to a line or a
    /// point there.
    fn slide_gap(&self, target: &[PrincipalContact], angles: [f64; 3], bounds: &Bounds) -> Option<f64> {
        let line = self.line(target, angles, bounds)?;
        // The rotation itself out of the bounds: worse than any rotation within.
        let (lo, hi) = (bounds.min.to_array(), bounds.max.to_array());
        let turned_out: f64 = (0..3).map(|k| outside(lo[3 + k], hi[3 + k], line.angles[k])).sum();
        if turned_out > 0.0 {
            return Some(2.0 * self.scale + turned_out * self.scale);
        }
        let spread = |list: &Intervals| -> Vec<f64> {
            list.iter()
                .flat_map(|&(a, b)| {
                    (0..SLIDE_SAMPLES).map(move |i| a + (b - a) * (i as f64 + 0.5) / SLIDE_SAMPLES as f64)
                })
                .collect()
        };
        if line.allowed.is_empty() {
            // Nowhere allowed: the scale plus how far the line misses the elements and
            // the bounds, at best.
            let mut samples = spread(&line.in_bounds);
            if samples.is_empty() {
                samples = spread(&line.within);
                samples.retain(|s| s.is_finite());
            }
            let miss = samples
                .into_iter()
                .map(|s| line.violation(s, bounds))
                .fold(f64::INFINITY, f64::min);
            return Some(self.scale + miss.min(self.scale));
        }
        let margin = scaled(SEPARATION_REL, self.scale);
        let free = line.free(self, scaled(CONTACT_REL, self.scale));
        if let Some(longest) = free.iter().map(|&(a, b)| b - a).reduce(f64::max) {
            if longest >= 2.0 * margin || line.d == DVec3::ZERO {
                return Some(-longest.max(2.0 * margin));
            }
        }
        let samples = spread(&line.allowed);
        let depth: f64 = samples
            .iter()
            .map(|&s| {
                let at = DAffine3::from_translation(s * line.d) * line.placed;
                self.scene.penetration_excess(&at)
            })
            .sum();
        Some(depth / samples.len() as f64)
    }

    /// A witness of `target` at a rotation within box `b`, found by compass searches
    /// over the rotation that minimise [`Problem::slide_gap`]: from near the box's
    /// central rotation, then (with `spread`) from near the centres of its eight
    /// octants and near its eight corners. `None` when the contacts do not pin the translation or no search ends
    /// on a free stretch.
    pub(super) fn slide_search(
        &self,
        target: &[PrincipalContact],
        b: &Bounds,
        spread: bool,
        others: &mut Vec<(Vec<PrincipalContact>, Pose)>,
    ) -> Option<Pose> {
        // Off the centres: a symmetric box centres on rotations where faces are
        // parallel, which show more contacts than a generic rotation nearby.
        let octant = |c: u32| -> [f64; 3] {
            std::array::from_fn(|k| 0.25 + 0.5 * f64::from((c >> k) & 1) + OFF_CENTRE[k] - 0.5)
        };
        // Thin states often hold only against a bound of the rotation: the corners too,
        // just inside.
        let corner = |c: u32| -> [f64; 3] {
            std::array::from_fn(|k| 0.05 + 0.9 * f64::from((c >> k) & 1) + OFF_CENTRE[k] - 0.5)
        };
        let count = if spread { 8 } else { 0 };
        let mut starts = std::iter::once(OFF_CENTRE)
            .chain((0..count).map(octant))
            .chain((0..count).map(corner));
        let first = starts.next()?;
        // A target the slide cannot take is known at the first start.
        let found = self.slide_search_from(target, b, first, others)?;
        if found.is_some() {
            return found;
        }
        starts.find_map(|w| self.slide_search_from(target, b, w, others).flatten())
    }

    /// One compass search of [`Problem::slide_search`] from the rotation at fractions
    /// `from` of the box's widths: `None` when the contacts do not pin the translation
    /// there, `Some(None)` when the search ends without a witness.
    fn slide_search_from(
        &self,
        target: &[PrincipalContact],
        b: &Bounds,
        from: [f64; 3],
        others: &mut Vec<(Vec<PrincipalContact>, Pose)>,
    ) -> Option<Option<Pose>> {
        let (lo, hi) = (b.min.to_array(), b.max.to_array());
        let mut at: [f64; 3] = std::array::from_fn(|k| lo[3 + k] + (hi[3 + k] - lo[3 + k]) * from[k]);
        let mut best = self.slide_gap(target, at, b)?;
        let mut step: [f64; 3] = std::array::from_fn(|k| 0.25 * (hi[3 + k] - lo[3 + k]));
        let goal = -2.0 * scaled(SEPARATION_REL, self.scale);
        let mut evaluations = 0;
        while best > goal && evaluations < SLIDE_EVALUATIONS && step.iter().any(|&h| h > 1e-9) {
            let mut moved = false;
            for k in 0..3 {
                for sign in [1.0, -1.0] {
                    let mut next = at;
                    next[k] = (at[k] + sign * step[k]).clamp(lo[3 + k], hi[3 + k]);
                    if next == at {
                        continue;
                    }
                    evaluations += 1;
                    if let Some(gap) = self.slide_gap(target, next, b) {
                        if gap < best {
                            (best, at, moved) = (gap, next, true);
                            // A step that helps may help longer.
                            step[k] = (2.0 * step[k]).min(0.25 * (hi[3 + k] - lo[3 + k]));
                            break;
                        }
                    }
                }
            }
            if !moved {
                step = step.map(|h| 0.5 * h);
            }
        }
        Some((best <= goal).then(|| self.slide(target, at, b, others)).flatten())
    }

    /// The line (or point) of translations on which the target's contacts hold at the
    /// rotation `angles`, cut to the bounds and to the elements.
    fn line(&self, target: &[PrincipalContact], angles: [f64; 3], bounds: &Bounds) -> Option<Line> {
        let angles = self.project_rotation(target, angles)?;
        let base = self.placement(&Pose::from_array([0.0, 0.0, 0.0, angles[0], angles[1], angles[2]]));
        let linear = self.linear(target, &base)?;
        // The translation: u = u0 + s d on the solution line (a point when d = 0).
        let tol = scaled(CONTACT_REL, self.scale);
        let basis = orthonormal(linear.rows.iter().copied(), Some(tol))?;
        let u0: DVec3 = basis.iter().map(|&(q, r)| q * r).sum();
        let d = match basis[..] {
            [_, _, _] => DVec3::ZERO,
            [(q1, _), (q2, _)] => q1.cross(q2).normalize(),
            _ => return None,
        };
        let g_inverse = self.assembled.matrix3.inverse();
        let mut allowed: Intervals = vec![(f64::NEG_INFINITY, f64::INFINITY)];
        // Affine constraints lo ≤ v + s k ≤ hi.
        let keep = |allowed: &mut Intervals, v: f64, k: f64, lo: f64, hi: f64| {
            let range = if k.abs() < 1e-15 {
                if v >= lo && v <= hi {
                    (f64::NEG_INFINITY, f64::INFINITY)
                } else {
                    (1.0, -1.0)
                }
            } else if k > 0.0 {
                ((lo - v) / k, (hi - v) / k)
            } else {
                ((hi - v) / k, (lo - v) / k)
            };
            *allowed = intersect(allowed, &[range]);
        };
        for &(a, c, l, h) in &linear.ranges {
            keep(&mut allowed, a.dot(u0) + c, a.dot(d), l, h);
        }
        // The overlaps of edges and faces lying in faces cut `allowed` only: poses on
        // the rest of the line show other states worth keeping.
        let mut loose = allowed.clone();
        for (set, &overlap) in linear.in_faces.iter().zip(&linear.overlaps) {
            // Per triangle, the hull of its points' stretches: the overlap of a convex
            // piece with a triangle moves along a convex set of the line.
            let mut union: Intervals = Vec::new();
            for (k, triangles) in linear.triangles.iter().enumerate() {
                for t in triangles {
                    let hull = set
                        .iter()
                        .filter(|&&(_, _, j)| j == k)
                        .filter_map(|&(x0, sign, _)| in_triangle(t, x0 + sign * u0, sign * d))
                        .reduce(|a, b| (a.0.min(b.0), a.1.max(b.1)));
                    union.extend(hull);
                }
            }
            let union = merge(union);
            allowed = intersect(&allowed, &union);
            if !overlap {
                loose = intersect(&loose, &union);
            }
        }
        // The bounds alone, and with the elements.
        let mut in_bounds: Intervals = vec![(f64::NEG_INFINITY, f64::INFINITY)];
        let (lo, hi) = (bounds.min.to_array(), bounds.max.to_array());
        for k in 0..3 {
            let row = g_inverse.row(k);
            keep(&mut in_bounds, row.dot(u0), row.dot(d), lo[k], hi[k]);
        }
        if d == DVec3::ZERO {
            let point = |list: &Intervals| if list.is_empty() { Vec::new() } else { vec![(0.0, 0.0)] };
            (allowed, loose, in_bounds) = (point(&allowed), point(&loose), point(&in_bounds));
        }
        in_bounds.retain(|&(a, b)| a.is_finite() && b.is_finite());
        let within = allowed.clone();
        let allowed = intersect(&allowed, &in_bounds);
        let loose = intersect(&loose, &in_bounds);
        Some(Line {
            angles,
            u0,
            d,
            within,
            in_bounds,
            allowed,
            loose,
            linear,
            placed: DAffine3::from_translation(u0) * base,
            g_inverse,
        })
    }

    /// The target's contacts as linear conditions on the translation at the rotation
    /// of `base` (the moving part's placement with no translation). Faces on faces,
    /// edges in faces and touching edges give their equations only where the rotation
    /// makes them parallel ([`Problem::project_rotation`]). `None` when two crossing
    /// edges are parallel at this rotation.
    fn linear(&self, target: &[PrincipalContact], base: &DAffine3) -> Option<Linear> {
        let margin = 2.0 * scaled(SEPARATION_REL, self.scale);
        let fixed_point = |v| self.fixed.vertex(v).position;
        let moving_point = |v| base.transform_point3(self.moving.vertex(v).position);
        let moving_edge = |x| self.moving.edge_points(x).map(|p| base.transform_point3(p));
        let mut out = Linear::default();
        for pc in target {
            match (pc.kind, pc.fixed, pc.moving) {
                (ContactKind::FaceVertex, ElementId::Face(f), ElementId::Vertex(v)) => {
                    let face = &self.fixed.face(f);
                    let q = moving_point(v);
                    out.rows.push((face.normal, face.offset - face.normal.dot(q)));
                    out.in_face([q], 1.0, face_triangles(self.fixed, f, &DAffine3::IDENTITY));
                }
                (ContactKind::VertexFace, ElementId::Vertex(v), ElementId::Face(g)) => {
                    let p = fixed_point(v);
                    let triangles = face_triangles(self.moving, g, base);
                    let m = base.transform_vector3(self.moving.face(g).normal).normalize();
                    let q0 = triangles.first()?[0];
                    out.rows.push((m, m.dot(p - q0)));
                    out.in_face([p], -1.0, triangles);
                }
                (ContactKind::EdgeEdge, ElementId::Edge(e), ElementId::Edge(x)) => {
                    let [a0, a1] = self.fixed.edge_points(e);
                    let [b0, b1] = moving_edge(x);
                    let (da, db) = (a1 - a0, b1 - b0);
                    let c = da.cross(db);
                    let c2 = c.length_squared();
                    if c2 <= 1e-18 * da.length_squared() * db.length_squared() {
                        return None;
                    }
                    out.rows.push((c, c.dot(a0 - b0)));
                    // a0 + α da = b0 + u + β db.
                    let (ka, kb) = (db.cross(c) / c2, da.cross(c) / c2);
                    let w0 = b0 - a0;
                    let (ra, rb) = (margin / da.length(), margin / db.length());
                    out.ranges.push((ka, w0.dot(ka), ra, 1.0 - ra));
                    out.ranges.push((kb, w0.dot(kb), rb, 1.0 - rb));
                }
                (ContactKind::EdgeVertex, ElementId::Edge(e), ElementId::Vertex(v)) => {
                    let [a0, a1] = self.fixed.edge_points(e);
                    let q = moving_point(v);
                    let da = a1 - a0;
                    for p in perpendiculars(da) {
                        out.rows.push((p, p.dot(a0 - q)));
                    }
                    let k = da / da.length_squared();
                    let r = margin / da.length();
                    out.ranges.push((k, (q - a0).dot(k), r, 1.0 - r));
                }
                (ContactKind::VertexEdge, ElementId::Vertex(v), ElementId::Edge(x)) => {
                    let p = fixed_point(v);
                    let [b0, b1] = moving_edge(x);
                    let db = b1 - b0;
                    for n in perpendiculars(db) {
                        out.rows.push((n, n.dot(p - b0)));
                    }
                    let k = db / db.length_squared();
                    let r = margin / db.length();
                    out.ranges.push((-k, (p - b0).dot(k), r, 1.0 - r));
                }
                (ContactKind::VertexVertex, ElementId::Vertex(v), ElementId::Vertex(w)) => {
                    let delta = fixed_point(v) - moving_point(w);
                    for axis in [DVec3::X, DVec3::Y, DVec3::Z] {
                        out.rows.push((axis, axis.dot(delta)));
                    }
                }
                // The contacts that also hold the rotation: at a rotation where they are
                // parallel (see [`Problem::project_rotation`]), points of the moving
                // element on the fixed one's plane or line, and the two overlapping
                // (points spread over one inside the other).
                (ContactKind::FaceEdge, ElementId::Face(f), ElementId::Edge(x)) => {
                    let face = &self.fixed.face(f);
                    for q in moving_edge(x) {
                        out.rows.push((face.normal, face.offset - face.normal.dot(q)));
                    }
                    out.in_face(
                        along(moving_edge(x)),
                        1.0,
                        face_triangles(self.fixed, f, &DAffine3::IDENTITY),
                    );
                }
                (ContactKind::EdgeFace, ElementId::Edge(e), ElementId::Face(g)) => {
                    let triangles = face_triangles(self.moving, g, base);
                    let m = base.transform_vector3(self.moving.face(g).normal).normalize();
                    let q0 = triangles.first()?[0];
                    for a in self.fixed.edge_points(e) {
                        out.rows.push((m, m.dot(a - q0)));
                    }
                    out.in_face(along(self.fixed.edge_points(e)), -1.0, triangles);
                }
                (ContactKind::FaceFace, ElementId::Face(f), ElementId::Face(g)) => {
                    let face = &self.fixed.face(f);
                    let triangles = face_triangles(self.moving, g, base);
                    for q in triangles.first()? {
                        out.rows.push((face.normal, face.offset - face.normal.dot(*q)));
                    }
                    // One face's corners and edge midpoints in the other, either way.
                    let spread = |part: &Part, f: FaceId, place: &DAffine3| -> Vec<DVec3> {
                        part.face(f)
                            .loops
                            .iter()
                            .flat_map(|l| l.edges.iter())
                            .flat_map(|&x| {
                                let [a, b] = part.edge_points(x).map(|p| place.transform_point3(p));
                                [a, a.midpoint(b)]
                            })
                            .collect()
                    };
                    let mut set: Vec<(DVec3, f64, usize)> = Vec::new();
                    out.triangles.push(face_triangles(self.fixed, f, &DAffine3::IDENTITY));
                    set.extend(
                        spread(self.moving, g, base)
                            .into_iter()
                            .map(|q| (q, 1.0, out.triangles.len() - 1)),
                    );
                    out.triangles.push(triangles);
                    set.extend(
                        spread(self.fixed, f, &DAffine3::IDENTITY)
                            .into_iter()
                            .map(|p| (p, -1.0, out.triangles.len() - 1)),
                    );
                    out.in_faces.push(set);
                    out.overlaps.push(true);
                }
                (ContactKind::EdgeEdgeTouch, ElementId::Edge(e), ElementId::Edge(x)) => {
                    let [a0, a1] = self.fixed.edge_points(e);
                    let [b0, b1] = moving_edge(x);
                    let da = a1 - a0;
                    for p in perpendiculars(da) {
                        out.rows.push((p, p.dot(a0 - b0)));
                    }
                    // The moving edge's middle within the fixed edge.
                    let k = da / da.length_squared();
                    out.ranges.push((k, (b0.midpoint(b1) - a0).dot(k), 0.0, 1.0));
                }
                _ => return None,
            }
        }
        Some(out)
    }

    /// The rotation conditions of the target's contacts at `angles`: each vanishes
    /// where the contact's elements are parallel as it needs (a face's normal across an
    /// edge in it, two faces' normals opposed, two touching edges along one line).
    fn rotation_conditions(&self, target: &[PrincipalContact], angles: [f64; 3]) -> Vec<f64> {
        let base = self.placement(&Pose::from_array([0.0, 0.0, 0.0, angles[0], angles[1], angles[2]]));
        let edge = |part: &Part, x| part.edge_direction(x);
        let normal = |part: &Part, f| part.face(f).normal;
        let mut out = Vec::new();
        for pc in target {
            match (pc.fixed, pc.moving) {
                (ElementId::Face(f), ElementId::Edge(x)) => {
                    out.push(normal(self.fixed, f).dot(base.transform_vector3(edge(self.moving, x))));
                }
                (ElementId::Edge(e), ElementId::Face(g)) => {
                    out.push(edge(self.fixed, e).dot(base.transform_vector3(normal(self.moving, g))));
                }
                (ElementId::Face(f), ElementId::Face(g)) => {
                    let m = base.transform_vector3(normal(self.moving, g));
                    out.extend(perpendiculars(normal(self.fixed, f)).map(|p| p.dot(m)));
                }
                (ElementId::Edge(e), ElementId::Edge(x)) if pc.kind == ContactKind::EdgeEdgeTouch => {
                    let m = base.transform_vector3(edge(self.moving, x));
                    out.extend(perpendiculars(edge(self.fixed, e)).map(|p| p.dot(m)));
                }
                _ => {}
            }
        }
        out
    }

    /// The rotation nearest `angles` (Gauss–Newton, minimum-norm steps) at which the
    /// target's contacts are parallel as they need; `angles` itself when no contact
    /// holds the rotation. `None` when the iteration does not settle.
    fn project_rotation(&self, target: &[PrincipalContact], angles: [f64; 3]) -> Option<[f64; 3]> {
        let mut at = angles;
        for _ in 0..PROJECTION_STEPS {
            let c = self.rotation_conditions(target, at);
            if c.iter().all(|v| v.abs() <= 1e-3 * PARALLEL_SIN) {
                return Some(at);
            }
            let h = 1e-7;
            // The Jacobian's rows (one per condition) by central differences.
            let (up, down): (Vec<Vec<f64>>, Vec<Vec<f64>>) = (0..3)
                .map(|k| {
                    let (mut plus, mut minus) = (at, at);
                    plus[k] += h;
                    minus[k] -= h;
                    (
                        self.rotation_conditions(target, plus),
                        self.rotation_conditions(target, minus),
                    )
                })
                .unzip();
            let rows = (0..c.len()).map(|i| {
                let row = DVec3::from_array(std::array::from_fn(|k| (up[k][i] - down[k][i]) / (2.0 * h)));
                (row, c[i])
            });
            // The minimum-norm step J⁺ c, rows made orthonormal (a condition repeated by
            // another contact drops out).
            let basis = orthonormal(rows, None)?;
            let step: DVec3 = basis.iter().map(|&(q, r)| q * r).sum();
            if !step.is_finite() || basis.is_empty() {
                return None;
            }
            at = std::array::from_fn(|k| at[k] - step[k]);
        }
        None
    }
}

/// Free stretches tried per line, the longest first.
const SLIDE_TRIES: usize = 4;
/// Rotations evaluated by one compass search, at most.
const SLIDE_EVALUATIONS: usize = 100;
/// Where in a box of rotations the compass search starts (fractions of each width).
const OFF_CENTRE: [f64; 3] = [0.5123, 0.4689, 0.5217];
/// Gauss–Newton steps of [`Problem::project_rotation`], at most.
const PROJECTION_STEPS: usize = 12;
/// Points of an edge tried in a face, for an edge lying in a face.
const EDGE_SAMPLES: usize = 8;
/// Points of a line at which [`Problem::slide_gap`] measures the penetration.
const SLIDE_SAMPLES: usize = 16;

/// The translations `u0 + s d` (in the fixed frame) on which a target's contacts hold at
/// one rotation: `allowed` the stretches within the bounds and the elements.
struct Line {
    /// The rotation, made parallel where the contacts need it.
    angles: [f64; 3],
    u0: DVec3,
    d: DVec3,
    /// The stretches where the contact points are inside their elements.
    within: Intervals,
    /// The stretches within the translation bounds.
    in_bounds: Intervals,
    /// Both: where a witness may be.
    allowed: Intervals,
    /// [`Line::allowed`] with only the point contacts inside their elements (not yet
    /// the edges and faces lying in faces overlapping them).
    loose: Intervals,
    /// The conditions the line was cut by.
    linear: Linear,
    /// The moving part placed at `u0`.
    placed: DAffine3,
    /// From the fixed frame's translation back to the pose's (G's linear part inverted).
    g_inverse: glam::DMat3,
}

impl Line {
    /// The allowed stretches where the parts penetrate by at most `depth`.
    fn free(&self, problem: &Problem<'_>, depth: f64) -> Intervals {
        self.free_of(&self.allowed, problem, depth)
    }

    /// The stretches of `list` where the parts penetrate by at most `depth`.
    fn free_of(&self, list: &Intervals, problem: &Problem<'_>, depth: f64) -> Intervals {
        // A point is a line of no length.
        let d = if self.d == DVec3::ZERO { DVec3::X } else { self.d };
        subtract(list, problem.scene.blocked_along(&self.placed, d, depth))
    }

    /// How far the point at `s` is from its contact points lying in their elements
    /// and from the bounds (0 when it is within both).
    fn violation(&self, s: f64, bounds: &Bounds) -> f64 {
        let u = self.u0 + s * self.d;
        let ranges: f64 = self
            .linear
            .ranges
            .iter()
            .map(|&(a, c, lo, hi)| outside(lo, hi, a.dot(u) + c) / a.length().max(1e-300))
            .sum();
        let faces: f64 = self
            .linear
            .in_faces
            .iter()
            .map(|set| {
                set.iter()
                    .flat_map(|&(x0, sign, k)| {
                        let x = x0 + sign * u;
                        self.linear.triangles[k].iter().map(move |t| triangle_distance(t, x))
                    })
                    .fold(f64::INFINITY, f64::min)
            })
            .sum();
        let t = self.pose(s).to_array();
        let (lo, hi) = (bounds.min.to_array(), bounds.max.to_array());
        let out_of_bounds: f64 = (0..3).map(|k| outside(lo[k], hi[k], t[k])).sum();
        ranges + faces + out_of_bounds
    }

    /// The pose at parameter `s`.
    fn pose(&self, s: f64) -> Pose {
        let angles = self.angles;
        let t = self.g_inverse * (self.u0 + s * self.d);
        Pose::from_array([t.x, t.y, t.z, angles[0], angles[1], angles[2]])
    }
}

/// How far `x` lies outside `[lo, hi]` (0 inside).
fn outside(lo: f64, hi: f64, x: f64) -> f64 {
    (lo - x).max(x - hi).max(0.0)
}

/// The parameters `s` at which `x + s dx` lies in the triangle (barycentric
/// coordinates in its plane, all at least 0), or `None`.
fn in_triangle(t: &[DVec3; 3], x: DVec3, dx: DVec3) -> Option<(f64, f64)> {
    let n = (t[1] - t[0]).cross(t[2] - t[0]);
    let n2 = n.length_squared();
    if n2 == 0.0 {
        return None;
    }
    let (mut lo, mut hi) = (f64::NEG_INFINITY, f64::INFINITY);
    for i in 0..3 {
        let (p, q) = (t[(i + 1) % 3], t[(i + 2) % 3]);
        // λ_i = ((q − p) × (x − p)) · n / |n|², affine in s.
        let e = q - p;
        let v = e.cross(x - p).dot(n) / n2;
        let k = e.cross(dx).dot(n) / n2;
        if k.abs() < 1e-15 {
            if v < 0.0 {
                return None;
            }
        } else if k > 0.0 {
            lo = lo.max(-v / k);
        } else {
            hi = hi.min(-v / k);
        }
    }
    (lo <= hi).then_some((lo, hi))
}

/// Equations `a · x = b` made orthonormal (Gram–Schmidt): their minimum-norm solution
/// is `Σ q r` over the rows `(q, r)` returned. A row that depends on the earlier ones
/// is dropped; with `tol`, `None` when its right-hand side then disagrees by more than
/// `tol` (a length, per unit of `a`).
fn orthonormal(rows: impl IntoIterator<Item = (DVec3, f64)>, tol: Option<f64>) -> Option<Vec<(DVec3, f64)>> {
    let mut basis: Vec<(DVec3, f64)> = Vec::new();
    for (a, b) in rows {
        let (mut a2, mut b2) = (a, b);
        for &(q, r) in &basis {
            let k = a2.dot(q);
            a2 -= k * q;
            b2 -= k * r;
        }
        let length = a2.length();
        if length > 1e-9 * a.length().max(1e-300) {
            basis.push((a2 / length, b2 / length));
        } else if tol.is_some_and(|tol| b2.abs() > tol * a.length()) {
            return None;
        }
    }
    Some(basis)
}

/// The distance from `x` to a triangle (to its plane's nearest point when that falls
/// inside, else to its nearest side).
fn triangle_distance(t: &[DVec3; 3], x: DVec3) -> f64 {
    let n = (t[1] - t[0]).cross(t[2] - t[0]);
    let n2 = n.length_squared();
    if n2 == 0.0 {
        return f64::INFINITY;
    }
    let inside = (0..3).all(|i| {
        let (p, q) = (t[(i + 1) % 3], t[(i + 2) % 3]);
        (q - p).cross(x - p).dot(n) >= 0.0
    });
    if inside {
        return (x - t[0]).dot(n).abs() / n2.sqrt();
    }
    (0..3)
        .map(|i| {
            let (p, q) = (t[i], t[(i + 1) % 3]);
            let e = q - p;
            let w = ((x - p).dot(e) / e.length_squared()).clamp(0.0, 1.0);
            x.distance(p + w * e)
        })
        .fold(f64::INFINITY, f64::min)
}

/// The union of intervals, sorted and disjoint.
fn merge(mut list: Intervals) -> Intervals {
    list.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut out: Intervals = Vec::new();
    for (a, b) in list {
        match out.last_mut() {
            Some(last) if a <= last.1 => last.1 = last.1.max(b),
            _ => out.push((a, b)),
        }
    }
    out
}

/// The intersection of two sorted, disjoint interval lists.
fn intersect(x: &[(f64, f64)], y: &[(f64, f64)]) -> Intervals {
    let mut out = Vec::new();
    for &(a, b) in x {
        for &(c, d) in y {
            let (lo, hi) = (a.max(c), b.min(d));
            if lo <= hi {
                out.push((lo, hi));
            }
        }
    }
    merge(out)
}

/// `x` without the open intervals `cut`.
fn subtract(x: &[(f64, f64)], cut: Intervals) -> Intervals {
    let cut = merge(cut);
    let mut out = Vec::new();
    for &(mut a, b) in x {
        for &(c, d) in &cut {
            if d <= a || c >= b {
                continue;
            }
            if c > a {
                out.push((a, c));
            }
            a = a.max(d);
        }
        if a <= b {
            out.push((a, b));
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::fixture;

    #[test]
    fn repeated_equations_drop_out_and_contradicting_ones_fail() {
        let rows = [(DVec3::Z, 2.0), (2.0 * DVec3::Z, 4.0), (DVec3::X, 1.0)];
        let basis = orthonormal(rows, Some(1e-12)).unwrap();
        assert_eq!(basis.len(), 2);
        let x: DVec3 = basis.iter().map(|&(q, r)| q * r).sum();
        assert!(x.abs_diff_eq(DVec3::new(1.0, 0.0, 2.0), 1e-12));
        assert!(orthonormal([(DVec3::Z, 2.0), (DVec3::Z, 3.0)], Some(1e-12)).is_none());
        assert_eq!(orthonormal([(DVec3::Z, 2.0), (DVec3::Z, 3.0)], None).unwrap().len(), 1);
    }

    #[test]
    fn intervals_subtract_and_intersect() {
        assert_eq!(
            subtract(&[(0.0, 10.0)], vec![(2.0, 3.0), (2.5, 4.0), (9.0, 12.0)]),
            vec![(0.0, 2.0), (4.0, 9.0)]
        );
        assert_eq!(
            intersect(&[(0.0, 2.0), (4.0, 9.0)], &[(1.0, 5.0)]),
            vec![(1.0, 2.0), (4.0, 5.0)]
        );
    }

    /// The peg over a block, x and y within ±2, z from 0 to 45, each angle within ±2°.
    fn peg_bounds() -> Bounds {
        Bounds::from_degrees([-2.0, -2.0, 0.0, -2.0, -2.0, -2.0], [2.0, 2.0, 45.0, 2.0, 2.0, 2.0]).unwrap()
    }

    #[test]
    fn a_corner_of_the_hole_in_an_edge_of_the_peg_is_found_by_turning() {
        // The block's vertex v7 in the peg's edge e0 holds only within about 1e-3 rad of
        // rz = 0 and near the rx, ry corner of the bounds: local searches from spread
        // starts miss it (the recall oracle found it).
        let (a, b) = (fixture("block_with_chamfered_hole.off"), fixture("peg.off"));
        let bounds = peg_bounds();
        let problem = Problem::new(&a, &b, bounds, DAffine3::IDENTITY);
        let target = vec![PrincipalContact {
            fixed: "v7".parse().unwrap(),
            moving: "e0".parse().unwrap(),
            kind: ContactKind::VertexEdge,
        }];
        let mut others = Vec::new();
        let pose = problem
            .slide_search(&target, &bounds, false, &mut others)
            .expect("a witness");
        assert_eq!(problem.clean_state(&pose), Some(target.clone()));
        // At identity the line is free but the peg's faces lie along the hole's walls:
        // the pose there shows more contacts, never the target alone.
        let at_identity = problem.line(&target, [0.0; 3], &bounds).expect("a line");
        assert_ne!(problem.clean_state(&at_identity.pose(0.5)), Some(target));
    }

    #[test]
    fn an_edge_lying_in_a_face_is_slid_onto_the_face_not_its_plane() {
        // The peg's edge e11 in the hole's wall f11 and its vertex v2 on the chamfer f7:
        // at this rotation the line of translations holding both runs mostly where the
        // edge lies in the wall's plane above the wall (the oracle found the state, the
        // slide took the line's middle). Only 0.02 mm of it has the edge on the wall.
        let (a, b) = (fixture("block_with_chamfered_hole.off"), fixture("peg.off"));
        let bounds = peg_bounds();
        let problem = Problem::new(&a, &b, bounds, DAffine3::IDENTITY);
        let target = vec![
            PrincipalContact {
                fixed: "f7".parse().unwrap(),
                moving: "v2".parse().unwrap(),
                kind: ContactKind::FaceVertex,
            },
            PrincipalContact {
                fixed: "f11".parse().unwrap(),
                moving: "e11".parse().unwrap(),
                kind: ContactKind::FaceEdge,
            },
        ];
        let angles = [0.028925019148872643, 0.0004888715855397775, -0.016895017909574504];
        let mut others = Vec::new();
        let pose = problem.slide(&target, angles, &bounds, &mut others).expect("a witness");
        assert_eq!(problem.clean_state(&pose), Some(target.clone()));
        let line = problem.line(&target, angles, &bounds).expect("a line");
        let length = |list: &Intervals| list.iter().map(|(a, b)| b - a).sum::<f64>();
        assert!(length(&line.allowed) < 0.05, "{:?}", line.allowed);
    }

    #[test]
    fn a_rotation_is_made_parallel_for_an_edge_in_a_face() {
        let (a, b) = (fixture("block_with_hole.off"), fixture("peg.off"));
        let bounds = peg_bounds();
        let problem = Problem::new(&a, &b, bounds, DAffine3::IDENTITY);
        let (mut pairs, mut projected) = (0, 0);
        for f in 0..a.faces().len() as u32 {
            for x in 0..b.edges().len() as u32 {
                let target = [PrincipalContact {
                    fixed: ElementId::Face(FaceId(f)),
                    moving: ElementId::Edge(crate::model::EdgeId(x)),
                    kind: ContactKind::FaceEdge,
                }];
                let start = [0.01, -0.02, 0.015];
                pairs += 1;
                let Some(turned) = problem.project_rotation(&target, start) else {
                    continue;
                };
                projected += 1;
                let base = problem.placement(&Pose::from_array([0.0, 0.0, 0.0, turned[0], turned[1], turned[2]]));
                let [p, q] = b.edge_points(crate::model::EdgeId(x)).map(|p| base.transform_point3(p));
                let n = a.faces()[f as usize].normal;
                crate::assert_near!(n.dot((q - p).normalize()), 0.0, 1e-12);
            }
        }
        // Gauss–Newton reaches a parallel rotation for every pair from this start.
        assert_eq!(projected, pairs);
    }

    #[test]
    fn a_line_crosses_a_triangle_between_two_of_its_sides() {
        let t = [DVec3::ZERO, DVec3::X, DVec3::Y];
        let (lo, hi) = in_triangle(&t, DVec3::new(-1.0, 0.25, 0.0), DVec3::X).unwrap();
        crate::assert_near!(lo, 1.0, 1e-12);
        crate::assert_near!(hi, 1.75, 1e-12);
    }
}
