//! Geometric feasibility: is there a pose within the bounds at which a contact state
//! holds, with no penetration? And if so, a witness pose that proves it.
//!
//! A search has three layers:
//! 1. a conservative reach test by interval arithmetic (can the moving element come
//!    near the fixed one at all within the bounds?), which prunes without optimising;
//! 2. Levenberg–Marquardt within the bounds on residuals that vanish exactly when the
//!    contacts hold with their contact points inside the elements' relative interiors
//!    (with a margin) and nothing penetrates, from constructive starts that place the
//!    contact point directly;
//! 3. verification of every pose found by the contact module: P(X) must equal the state
//!    asked for, with no penetration. A pose showing another state is reported as such.

mod interval;
mod solver;

use glam::{DAffine3, DVec3};

use crate::contact::queries::{PlanarRegion, Segment, point_segment};
use crate::contact::{ContactKind, ContactScene, PrincipalContact};
use crate::model::{ElementId, FaceId, Part};
use crate::pose::{Bounds, Pose};
use crate::tolerance::{CONTACT_REL, SEPARATION_REL, scaled};

/// Every primitive principal contact (DOMAIN.md section 3): faces of the fixed part
/// against convex vertices of the moving part (f-v), convex edges against convex edges
/// (e-e), convex vertices of the fixed part against faces of the moving part (v-f).
#[must_use]
pub fn primitive_contacts(fixed: &Part, moving: &Part) -> Vec<PrincipalContact> {
    let faces = |p: &Part| {
        (0..p.faces().len() as u32)
            .map(|i| ElementId::Face(FaceId(i)))
            .collect::<Vec<_>>()
    };
    let vertices = |p: &Part| p.convex_vertices().map(ElementId::Vertex).collect::<Vec<_>>();
    let edges = |p: &Part| p.convex_edges().map(ElementId::Edge).collect::<Vec<_>>();
    let mut out = Vec::new();
    for f in faces(fixed) {
        out.extend(vertices(moving).into_iter().map(|v| PrincipalContact {
            fixed: f,
            moving: v,
            kind: ContactKind::FaceVertex,
        }));
    }
    for e in edges(fixed) {
        out.extend(edges(moving).into_iter().map(|x| PrincipalContact {
            fixed: e,
            moving: x,
            kind: ContactKind::EdgeEdge,
        }));
    }
    for v in vertices(fixed) {
        out.extend(faces(moving).into_iter().map(|f| PrincipalContact {
            fixed: v,
            moving: f,
            kind: ContactKind::VertexFace,
        }));
    }
    out
}

/// A face's plane and loops as points, in its part's own frame.
#[derive(Clone, Debug)]
struct FaceShape {
    normal: DVec3,
    offset: f64,
    loops: Vec<Vec<DVec3>>,
    /// A point well inside the face: the centroid of its largest triangle.
    inner: DVec3,
    /// The margin kept from the face's boundary: a quarter of its inradius scale,
    /// at most the global margin.
    margin: f64,
}

impl FaceShape {
    fn all(part: &Part, margin: f64) -> Vec<FaceShape> {
        part.faces()
            .iter()
            .map(|f| {
                let at = |v: crate::model::VertexId| part.vertex(v).position;
                let loops: Vec<Vec<DVec3>> = f
                    .loops
                    .iter()
                    .map(|l| l.vertices.iter().map(|&v| at(v)).collect())
                    .collect();
                let (inner, _) = f
                    .triangles
                    .iter()
                    .map(|t| {
                        let [a, b, c] = t.map(at);
                        ((a + b + c) / 3.0, (b - a).cross(c - a).length())
                    })
                    .fold(
                        (at(f.outer().vertices[0]), -1.0),
                        |best, x| if x.1 > best.1 { x } else { best },
                    );
                let perimeter: f64 = loops
                    .iter()
                    .flat_map(|l| (0..l.len()).map(move |i| l[i].distance(l[(i + 1) % l.len()])))
                    .sum();
                let width = if perimeter > 0.0 { 2.0 * f.area / perimeter } else { 0.0 };
                FaceShape {
                    normal: f.normal,
                    offset: f.offset,
                    loops,
                    inner,
                    margin: margin.min(0.25 * width),
                }
            })
            .collect()
    }

    fn region(&self) -> PlanarRegion<'_> {
        PlanarRegion {
            normal: self.normal,
            offset: self.offset,
            loops: &self.loops,
            triangles: &[],
        }
    }

    /// How far inside the face's outline the projection of `p` lies (negative outside).
    fn inside_depth(&self, p: DVec3) -> f64 {
        let region = self.region();
        let edge_distance = region
            .boundary_segments()
            .map(|s| point_segment(region.project(p), &s).0)
            .fold(f64::INFINITY, f64::min);
        if region.contains_projection(p) {
            edge_distance
        } else {
            -edge_distance
        }
    }
}

/// Penalty keeping a value at least `margin` (hinge, zero when satisfied).
fn hinge(value: f64, margin: f64) -> f64 {
    (margin - value).max(0.0)
}

/// The outcome of a search for a pose realising a state.
#[derive(Clone, Debug, PartialEq)]
pub enum Search {
    /// A verified witness of the state asked for.
    Found(Pose),
    /// Pruned without optimisation: the elements cannot come near within the bounds.
    Unreachable,
    /// No start led to the state; poses realising other states met on the way are
    /// listed (verified, no penetration), so that they are not lost.
    NotFound {
        /// Other states seen, with their witnesses.
        others: Vec<(Vec<PrincipalContact>, Pose)>,
    },
}

/// Counts of work done.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize)]
pub struct SearchStats {
    /// Targets pruned by the reach test.
    pub pruned: usize,
    /// Local optimisations run.
    pub optimisations: usize,
}

/// A fixed and a moving part with misalignment bounds: the setting of every search.
pub struct Problem<'a> {
    fixed: &'a Part,
    moving: &'a Part,
    bounds: Bounds,
    assembled: DAffine3,
    scene: ContactScene<'a>,
    fixed_faces: Vec<FaceShape>,
    moving_faces: Vec<FaceShape>,
    reach: interval::ReachBox,
    scale: f64,
    margin: f64,
}

impl<'a> Problem<'a> {
    /// Prepares the searches for two parts and bounds; `assembled` is G (DOMAIN.md
    /// section 5).
    #[must_use]
    pub fn new(fixed: &'a Part, moving: &'a Part, bounds: Bounds, assembled: DAffine3) -> Problem<'a> {
        let scene = ContactScene::new(fixed, moving);
        let scale = scene.scale();
        let margin = 1e-3 * scale;
        Problem {
            fixed,
            moving,
            bounds,
            assembled,
            fixed_faces: FaceShape::all(fixed, margin),
            moving_faces: FaceShape::all(moving, margin),
            reach: interval::ReachBox::new(&bounds),
            scene,
            scale,
            margin,
        }
    }

    /// The contact scene of the two parts.
    #[must_use]
    pub fn scene(&self) -> &ContactScene<'a> {
        &self.scene
    }

    fn placement(&self, pose: &Pose) -> DAffine3 {
        pose.to_affine(&self.assembled)
    }

    /// The residuals of a primitive contact and of non-penetration at a pose.
    fn residuals(&self, target: &PrincipalContact, pose: &Pose, out: &mut Vec<f64>) {
        out.clear();
        let t = self.placement(pose);
        match (target.kind, target.fixed, target.moving) {
            (ContactKind::FaceVertex, ElementId::Face(f), ElementId::Vertex(v)) => {
                let p = t.transform_point3(self.moving.vertex(v).position);
                let face = &self.fixed_faces[f.index()];
                out.push(face.normal.dot(p) - face.offset);
                out.push(hinge(face.inside_depth(p), face.margin));
                // The vertex's neighbours rise off the face: B leaves the contact plane.
                for w in neighbours(self.moving, v) {
                    let q = t.transform_point3(w);
                    out.push(hinge(face.normal.dot(q - p), self.clearance(p.distance(q))));
                }
            }
            (ContactKind::VertexFace, ElementId::Vertex(v), ElementId::Face(f)) => {
                let to_b = t.inverse();
                let q = to_b.transform_point3(self.fixed.vertex(v).position);
                let face = &self.moving_faces[f.index()];
                out.push(face.normal.dot(q) - face.offset);
                out.push(hinge(face.inside_depth(q), face.margin));
                // The vertex's neighbours in A lie beyond B's face (on A's side).
                for w in neighbours(self.fixed, v) {
                    let r = to_b.transform_point3(w);
                    out.push(hinge(face.normal.dot(r - q), self.clearance(q.distance(r))));
                }
            }
            (ContactKind::EdgeEdge, ElementId::Edge(e), ElementId::Edge(x)) => {
                let [a0, a1] = self.fixed.edge_points(e);
                let [b0, b1] = self.moving.edge_points(x).map(|p| t.transform_point3(p));
                let (u, w) = (a1 - a0, b1 - b0);
                let n = u.cross(w);
                // Closest points of the two lines, as parameters along each edge.
                let r = a0 - b0;
                let (uu, uw, ww, ur, wr) = (u.dot(u), u.dot(w), w.dot(w), u.dot(r), w.dot(r));
                let det = uu * ww - uw * uw;
                let (s, v) = if det > 1e-12 * uu * ww {
                    ((uw * wr - ww * ur) / det, (uu * wr - uw * ur) / det)
                } else {
                    (0.5, 0.5)
                };
                out.push(if n.length() > 1e-12 * u.length() * w.length() {
                    n.normalize().dot(b0 - a0)
                } else {
                    point_segment(b0, &Segment::new(a0, a1)).0
                });
                let (mu, mw) = (
                    (self.margin / u.length()).min(0.25),
                    (self.margin / w.length()).min(0.25),
                );
                out.push(hinge(s, mu) + hinge(1.0 - s, mu));
                out.push(hinge(v, mw) + hinge(1.0 - v, mw));
                // The faces beside each edge fall away from the contact: along the
                // common normal (outward from A at e), A's neighbouring corners lie
                // below the contact and B's above it.
                let [fa, ga] = self.fixed.edge(e).faces.map(|f| self.fixed.face(f).normal);
                if n.length() > 0.0 {
                    let n = n.normalize();
                    let n = if n.dot(fa + ga) < 0.0 { -n } else { n };
                    for w in edge_neighbours(self.fixed, e) {
                        out.push(hinge(n.dot(a0 - w), self.clearance(a0.distance(w))));
                    }
                    for w in edge_neighbours(self.moving, x) {
                        let q = t.transform_point3(w);
                        out.push(hinge(n.dot(q - b0), self.clearance(b0.distance(q))));
                    }
                }
            }
            // find_primitive turns other contacts away before any residual is computed.
            _ => {}
        }
        let depth = self.scene.penetration_depth(&t);
        out.push(depth.max(0.0));
    }

    /// The clearance asked of a neighbouring corner at distance `d` from the contact:
    /// the margin, or a fraction of `d` for short edges.
    fn clearance(&self, d: f64) -> f64 {
        self.margin.min(0.25 * d)
    }

    /// Starting poses that put the contact point in place, for several orientations
    /// spread over the bounds.
    fn starts(&self, target: &PrincipalContact) -> Vec<Pose> {
        let (lo, hi) = (self.bounds.min.to_array(), self.bounds.max.to_array());
        let mut orientations = vec![[0.5, 0.5, 0.5]];
        for corner in 0..8 {
            orientations.push([
                0.25 + 0.5 * f64::from(corner & 1),
                0.25 + 0.5 * f64::from((corner >> 1) & 1),
                0.25 + 0.5 * f64::from((corner >> 2) & 1),
            ]);
        }
        let g_inverse = self.assembled.inverse();
        orientations
            .into_iter()
            .map(|w| {
                let angle = |k: usize| lo[3 + k] + (hi[3 + k] - lo[3 + k]) * w[k];
                let mut pose = Pose::from_array([0.0, 0.0, 0.0, angle(0), angle(1), angle(2)]);
                let r = pose.rotation();
                // Where the contact point should go (A's frame) and which point of B it is.
                let (goal, on_b) = match (target.fixed, target.moving) {
                    (ElementId::Face(f), ElementId::Vertex(v)) => {
                        (self.fixed_faces[f.index()].inner, self.moving.vertex(v).position)
                    }
                    (ElementId::Vertex(v), ElementId::Face(f)) => {
                        (self.fixed.vertex(v).position, self.moving_faces[f.index()].inner)
                    }
                    (ElementId::Edge(e), ElementId::Edge(x)) => {
                        let ([a0, a1], [b0, b1]) = (self.fixed.edge_points(e), self.moving.edge_points(x));
                        ((a0 + a1) * 0.5, (b0 + b1) * 0.5)
                    }
                    _ => (DVec3::ZERO, DVec3::ZERO),
                };
                let t = g_inverse.transform_point3(goal) - r * on_b;
                pose.x = t.x;
                pose.y = t.y;
                pose.z = t.z;
                self.bounds.clamp(&pose)
            })
            .collect()
    }

    /// Whether the reach test rules the contact out: over every pose in the bounds, the
    /// moving element's box stays away from the fixed element's box.
    fn unreachable(&self, target: &PrincipalContact) -> bool {
        if self.assembled != DAffine3::IDENTITY {
            return false; // the enclosure assumes G = identity
        }
        let fixed_box = |e: ElementId| bounds_of(points_of(self.fixed, e));
        let moving_box = |e: ElementId| {
            points_of(self.moving, e)
                .into_iter()
                .map(|p| self.reach.of(p))
                .fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), (a, b)| {
                    (lo.min(a), hi.max(b))
                })
        };
        let (flo, fhi) = fixed_box(target.fixed);
        let (mlo, mhi) = moving_box(target.moving);
        let slack = scaled(CONTACT_REL, self.scale);
        (mlo - fhi).max(flo - mhi).max_element() > slack
    }

    /// Searches for a witness of a primitive contact (f-v, e-e or v-f, with elements
    /// of those kinds); any other contact gives [`Search::NotFound`] with no search.
    pub fn find_primitive(&self, target: &PrincipalContact, stats: &mut SearchStats) -> Search {
        let primitive = matches!(
            (target.kind, target.fixed, target.moving),
            (ContactKind::FaceVertex, ElementId::Face(_), ElementId::Vertex(_))
                | (ContactKind::VertexFace, ElementId::Vertex(_), ElementId::Face(_))
                | (ContactKind::EdgeEdge, ElementId::Edge(_), ElementId::Edge(_))
        );
        if !primitive {
            return Search::NotFound { others: Vec::new() };
        }
        if self.unreachable(target) {
            stats.pruned += 1;
            return Search::Unreachable;
        }
        let mut others: Vec<(Vec<PrincipalContact>, Pose)> = Vec::new();
        for start in self.starts(target) {
            stats.optimisations += 1;
            let pose = solver::minimise(|x, out| self.residuals(target, x, out), start, &self.bounds, self.scale);
            let report = self.scene.evaluate(&self.placement(&pose), CONTACT_REL);
            let clear = report.min_gap.is_none_or(|g| g >= scaled(SEPARATION_REL, self.scale));
            if report.penetration > 0.0 || report.contacts.is_empty() || !clear {
                continue;
            }
            if report.contacts == [*target] {
                return Search::Found(pose);
            }
            if !others.iter().any(|(state, _)| *state == report.contacts) {
                others.push((report.contacts, pose));
            }
        }
        Search::NotFound { others }
    }

    /// Stage 1: every primitive contact with a verified witness.
    #[must_use]
    pub fn feasible_primitives(&self, stats: &mut SearchStats) -> Vec<(PrincipalContact, Pose)> {
        primitive_contacts(self.fixed, self.moving)
            .into_iter()
            .filter_map(|ppc| match self.find_primitive(&ppc, stats) {
                Search::Found(pose) => Some((ppc, pose)),
                _ => None,
            })
            .collect()
    }
}

/// The other end points of the edges at a vertex.
fn neighbours(part: &Part, v: crate::model::VertexId) -> Vec<DVec3> {
    part.vertex(v)
        .edges
        .iter()
        .map(|&e| {
            let [a, b] = part.edge(e).vertices;
            part.vertex(if a == v { b } else { a }).position
        })
        .collect()
}

/// The corners of an edge's two faces that are not on the edge, next to its ends.
fn edge_neighbours(part: &Part, e: crate::model::EdgeId) -> Vec<DVec3> {
    let ends = part.edge(e).vertices;
    ends.iter()
        .flat_map(|&v| {
            part.vertex(v)
                .edges
                .iter()
                .filter(move |&&x| x != e)
                .map(move |&x| (v, x))
        })
        .map(|(v, x)| {
            let [a, b] = part.edge(x).vertices;
            part.vertex(if a == v { b } else { a }).position
        })
        .collect()
}

fn points_of(part: &Part, e: ElementId) -> Vec<DVec3> {
    match e {
        ElementId::Vertex(v) => vec![part.vertex(v).position],
        ElementId::Edge(x) => part.edge_points(x).to_vec(),
        ElementId::Face(f) => part
            .face(f)
            .outer()
            .vertices
            .iter()
            .map(|&v| part.vertex(v).position)
            .collect(),
    }
}

fn bounds_of(points: Vec<DVec3>) -> (DVec3, DVec3) {
    points
        .into_iter()
        .fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), p| {
            (lo.min(p), hi.max(p))
        })
}
