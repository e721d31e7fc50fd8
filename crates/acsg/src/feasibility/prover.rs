//! A conservative infeasibility prover: interval constraint propagation over boxes of
//! poses (branch and prune).
//!
//! In the frame of G (where `p = R p_B + t`), every contact of a state gives
//! constraints that are linear in the translation `t` once the rotation's range is
//! enclosed by intervals: a point of one part on a plane of the other, two crossing
//! edges in one plane, the contact point inside both elements' boxes. Non-penetration
//! gives more: no vertex of one part strictly inside a convex piece of the other. Each
//! constraint narrows the translation box; an empty box proves that no pose in it
//! realises the state. Points of edges that pass through a piece of the other part (at
//! the box's centre) are kept out like vertices: two pieces can cross with no vertex of
//! either inside the other. In boxes of small rotations a second-order test follows
//! ([`linearised`]): every condition becomes linear in the translation and the turn, up
//! to a remainder quadratic in the box, and linear programming, by cases over the
//! either-or conditions, proves what no single condition shows. Boxes that survive are
//! split (rotations first, they are what the intervals overestimate) up to a budget.
//! Every step is an enclosure, so a target is only ever excluded when no pose in the
//! bounds can show it.

use std::borrow::Cow;

use glam::{DAffine3, DVec3};

mod along;
mod linearised;

pub(crate) use linearised::TurnedRows;

use super::interval::{Interval, IntervalMat, rotation_enclosure};
use crate::contact::{ContactKind, PrincipalContact};
use crate::geometry::newell;
use crate::model::{EdgeId, ElementId, FaceId, Part, VertexId};
use crate::pose::Bounds;
use crate::tolerance::{CONTACT_REL, SEPARATION_REL, scaled};

type IVec = [Interval; 3];

/// One linear constraint `coeffs · t ∈ range` on the translation.
#[derive(Clone, Copy, Debug)]
struct Linear {
    coeffs: IVec,
    range: Interval,
}

/// A contact's constraint on poses, before the rotation is enclosed.
#[derive(Clone, Copy, Debug)]
enum Link {
    /// A point `w` of the moving part on a plane `n · p = d` of the fixed part.
    MovingPointOnFixedPlane { w: DVec3, n: DVec3, d: f64 },
    /// A point `a` of the fixed part on a plane `m · q = e` of the moving part.
    FixedPointOnMovingPlane { a: DVec3, m: DVec3, e: f64 },
    /// Crossing edges `a0 + s da` and `b0 + u db` meet: `(da × R db) · (a0 − R b0 − t) = 0`.
    Crossing { a0: DVec3, da: DVec3, b0: DVec3, db: DVec3 },
    /// The contact point lies in both elements' boxes: `t ∈ box_A − R box_B`.
    Region { a: (DVec3, DVec3), b: (DVec3, DVec3) },
}

/// The constraints of one target, prepared once for many boxes.
pub(crate) struct Links {
    links: Vec<Link>,
    apart: Vec<Apart>,
    /// The rim pieces ([`Apart`]'s `held_rim`) that a contact may hold a vertex at.
    held_rims: Vec<Vec<[DVec3; 2]>>,
    straddles: Vec<Straddle>,
    /// The contacts of a vertex on a face, along a segment or over an area (f-v, v-f,
    /// f-f, f-e, e-f), by their elements: the two elements must share a point.
    overlaps: Vec<Overlap>,
    /// Crossings whose edge may lie along a face at the other edge: a checker then
    /// reads that edge on the face (a pair a witness keeps apart).
    along: Vec<along::AlongFace>,
    /// Whether the second-order test also asks the elements' boxes of the contacts
    /// along a segment or over an area to meet ([`Prover::last_links`]).
    meet_regions: bool,
}

/// A contact of a vertex on a face, along a segment or over an area: some point lies
/// in both elements, so the convex hulls of some convex part of each meet.
#[derive(Clone, Copy, Debug)]
struct Overlap {
    fixed: ElementId,
    moving: ElementId,
    /// How far the loose reading asks the two to overlap ([`Prover::may_overlap`]).
    thin: Thin,
}

/// How far inside a side of a face's convex part the other element's corners must all
/// reach for the two to share a point there that the loose reading keeps.
#[derive(Clone, Copy, Debug)]
enum Thin {
    /// A face on a face: this far inside every side.
    Overlap(f64),
    /// A vertex or an edge on a face: this far (times the side's `side_sine`) inside a
    /// side on the face's rim; beyond a diagonal of its cover by at most the slack.
    Rim(f64),
}

impl Links {
    /// The same constraints without the pairs a witness keeps apart: what holds
    /// wherever the target's contacts hold, other pairs touching or not.
    pub fn without_apart(mut self) -> Links {
        self.apart.clear();
        self.along.clear();
        self
    }
}

/// A segment of one part that crosses a plane of the other through the contact: an
/// edge crossing another edge meets every plane through the other's line at the
/// crossing point, so its ends lie on both sides of each such plane (or on it). The
/// crossing row alone says only that the two lines meet somewhere, which near-parallel
/// edges nearly always do.
#[derive(Clone, Copy, Debug)]
struct Straddle {
    /// Whether the segment is the moving part's (in its frame; the plane the fixed
    /// part's, in G's frame), or the other way round.
    moving: bool,
    ends: [DVec3; 2],
    plane: (DVec3, f64),
}

/// A face and a vertex of the other part that a witness of the target keeps apart:
/// they are neither a listed contact nor parts of one, so when the vertex lies over the
/// face it is at least the separation off the face's plane, on either side (closer is
/// a pair closer than a witness allows, touching is another contact).
///
/// `held_rim`: the pieces of the face's rim (edges, corners as points, in
/// [`Links::held_rims`]) in the closure of an element on which a contact of the target
/// holds the vertex (a neighbouring face, a rim edge or corner). Near such a piece a
/// checker reads the vertex as touching that edge or corner, a touch the contact may
/// hold (the principal rule); anywhere else within the separation of the face, it
/// reads a touch no contact holds.
#[derive(Clone, Copy, Debug)]
enum Apart {
    /// A face of the fixed part and a vertex of the moving part.
    FixedFace {
        face: usize,
        vertex: usize,
        held_rim: Option<usize>,
    },
    /// A face of the moving part and a vertex of the fixed part.
    MovingFace {
        face: usize,
        vertex: usize,
        held_rim: Option<usize>,
    },
}

/// Points of edges inside a piece of the other part.
struct Through {
    moving: Vec<EdgePoint>,
    fixed: Vec<EdgePoint>,
}

/// A point of an edge (in its part's frame) inside a piece of the other part.
#[derive(Clone, Copy, Debug)]
struct EdgePoint {
    edge: usize,
    point: DVec3,
    piece: usize,
}

/// What a box's rotations make of the parts, once per box (intervals over the box).
struct Turned {
    /// The rotation's enclosure.
    r: IntervalMat,
    /// The contacts' constraints on the translation.
    constraints: Vec<Linear>,
    /// `R w` for every vertex of the moving part.
    moved: Vec<IVec>,
    /// `R m` for every face normal of the moving part.
    normals: Vec<IVec>,
    /// The moving part's pieces' planes, turned.
    pieces: Vec<Vec<(IVec, f64)>>,
    /// The moving part's piece boxes, turned.
    boxes: Vec<(DVec3, DVec3)>,
}

/// The points that non-penetration keeps out of pieces in one box: the moving part's
/// turned (`R w`) and the fixed part's, each with the other part's piece.
struct PairsInReach {
    moving: Vec<(IVec, usize)>,
    fixed: Vec<(DVec3, usize)>,
}

/// One part's geometry as the prover uses it (the fixed part in G's frame).
struct Shape {
    vertices: Vec<DVec3>,
    /// Per edge: its end points' indices.
    edges: Vec<[usize; 2]>,
    /// Per face: outward normal and offset.
    planes: Vec<(DVec3, f64)>,
    /// Per convex piece: its bounding planes.
    pieces: Vec<Vec<(DVec3, f64)>>,
    /// Per convex piece: its bounding box (a point outside it is outside the piece).
    piece_boxes: Vec<(DVec3, DVec3)>,
    /// Per face: convex polygons covering it, for "lies over the face": the face's
    /// outline when it is convex, else its triangles.
    convex_parts: Vec<Vec<ConvexPart>>,
    /// Per face: its bounding box.
    face_boxes: Vec<(DVec3, DVec3)>,
}

impl Shape {
    fn new(part: &Part, frame: &DAffine3) -> Shape {
        let face_boxes = part
            .faces()
            .iter()
            .map(|f| {
                bounds_of(
                    f.outer()
                        .vertices
                        .iter()
                        .map(|&v| frame.transform_point3(part.vertex(v).position)),
                )
            })
            .collect();
        let plane = |n: DVec3, d: f64| {
            let n2 = frame.transform_vector3(n).normalize();
            (n2, n2.dot(frame.transform_point3(n * d)))
        };
        Shape {
            vertices: part
                .vertices()
                .iter()
                .map(|v| frame.transform_point3(v.position))
                .collect(),
            edges: part.edges().iter().map(|e| e.vertices.map(|v| v.index())).collect(),
            planes: part.faces().iter().map(|f| plane(f.normal, f.offset)).collect(),
            pieces: part
                .convex_pieces()
                .iter()
                .map(|piece| piece.faces().iter().map(|f| plane(f.normal, f.offset)).collect())
                .collect(),
            piece_boxes: part
                .convex_pieces()
                .iter()
                .map(|piece| bounds_of(piece.vertices().iter().map(|&v| frame.transform_point3(v))))
                .collect(),
            convex_parts: part
                .faces()
                .iter()
                .enumerate()
                .map(|(id, f)| {
                    let at = |v: VertexId| frame.transform_point3(part.vertex(v).position);
                    if f.holes().is_empty() && !part.face_outline_is_nonconvex(FaceId(id as u32)) {
                        let outline = &f.outer().vertices;
                        vec![ConvexPart::new(
                            outline.iter().map(|&v| at(v)).collect(),
                            vec![false; outline.len()],
                        )]
                    } else {
                        triangle_cover(&f.triangles, at)
                    }
                })
                .collect(),
            face_boxes,
        }
    }
}

/// A convex polygon of a face's cover.
pub(super) struct ConvexPart {
    corners: Vec<DVec3>,
    /// Per side (from corner `k` to `k + 1`): whether it lies inside the face (a
    /// diagonal another triangle of the cover shares), not on its rim.
    inner: Vec<bool>,
    /// `sin(α/2)` for its sharpest corner angle α: a point at distance `D` from the
    /// polygon, in its plane, lies at least `D · sin(α/2)` outside one of its sides.
    sharpest: f64,
    /// Its Newell normal (the corners' turning sense), kept: the tests of a box ask
    /// for it every time.
    normal: DVec3,
    /// Per side, the lesser `min(1, sin α)` of the corner angles α at its two ends: a
    /// point of the part within `d` of the side's line lies within `d / side_sine` of
    /// the side.
    side_sine: Vec<f64>,
}

impl ConvexPart {
    fn new(corners: Vec<DVec3>, inner: Vec<bool>) -> ConvexPart {
        let k = corners.len();
        let angles: Vec<f64> = (0..k)
            .map(|i| {
                let (prev, at, next) = (corners[(i + k - 1) % k], corners[i], corners[(i + 1) % k]);
                (prev - at).angle_between(next - at)
            })
            .collect();
        let finite = |x: f64| if x.is_finite() { x.clamp(0.0, 1.0) } else { 0.0 };
        let sharpest = finite(angles.iter().map(|&a| (0.5 * a).sin()).fold(1.0, f64::min));
        let side_sine = (0..k)
            .map(|i| finite(angles[i].sin().min(angles[(i + 1) % k].sin())))
            .collect();
        ConvexPart {
            normal: newell(corners.iter().copied()),
            corners,
            inner,
            sharpest,
            side_sine,
        }
    }

    /// `1` when the corners turn counter-clockwise about `n`, else `-1`.
    fn sense(&self, n: DVec3) -> f64 {
        self.normal.dot(n).signum()
    }
}

/// A face's cover by its triangles, each side marked inner when another triangle
/// runs it the other way.
fn triangle_cover(triangles: &[[VertexId; 3]], at: impl Fn(VertexId) -> DVec3) -> Vec<ConvexPart> {
    let shared = |a: VertexId, b: VertexId| {
        triangles
            .iter()
            .any(|t| (0..3).any(|k| t[k] == b && t[(k + 1) % 3] == a))
    };
    triangles
        .iter()
        .map(|t| {
            let inner = (0..3).map(|k| shared(t[k], t[(k + 1) % 3])).collect();
            ConvexPart::new(t.map(&at).to_vec(), inner)
        })
        .collect()
}

/// The elements of the other part on which the target's contacts hold `vertex` (an
/// element of `part`); `sides` gives a contact's (this part's, the other part's)
/// elements.
fn holders_of(
    target: &[PrincipalContact],
    vertex: ElementId,
    sides: impl Fn(&PrincipalContact) -> (ElementId, ElementId),
    part: &Part,
) -> Vec<ElementId> {
    target
        .iter()
        .map(sides)
        .filter(|&(on, _)| part.in_closure(on, vertex))
        .map(|(_, holder)| holder)
        .collect()
}

/// The pieces of a face's rim in the closure of one of `holders` (elements of the
/// face's part), as segments of `shape` (a corner as a segment of length zero), pushed
/// onto `rims`; their index there, `None` when there are none.
fn held_rim(
    part: &Part,
    shape: &Shape,
    holders: &[ElementId],
    face: FaceId,
    rims: &mut Vec<Vec<[DVec3; 2]>>,
) -> Option<usize> {
    if holders.is_empty() {
        return None;
    }
    let held = |x: ElementId| holders.iter().any(|&h| part.in_closure(h, x));
    let face = ElementId::Face(face);
    let edges = part
        .closure_edges(face)
        .into_iter()
        .filter(|&e| held(ElementId::Edge(e)))
        .map(|e| part.edge(e).vertices.map(|v| shape.vertices[v.index()]));
    let corners = part
        .closure_vertices(face)
        .into_iter()
        .filter(|&v| held(ElementId::Vertex(v)))
        .map(|v| [shape.vertices[v.index()]; 2]);
    let pieces: Vec<[DVec3; 2]> = edges.chain(corners).collect();
    if pieces.is_empty() {
        return None;
    }
    rims.push(pieces);
    Some(rims.len() - 1)
}

/// Whether every point of a box is farther than `distance` from every segment.
pub(super) fn clear_of(segments: &[[DVec3; 2]], p: &IVec, distance: f64) -> bool {
    segments.iter().all(|[a, b]| {
        let (lo, hi) = (a.min(*b), a.max(*b));
        let gap: f64 = (0..3)
            .map(|k| (lo[k] - p[k].hi).max(p[k].lo - hi[k]).max(0.0).powi(2))
            .sum();
        gap > distance * distance
    })
}

/// The prover for one pair of parts, bounds and assembled pose.
pub(crate) struct Prover<'a> {
    fixed: &'a Part,
    moving: &'a Part,
    /// The fixed part in G's frame.
    a: Shape,
    b: Shape,
    /// G⁻¹, which maps the fixed part's frame to G's.
    to_g: DAffine3,
    /// Tolerance on every constraint (a small multiple of the contact tolerance).
    slack: f64,
    /// The farthest vertex from the origin (in its frame): how far a unit turn moves a
    /// point, to weigh rotations against translations when splitting boxes.
    reach: f64,
    /// How far inside its elements a point contact must be: a witness is clean only if
    /// every pair that does not touch is at least the separation tolerance apart, so the
    /// point keeps that far from the elements' boundaries (half of it, to be safe).
    margin: f64,
    /// The loose reading's tolerance ([`super::LOOSE_CONTACT_REL`]).
    loose: f64,
    /// The widest box of tilts (sum of the `rx` and `ry` half-widths, whatever the yaw)
    /// the second-order test is tried in: wider boxes cost more programmes and are
    /// more often split than proved.
    max_turn: f64,
}

impl<'a> Prover<'a> {
    pub fn new(fixed: &'a Part, moving: &'a Part, assembled: &DAffine3, scale: f64) -> Prover<'a> {
        let to_g = assembled.inverse();
        let (a, b) = (Shape::new(fixed, &to_g), Shape::new(moving, &DAffine3::IDENTITY));
        let reach = a
            .vertices
            .iter()
            .chain(&b.vertices)
            .map(|p| p.length())
            .fold(1.0, f64::max);
        Prover {
            fixed,
            moving,
            a,
            b,
            reach,
            to_g,
            slack: scaled(10.0 * CONTACT_REL, scale),
            margin: scaled(0.5 * SEPARATION_REL, scale),
            loose: scaled(super::LOOSE_CONTACT_REL, scale),
            max_turn: linearised::TURN_PER_EFFORT,
        }
    }

    /// The box of an element's closure (the fixed part's in G's frame), shrunk by
    /// `inset` (the distance the contact point keeps off the element's boundary);
    /// `None` when nothing is left.
    fn element_box(&self, fixed: bool, e: ElementId, inset: f64) -> Option<(DVec3, DVec3)> {
        let (part, shape) = if fixed {
            (self.fixed, &self.a)
        } else {
            (self.moving, &self.b)
        };
        let (lo, hi) = bounds_of(part.closure_vertices(e).iter().map(|v| shape.vertices[v.index()]));
        // A disc (face) or segment (edge) of radius `inset` around the point stays in
        // the element, so in each axis the point keeps `inset · |extent of a unit step|`.
        let shrink = match e {
            ElementId::Face(f) => {
                let n = shape.planes[f.index()].0;
                (DVec3::ONE - n * n).max(DVec3::ZERO).to_array().map(f64::sqrt).into()
            }
            ElementId::Edge(x) => {
                let [a, b] = part.edge(x).vertices.map(|v| shape.vertices[v.index()]);
                (b - a).normalize().abs()
            }
            ElementId::Vertex(_) => DVec3::ZERO,
        } * inset;
        let (lo, hi) = (lo + shrink, hi - shrink);
        lo.cmple(hi).all().then_some((lo, hi))
    }

    /// Scales the second-order test's reach with the search effort (see
    /// [`super::Problem::set_effort`]).
    pub fn set_effort(&mut self, effort: u32) {
        self.max_turn = (linearised::TURN_PER_EFFORT * f64::from(effort.max(1))).min(linearised::MAX_TURN);
    }

    /// The constraints of a state's contacts; `None` when they are already
    /// contradictory without looking at poses.
    pub fn links(&self, target: &[PrincipalContact]) -> Option<Links> {
        self.links_with(target, false)
    }

    /// [`Prover::links`] for the last proofs: a face and a corner of the other part
    /// are kept apart unless a contact holds both ([`held_together`], not
    /// [`implied`]), and the second-order test also asks the boxes of the contacts
    /// along a segment or over an area to meet. A decision tries them briefly after its
    /// starts; once the searches and sweeps are done, the last proofs try them at
    /// length on what is still undecided. Used throughout the decisions, they once left
    /// the sweeps no box to read, and two states of the chamfered hole turned about y
    /// and z were lost; tried briefly, they lose none on the nine fixture pairs.
    pub fn last_links(&self, target: &[PrincipalContact]) -> Option<Links> {
        self.links_with(target, true)
    }

    fn links_with(&self, target: &[PrincipalContact], last: bool) -> Option<Links> {
        let links = self.link_list(target)?;
        let implied = |a: ElementId, b: ElementId| {
            if last {
                held_together(self.fixed, self.moving, target, a, b)
            } else {
                implied(self.fixed, self.moving, target, a, b)
            }
        };
        let mut held_rims = Vec::new();
        let mut apart = Vec::new();
        for vertex in 0..self.moving.vertices().len() {
            let b = ElementId::Vertex(VertexId(vertex as u32));
            let holders = holders_of(target, b, |pc| (pc.moving, pc.fixed), self.moving);
            for face in 0..self.fixed.faces().len() {
                let a = ElementId::Face(FaceId(face as u32));
                if !implied(a, b) {
                    let held_rim = held_rim(self.fixed, &self.a, &holders, FaceId(face as u32), &mut held_rims);
                    apart.push(Apart::FixedFace { face, vertex, held_rim });
                }
            }
        }
        for vertex in 0..self.fixed.vertices().len() {
            let a = ElementId::Vertex(VertexId(vertex as u32));
            let holders = holders_of(target, a, |pc| (pc.fixed, pc.moving), self.fixed);
            for face in 0..self.moving.faces().len() {
                let b = ElementId::Face(FaceId(face as u32));
                if !implied(a, b) {
                    let held_rim = held_rim(self.moving, &self.b, &holders, FaceId(face as u32), &mut held_rims);
                    apart.push(Apart::MovingFace { face, vertex, held_rim });
                }
            }
        }
        let overlaps = target
            .iter()
            .filter(|pc| {
                matches!(
                    pc.kind,
                    ContactKind::FaceFace
                        | ContactKind::FaceEdge
                        | ContactKind::EdgeFace
                        | ContactKind::FaceVertex
                        | ContactKind::VertexFace
                )
            })
            .map(|pc| Overlap {
                fixed: pc.fixed,
                moving: pc.moving,
                thin: match pc.kind {
                    ContactKind::FaceFace => Thin::Overlap(0.25 * self.loose),
                    _ => Thin::Rim(0.5 * self.loose),
                },
            })
            .collect();
        Some(Links {
            links,
            apart,
            held_rims,
            overlaps,
            straddles: self.straddles(target),
            along: self.along_faces(target),
            meet_regions: last,
        })
    }

    /// The [`Straddle`]s of a state's contacts along edges: for an edge–edge contact,
    /// each edge's ends across two perpendicular planes through the other edge's line;
    /// for a vertex on an edge, the edge's ends across the three planes through the
    /// vertex normal to the vertex's part's axes.
    fn straddles(&self, target: &[PrincipalContact]) -> Vec<Straddle> {
        let mut out = Vec::new();
        let ends = |fixed: bool, x: EdgeId| {
            let (part, shape) = if fixed {
                (self.fixed, &self.a)
            } else {
                (self.moving, &self.b)
            };
            part.edge(x).vertices.map(|v| shape.vertices[v.index()])
        };
        let mut across = |moving: bool, ends: [DVec3; 2], at: DVec3, normals: &[DVec3]| {
            for &n in normals {
                out.push(Straddle {
                    moving,
                    ends,
                    plane: (n, n.dot(at)),
                });
            }
        };
        for pc in target {
            match (pc.kind, pc.fixed, pc.moving) {
                (ContactKind::EdgeEdge, ElementId::Edge(x), ElementId::Edge(y)) => {
                    let (a, b) = (ends(true, x), ends(false, y));
                    for (moving, line, ends) in [(true, a, b), (false, b, a)] {
                        let (u, v) = (line[1] - line[0]).normalize().any_orthonormal_pair();
                        across(moving, ends, line[0], &[u, v]);
                    }
                }
                (ContactKind::EdgeVertex, ElementId::Edge(x), ElementId::Vertex(v)) => {
                    across(false, ends(true, x), self.b.vertices[v.index()], &DVec3::AXES);
                }
                (ContactKind::VertexEdge, ElementId::Vertex(v), ElementId::Edge(y)) => {
                    across(true, ends(false, y), self.a.vertices[v.index()], &DVec3::AXES);
                }
                _ => {}
            }
        }
        out
    }

    fn link_list(&self, target: &[PrincipalContact]) -> Option<Vec<Link>> {
        let mut out = Vec::new();
        for pc in target {
            let (ea, eb) = (pc.fixed, pc.moving);
            // A point contact keeps the whole separation inside its elements (a vertex
            // in a face or on an edge, a crossing off both edges' ends): a checker reads
            // a point nearer the boundary as the boundary's contact, and
            // docs/concepts.md#tolerances asks a robust witness to keep that far in.
            // Contacts along a segment or over an area keep half of it: their region
            // must be wider than the separation, or some checker reads the neighbouring
            // contact.
            let m = self.margin;
            let (inset_a, inset_b) = match pc.kind {
                ContactKind::FaceVertex | ContactKind::EdgeVertex => (2.0 * m, 0.0),
                ContactKind::VertexFace | ContactKind::VertexEdge => (0.0, 2.0 * m),
                ContactKind::VertexVertex => (0.0, 0.0),
                ContactKind::EdgeEdge => (2.0 * m, 2.0 * m),
                _ => (m, m),
            };
            out.push(Link::Region {
                a: self.element_box(true, ea, inset_a)?,
                b: self.element_box(false, eb, inset_b)?,
            });
            if pc.kind == ContactKind::EdgeEdge {
                if let (ElementId::Edge(x), ElementId::Edge(y)) = (ea, eb) {
                    let [a0, a1] = self.fixed.edge(x).vertices.map(|v| self.a.vertices[v.index()]);
                    let [b0, b1] = self.moving.edge(y).vertices.map(|v| self.b.vertices[v.index()]);
                    out.push(Link::Crossing {
                        a0,
                        da: (a1 - a0).normalize(),
                        b0,
                        db: (b1 - b0).normalize(),
                    });
                }
                continue;
            }
            // The element of lower dimension lies on every plane through the other.
            let (da, db) = (ea.dimension(), eb.dimension());
            if da >= db {
                for f in planes_through(self.fixed, ea) {
                    let (n, d) = self.a.planes[f];
                    for v in self.moving.closure_vertices(eb) {
                        out.push(Link::MovingPointOnFixedPlane {
                            w: self.b.vertices[v.index()],
                            n,
                            d,
                        });
                    }
                }
            }
            if db >= da {
                for f in planes_through(self.moving, eb) {
                    let (m, e) = self.b.planes[f];
                    for v in self.fixed.closure_vertices(ea) {
                        out.push(Link::FixedPointOnMovingPlane {
                            a: self.a.vertices[v.index()],
                            m,
                            e,
                        });
                    }
                }
            }
        }
        self.tighten_points(&mut out)?;
        Some(out)
    }

    /// Where one vertex is the contact point of several constraints (on planes, in
    /// boxes), they bound the same point: intersect them without the pose, which the
    /// per-box contraction cannot do (it encloses `R w` anew in each).
    fn tighten_points(&self, links: &mut [Link]) -> Option<()> {
        self.tighten_side(links, true)?;
        self.tighten_side(links, false)
    }

    /// [`Prover::tighten_points`] for the moving part's vertices (`p = R w + t`, in G's
    /// frame) or the fixed part's (`q = Rᵀ (a − t)`, in the moving part's frame).
    fn tighten_side(&self, links: &mut [Link], moving: bool) -> Option<()> {
        // A point on a plane of the other part: (point, normal, offset).
        let on_plane = |link: &Link| match (*link, moving) {
            (Link::MovingPointOnFixedPlane { w, n, d }, true) => Some((w, n, d)),
            (Link::FixedPointOnMovingPlane { a, m, e }, false) => Some((a, m, e)),
            _ => None,
        };
        // A region whose box on this side is the single point `at`: the other side's box.
        let mut points: Vec<DVec3> = Vec::new();
        for (w, _, _) in links.iter().filter_map(on_plane) {
            if !points.contains(&w) {
                points.push(w);
            }
        }
        for at in points {
            let mut p = [Interval::new(-FAR, FAR); 3];
            for link in links.iter_mut() {
                if let Some((w, n, d)) = on_plane(link) {
                    if w == at {
                        let range = Interval::point(d).widen(self.slack);
                        narrow(
                            Linear {
                                coeffs: point(n),
                                range,
                            },
                            &mut p,
                        )?;
                    }
                } else if let Some(&mut (lo, hi)) = region_other(link, at, moving) {
                    for k in 0..3 {
                        p[k] = p[k].meet(Interval::new(lo[k], hi[k]));
                    }
                }
            }
            if p.iter().any(|i| i.is_empty()) {
                return None;
            }
            if p.iter().all(|i| i.width() < FAR) {
                let tightened = (
                    DVec3::new(p[0].lo, p[1].lo, p[2].lo),
                    DVec3::new(p[0].hi, p[1].hi, p[2].hi),
                );
                for link in links.iter_mut() {
                    if let Some(other) = region_other(link, at, moving) {
                        *other = tightened;
                    }
                }
            }
        }
        Some(())
    }

    /// Maps a point of the fixed part's frame into G's frame.
    pub fn fixed_point(&self, p: DVec3) -> DVec3 {
        self.to_g.transform_point3(p)
    }

    /// Maps a direction of the fixed part's frame into G's frame.
    pub fn fixed_direction(&self, d: DVec3) -> DVec3 {
        self.to_g.transform_vector3(d)
    }

    /// Narrows the translation part of a box by every constraint of `links` until it
    /// settles; `None` when it becomes empty (no pose in the box realises the state).
    pub fn narrow(&self, links: &Links, bounds: &Bounds) -> Option<Bounds> {
        let narrowed = self.contract(links, bounds)?;
        self.linearised(links, &narrowed)
    }

    /// The component among `components` to halve, rotations weighed as the arc they
    /// sweep at the parts' size; `None` when the box is already below the slack there.
    pub fn split_among(&self, bounds: &Bounds, components: std::ops::Range<usize>) -> Option<usize> {
        self.widest_above(bounds, components, self.slack)
    }

    /// The component among `components` that is widest, rotations weighed as the arc
    /// they sweep at the parts' size; `None` when it is no wider than `floor` (a length).
    pub fn widest_above(&self, bounds: &Bounds, components: std::ops::Range<usize>, floor: f64) -> Option<usize> {
        let (lo, hi) = (bounds.min.to_array(), bounds.max.to_array());
        let weight = |k: usize| (hi[k] - lo[k]) * if k < 3 { 1.0 } else { 2.0 * self.reach };
        let k = components.max_by(|&i, &j| weight(i).total_cmp(&weight(j)))?;
        (weight(k) > floor.max(self.slack)).then_some(k)
    }

    /// Interval propagation over one box: the translation narrowed by the contacts,
    /// the pairs kept apart and non-penetration, round by round until it settles.
    fn contract(&self, links: &Links, bounds: &Bounds) -> Option<Bounds> {
        let mut t = [
            Interval::new(bounds.min.x, bounds.max.x),
            Interval::new(bounds.min.y, bounds.max.y),
            Interval::new(bounds.min.z, bounds.max.z),
        ];
        let turned = self.turned(links, bounds);
        for &c in &turned.constraints {
            narrow(c, &mut t)?;
        }
        let pairs = self.pairs_in_reach(&turned, bounds, &t);
        for _round in 0..6 {
            let before = t;
            for &c in &turned.constraints {
                narrow(c, &mut t)?;
            }
            self.keep_apart(&links.apart, &turned.r, &turned.moved, &turned.normals, &mut t)?;
            self.keep_out_of_pieces(&turned, &pairs, &mut t)?;
            let shrink: f64 = (0..3).map(|k| before[k].width() - t[k].width()).fold(0.0, f64::max);
            if shrink <= 1e-3 * (0..3).map(|k| t[k].width()).fold(self.slack, f64::max) {
                break;
            }
        }
        if !links.overlaps.iter().all(|o| self.may_overlap(o, &turned.r, &t)) {
            return None;
        }
        if links.along.iter().any(|a| self.lies_along(a, &turned.r, &t)) {
            return None;
        }
        Some(with_translation(bounds, &t))
    }

    /// Whether the two elements of a contact of a vertex on a face, along a segment or
    /// over an area may share a point somewhere in the box that the loose reading,
    /// which a witness must agree with ([`super::witness_flaw`]), keeps: false when,
    /// for every convex part of each, a side of one has every corner of the other
    /// outside it, or too little inside it ([`Thin`]). Each element is taken as the
    /// convex parts of its face, its edge as a part of two corners, its vertex as a
    /// part of one.
    ///
    /// That reading keeps a piece of two faces' overlap only where it is wider than
    /// its tolerance (twice its area over its perimeter, each piece within one triangle
    /// of each face's cover, so within one pair of parts): when every pair meets at
    /// most a quarter of that tolerance inside a side, no piece is kept. It keeps a
    /// vertex or a stretch of an edge on a face only farther than its tolerance from
    /// the face's boundary: when in every part of the face the vertex or edge lies
    /// outside a side, or within half that tolerance (times the side's `side_sine`)
    /// inside a side on the rim, none is kept.
    fn may_overlap(&self, overlap: &Overlap, r: &IntervalMat, t: &IVec) -> bool {
        let slack = self.slack;
        let (fixed, moving) = (
            convex_parts_of(self.fixed, &self.a, overlap.fixed),
            convex_parts_of(self.moving, &self.b, overlap.moving),
        );
        let plane_of = |shape: &Shape, e: ElementId| match e {
            ElementId::Face(f) => Some(shape.planes[f.index()].0),
            _ => None,
        };
        // The moving part's corners in G's frame, the fixed part's in the moving
        // part's frame (R⁻¹ = Rᵀ).
        let rt: IntervalMat = std::array::from_fn(|i| std::array::from_fn(|j| r[j][i]));
        let placed = |q: DVec3| add(mat_vec(r, q), *t);
        let brought_back = |p: DVec3| {
            let d = sub(point(p), *t);
            std::array::from_fn(|i| dot(rt[i], d))
        };
        // How far inside side `k` of `part` the other's corners must reach.
        let reach = |part: &PartOf<'_>, k: usize| match overlap.thin {
            Thin::Overlap(d) => d,
            Thin::Rim(d) if !part.inner[k] => d * part.side_sine[k],
            Thin::Rim(_) => -slack,
        };
        // Some side of `polygon` (in a face of normal `n`) has every point outside it,
        // or too little inside.
        let separates = |part: &PartOf<'_>, n: DVec3, others: &[IVec]| {
            let sign = part.normal.dot(n).signum();
            part.corners.len() >= 3
                && sides(&part.corners).enumerate().any(|(k, (x, y))| {
                    let inward = sign * n.cross(y - x) / x.distance(y);
                    let least = inward.dot(x) + reach(part, k);
                    others.iter().all(|q| dot(point(inward), *q).hi < least)
                })
        };
        let fixed_normal = plane_of(&self.a, overlap.fixed);
        let moving_normal = plane_of(&self.b, overlap.moving);
        // Each part's corners carried to the other frame once, not once per pair.
        let moving_placed: Vec<Vec<IVec>> = moving
            .iter()
            .map(|q| q.corners.iter().map(|&c| placed(c)).collect())
            .collect();
        let fixed_back: Vec<Vec<IVec>> = fixed
            .iter()
            .map(|p| p.corners.iter().map(|&c| brought_back(c)).collect())
            .collect();
        fixed.iter().zip(&fixed_back).any(|(p, p_back)| {
            moving.iter().zip(&moving_placed).any(|(q, q_placed)| {
                let apart = fixed_normal.is_some_and(|n| separates(p, n, q_placed))
                    || moving_normal.is_some_and(|n| separates(q, n, p_back));
                !apart
            })
        })
    }

    /// Everything of a box that depends on its rotations only.
    fn turned(&self, links: &Links, bounds: &Bounds) -> Turned {
        let r = rotation_enclosure(bounds);
        let moved: Vec<IVec> = self.b.vertices.iter().map(|&w| mat_vec(&r, w)).collect();
        // The moving part's piece boxes turned by the rotation enclosure.
        let turned_boxes = self
            .b
            .piece_boxes
            .iter()
            .map(|&b| {
                let turned = mat_box(&r, b);
                (
                    DVec3::from_array(turned.map(|i| i.lo)),
                    DVec3::from_array(turned.map(|i| i.hi)),
                )
            })
            .collect();
        Turned {
            constraints: links.links.iter().flat_map(|link| self.linear(link, &r)).collect(),
            normals: self.b.planes.iter().map(|&(m, _)| mat_vec(&r, m)).collect(),
            pieces: self
                .b
                .pieces
                .iter()
                .map(|piece| piece.iter().map(|&(m, e)| (mat_vec(&r, m), e)).collect())
                .collect(),
            boxes: turned_boxes,
            moved,
            r,
        }
    }

    /// The (vertex, piece) pairs whose boxes meet once the contacts narrowed `t` (only
    /// those can ever constrain it, as it only shrinks: a vertex outside a piece's box is
    /// outside the piece), and the points of edges that pass through a piece of the
    /// other part at the box's centre, kept out of it like the vertices (two pieces can
    /// cross with no vertex of either inside the other).
    fn pairs_in_reach(&self, turned: &Turned, bounds: &Bounds, t: &IVec) -> PairsInReach {
        let s = self.slack;
        let meets = |p: IVec, (lo, hi): (DVec3, DVec3)| (0..3).all(|k| p[k].hi >= lo[k] - s && p[k].lo <= hi[k] + s);
        let fixed_boxes = &self.a.piece_boxes;
        let mut moving: Vec<(IVec, usize)> = (0..turned.moved.len())
            .flat_map(|i| (0..fixed_boxes.len()).map(move |j| (i, j)))
            .filter(|&(i, j)| meets(add(turned.moved[i], *t), fixed_boxes[j]))
            .map(|(i, j)| (turned.moved[i], j))
            .collect();
        let mut fixed: Vec<(DVec3, usize)> = (0..self.a.vertices.len())
            .flat_map(|i| (0..turned.boxes.len()).map(move |j| (i, j)))
            .filter(|&(i, j)| meets(sub(point(self.a.vertices[i]), *t), turned.boxes[j]))
            .map(|(i, j)| (self.a.vertices[i], j))
            .collect();
        let through = self.edges_through(&bounds.center());
        moving.extend(through.moving.iter().map(|p| (mat_vec(&turned.r, p.point), p.piece)));
        fixed.extend(through.fixed.iter().map(|p| (p.point, p.piece)));
        PairsInReach { moving, fixed }
    }

    /// Narrows `t` so that no point of one part (of the pairs in reach) lies strictly
    /// inside a convex piece of the other.
    fn keep_out_of_pieces(&self, turned: &Turned, pairs: &PairsInReach, t: &mut IVec) -> Option<()> {
        let s = self.slack;
        for &(w, j) in &pairs.moving {
            let p = add(w, *t);
            outside_some(
                self.a.pieces[j].iter().map(|&(n, d)| (point(n), d)),
                |(coeffs, d)| {
                    let value = dot(coeffs, p);
                    let bound = Linear {
                        coeffs,
                        range: Interval::new(d - s - dot(coeffs, w).hi, f64::INFINITY),
                    };
                    (value, d - s, bound)
                },
                t,
            )?;
        }
        for &(a, j) in &pairs.fixed {
            let q = sub(point(a), *t);
            outside_some(
                turned.pieces[j].iter().copied(),
                |(u, e)| {
                    // (R m) · (a − t) ≥ e − s  ⇔  u · t ≤ u · a − e + s
                    let value = dot(u, q);
                    let bound = Linear {
                        coeffs: u,
                        range: Interval::new(f64::NEG_INFINITY, dot(u, point(a)).hi - e + s),
                    };
                    (value, e - s, bound)
                },
                t,
            )?;
        }
        Some(())
    }

    /// Points of edges that pass through a convex piece of the other part at a pose
    /// (the middle of the stretch inside, each edge and piece at most once): the
    /// moving part's in its frame, the fixed part's in G's.
    fn edges_through(&self, pose: &crate::pose::Pose) -> Through {
        let (r, t) = (pose.rotation(), pose.translation());
        let placed: Vec<DVec3> = self.b.vertices.iter().map(|&w| r * w + t).collect();
        let back: Vec<DVec3> = self.a.vertices.iter().map(|&a| r.transpose() * (a - t)).collect();
        let inside = |p0: DVec3, p1: DVec3, planes: &[(DVec3, f64)], (lo, hi): (DVec3, DVec3)| -> Option<f64> {
            if p0.min(p1).cmpgt(hi).any() || p0.max(p1).cmplt(lo).any() {
                return None;
            }
            let (mut from, mut to) = (0.0_f64, 1.0_f64);
            for &(n, d) in planes {
                let (a, b) = (n.dot(p0) - d, n.dot(p1 - p0));
                if b.abs() < 1e-15 {
                    if a >= 0.0 {
                        return None;
                    }
                } else if b > 0.0 {
                    to = to.min(-a / b);
                } else {
                    from = from.max(-a / b);
                }
            }
            (to - from > 1e-9).then_some(0.5 * (from + to))
        };
        // The edges of `shape` (its vertices placed at `at`) through the pieces of `other`.
        let points = |shape: &Shape, at: &[DVec3], other: &Shape| -> Vec<EdgePoint> {
            let mut out = Vec::new();
            for (edge, &[i, k]) in shape.edges.iter().enumerate() {
                for (piece, planes) in other.pieces.iter().enumerate() {
                    if let Some(mid) = inside(at[i], at[k], planes, other.piece_boxes[piece]) {
                        let (p0, p1) = (shape.vertices[i], shape.vertices[k]);
                        out.push(EdgePoint {
                            edge,
                            point: p0 + mid * (p1 - p0),
                            piece,
                        });
                    }
                }
            }
            out
        };
        Through {
            moving: points(&self.b, &placed, &self.a),
            fixed: points(&self.a, &back, &self.b),
        }
    }

    /// Narrows `t` by the face–vertex pairs a witness keeps apart: a vertex that lies
    /// over a face (its box projects into one of the face's triangles) and cannot be
    /// the margin below the face's plane must be the margin above it, and the other way
    /// round.
    /// `moved` holds `R w` for every vertex of the moving part and `normals` `R m` for
    /// every face normal of it, over the box.
    fn keep_apart(
        &self,
        apart: &[Apart],
        r: &IntervalMat,
        moved: &[IVec],
        normals: &[IVec],
        t: &mut IVec,
    ) -> Option<()> {
        let m = self.margin;
        for pair in apart {
            match *pair {
                Apart::FixedFace { face, vertex, .. } => {
                    let (n, d) = self.a.planes[face];
                    let rw = moved[vertex];
                    let p = add(rw, *t);
                    let h = dot(point(n), p).sub(Interval::point(d));
                    if h.lo >= m || h.hi <= -m || !over_face(&self.a.convex_parts[face], n, &p, self.slack) {
                        continue;
                    }
                    let n_rw = dot(point(n), rw);
                    let range = if h.lo > -m {
                        Interval::new(d + m - n_rw.hi, f64::INFINITY)
                    } else if h.hi < m {
                        Interval::new(f64::NEG_INFINITY, d - m - n_rw.lo)
                    } else {
                        continue;
                    };
                    narrow(
                        Linear {
                            coeffs: point(n),
                            range,
                        },
                        t,
                    )?;
                }
                Apart::MovingFace { face, vertex, .. } => {
                    let (mn, e) = self.b.planes[face];
                    let u = normals[face];
                    let a = point(self.a.vertices[vertex]);
                    let from_t = sub(a, *t);
                    let h = dot(u, from_t).sub(Interval::point(e));
                    if h.lo >= m || h.hi <= -m {
                        continue;
                    }
                    // The vertex in the moving part's frame: Rᵀ (a − t).
                    let q: IVec = std::array::from_fn(|k| {
                        (0..3).fold(Interval::point(0.0), |acc, j| acc.add(r[j][k].mul(from_t[j])))
                    });
                    if !over_face(&self.b.convex_parts[face], mn, &q, self.slack) {
                        continue;
                    }
                    let ua = dot(u, a);
                    // (R m)·(a − t) − e ≥ m  ⇔  u·t ≤ u·a − e − m; ≤ −m the other way.
                    let range = if h.lo > -m {
                        Interval::new(f64::NEG_INFINITY, ua.hi - e - m)
                    } else if h.hi < m {
                        Interval::new(ua.lo - e + m, f64::INFINITY)
                    } else {
                        continue;
                    };
                    narrow(Linear { coeffs: u, range }, t)?;
                }
            }
        }
        Some(())
    }

    /// The linear constraints on `t` of one contact link, with R enclosed by `r`.
    fn linear(&self, link: &Link, r: &IntervalMat) -> Vec<Linear> {
        let s = self.slack;
        match *link {
            Link::MovingPointOnFixedPlane { w, n, d } => {
                let coeffs = point(n);
                let range = Interval::point(d).sub(dot(coeffs, mat_vec(r, w))).widen(s);
                vec![Linear { coeffs, range }]
            }
            Link::FixedPointOnMovingPlane { a, m, e } => {
                let u = mat_vec(r, m);
                let range = dot(u, point(a)).sub(Interval::point(e)).widen(s);
                vec![Linear { coeffs: u, range }]
            }
            Link::Crossing { a0, da, b0, db } => {
                let n = cross(point(da), mat_vec(r, db));
                let c = sub(point(a0), mat_vec(r, b0));
                vec![Linear {
                    coeffs: n,
                    range: dot(n, c).widen(s),
                }]
            }
            Link::Region { a, b } => {
                let rb = mat_box(r, b);
                (0..3)
                    .map(|k| Linear {
                        coeffs: point(DVec3::AXES[k]),
                        range: Interval::new(a.0[k], a.1[k]).sub(rb[k]).widen(s),
                    })
                    .collect()
            }
        }
    }
}

/// Whether the pair (`a` of the fixed part, `b` of the moving part) touches wherever
/// the target's contacts hold, so a witness need not keep it apart: each element holds
/// a contact's element on its side (a face around a touching vertex), or, for a contact
/// along a segment or an area, lies in its closure (an edge's end on the face it lies
/// in).
pub(crate) fn implied(fixed: &Part, moving: &Part, target: &[PrincipalContact], a: ElementId, b: ElementId) -> bool {
    target.iter().any(|pc| {
        let region = matches!(
            pc.kind,
            ContactKind::FaceFace | ContactKind::FaceEdge | ContactKind::EdgeFace | ContactKind::EdgeEdgeTouch
        );
        let holds =
            |part: &Part, x: ElementId, y: ElementId| part.in_closure(y, x) || (region && part.in_closure(x, y));
        holds(fixed, pc.fixed, a) && holds(moving, pc.moving, b)
    })
}

/// Whether a face and a vertex of the other part (`a` of the fixed part, `b` of the
/// moving part) touch wherever the target's contacts hold, or lie in the closure of
/// one that does: both hold a contact's elements (a face around a touching vertex), or
/// both lie in the closures of a contact's elements along a segment or over an area
/// (an edge's end on the face it lies in). Stricter than [`implied`]: a face around an
/// edge that lies on a face and a corner of that face touch only where the corner is
/// on the edge, which the held rim ([`Apart`]'s `held_rim`) allows for; anywhere
/// else a checker reads the corner on the face, a contact no contact of the target
/// holds.
fn held_together(fixed: &Part, moving: &Part, target: &[PrincipalContact], a: ElementId, b: ElementId) -> bool {
    target.iter().any(|pc| {
        let region = matches!(
            pc.kind,
            ContactKind::FaceFace | ContactKind::FaceEdge | ContactKind::EdgeFace | ContactKind::EdgeEdgeTouch
        );
        let around = fixed.in_closure(a, pc.fixed) && moving.in_closure(b, pc.moving);
        let within = region && fixed.in_closure(pc.fixed, a) && moving.in_closure(pc.moving, b);
        around || within
    })
}

/// Whether no contact of `target` other than `pc` touches the closure of `face` (of
/// the fixed part when `fixed_side`, else of the moving part): then a checker reading
/// an edge on that face reads a contact the target does not hold.
pub(crate) fn face_untouched(
    (fixed, moving): (&Part, &Part),
    target: &[PrincipalContact],
    pc: &PrincipalContact,
    fixed_side: bool,
    face: ElementId,
) -> bool {
    target.iter().filter(|&other| other != pc).all(|other| {
        if fixed_side {
            !fixed.in_closure(face, other.fixed)
        } else {
            !moving.in_closure(face, other.moving)
        }
    })
}

/// A box with its translation intervals replaced (they only ever narrow inside it).
fn with_translation(bounds: &Bounds, t: &IVec) -> Bounds {
    let (mut lo, mut hi) = (bounds.min.to_array(), bounds.max.to_array());
    for k in 0..3 {
        lo[k] = t[k].lo;
        hi[k] = t[k].hi;
    }
    Bounds::try_new(lo, hi).unwrap_or(*bounds)
}

/// The other side's box of a region link whose box on this side (the moving part's
/// when `moving`) is the single point `at`.
fn region_other(link: &mut Link, at: DVec3, moving: bool) -> Option<&mut (DVec3, DVec3)> {
    match link {
        Link::Region { a, b } => {
            let (this, other) = if moving { (b, a) } else { (a, b) };
            (this.0 == at && this.1 == at).then_some(other)
        }
        _ => None,
    }
}

/// A point must be on the outer side (`value ≥ limit`) of at least one plane of a
/// piece: when it is certainly inside all but one, that one's bound narrows `t`;
/// inside all, the box is empty.
fn outside_some<P>(
    planes: impl Iterator<Item = P>,
    test: impl Fn(P) -> (Interval, f64, Linear),
    t: &mut IVec,
) -> Option<()> {
    let mut candidate = None;
    for plane in planes {
        let (value, limit, bound) = test(plane);
        if value.hi >= limit {
            if candidate.is_some() {
                return Some(()); // two planes may still hold it out
            }
            candidate = Some(bound);
        }
    }
    match candidate {
        None => None,
        Some(bound) => narrow(bound, t),
    }
}

/// Whether every point of a box projects, along the face normal `n`, into one of a
/// face's convex parts, at least `margin` inside it (a vertex on the face's boundary
/// touches the face's closure, not the face: it is no gap a witness must keep; one
/// more than the contact tolerance inside is a gap, or touches the face itself).
fn over_face(parts: &[ConvexPart], n: DVec3, p: &IVec, margin: f64) -> bool {
    let corners: [DVec3; 8] = std::array::from_fn(|c| {
        DVec3::new(
            if c & 1 == 0 { p[0].lo } else { p[0].hi },
            if c & 2 == 0 { p[1].lo } else { p[1].hi },
            if c & 4 == 0 { p[2].lo } else { p[2].hi },
        )
    });
    if corners.iter().any(|c| !c.is_finite()) {
        return false;
    }
    parts.iter().any(|part| {
        let (polygon, sign) = (&part.corners[..], part.sense(n));
        corners
            .iter()
            .all(|&q| sides(polygon).all(|(x, y)| (y - x).cross(q - x).dot(n) * sign >= margin * x.distance(y)))
    })
}

/// One convex part of an element, as [`Prover::may_overlap`] sees it.
struct PartOf<'s> {
    corners: Cow<'s, [DVec3]>,
    normal: DVec3,
    /// Per side, whether it is a diagonal of the face's cover, and the sine of its
    /// sharper end (see [`ConvexPart`]); empty for an edge or a vertex.
    inner: Cow<'s, [bool]>,
    side_sine: Cow<'s, [f64]>,
}

/// An element's convex parts, each as its corners and their Newell normal: a face's
/// cover, an edge as a part of two corners, a vertex as a part of one (normal zero).
fn convex_parts_of<'s>(part: &Part, shape: &'s Shape, e: ElementId) -> Vec<PartOf<'s>> {
    let single = |corners: Vec<DVec3>| PartOf {
        corners: Cow::Owned(corners),
        normal: DVec3::ZERO,
        inner: Cow::Owned(Vec::new()),
        side_sine: Cow::Owned(Vec::new()),
    };
    match e {
        ElementId::Face(f) => shape.convex_parts[f.index()]
            .iter()
            .map(|c| PartOf {
                corners: Cow::Borrowed(&c.corners[..]),
                normal: c.normal,
                inner: Cow::Borrowed(&c.inner[..]),
                side_sine: Cow::Borrowed(&c.side_sine[..]),
            })
            .collect(),
        ElementId::Edge(x) => vec![single(
            part.edge(x).vertices.map(|v| shape.vertices[v.index()]).to_vec(),
        )],
        ElementId::Vertex(v) => vec![single(vec![shape.vertices[v.index()]])],
    }
}

/// The sides of a closed polygon, each as its two ends in order.
fn sides(polygon: &[DVec3]) -> impl Iterator<Item = (DVec3, DVec3)> + '_ {
    (0..polygon.len()).map(|i| (polygon[i], polygon[(i + 1) % polygon.len()]))
}

/// Narrows `t` by `coeffs · t ∈ range`; `None` when no `t` in the box satisfies it.
fn narrow(c: Linear, t: &mut IVec) -> Option<()> {
    let total = dot(c.coeffs, *t);
    if total.meet(c.range).is_empty() {
        return None;
    }
    for k in 0..3 {
        if c.coeffs[k].contains_zero() || c.coeffs[k].lo.abs().min(c.coeffs[k].hi.abs()) < 1e-9 {
            continue;
        }
        let rest = (0..3)
            .filter(|&j| j != k)
            .fold(c.range, |acc, j| acc.sub(c.coeffs[j].mul(t[j])));
        t[k] = t[k].meet(rest.div(c.coeffs[k]));
        if t[k].is_empty() {
            return None;
        }
    }
    Some(())
}

/// Indices of the faces whose planes contain an element.
fn planes_through(part: &Part, e: ElementId) -> Vec<usize> {
    match e {
        ElementId::Face(f) => vec![f.index()],
        ElementId::Edge(x) => part.edge(x).faces.iter().map(|f| f.index()).collect(),
        ElementId::Vertex(v) => part.vertex(v).faces.iter().map(|f| f.index()).collect(),
    }
}

fn point(p: DVec3) -> IVec {
    [Interval::point(p.x), Interval::point(p.y), Interval::point(p.z)]
}

fn add(a: IVec, b: IVec) -> IVec {
    [a[0].add(b[0]), a[1].add(b[1]), a[2].add(b[2])]
}

fn sub(a: IVec, b: IVec) -> IVec {
    [a[0].sub(b[0]), a[1].sub(b[1]), a[2].sub(b[2])]
}

fn dot(a: IVec, b: IVec) -> Interval {
    a[0].mul(b[0]).add(a[1].mul(b[1])).add(a[2].mul(b[2]))
}

fn cross(a: IVec, b: IVec) -> IVec {
    [
        a[1].mul(b[2]).sub(a[2].mul(b[1])),
        a[2].mul(b[0]).sub(a[0].mul(b[2])),
        a[0].mul(b[1]).sub(a[1].mul(b[0])),
    ]
}

fn mat_vec(r: &IntervalMat, p: DVec3) -> IVec {
    std::array::from_fn(|i| dot(r[i], point(p)))
}

fn mat_box(r: &IntervalMat, (lo, hi): (DVec3, DVec3)) -> IVec {
    let b = [
        Interval::new(lo.x, hi.x),
        Interval::new(lo.y, hi.y),
        Interval::new(lo.z, hi.z),
    ];
    std::array::from_fn(|i| dot(r[i], b))
}

fn bounds_of(points: impl Iterator<Item = DVec3>) -> (DVec3, DVec3) {
    points.fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), p| {
        (lo.min(p), hi.max(p))
    })
}

/// A coordinate bound standing for "anywhere" (finite, so that `0 · FAR` is 0).
const FAR: f64 = 1e15;

#[cfg(test)]
mod tests {
    use super::*;
    use crate::pose::Pose;
    use crate::testing::{edge_between, fixture};

    #[test]
    fn a_face_and_a_corner_are_held_together_only_where_a_contact_puts_them() {
        // The plain hole's top face (f3, z = 50) around its rim edge (e11, x = 35) and
        // the peg's bottom face (f2) with its corner v0.
        use crate::contact::ContactKind as K;
        use crate::testing::contact;
        let (hole, peg) = (fixture("block_with_hole.off"), fixture("peg.off"));
        let (top, corner) = ("f3".parse().unwrap(), "v0".parse().unwrap());
        let together = |target: &[PrincipalContact]| held_together(&hole, &peg, target, top, corner);
        // The rim edge lying on the bottom face holds neither the top face nor the
        // corner: they touch only where the corner is on the rim edge (the held rim).
        let rim_on_bottom = [contact("e11", "f2", K::EdgeFace)];
        assert!(!together(&rim_on_bottom));
        // The looser rule, for the ends of crossing edges, takes them as touching.
        assert!(implied(&hole, &peg, &rim_on_bottom, top, corner));
        // The bottom face on the top face: its corners lie in the top face's plane.
        assert!(together(&[contact("f3", "f2", K::FaceFace)]));
        // The corner on the top face, and an edge ending at it lying on it (e0, e1);
        // an edge away from it (e5) does not hold it.
        assert!(together(&[contact("f3", "v0", K::FaceVertex)]));
        assert!(together(&[contact("f3", "e0", K::FaceEdge)]));
        assert!(together(&[contact("f3", "e1", K::FaceEdge)]));
        assert!(!together(&[contact("f3", "e5", K::FaceEdge)]));
        // Another face, or another corner, is not.
        assert!(!together(&[contact("f5", "v0", K::FaceVertex)]));
        assert!(!together(&[contact("f3", "v7", K::FaceVertex)]));
    }

    #[test]
    fn a_face_on_a_face_needs_an_overlap_wider_than_the_loose_tolerance() {
        // The peg's bottom face (f2, x and y from 36 to 64 in its frame, z = 10) flat on
        // the plain hole's top face (f3, z = 50, around the hole from 35 to 65): shifted
        // by y = 1 the bottom meets the top face only along the rim edge's line, an
        // overlap no reading keeps; shifted by 1.2 it overlaps a strip 0.2 wide.
        use crate::contact::ContactKind as K;
        use crate::feasibility::LOOSE_CONTACT_REL;
        use crate::testing::contact;
        with_peg_over_the_plain_hole(|problem| {
            let flat = [contact("f3", "f2", K::FaceFace)];
            let at = |y: f64| [0.2, y, 40.0, 0.0, 0.0, 0.0];
            let read = |x: [f64; 6], tolerance: f64| read_at(problem, x, tolerance).contains(&flat[0]);
            let point = |x: [f64; 6]| Bounds::try_new(x, x).unwrap();
            // On the rim's line: neither reading has the faces on each other, and the
            // last proofs rule the pose out.
            assert!(!read(at(1.0), LOOSE_CONTACT_REL));
            assert!(problem.last_exclusion(&flat, &point(at(1.0))).is_some());
            // A box reaching 1e-5 past the rim (a strip far thinner than the loose
            // tolerance, 1.5e-4): still ruled out.
            let mut past = at(1.0 + 1e-5);
            past[3] = 1e-8;
            let mut before = at(0.99);
            before[3] = -1e-8;
            assert!(
                problem
                    .last_exclusion(&flat, &Bounds::try_new(before, past).unwrap())
                    .is_some()
            );
            // Over a strip 0.2 wide both readings have the face on the face, and the rule
            // stands down.
            assert!(read(at(1.2), CONTACT_REL) && read(at(1.2), LOOSE_CONTACT_REL));
            assert!(problem.last_exclusion(&flat, &point(at(1.2))).is_none());
        });
    }

    #[test]
    fn an_edge_on_a_face_keeps_clear_of_the_faces_rim_as_the_loose_reading_asks() {
        // The peg tilted by 0.01 rad about y, its lowest bottom edge (e9, along y) lying
        // on the plain hole's top face (f3, z = 50), `past` beyond the hole's rim edge
        // (x = 65). The top face has a hole, so its box says nothing of the rim: the
        // rule reads its cover's sides on the rim.
        use crate::contact::ContactKind as K;
        use crate::feasibility::LOOSE_CONTACT_REL;
        use crate::testing::contact;
        with_peg_over_the_plain_hole(|problem| {
            let on_top = [contact("f3", "e9", K::FaceEdge)];
            let tilt: f64 = 0.01;
            let at = |past: f64| {
                let x = 65.0 + past - 64.0 * tilt.cos() - 10.0 * tilt.sin();
                let z = 50.0 + 64.0 * tilt.sin() - 10.0 * tilt.cos();
                [x, 0.0, z, 0.0, tilt, 0.0]
            };
            let read = |x: [f64; 6], tolerance: f64| read_at(problem, x, tolerance);
            let point = |x: [f64; 6]| Bounds::try_new(x, x).unwrap();
            let loose = scaled(LOOSE_CONTACT_REL, problem.scale);
            // A fifth of the loose tolerance past the rim: the strict reading has the edge
            // on the face, the loose one has it along the rim edge instead, and the last
            // proofs rule the pose out.
            let near = at(0.2 * loose);
            assert_eq!(read(near, CONTACT_REL), on_top);
            assert!(!read(near, LOOSE_CONTACT_REL).contains(&on_top[0]));
            assert!(problem.last_exclusion(&on_top, &point(near)).is_some());
            // Half a millimetre past it, a witness: both readings agree, and the rule
            // stands down.
            let far = at(0.5);
            assert_eq!(read(far, CONTACT_REL), on_top);
            assert_eq!(read(far, LOOSE_CONTACT_REL), on_top);
            assert!(problem.last_exclusion(&on_top, &point(far)).is_none());
        });
    }

    /// The plain hole (fixed) and the square peg, x and y within ±2, z from 0 to 45,
    /// tilted up to 0.02 rad about x and y, no yaw.
    fn with_peg_over_the_plain_hole<T>(f: impl FnOnce(&crate::feasibility::Problem<'_>) -> T) -> T {
        let (hole, peg) = (fixture("block_with_hole.off"), fixture("peg.off"));
        let bounds = Bounds::try_new([-2.0, -2.0, 0.0, -0.02, -0.02, 0.0], [2.0, 2.0, 45.0, 0.02, 0.02, 0.0]).unwrap();
        f(&crate::feasibility::Problem::new(
            &hole,
            &peg,
            bounds,
            DAffine3::IDENTITY,
        ))
    }

    /// The state read at `x` with the given relative tolerance.
    fn read_at(problem: &crate::feasibility::Problem<'_>, x: [f64; 6], tolerance: f64) -> Vec<PrincipalContact> {
        let placed = Pose::from_array(x).to_affine(&DAffine3::IDENTITY);
        problem.scene().state(&placed, tolerance).contacts
    }

    #[test]
    fn the_last_proofs_see_a_rim_edge_on_a_tilted_bottom_needs_the_bottom_over_the_rim() {
        // The hole's rim edge e11 (x = 35, z = 50, along y) lying on the peg's bottom
        // face f2 (a square, x from 36 to 64 in its frame) needs the bottom to reach
        // past the rim by the margin: x + 36 cos ry + 10 sin ry ≤ 35 − m. With x ≥ −1
        // and the peg tilted by ry < 0, the part of the bottom past the rim dips below
        // the top face (it descends towards −x): the overhang w penetrates by w |ry|.
        // Propagation, axis by axis, leaves boxes a few µm wide open; the linearised
        // conditions of the last proofs, with the regions' boxes meeting as rows, close
        // them.
        use crate::contact::ContactKind as K;
        use crate::testing::contact;
        let (hole, peg) = (fixture("block_with_hole.off"), fixture("peg.off"));
        let two = 2f64.to_radians();
        let bounds = Bounds::try_new([-2.0, -2.0, 0.0, -two, -two, 0.0], [2.0, 2.0, 45.0, two, two, 0.0]).unwrap();
        let problem = super::super::Problem::new(&hole, &peg, bounds, DAffine3::IDENTITY);
        let target = [contact("e11", "f2", K::EdgeFace)];
        // ry = −0.00304, the overhang up to about 0.03 mm, all along the rim.
        let (x, z, ry) = (-0.96954, 39.89052, -0.0030388);
        let tilted_in = Bounds::try_new(
            [x - 1e-3, 0.0, z - 1e-3, -5e-8, ry - 1.2e-5, 0.0],
            [x + 1e-3, 1.0, z + 1e-3, 5e-8, ry + 1.2e-5, 0.0],
        )
        .unwrap();
        assert_eq!(problem.exclusion(&target, &tilted_in), None);
        assert!(problem.last_exclusion(&target, &tilted_in).is_some());
        // Tilted the other way (ry > 0) the bottom rises past the rim; with the peg
        // moved to x = −1.1 it overhangs it by about 0.065 mm: a witness of the rim on
        // the bottom, alone.
        let ry: f64 = 0.0035;
        let (c, s) = (ry.cos(), ry.sin());
        let x = -1.1;
        // The rim meets the bottom at 36 + u along its x (the part before it is past
        // the rim): (36 + u) c + 10 s + x = 35; the rim's height there is 50.
        let overhang = (35.0 - 10.0 * s - x) / c - 36.0;
        let z = 50.0 + (36.0 + overhang) * s - 10.0 * c;
        let pose = Pose::from_array([x, 0.0, z, 0.0, ry, 0.0]);
        assert!(overhang > 0.06, "{overhang}");
        assert_eq!(problem.verify(&pose), Some(target.to_vec()));
        let around = Bounds::try_new(
            [x - 1e-3, -0.1, z - 1e-3, -1e-6, ry - 1e-5, 0.0],
            [x + 1e-3, 0.1, z + 1e-3, 1e-6, ry + 1e-5, 0.0],
        )
        .unwrap();
        assert_eq!(problem.exclusion(&target, &around), None);
        assert_eq!(problem.last_exclusion(&target, &around), None);
        // The last proofs going on from handed boxes: from the tilted-in box alone
        // they prove the candidate; handed the witness's box too, they do not.
        let mut stats = crate::feasibility::SearchStats::default();
        assert!(
            problem
                .prove_last(&target, &tilted_in, &[tilted_in], &mut stats)
                .is_ok()
        );
        assert!(
            problem
                .prove_last(&target, &tilted_in, &[tilted_in, around], &mut stats)
                .is_err()
        );
    }

    #[test]
    fn a_convex_part_knows_its_sharpest_corner_and_a_box_its_distance_from_a_rim() {
        let square = ConvexPart::new(
            vec![DVec3::ZERO, DVec3::X, DVec3::new(1.0, 1.0, 0.0), DVec3::Y],
            vec![false; 4],
        );
        assert!((square.sharpest - std::f64::consts::FRAC_PI_4.sin()).abs() < 1e-12);
        // A right triangle with legs 1 and 2: its sharpest corner is atan(1/2).
        let thin = ConvexPart::new(vec![DVec3::ZERO, 2.0 * DVec3::X, DVec3::Y], vec![false; 3]);
        assert!((thin.sharpest - (0.5 * 0.5_f64.atan()).sin()).abs() < 1e-12);
        // A point 3 above the middle of a unit segment along x, boxed by ±0.5.
        let rim = [[DVec3::ZERO, DVec3::X]];
        let p = [
            Interval::new(0.0, 1.0),
            Interval::new(-0.5, 0.5),
            Interval::new(2.5, 3.5),
        ];
        assert!(clear_of(&rim, &p, 2.4));
        assert!(!clear_of(&rim, &p, 2.6));
    }

    /// The box of poses within `eps` of a pose.
    fn around(pose: [f64; 6], eps: f64) -> Bounds {
        Bounds::try_new(pose.map(|x| x - eps), pose.map(|x| x + eps)).unwrap()
    }

    #[test]
    fn witnesses_are_never_excluded() {
        let (a, b) = (fixture("block_with_chamfered_hole.off"), fixture("peg.off"));
        let r = 2f64.to_radians();
        let full = Bounds::try_new([-2.0, -2.0, 0.0, -r, -r, -r], [2.0, 2.0, 45.0, r, r, r]).unwrap();
        let problem = super::super::Problem::new(&a, &b, full, DAffine3::IDENTITY);
        for pose in [
            [
                -0.02143060850670711,
                -1.9414348134915005,
                0.0,
                -0.03490658503988659,
                0.03490658503988659,
                0.017079582983981333,
            ],
            [-1.0, 0.0, 0.0, 4.085204392092581e-17, 1.4704830081180945e-14, 0.0],
        ] {
            let t = Pose::from_array(pose).to_affine(&DAffine3::IDENTITY);
            let state = problem.scene().evaluate(&t, CONTACT_REL).contacts;
            assert!(!state.is_empty());
            assert_eq!(problem.exclusion(&state, &full), None, "{state:?} in the full bounds");
            for eps in [0.0, 1e-9, 1e-4] {
                assert_eq!(
                    problem.exclusion(&state, &around(pose, eps)),
                    None,
                    "{state:?} at {pose:?} ± {eps}"
                );
            }
        }
    }

    /// A box as OFF text.
    fn bar(lo: [f64; 3], hi: [f64; 3]) -> Part {
        let size = DVec3::from(hi) - DVec3::from(lo);
        prism(
            DVec3::from(lo),
            [DVec3::X * size.x, DVec3::Y * size.y, DVec3::Z * size.z],
        )
    }

    /// A parallelepiped with a corner at `o` and sides `s` (a right-handed frame).
    fn prism(o: DVec3, s: [DVec3; 3]) -> Part {
        let mut off = String::from("OFF\n8 6 0\n");
        for c in 0..8 {
            let p = (0..3).fold(o, |p, k| if c >> k & 1 == 0 { p } else { p + s[k] });
            off += &format!("{} {} {}\n", p.x, p.y, p.z);
        }
        off += "4 0 2 3 1\n4 4 5 7 6\n4 0 1 5 4\n4 2 6 7 3\n4 0 4 6 2\n4 1 3 7 5\n";
        crate::examples::builtin("prism.off", &off)
    }

    /// A bar of square section standing on its edge: its lowest edge runs from `o`
    /// along `along` (horizontal), its section 1 wide.
    fn ridge(o: DVec3, along: DVec3) -> Part {
        let side = DVec3::Z.cross(along).normalize();
        let (a, b) = ((side + DVec3::Z) / 2f64.sqrt(), (DVec3::Z - side) / 2f64.sqrt());
        prism(o, [along, a, b])
    }

    #[test]
    fn edges_whose_lines_cross_beyond_an_end_are_excluded() {
        // A bar along the diagonal x = y, its top edge from (0, 0, 1) to (10, 10, 1);
        // a ridge along x = −y, its lowest edge from (0, 0, 1) to (10, −10, 1). Moved by
        // t = (−8 ± 0.5, 4 ± 0.5, 0), the ridge's line meets the bar's edge's line at
        // s = (tx + ty) / 2 ≈ −2 along the diagonal: before the edge's start, though
        // well inside the box around the edge that the interval test uses.
        use crate::contact::{ContactKind, PrincipalContact};
        let diagonal = DVec3::new(10.0, 10.0, 0.0);
        let across = DVec3::new(-0.2, 0.2, 0.0);
        let fixed = prism(DVec3::ZERO, [diagonal, across, DVec3::Z]);
        let ridge_start = DVec3::Z;
        let along = DVec3::new(10.0, -10.0, 0.0);
        let moving = ridge(ridge_start, along);
        let target = [PrincipalContact {
            fixed: edge_between(&fixed, DVec3::Z, DVec3::Z + diagonal),
            moving: edge_between(&moving, ridge_start, ridge_start + along),
            kind: ContactKind::EdgeEdge,
        }];
        let prover = Prover::new(&fixed, &moving, &DAffine3::IDENTITY, 30.0);
        let links = prover.links(&target).unwrap();
        let r = 1e-4;
        let beyond = Bounds::try_new([-8.5, 3.5, -0.01, -r, -r, -r], [-7.5, 4.5, 0.01, r, r, r]).unwrap();
        assert!(prover.narrow(&links, &beyond).is_none());
        // Moved by (4, 6, 0) the lines meet at (5, 5, 1), on both edges: a witness.
        let across_edges = Bounds::try_new([3.5, 5.5, -0.01, -r, -r, -r], [4.5, 6.5, 0.01, r, r, r]).unwrap();
        assert!(prover.narrow(&links, &across_edges).is_some());
    }

    #[test]
    fn bars_crossing_with_no_vertex_inside_the_other_are_excluded() {
        // Two bars crossed like a plus sign, 2 deep into each other: no vertex of
        // either lies inside the other, but their edges pass through each other.
        let fixed = bar([-50.0, -5.0, 0.0], [50.0, 5.0, 10.0]);
        let r = 0.01;
        // Sliding along the moving bar's own length keeps them crossed.
        let slide = Bounds::try_new([-1.0, -20.0, -0.5, -r, -r, -r], [1.0, 20.0, 0.5, r, r, r]).unwrap();
        for (z, crossed) in [(8.0, true), (11.0, false)] {
            let moving = bar([-5.0, -50.0, z], [5.0, 50.0, z + 10.0]);
            let prover = Prover::new(&fixed, &moving, &DAffine3::IDENTITY, 150.0);
            let links = prover.links(&[]).unwrap();
            assert_eq!(
                prover.narrow(&links, &slide).is_none(),
                crossed,
                "moving bar at z = {z}"
            );
        }
    }

    #[test]
    fn a_corner_held_on_the_floor_by_a_bound_is_excluded_near_the_flush_pose() {
        // The paper's box stands flush on the L-block's floor (face 3, z = 50) and
        // against its wall; z ≥ 0 forbids lowering it. Its corner v0 alone on the floor
        // needs v2 lifted (rx > 0) and so v4, at the wall, below the floor: no single
        // condition shows it, the linearised conditions together do.
        use crate::contact::{ContactKind, PrincipalContact};
        use crate::model::{FaceId, VertexId};
        let (fixed, moving) = crate::examples::l_block_and_box();
        let problem = super::super::Problem::new(&fixed, &moving, crate::examples::paper_bounds(), DAffine3::IDENTITY);
        let corner = [PrincipalContact {
            fixed: ElementId::Face(FaceId(3)),
            moving: ElementId::Vertex(VertexId(0)),
            kind: ContactKind::FaceVertex,
        }];
        let r = 1e-4;
        let near = Bounds::try_new([-1.0, -1.0, 0.0, -r, -r, -r], [1.0, 1.0, 0.05, r, r, r]).unwrap();
        assert!(problem.exclusion(&corner, &near).is_some());
        // Allowed below the flush height, the box tilts onto v0: not excluded.
        let lower = Bounds::try_new([-1.0, -1.0, -0.05, -r, -r, -r], [1.0, 1.0, 0.05, r, r, r]).unwrap();
        assert_eq!(problem.exclusion(&corner, &lower), None);
        // The same turned about z by 0.1 to 0.3 rad (where v4 stays over the floor):
        // heights over the floor do not depend on the yaw, so at the thorough effort
        // the narrow tilts alone let the linearised test apply.
        let yawed = Bounds::try_new([-1.0, -1.0, 0.0, -r, -r, 0.1], [1.0, 1.0, 0.05, r, r, 0.3]).unwrap();
        let mut problem = problem;
        problem.set_effort(crate::feasibility::THOROUGH_EFFORT);
        assert!(problem.exclusion(&corner, &yawed).is_some());
        let yawed_lower = Bounds::try_new([-1.0, -1.0, -0.05, -r, -r, 0.1], [1.0, 1.0, 0.05, r, r, 0.3]).unwrap();
        assert_eq!(problem.exclusion(&corner, &yawed_lower), None);
    }

    /// Soundness: every clean state the optimiser reaches on its own (no pruning in the
    /// way) survives every exclusion test over the bounds it was found in.
    #[test]
    fn states_found_without_pruning_are_never_excluded() {
        let r = 2f64.to_radians();
        let cases = [
            (crate::examples::l_block_and_box(), crate::examples::paper_bounds()),
            (
                (fixture("block_with_chamfered_hole.off"), fixture("peg.off")),
                Bounds::try_new([-2.0, -2.0, 0.0, -r, -r, -r], [2.0, 2.0, 45.0, r, r, r]).unwrap(),
            ),
        ];
        for ((a, b), bounds) in cases {
            let problem = super::super::Problem::new(&a, &b, bounds, DAffine3::IDENTITY);
            let mut checked = 0;
            for ppc in super::super::primitive_contacts(&a, &b) {
                for start in problem.starts(&[ppc], 3, problem.bounds()) {
                    let pose = problem.solve(&[ppc], start, problem.bounds());
                    if let Some(state) = problem.verify(&pose) {
                        checked += 1;
                        let at = Bounds::try_new(pose.to_array(), pose.to_array()).unwrap();
                        for b in [*problem.bounds(), at] {
                            assert_eq!(
                                problem.exclusion(&state, &b),
                                None,
                                "{state:?} excluded, witness {pose:?}"
                            );
                        }
                    }
                }
            }
            assert!(checked > 20, "only {checked} states reached");
        }
    }

    /// A corner on a face keeps the whole separation off the face's rim, as a robust
    /// witness does: three quarters of it in, the loosest checker reads the corner on
    /// the rim and the prover excludes the pose; one and a half in, both take it.
    #[test]
    fn a_corner_keeps_the_separation_off_the_faces_rim() {
        let (slab, cube) = crate::examples::cube_and_slab();
        let bounds = Bounds::try_new([80.0, 80.0, -5.0, -0.5, -0.5, -0.5], [110.0, 110.0, 5.0, 0.5, 0.5, 0.5]).unwrap();
        let problem = super::super::Problem::new(&slab, &cube, bounds, DAffine3::IDENTITY);
        let separation = scaled(SEPARATION_REL, problem.scale);
        // The cube hangs over the slab's corner (100, 100, 0), its bottom face tilted
        // to rise over the slab, resting on the corner `inside` from the face's edge
        // at x = 10 (in the cube's frame), which lies beyond the slab.
        let turn = [-0.2, 0.2, 0.0];
        let turned = Pose::from_array([0.0, 0.0, 0.0, turn[0], turn[1], turn[2]]).to_affine(&DAffine3::IDENTITY);
        let at = |inside: f64| {
            let t = DVec3::new(100.0, 100.0, 0.0) - turned.transform_point3(DVec3::new(10.0 - inside, 5.0, 0.0));
            [t.x, t.y, t.z, turn[0], turn[1], turn[2]]
        };
        let deep = at(1.5 * separation);
        let state = problem
            .scene()
            .evaluate(&Pose::from_array(deep).to_affine(&DAffine3::IDENTITY), CONTACT_REL)
            .contacts;
        assert!(
            state.len() == 1 && state[0].kind == ContactKind::VertexFace,
            "{state:?}"
        );
        assert_eq!(problem.clean_state(&Pose::from_array(deep)), Some(state.clone()));
        assert_eq!(problem.exclusion(&state, &around(deep, 0.0)), None);
        let shallow = at(0.75 * separation);
        assert_eq!(problem.clean_state(&Pose::from_array(shallow)), None);
        assert!(problem.exclusion(&state, &around(shallow, 0.0)).is_some());
    }
}
