//! An independent contact-state evaluator for the recall oracle: P(X) by the principal
//! contact rule of docs/concepts.md#principal-contacts, read straight off the two parts' B-reps
//! (vertex positions, edge end points, face loops and planes, convexity flags), with the
//! robustness test of section 7. It shares nothing with `acsg::contact` but the id and
//! kind types it reports in.
//!
//! At a pose, every pair of elements (a of A, b of B) is classified:
//! - touching: relint(a) ∩ relint(b) is not empty within the touching tolerance τ; the
//!   intersection I(a, b) is kept (a point, segments, or the overlap of two faces);
//! - apart: the closures are at least δ (the robustness gap) apart;
//! - anything in between makes the pose non-robust (a checker with another tolerance
//!   could read another state there).
//!
//! The closure distance of any two elements is reached at a vertex-vertex, vertex-edge,
//! edge-edge or vertex-face pair (or is zero because an edge pierces a face, which is
//! penetration), so those primitive pairs are the only gaps measured. A touching pair is
//! principal unless another touching pair of elements whose closures contain it has an
//! intersection whose closure contains its own. Containment in the closure of a face
//! overlap is decided locally, by the two faces' tangent cones at the point.

use std::f64::consts::TAU;

use acsg::contact::{ContactKind, PrincipalContact};
use acsg::model::{EdgeId, ElementId, FaceId, Part, VertexId};
use acsg::pose::Pose;
use glam::{DVec2, DVec3};

/// A contact holds when its elements come this close, relative to L. The oracle's
/// samples hold the contacts they are built on to round-off (about 1e-14 L), so this is
/// kept well below the 1e-9 L of docs/concepts.md#tolerances: a pair that is only within
/// 1e-9 L of touching is a near-coincidence (two nearly coplanar facets of U, say),
/// where checkers with different rules can read different states, and a pair between
/// this and the robustness gap makes the pose non-robust. At a robust pose every
/// checker whose tolerance lies between this and 1e-6 L (the library's 1e-9 L among
/// them) reads the same state.
pub const TOUCH_REL: f64 = 1e-11;

/// Pairs that do not touch must be this far apart, and point contacts this far inside
/// their elements, relative to L.
pub const ROBUST_REL: f64 = 1e-6;

/// What the evaluator reads at one pose.
#[derive(Clone, Debug, PartialEq)]
pub enum Verdict {
    /// A robust pose and its contact state P(X), sorted.
    State(Vec<PrincipalContact>),
    /// Some pair lies between touching and the robustness gap, or a point contact sits
    /// too close to the boundary of one of its elements.
    NonRobust(String),
    /// An edge passes through the interior of a face of the other part.
    Penetrating(String),
}

/// The intersection I(a, b) of the relative interiors of a touching pair.
#[derive(Clone, Debug, PartialEq)]
enum Meet {
    Point(DVec3),
    /// Disjoint open segments (an edge lying in a face, collinear edges).
    Segments(Vec<[DVec3; 2]>),
    /// The overlap of two coplanar faces with opposite normals.
    Overlap {
        fixed: usize,
        moving: usize,
    },
}

#[derive(Clone, Debug)]
struct Touch {
    fixed: ElementId,
    moving: ElementId,
    meet: Meet,
}

/// One part's topology, read once from its B-rep.
struct Topology {
    edge_ends: Vec<[usize; 2]>,
    edge_convex: Vec<bool>,
    vertex_convex: Vec<bool>,
    /// Per face, per loop (outer first), the vertex indices in order.
    loops: Vec<Vec<Vec<usize>>>,
    /// Per face, every vertex and every edge of its closure, sorted.
    face_vertices: Vec<Vec<usize>>,
    face_edges: Vec<Vec<usize>>,
}

impl Topology {
    fn of(part: &Part) -> Topology {
        let loops: Vec<Vec<Vec<usize>>> = part
            .faces()
            .iter()
            .map(|f| {
                f.loops
                    .iter()
                    .map(|l| l.vertices.iter().map(|v| v.index()).collect())
                    .collect()
            })
            .collect();
        let sorted = |mut v: Vec<usize>| {
            v.sort_unstable();
            v.dedup();
            v
        };
        let face_vertices = loops.iter().map(|ls| sorted(ls.concat())).collect();
        let face_edges = part
            .faces()
            .iter()
            .map(|f| sorted(f.loops.iter().flat_map(|l| l.edges.iter().map(|e| e.index())).collect()))
            .collect();
        Topology {
            edge_ends: part.edges().iter().map(|e| e.vertices.map(|v| v.index())).collect(),
            edge_convex: part.edges().iter().map(|e| e.convex).collect(),
            vertex_convex: part.vertices().iter().map(|v| v.convex).collect(),
            loops,
            face_vertices,
            face_edges,
        }
    }

    /// Whether `inner` lies in the closure of `outer` (an element lies in its own).
    fn in_closure(&self, inner: ElementId, outer: ElementId) -> bool {
        use ElementId::{Edge, Face, Vertex};
        match (inner, outer) {
            _ if inner == outer => true,
            (Vertex(v), Edge(e)) => self.edge_ends[e.index()].contains(&v.index()),
            (Vertex(v), Face(f)) => self.face_vertices[f.index()].binary_search(&v.index()).is_ok(),
            (Edge(e), Face(f)) => self.face_edges[f.index()].binary_search(&e.index()).is_ok(),
            _ => false,
        }
    }

    fn convex(&self, e: ElementId) -> bool {
        match e {
            ElementId::Vertex(v) => self.vertex_convex[v.index()],
            ElementId::Edge(x) => self.edge_convex[x.index()],
            ElementId::Face(_) => true,
        }
    }
}

/// A face placed in A's frame: its plane, an in-plane frame and its loops.
#[derive(Clone, Debug)]
struct PlacedFace {
    normal: DVec3,
    offset: f64,
    u: DVec3,
    v: DVec3,
    /// Loops as 3D points and as 2D points in (u, v).
    loops: Vec<Vec<DVec3>>,
    flat: Vec<Vec<DVec2>>,
    lo: DVec3,
    hi: DVec3,
}

impl PlacedFace {
    fn new(normal: DVec3, offset: f64, loops: Vec<Vec<DVec3>>) -> PlacedFace {
        let u = normal.any_orthonormal_vector();
        let v = normal.cross(u);
        let flat = loops
            .iter()
            .map(|l| l.iter().map(|p| DVec2::new(p.dot(u), p.dot(v))).collect())
            .collect();
        let (lo, hi) = bounding_box(loops.iter().flatten().copied());
        PlacedFace {
            normal,
            offset,
            u,
            v,
            loops,
            flat,
            lo,
            hi,
        }
    }

    fn flatten(&self, p: DVec3) -> DVec2 {
        DVec2::new(p.dot(self.u), p.dot(self.v))
    }

    /// Whether the projection of `p` lies inside the face region (even-odd over every
    /// loop, so holes are outside).
    fn contains(&self, p: DVec3) -> bool {
        let q = self.flatten(p);
        let mut inside = false;
        for l in &self.flat {
            for i in 0..l.len() {
                let (a, b) = (l[i], l[(i + 1) % l.len()]);
                if (a.y > q.y) != (b.y > q.y) && q.x < a.x + (q.y - a.y) * (b.x - a.x) / (b.y - a.y) {
                    inside = !inside;
                }
            }
        }
        inside
    }

    /// Distance from the projection of `p` to the face's boundary.
    fn boundary_distance(&self, p: DVec3) -> f64 {
        let q = self.flatten(p);
        let mut best = f64::INFINITY;
        for l in &self.flat {
            for i in 0..l.len() {
                best = best.min(point_segment_2d(q, l[i], l[(i + 1) % l.len()]));
            }
        }
        best
    }

    /// Distance from `p` to the face's closed region.
    fn distance(&self, p: DVec3) -> f64 {
        let h = self.normal.dot(p) - self.offset;
        if self.contains(p) {
            h.abs()
        } else {
            h.hypot(self.boundary_distance(p))
        }
    }

    /// Whether the segment (p, q) passes through the face's region, its ends more than
    /// `tol` apart on either side of the plane.
    fn crossed_by(&self, p: DVec3, q: DVec3, tol: f64) -> bool {
        let (hp, hq) = (self.normal.dot(p) - self.offset, self.normal.dot(q) - self.offset);
        ((hp > tol && hq < -tol) || (hp < -tol && hq > tol)) && self.contains(p.lerp(q, hp / (hp - hq)))
    }

    /// Every boundary segment, in loop order (the face's interior on its left).
    fn segments(&self) -> impl Iterator<Item = (DVec3, DVec3)> + '_ {
        self.loops
            .iter()
            .flat_map(|l| (0..l.len()).map(move |i| (l[i], l[(i + 1) % l.len()])))
    }
}

fn bounding_box(points: impl Iterator<Item = DVec3>) -> (DVec3, DVec3) {
    points.fold(
        (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
        |(lo, hi), p| (lo.min(p), hi.max(p)),
    )
}

fn point_segment_2d(p: DVec2, a: DVec2, b: DVec2) -> f64 {
    let d = b - a;
    let t = if d.length_squared() > 0.0 {
        ((p - a).dot(d) / d.length_squared()).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (a + d * t).distance(p)
}

fn point_segment(p: DVec3, a: DVec3, b: DVec3) -> f64 {
    let d = b - a;
    let t = if d.length_squared() > 0.0 {
        ((p - a).dot(d) / d.length_squared()).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (a + d * t).distance(p)
}

/// Closest points of two closed segments (Ericson, Real-Time Collision Detection 5.1.9):
/// their parameters and distance.
fn segment_segment(p0: DVec3, p1: DVec3, q0: DVec3, q1: DVec3) -> (f64, f64, f64) {
    let (d1, d2, r) = (p1 - p0, q1 - q0, p0 - q0);
    let (a, e, f) = (d1.length_squared(), d2.length_squared(), d2.dot(r));
    let c = d1.dot(r);
    let b = d1.dot(d2);
    let denom = a * e - b * b;
    let mut s = if denom > 1e-300 {
        ((b * f - c * e) / denom).clamp(0.0, 1.0)
    } else {
        0.0
    };
    let mut t = (b * s + f) / e;
    if t < 0.0 {
        t = 0.0;
        s = (-c / a).clamp(0.0, 1.0);
    } else if t > 1.0 {
        t = 1.0;
        s = ((b - c) / a).clamp(0.0, 1.0);
    }
    let dist = (p0 + d1 * s).distance(q0 + d2 * t);
    (s, t, dist)
}

/// A tangent cone of a face at a point of its plane, as seen in some reference frame:
/// the directions (angles, counter-clockwise about the frame's normal) along which one
/// enters the face's interior.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Cone {
    Empty,
    Full,
    /// Start angle and sweep in (0, 2π].
    Arc(f64, f64),
}

/// Whether two cones share an open set of directions.
fn cones_overlap(a: Cone, b: Cone) -> bool {
    const EPS: f64 = 1e-9;
    match (a, b) {
        (Cone::Empty, _) | (_, Cone::Empty) => false,
        (Cone::Full, _) | (_, Cone::Full) => true,
        (Cone::Arc(s1, w1), Cone::Arc(s2, w2)) => {
            (s2 - s1).rem_euclid(TAU) < w1 - EPS || (s1 - s2).rem_euclid(TAU) < w2 - EPS
        }
    }
}

/// A placed part: positions in A's frame, faces, and element boxes.
struct Placed {
    vertices: Vec<DVec3>,
    faces: Vec<PlacedFace>,
}

impl Placed {
    fn new(part: &Part, place: impl Fn(DVec3) -> DVec3, turn: impl Fn(DVec3) -> DVec3) -> Placed {
        let vertices: Vec<DVec3> = part.vertices().iter().map(|v| place(v.position)).collect();
        let faces = part
            .faces()
            .iter()
            .map(|f| {
                let loops: Vec<Vec<DVec3>> = f
                    .loops
                    .iter()
                    .map(|l| l.vertices.iter().map(|v| vertices[v.index()]).collect())
                    .collect();
                let normal = turn(f.normal);
                // The plane through the placed outer loop, so that round-off of the
                // placement does not shift it.
                let offset = loops[0].iter().map(|p| normal.dot(*p)).sum::<f64>() / loops[0].len() as f64;
                PlacedFace::new(normal, offset, loops)
            })
            .collect();
        Placed { vertices, faces }
    }
}

/// The evaluator for one pair of parts.
pub struct Evaluator<'a> {
    moving_part: &'a Part,
    fixed_topology: Topology,
    moving_topology: Topology,
    fixed: Placed,
    /// L, the larger bounding-box diagonal.
    pub scale: f64,
    /// τ and δ in length units.
    pub touch: f64,
    pub robust: f64,
}

/// What scanning every pair at one pose finds.
#[derive(Default)]
struct Scan {
    touches: Vec<Touch>,
    problem: Option<String>,
    penetration: Option<String>,
}

impl Scan {
    fn non_robust(&mut self, what: impl FnOnce() -> String) {
        if self.problem.is_none() {
            self.problem = Some(what());
        }
    }
}

impl<'a> Evaluator<'a> {
    pub fn new(fixed: &'a Part, moving: &'a Part) -> Evaluator<'a> {
        Evaluator::with_touch(fixed, moving, TOUCH_REL)
    }

    /// An evaluator whose contacts hold within `touch_rel · L` (1e-9 to read poses
    /// found elsewhere, such as the generator's witnesses, as docs/concepts.md#tolerances
    /// does).
    pub fn with_touch(fixed: &'a Part, moving: &'a Part, touch_rel: f64) -> Evaluator<'a> {
        let scale = fixed.bounds().diagonal().max(moving.bounds().diagonal());
        Evaluator {
            moving_part: moving,
            fixed_topology: Topology::of(fixed),
            moving_topology: Topology::of(moving),
            fixed: Placed::new(fixed, |p| p, |n| n),
            scale,
            touch: touch_rel * scale,
            robust: ROBUST_REL * scale,
        }
    }

    /// P(X) at `pose` (assembled pose G = identity), or why the pose is not a clean one.
    pub fn evaluate(&self, pose: &Pose) -> Verdict {
        let moving = self.place(pose);
        let mut scan = Scan::default();
        self.scan_pairs(&moving, &mut scan);
        if let Some(why) = scan.penetration {
            return Verdict::Penetrating(why);
        }
        if let Some(why) = scan.problem {
            return Verdict::NonRobust(why);
        }
        let principal = self.principal(&scan.touches, &moving);
        if let Some(why) = self.point_contact_too_close_to_boundary(&principal, &moving) {
            return Verdict::NonRobust(why);
        }
        let mut state: Vec<PrincipalContact> = principal
            .iter()
            .map(|t| PrincipalContact {
                fixed: t.fixed,
                moving: t.moving,
                kind: kind_of(t),
            })
            .collect();
        state.sort();
        Verdict::State(state)
    }

    /// The moving part placed at `pose`: p ↦ R p + t.
    fn place(&self, pose: &Pose) -> Placed {
        let (r, t) = (pose.rotation(), pose.translation());
        Placed::new(self.moving_part, |p| r * p + t, |n| r * n)
    }

    /// How close two points that the principal rule compares must be to count as one:
    /// at a robust pose they coincide up to round-off (which grows where two edges cross
    /// at a small angle), or lie at least δ apart.
    fn locate(&self) -> f64 {
        0.5 * self.robust
    }

    /// Every touching pair at `pose` with its intersection, and the first robustness
    /// problem if any: for failure messages.
    pub fn explain(&self, pose: &Pose) -> String {
        let moving = self.place(pose);
        let mut scan = Scan::default();
        self.scan_pairs(&moving, &mut scan);
        let mut out: Vec<String> = scan
            .touches
            .iter()
            .map(|t| format!("{} {} {:?}", t.fixed, t.moving, t.meet))
            .collect();
        out.extend(scan.problem);
        out.extend(scan.penetration);
        out.join("\n")
    }

    /// Whether a contact is degenerate (docs/concepts.md#degenerate-contacts), from the
    /// parts' own convexity flags.
    pub fn degenerate(&self, c: &PrincipalContact) -> bool {
        use ContactKind::{EdgeEdgeTouch, EdgeVertex, VertexEdge, VertexVertex};
        matches!(c.kind, VertexVertex | EdgeVertex | VertexEdge | EdgeEdgeTouch)
            && self.fixed_topology.convex(c.fixed)
            && self.moving_topology.convex(c.moving)
    }

    /// Every element pair whose boxes come within δ, classified.
    fn scan_pairs(&self, moving: &Placed, scan: &mut Scan) {
        let margin = DVec3::splat(self.robust);
        let near = |(lo1, hi1): (DVec3, DVec3), (lo2, hi2): (DVec3, DVec3)| {
            (lo1 - margin).cmple(hi2).all() && (lo2 - margin).cmple(hi1).all()
        };
        let vbox = |p: DVec3| (p, p);
        let ebox = |p: DVec3, q: DVec3| (p.min(q), p.max(q));
        let (pa, pb) = (&self.fixed.vertices, &moving.vertices);
        let (ea, eb) = (&self.fixed_topology.edge_ends, &self.moving_topology.edge_ends);

        for (i, &p) in pa.iter().enumerate() {
            for (j, &q) in pb.iter().enumerate() {
                if near(vbox(p), vbox(q)) {
                    self.vertex_vertex(i, j, p, q, scan);
                }
            }
            for (j, e) in eb.iter().enumerate() {
                let (q0, q1) = (pb[e[0]], pb[e[1]]);
                if near(vbox(p), ebox(q0, q1)) {
                    self.vertex_edge(Side::FixedVertex, i, j, p, [q0, q1], scan);
                }
            }
            for (j, f) in moving.faces.iter().enumerate() {
                if near(vbox(p), (f.lo, f.hi)) {
                    self.vertex_face(Side::FixedVertex, i, j, p, f, scan);
                }
            }
        }
        for (i, e) in ea.iter().enumerate() {
            let (p0, p1) = (pa[e[0]], pa[e[1]]);
            for (j, &q) in pb.iter().enumerate() {
                if near(ebox(p0, p1), vbox(q)) {
                    self.vertex_edge(Side::MovingVertex, j, i, q, [p0, p1], scan);
                }
            }
            for (j, g) in eb.iter().enumerate() {
                let (q0, q1) = (pb[g[0]], pb[g[1]]);
                if near(ebox(p0, p1), ebox(q0, q1)) {
                    self.edge_edge(i, j, [p0, p1], [q0, q1], scan);
                }
            }
            for (j, f) in moving.faces.iter().enumerate() {
                if near(ebox(p0, p1), (f.lo, f.hi)) {
                    self.edge_face(Side::FixedVertex, i, j, [p0, p1], &moving.faces, scan);
                }
            }
        }
        for (i, f) in self.fixed.faces.iter().enumerate() {
            for (j, &q) in pb.iter().enumerate() {
                if near((f.lo, f.hi), vbox(q)) {
                    self.vertex_face(Side::MovingVertex, j, i, q, f, scan);
                }
            }
            for (j, g) in eb.iter().enumerate() {
                let (q0, q1) = (pb[g[0]], pb[g[1]]);
                if near((f.lo, f.hi), ebox(q0, q1)) {
                    self.edge_face(Side::MovingVertex, j, i, [q0, q1], &self.fixed.faces, scan);
                }
            }
            for (j, g) in moving.faces.iter().enumerate() {
                if near((f.lo, f.hi), (g.lo, g.hi)) {
                    self.face_face(i, j, f, g, scan);
                }
            }
        }
    }

    fn vertex_vertex(&self, i: usize, j: usize, p: DVec3, q: DVec3, scan: &mut Scan) {
        let d = p.distance(q);
        if d <= self.touch {
            scan.touches.push(Touch {
                fixed: vertex(i),
                moving: vertex(j),
                meet: Meet::Point((p + q) * 0.5),
            });
        } else if d < self.robust {
            scan.non_robust(|| format!("v{i} and v{j} are {d:e} apart"));
        }
    }

    /// A vertex of one part against an edge of the other; `side` says whose vertex.
    fn vertex_edge(&self, side: Side, vi: usize, ei: usize, p: DVec3, [q0, q1]: [DVec3; 2], scan: &mut Scan) {
        let d = point_segment(p, q0, q1);
        if d <= self.touch {
            // Near an end it is that end vertex's contact, not the edge's; in between,
            // checkers may read either.
            let end = p.distance(q0).min(p.distance(q1));
            if end > self.touch && end < self.robust {
                scan.non_robust(|| format!("{} v{vi} touches edge e{ei} {end:e} from its end", side.vertex_owner()));
            }
            if end > self.touch {
                let (v, e) = (vertex(vi), edge(ei));
                let (fixed, moving) = side.order(v, e);
                scan.touches.push(Touch {
                    fixed,
                    moving,
                    meet: Meet::Point(p),
                });
            }
        } else if d < self.robust {
            scan.non_robust(|| format!("{} v{vi} and edge e{ei} are {d:e} apart", side.vertex_owner()));
        }
    }

    fn edge_edge(&self, i: usize, j: usize, [p0, p1]: [DVec3; 2], [q0, q1]: [DVec3; 2], scan: &mut Scan) {
        let (s, t, d) = segment_segment(p0, p1, q0, q1);
        if d > self.touch {
            if d < self.robust {
                scan.non_robust(|| format!("edges e{i} and e{j} are {d:e} apart"));
            }
            return;
        }
        let tol = self.touch;
        let line_distance = |x: DVec3, a: DVec3, b: DVec3| (x - a).cross(b - a).length() / (b - a).length();
        let collinear = (line_distance(q0, p0, p1) <= tol && line_distance(q1, p0, p1) <= tol)
            || (line_distance(p0, q0, q1) <= tol && line_distance(p1, q0, q1) <= tol);
        let meet = if collinear {
            // Overlap of the open segments, measured along e_i.
            let dir = (p1 - p0).normalize();
            let len = (p1 - p0).length();
            let (a, b) = ((q0 - p0).dot(dir), (q1 - p0).dot(dir));
            let (lo, hi) = (a.min(b).max(0.0), a.max(b).min(len));
            if hi - lo <= tol {
                return;
            }
            Meet::Segments(vec![[p0 + dir * lo, p0 + dir * hi]])
        } else {
            let (x, y) = (p0 + (p1 - p0) * s, q0 + (q1 - q0) * t);
            let c = (x + y) * 0.5;
            let end = [p0, p1, q0, q1]
                .iter()
                .map(|e| e.distance(c))
                .fold(f64::INFINITY, f64::min);
            if end <= tol {
                return; // an end vertex touches: that vertex's contact
            }
            if end < self.robust {
                scan.non_robust(|| format!("edges e{i} and e{j} cross {end:e} from an end"));
            }
            // Edges so near parallel that an end of one lies within the robustness gap
            // of the other stay that close all the way from the crossing to that end: a
            // looser checker reads them touching along the stretch, up to the end's
            // own contact (a corner on a corner with the edges along each other).
            let end_near = [(p0, q0, q1), (p1, q0, q1), (q0, p0, p1), (q1, p0, p1)]
                .iter()
                .any(|&(x, a, b)| point_segment(x, a, b) < self.robust);
            if end_near {
                scan.non_robust(|| format!("edges e{i} and e{j} cross, an end within the robustness gap of the other"));
            }
            Meet::Point(c)
        };
        scan.touches.push(Touch {
            fixed: edge(i),
            moving: edge(j),
            meet,
        });
    }

    /// A vertex of one part against a face of the other.
    fn vertex_face(&self, side: Side, vi: usize, fi: usize, p: DVec3, f: &PlacedFace, scan: &mut Scan) {
        let inside = f.contains(p);
        let edge_distance = f.boundary_distance(p);
        if !inside && edge_distance > self.touch {
            return; // the closest point is on the boundary: a vertex-edge pair's business
        }
        let h = f.normal.dot(p) - f.offset;
        if h.abs() <= self.touch {
            if inside && edge_distance > self.touch && edge_distance < self.robust {
                scan.non_robust(|| {
                    format!(
                        "{} v{vi} touches face f{fi} {edge_distance:e} from its boundary",
                        side.vertex_owner()
                    )
                });
            }
            if inside && edge_distance > self.touch {
                let (fixed, moving) = side.order(vertex(vi), face(fi));
                scan.touches.push(Touch {
                    fixed,
                    moving,
                    meet: Meet::Point(p),
                });
            }
        } else if h.abs() < self.robust {
            scan.non_robust(|| format!("{} v{vi} is {h:e} off face f{fi}", side.vertex_owner()));
        }
    }

    /// An edge of one part against a face of the other, over the face's region: where
    /// both ends of a part of the edge over the open face lie within τ of the face's
    /// plane, that part lies in it (docs/concepts.md#tolerances: an edge with two points within
    /// 1e-9 L of a face's plane lies in it wherever it overlaps the face); a part that
    /// reaches the plane and gets more than τ behind it and inside the face's outline
    /// dips into the other part, unless it leaves that part through another face first
    /// (a thin wedge of it, behind the face's edge).
    fn edge_face(
        &self,
        side: Side,
        ei: usize,
        fi: usize,
        [p0, p1]: [DVec3; 2],
        owner_faces: &[PlacedFace],
        scan: &mut Scan,
    ) {
        let f = &owner_faces[fi];
        let tol = self.touch;
        let height = |p: DVec3| f.normal.dot(p) - f.offset;
        let (h0, h1) = (height(p0), height(p1));
        if (h0 > tol && h1 > tol) || (h0 < -tol && h1 < -tol) {
            return; // wholly in front of the plane, or wholly behind it
        }
        // How deep a point behind the face lies in the face's part: nothing if the way
        // back to the face passes through another of its faces, else the distance to
        // the nearest other face.
        let others = || {
            owner_faces
                .iter()
                .enumerate()
                .filter(|&(gi, _)| gi != fi)
                .map(|(_, g)| g)
        };
        let inside_depth = |x: DVec3| {
            let foot = x - f.normal * height(x);
            if others().any(|g| g.crossed_by(x, foot, tol)) {
                0.0
            } else {
                others().map(|g| g.distance(x)).fold(f64::INFINITY, f64::min)
            }
        };
        let mut lying: Vec<[DVec3; 2]> = Vec::new();
        for (s, e) in self.over_open_face(p0, p1, f) {
            let (a, b) = (p0.lerp(p1, s), p0.lerp(p1, e));
            let (ha, hb) = (height(a), height(b));
            if ha.abs() <= tol && hb.abs() <= tol {
                lying.push([a, b]);
            } else if ha.min(hb) < -tol && ha.max(hb) >= -tol {
                // How deep the edge gets behind the face and away from its boundary (at
                // the face's boundary the neighbouring face takes over): sampled.
                let depth = (0..=16)
                    .map(|k| a.lerp(b, f64::from(k) / 16.0))
                    .map(|x| (-height(x)).min(f.boundary_distance(x)).min(inside_depth(x)))
                    .fold(0.0, f64::max);
                if depth <= tol {
                    continue;
                }
                let owner = side.vertex_owner();
                if depth >= self.robust {
                    scan.penetration = Some(format!("{owner} e{ei} goes {depth:e} behind face f{fi}"));
                } else {
                    scan.non_robust(|| format!("{owner} e{ei} dips {depth:e} behind face f{fi}"));
                }
            }
        }
        if !lying.is_empty() {
            // Two points of the edge within τ of the plane but an end farther: the edge
            // is at a tiny angle to the face, and checkers may read it in the plane or not.
            let off = h0.abs().max(h1.abs());
            if off > tol {
                scan.non_robust(|| format!("{} e{ei} nearly lies in face f{fi} ({off:e} off)", side.vertex_owner()));
            }
            let (fixed, moving) = side.order(edge(ei), face(fi));
            scan.touches.push(Touch {
                fixed,
                moving,
                meet: Meet::Segments(lying),
            });
        }
    }

    /// The parameter intervals of the segment (p0, p1), projected on the face's plane,
    /// over the open face: cut where it crosses the face's boundary, kept where their
    /// middle lies more than τ inside the face.
    fn over_open_face(&self, p0: DVec3, p1: DVec3, f: &PlacedFace) -> Vec<(f64, f64)> {
        let (a, b) = (f.flatten(p0), f.flatten(p1));
        let d = b - a;
        let len = d.length();
        let tol = self.touch;
        if len <= tol {
            // Seen end-on: over the open face entirely or not at all.
            let over = f.contains(p0) && f.boundary_distance(p0) > tol;
            return if over { vec![(0.0, 1.0)] } else { Vec::new() };
        }
        let mut cuts = vec![0.0, 1.0];
        for l in &f.flat {
            for i in 0..l.len() {
                let (c0, c1) = (l[i], l[(i + 1) % l.len()]);
                let e = c1 - c0;
                let denom = d.perp_dot(e);
                if denom.abs() > 1e-12 * len * e.length() {
                    let t = (c0 - a).perp_dot(e) / denom;
                    let u = (c0 - a).perp_dot(d) / denom;
                    if (-1e-9..=1.0 + 1e-9).contains(&u) && t > 0.0 && t < 1.0 {
                        cuts.push(t);
                    }
                } else if (c0 - a).perp_dot(d).abs() <= tol * len {
                    // Collinear with a boundary segment: its ends cut the edge.
                    for c in [c0, c1] {
                        let t = (c - a).dot(d) / (len * len);
                        if t > 0.0 && t < 1.0 {
                            cuts.push(t);
                        }
                    }
                }
            }
        }
        cuts.sort_by(f64::total_cmp);
        cuts.windows(2)
            .filter(|w| (w[1] - w[0]) * len > tol)
            .filter(|w| {
                let mid = p0.lerp(p1, 0.5 * (w[0] + w[1]));
                f.contains(mid) && f.boundary_distance(mid) > tol
            })
            .map(|w| (w[0], w[1]))
            .collect()
    }

    /// Two faces: they touch when coplanar with opposite normals and their open regions
    /// overlap.
    fn face_face(&self, i: usize, j: usize, f: &PlacedFace, g: &PlacedFace, scan: &mut Scan) {
        let tol = self.touch;
        if f.normal.dot(g.normal) >= 0.0 {
            return;
        }
        let coplanar = g
            .loops
            .iter()
            .flatten()
            .all(|p| (f.normal.dot(*p) - f.offset).abs() <= tol)
            && f.loops
                .iter()
                .flatten()
                .all(|p| (g.normal.dot(*p) - g.offset).abs() <= tol);
        if coplanar && self.faces_overlap(f, g) {
            scan.touches.push(Touch {
                fixed: face(i),
                moving: face(j),
                meet: Meet::Overlap { fixed: i, moving: j },
            });
        }
    }

    /// Whether two coplanar faces' open regions overlap: either their boundaries cross
    /// properly, or at some corner of one lying in the closure of the other the two
    /// tangent cones share an open set of directions (every corner of a component of the
    /// overlap is one of these).
    fn faces_overlap(&self, f: &PlacedFace, g: &PlacedFace) -> bool {
        let tol = self.touch;
        for (a0, a1) in f.segments() {
            for (b0, b1) in g.segments() {
                let (s, t, d) = segment_segment(a0, a1, b0, b1);
                let c = a0 + (a1 - a0) * s;
                let crossing = d <= tol
                    && s > 0.0
                    && s < 1.0
                    && t > 0.0
                    && t < 1.0
                    && (a1 - a0).normalize().cross((b1 - b0).normalize()).length() > 1e-9
                    && [a0, a1, b0, b1].iter().all(|e| e.distance(c) > tol);
                if crossing {
                    return true;
                }
            }
        }
        let corner_in_other = |x: &PlacedFace, y: &PlacedFace| {
            x.loops
                .iter()
                .flatten()
                .any(|&p| cones_overlap(self.cone(f, x, p), self.cone(f, y, p)))
        };
        corner_in_other(g, f) || corner_in_other(f, g)
    }

    /// The tangent cone of `face` at `p` (a point of its plane), in the frame of `frame`.
    fn cone(&self, frame: &PlacedFace, face: &PlacedFace, p: DVec3) -> Cone {
        // At a robust pose a point of the plane is on a vertex or an edge of the face
        // (up to round-off, which grows where edges cross at a small angle) or at least
        // δ from them.
        let tol = self.locate();
        let angle = |w: DVec3| w.dot(frame.v).atan2(w.dot(frame.u));
        let same_side = face.normal.dot(frame.normal) > 0.0;
        // Directions from `from` counter-clockwise about the face's own normal to `to`.
        let arc = |from: DVec3, to: DVec3| {
            let (s, e) = if same_side {
                (angle(from), angle(to))
            } else {
                (angle(to), angle(from))
            };
            let sweep = (e - s).rem_euclid(TAU);
            Cone::Arc(s, if sweep == 0.0 { TAU } else { sweep })
        };
        for l in &face.loops {
            let n = l.len();
            for k in 0..n {
                if l[k].distance(p) <= tol {
                    // Interior on the left of the loop: from the outgoing side round to
                    // the incoming one.
                    return arc(l[(k + 1) % n] - l[k], l[(k + n - 1) % n] - l[k]);
                }
            }
        }
        for (a, b) in face.segments() {
            if point_segment(p, a, b) <= tol {
                return arc(b - a, a - b);
            }
        }
        if face.contains(p) { Cone::Full } else { Cone::Empty }
    }

    /// The touching pairs that no other touching pair implies
    /// (docs/concepts.md#principal-contacts).
    fn principal(&self, touches: &[Touch], moving: &Placed) -> Vec<Touch> {
        touches
            .iter()
            .enumerate()
            .filter(|&(i, t)| {
                !touches.iter().enumerate().any(|(k, u)| {
                    k != i
                        && self.fixed_topology.in_closure(t.fixed, u.fixed)
                        && self.moving_topology.in_closure(t.moving, u.moving)
                        && self.meet_contains(&u.meet, &t.meet, moving)
                })
            })
            .map(|(_, t)| t.clone())
            .collect()
    }

    /// Whether the closure of `outer` contains `inner` (checked at the inner set's ends,
    /// middles and quarter points; an overlap is never inside anything smaller).
    fn meet_contains(&self, outer: &Meet, inner: &Meet, moving: &Placed) -> bool {
        let points: Vec<DVec3> = match inner {
            Meet::Point(p) => vec![*p],
            Meet::Segments(segments) => segments
                .iter()
                .flat_map(|[a, b]| [0.0, 0.25, 0.5, 0.75, 1.0].map(|t| a.lerp(*b, t)))
                .collect(),
            Meet::Overlap { .. } => return false,
        };
        let tol = self.locate();
        points.iter().all(|&q| match outer {
            Meet::Point(p) => p.distance(q) <= tol,
            Meet::Segments(segments) => segments.iter().any(|[a, b]| point_segment(q, *a, *b) <= tol),
            Meet::Overlap { fixed, moving: m } => {
                let (f, g) = (&self.fixed.faces[*fixed], &moving.faces[*m]);
                cones_overlap(self.cone(f, f, q), self.cone(f, g, q))
            }
        })
    }

    /// A listed point contact must lie at least δ inside both its elements' relative
    /// interiors (docs/concepts.md#tolerances).
    fn point_contact_too_close_to_boundary(&self, principal: &[Touch], moving: &Placed) -> Option<String> {
        for t in principal {
            let Meet::Point(p) = t.meet else { continue };
            for (element, placed, topology) in [
                (t.fixed, &self.fixed, &self.fixed_topology),
                (t.moving, moving, &self.moving_topology),
            ] {
                let margin = match element {
                    ElementId::Vertex(_) => f64::INFINITY,
                    ElementId::Edge(e) => {
                        let [a, b] = topology.edge_ends[e.index()];
                        p.distance(placed.vertices[a]).min(p.distance(placed.vertices[b]))
                    }
                    ElementId::Face(f) => placed.faces[f.index()].boundary_distance(p),
                };
                if margin < self.robust {
                    return Some(format!(
                        "contact {}-{} at {p} lies {margin:e} from the boundary of {element}",
                        t.fixed, t.moving
                    ));
                }
            }
        }
        None
    }
}

/// Whose vertex (or edge) comes first in a mixed pair.
#[derive(Clone, Copy)]
enum Side {
    /// The lower-dimensional element is the fixed part's.
    FixedVertex,
    /// It is the moving part's.
    MovingVertex,
}

impl Side {
    /// (fixed, moving) from (the lower-dimensional element, the other one).
    fn order(self, low: ElementId, high: ElementId) -> (ElementId, ElementId) {
        match self {
            Side::FixedVertex => (low, high),
            Side::MovingVertex => (high, low),
        }
    }

    fn vertex_owner(self) -> &'static str {
        match self {
            Side::FixedVertex => "fixed",
            Side::MovingVertex => "moving",
        }
    }
}

fn vertex(i: usize) -> ElementId {
    ElementId::Vertex(VertexId(i as u32))
}

fn edge(i: usize) -> ElementId {
    ElementId::Edge(EdgeId(i as u32))
}

fn face(i: usize) -> ElementId {
    ElementId::Face(FaceId(i as u32))
}

fn kind_of(t: &Touch) -> ContactKind {
    use ElementId::{Edge, Face, Vertex};
    match (t.fixed, t.moving) {
        (Face(_), Face(_)) => ContactKind::FaceFace,
        (Face(_), Edge(_)) => ContactKind::FaceEdge,
        (Edge(_), Face(_)) => ContactKind::EdgeFace,
        (Face(_), Vertex(_)) => ContactKind::FaceVertex,
        (Vertex(_), Face(_)) => ContactKind::VertexFace,
        (Edge(_), Edge(_)) if matches!(t.meet, Meet::Segments(_)) => ContactKind::EdgeEdgeTouch,
        (Edge(_), Edge(_)) => ContactKind::EdgeEdge,
        (Edge(_), Vertex(_)) => ContactKind::EdgeVertex,
        (Vertex(_), Edge(_)) => ContactKind::VertexEdge,
        (Vertex(_), Vertex(_)) => ContactKind::VertexVertex,
    }
}

/// A contact as `f-v f3 v2` (kind, A's element, B's element).
pub fn describe(c: &PrincipalContact) -> String {
    format!("{} {} {}", c.kind.label(), c.fixed, c.moving)
}

/// A state as `{f-v f3 v2, e-e e1 e5}`.
pub fn describe_state(state: &[PrincipalContact]) -> String {
    let parts: Vec<String> = state.iter().map(describe).collect();
    format!("{{{}}}", parts.join(", "))
}
