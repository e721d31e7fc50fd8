//! Contact geometry at a pose: which elements touch, the contact state P(X) under the
//! principal-contact rule (docs/concepts.md#principal-contacts), and whether the parts
//! penetrate.
//!
//! ```
//! use acsg::contact::{ContactKind, ContactScene};
//! use glam::{DAffine3, DVec3};
//!
//! let (l_block, box_part) = acsg::examples::l_block_and_box();
//! let scene = ContactScene::new(&l_block, &box_part);
//! // At the assembled pose the box lies flat on the floor and against the wall.
//! let report = scene.evaluate(&DAffine3::IDENTITY, acsg::tolerance::CONTACT_REL);
//! let kinds: Vec<ContactKind> = report.contacts.iter().map(|c| c.kind).collect();
//! assert_eq!(kinds, [ContactKind::FaceFace, ContactKind::FaceFace]);
//! assert_eq!(report.penetration, 0.0);
//! // Lifted by 10 it touches the wall only.
//! let lifted = DAffine3::from_translation(DVec3::new(0.0, 0.0, 10.0));
//! assert_eq!(scene.evaluate(&lifted, acsg::tolerance::CONTACT_REL).contacts.len(), 1);
//! ```

mod bvh;
mod gauss;
mod penetration;
mod placed;
mod separation;
mod touch;

use std::fmt;

use glam::{DAffine3, DVec3};
use serde::{Deserialize, Serialize};

use bvh::Bvh;
pub use penetration::{PenetrationReport, penetration};
use placed::PlacedPart;
pub use separation::{Separation, convex_separation};

use crate::geometry::Aabb;
use crate::model::{ElementId, Part, length_scale};
use crate::tolerance::{GAP_SEARCH_REL, scaled};

/// The ten kinds of principal contact, the fixed part's element first.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
pub enum ContactKind {
    /// Face on face.
    #[serde(rename = "f-f")]
    FaceFace,
    /// An edge of the moving part lying in a face of the fixed part.
    #[serde(rename = "f-e")]
    FaceEdge,
    /// An edge of the fixed part lying in a face of the moving part.
    #[serde(rename = "e-f")]
    EdgeFace,
    /// A vertex of the moving part on a face of the fixed part.
    #[serde(rename = "f-v")]
    FaceVertex,
    /// A vertex of the fixed part on a face of the moving part.
    #[serde(rename = "v-f")]
    VertexFace,
    /// Two edges crossing at a point.
    #[serde(rename = "e-e")]
    EdgeEdge,
    /// Two collinear edges overlapping along a segment.
    #[serde(rename = "e-e-t")]
    EdgeEdgeTouch,
    /// A vertex of the moving part inside an edge of the fixed part.
    #[serde(rename = "e-v")]
    EdgeVertex,
    /// A vertex of the fixed part inside an edge of the moving part.
    #[serde(rename = "v-e")]
    VertexEdge,
    /// Vertex on vertex.
    #[serde(rename = "v-v")]
    VertexVertex,
}

impl ContactKind {
    /// The label used in outputs: `f-v`, `e-e-t`, ...
    #[must_use]
    pub fn label(self) -> &'static str {
        match self {
            ContactKind::FaceFace => "f-f",
            ContactKind::FaceEdge => "f-e",
            ContactKind::EdgeFace => "e-f",
            ContactKind::FaceVertex => "f-v",
            ContactKind::VertexFace => "v-f",
            ContactKind::EdgeEdge => "e-e",
            ContactKind::EdgeEdgeTouch => "e-e-t",
            ContactKind::EdgeVertex => "e-v",
            ContactKind::VertexEdge => "v-e",
            ContactKind::VertexVertex => "v-v",
        }
    }

    /// The kind of a contact between element `fixed` of the fixed part and element
    /// `moving` of the moving part; two edges touching along a segment are e-e-t,
    /// otherwise e-e. The one place where a pair of elements is told apart by kinds.
    #[must_use]
    pub fn of(fixed: ElementId, moving: ElementId, along_segment: bool) -> ContactKind {
        use ElementId::{Edge, Face, Vertex};
        match (fixed, moving) {
            (Face(_), Face(_)) => ContactKind::FaceFace,
            (Face(_), Edge(_)) => ContactKind::FaceEdge,
            (Edge(_), Face(_)) => ContactKind::EdgeFace,
            (Face(_), Vertex(_)) => ContactKind::FaceVertex,
            (Vertex(_), Face(_)) => ContactKind::VertexFace,
            (Edge(_), Edge(_)) if along_segment => ContactKind::EdgeEdgeTouch,
            (Edge(_), Edge(_)) => ContactKind::EdgeEdge,
            (Edge(_), Vertex(_)) => ContactKind::EdgeVertex,
            (Vertex(_), Edge(_)) => ContactKind::VertexEdge,
            (Vertex(_), Vertex(_)) => ContactKind::VertexVertex,
        }
    }
}

impl fmt::Display for ContactKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.label())
    }
}

/// One principal contact of a contact state.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct PrincipalContact {
    /// The element of the fixed part.
    pub fixed: ElementId,
    /// The element of the moving part.
    pub moving: ElementId,
    /// Its kind.
    pub kind: ContactKind,
}

/// The contact as text: kind, fixed element, moving element (`f-v f3 v7`).
///
/// ```
/// use acsg::contact::{ContactKind, PrincipalContact};
/// let pc = PrincipalContact { fixed: "f3".parse().unwrap(), moving: "v7".parse().unwrap(), kind: ContactKind::FaceVertex };
/// assert_eq!(pc.to_string(), "f-v f3 v7");
/// ```
impl fmt::Display for PrincipalContact {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{} {} {}", self.kind, self.fixed, self.moving)
    }
}

impl PrincipalContact {
    /// Whether the contact is degenerate: v-v, e-v, v-e or e-e-t with both elements
    /// convex (it holds only on a set that any small motion leaves).
    #[must_use]
    pub fn degenerate(&self, fixed: &Part, moving: &Part) -> bool {
        use ContactKind::{EdgeEdgeTouch, EdgeVertex, VertexEdge, VertexVertex};
        matches!(self.kind, VertexVertex | EdgeVertex | VertexEdge | EdgeEdgeTouch)
            && fixed.is_convex(self.fixed)
            && moving.is_convex(self.moving)
    }

    /// Degrees of freedom left by this contact alone (docs/concepts.md#degrees-of-freedom):
    /// 5 for single-point contacts, 4 for an edge in a face or a vertex in an edge, 3 for
    /// face on face or vertex on vertex, 2 for collinear edges.
    #[must_use]
    pub fn dof(&self) -> u8 {
        match self.kind {
            ContactKind::FaceVertex | ContactKind::VertexFace | ContactKind::EdgeEdge => 5,
            ContactKind::FaceEdge | ContactKind::EdgeFace | ContactKind::EdgeVertex | ContactKind::VertexEdge => 4,
            ContactKind::FaceFace | ContactKind::VertexVertex => 3,
            ContactKind::EdgeEdgeTouch => 2,
        }
    }
}

/// What [`ContactScene::evaluate`] finds at one pose.
#[derive(Clone, Debug, PartialEq)]
pub struct ContactReport {
    /// P(X): the principal contacts, sorted by (fixed, moving) element.
    pub contacts: Vec<PrincipalContact>,
    /// How deep the parts penetrate: 0 when they touch (overlap up to the tolerance) or
    /// are apart.
    pub penetration: f64,
    /// The smallest distance between two elements that do not touch, if below
    /// [`GAP_SEARCH_REL`]` · L`; `None` when every such pair is at least that far apart.
    pub min_gap: Option<f64>,
    /// The absolute contact tolerance used.
    pub tolerance: f64,
}

/// A fixed and a moving part, prepared for many contact evaluations: the fixed part's
/// elements are placed and indexed once.
#[derive(Debug)]
pub struct ContactScene<'a> {
    fixed: PlacedPart<'a>,
    moving_local: PlacedPart<'a>,
    moving: &'a Part,
    fixed_elements: Vec<ElementId>,
    fixed_boxes: Vec<Aabb>,
    moving_elements: Vec<ElementId>,
    moving_bvh: Bvh,
    fixed_pieces: penetration::PreparedPieces,
    moving_pieces: penetration::PreparedPieces,
    bvh: Bvh,
    scale: f64,
}

impl<'a> ContactScene<'a> {
    /// Prepares a scene.
    #[must_use]
    pub fn new(fixed: &'a Part, moving: &'a Part) -> ContactScene<'a> {
        let placed = PlacedPart::new(fixed, &DAffine3::IDENTITY);
        let fixed_elements = fixed.elements();
        let boxes: Vec<Aabb> = fixed_elements.iter().map(|&e| placed.bounds(e)).collect();
        let scale = length_scale(fixed, moving);
        let bvh = Bvh::new(&boxes);
        let moving_local = PlacedPart::new(moving, &DAffine3::IDENTITY);
        let moving_elements = moving.elements();
        let moving_boxes: Vec<Aabb> = moving_elements.iter().map(|&e| moving_local.bounds(e)).collect();
        ContactScene {
            fixed: placed,
            moving,
            fixed_elements,
            fixed_boxes: boxes,
            moving_bvh: Bvh::new(&moving_boxes),
            moving_local,
            moving_elements,
            fixed_pieces: penetration::PreparedPieces::new(fixed),
            moving_pieces: penetration::PreparedPieces::new(moving),
            bvh,
            scale,
        }
    }

    /// The signed penetration depth on the convex pieces ([`penetration()`]):
    /// positive when the parts penetrate, at most zero otherwise.
    #[must_use]
    pub fn penetration_depth(&self, moving_to_fixed: &DAffine3) -> f64 {
        penetration::penetration_prepared(&self.fixed_pieces, &self.moving_pieces, moving_to_fixed, self.scale).depth
    }

    /// Whether the parts penetrate by more than `depth` (at least 0): the same answer as
    /// `penetration_depth(..) > depth`, faster (pairs of pieces are dropped as soon as
    /// they cannot penetrate by more).
    #[must_use]
    pub fn penetrates_beyond(&self, moving_to_fixed: &DAffine3, depth: f64) -> bool {
        penetration::penetrates_beyond(&self.fixed_pieces, &self.moving_pieces, moving_to_fixed, depth)
    }

    /// The penetration depth when positive, else 0: the same value as
    /// `penetration_depth(..).max(0.0)`, faster (a pair of pieces is dropped at its first
    /// separating axis).
    #[must_use]
    pub fn penetration_excess(&self, moving_to_fixed: &DAffine3) -> f64 {
        penetration::penetration_excess(&self.fixed_pieces, &self.moving_pieces, moving_to_fixed)
    }

    /// The open intervals of `s` over which the moving part, placed by
    /// `moving_to_fixed` and then translated by `s · direction`, penetrates the fixed
    /// part by more than `depth`: one interval per pair of convex pieces that penetrates
    /// somewhere on the line (unsorted; their union is where the line is blocked).
    #[must_use]
    pub fn blocked_along(&self, moving_to_fixed: &DAffine3, direction: DVec3, depth: f64) -> Vec<(f64, f64)> {
        penetration::blocked_along(
            &self.fixed_pieces,
            &self.moving_pieces,
            moving_to_fixed,
            direction,
            depth,
        )
    }

    /// The distance between the closures of two elements of one part (the fixed one
    /// if `fixed`, else the moving one, in its own frame).
    #[must_use]
    pub fn distance_within(&self, fixed: bool, a: ElementId, b: ElementId) -> f64 {
        let part = if fixed { &self.fixed } else { &self.moving_local };
        touch::distance(part, a, part, b)
    }

    /// The distance between a fixed and a moving element's closures with the moving
    /// part placed by `moving_to_fixed`.
    #[must_use]
    pub fn element_distance(&self, moving_to_fixed: &DAffine3, fixed: ElementId, moving: ElementId) -> f64 {
        let placed = PlacedPart::new(self.moving, moving_to_fixed);
        touch::distance(&self.fixed, fixed, &placed, moving)
    }

    /// The fixed and the moving part.
    #[must_use]
    pub fn parts(&self) -> (&'a Part, &'a Part) {
        (self.fixed.part, self.moving)
    }

    /// L: the larger bounding-box diagonal of the two parts.
    #[must_use]
    pub fn scale(&self) -> f64 {
        self.scale
    }

    /// The contact state, penetration and smallest gap with the moving part placed by
    /// `moving_to_fixed`; contacts hold within `relative_tolerance · L`.
    #[must_use]
    pub fn evaluate(&self, moving_to_fixed: &DAffine3, relative_tolerance: f64) -> ContactReport {
        self.run(
            moving_to_fixed,
            relative_tolerance,
            Some(scaled(GAP_SEARCH_REL, self.scale)),
        )
    }

    /// [`ContactScene::evaluate`] without the search for the smallest gap (`min_gap` is
    /// `None`): P(X) and penetration only, the cheaper query for tight loops.
    #[must_use]
    pub fn state(&self, moving_to_fixed: &DAffine3, relative_tolerance: f64) -> ContactReport {
        self.run(moving_to_fixed, relative_tolerance, None)
    }

    /// The pairs of a fixed and a moving element that do not touch (within
    /// `relative_tolerance · L`) but are closer than `within`, sorted: what keeps a pose
    /// from being a clean witness when its smallest gap is too small.
    #[must_use]
    pub fn close_pairs(
        &self,
        moving_to_fixed: &DAffine3,
        relative_tolerance: f64,
        within: f64,
    ) -> Vec<(ElementId, ElementId)> {
        let tol = scaled(relative_tolerance, self.scale);
        let moving = PlacedPart::new(self.moving, moving_to_fixed);
        let mut out = Vec::new();
        self.bvh.query_pairs(&self.moving_bvh, moving_to_fixed, within, |i, j| {
            let (a, b) = (self.fixed_elements[i as usize], self.moving_elements[j as usize]);
            let box_gap = self.fixed_boxes[i as usize].gap(&moving.bounds(b));
            if self.gap_below(&moving, a, b, box_gap, tol, within).is_some() {
                out.push((a, b));
            }
        });
        out.sort();
        out
    }

    /// Every pair of a fixed and a moving element closer than `within`, touching or
    /// not, sorted: [`ContactScene::close_pairs`] with no pair counted as touching.
    #[must_use]
    pub fn pairs_within(&self, moving_to_fixed: &DAffine3, within: f64) -> Vec<(ElementId, ElementId)> {
        self.close_pairs(moving_to_fixed, f64::NEG_INFINITY, within)
    }

    /// [`ContactScene::evaluate`] with the smallest gap searched only up to
    /// `gap_search` (a length): `min_gap` is `None` when every pair that does not touch
    /// is at least that far apart. Enough to tell a clean witness (gap at least the
    /// separation tolerance) from a borderline pose, and much cheaper than the full
    /// search when the parts are close all around (a peg in its hole).
    #[must_use]
    pub fn evaluate_within(
        &self,
        moving_to_fixed: &DAffine3,
        relative_tolerance: f64,
        gap_search: f64,
    ) -> ContactReport {
        self.run(moving_to_fixed, relative_tolerance, Some(gap_search))
    }

    /// The distance between a fixed and a placed moving element when it is more than
    /// `tol` (they do not touch) and less than `limit`; `None` otherwise. The boxes'
    /// gap (`box_gap`) and the elements' face planes rule most pairs out before the
    /// exact distance is computed.
    fn gap_below(
        &self,
        moving: &PlacedPart<'_>,
        a: ElementId,
        b: ElementId,
        box_gap: f64,
        tol: f64,
        limit: f64,
    ) -> Option<f64> {
        if box_gap >= limit || touch::apart_by_plane(&self.fixed, a, moving, b, limit) {
            return None;
        }
        let d = touch::distance(&self.fixed, a, moving, b);
        (d > tol && d < limit).then_some(d)
    }

    /// P(X) as [`ContactScene::state`] gives it, but read over the overlap
    /// ([`touch::Reading::Overlap`]): an edge or face lying on a face where they
    /// overlap, whatever lies beyond the face's rim at a tiny angle. Where the two
    /// readings differ, checkers may read either state, so no witness shows one.
    #[must_use]
    pub(crate) fn state_over_overlap(
        &self,
        moving_to_fixed: &DAffine3,
        relative_tolerance: f64,
    ) -> Vec<PrincipalContact> {
        self.read(moving_to_fixed, relative_tolerance, None, touch::Reading::Overlap)
            .contacts
    }

    fn run(&self, moving_to_fixed: &DAffine3, relative_tolerance: f64, gap_search: Option<f64>) -> ContactReport {
        self.read(moving_to_fixed, relative_tolerance, gap_search, touch::Reading::Ends)
    }

    fn read(
        &self,
        moving_to_fixed: &DAffine3,
        relative_tolerance: f64,
        gap_search: Option<f64>,
        reading: touch::Reading,
    ) -> ContactReport {
        let tol = scaled(relative_tolerance, self.scale);
        let with_gap = gap_search.is_some();
        let search = gap_search.map_or(tol, |g| g.max(2.0 * tol));
        let moving = PlacedPart::new(self.moving, moving_to_fixed);
        let mut touches = Vec::new();
        let mut min_gap: Option<f64> = None;
        self.bvh.query_pairs(&self.moving_bvh, moving_to_fixed, search, |i, j| {
            let (a, b) = (self.fixed_elements[i as usize], self.moving_elements[j as usize]);
            // The boxes' gap bounds the elements' distance from below.
            let box_gap = self.fixed_boxes[i as usize].gap(&moving.bounds(b));
            if box_gap <= tol {
                if let Some(set) = touch::touch(&self.fixed, a, &moving, b, tol, reading) {
                    touches.push((a, b, set));
                    return;
                }
            }
            if with_gap {
                if let Some(d) = self.gap_below(&moving, a, b, box_gap, tol, min_gap.unwrap_or(search)) {
                    min_gap = Some(d);
                }
            }
        });
        let mut contacts: Vec<PrincipalContact> = touch::principal(self.fixed.part, self.moving, &touches, tol)
            .into_iter()
            .map(|(a, b)| {
                let along_segment = touches
                    .iter()
                    .any(|(x, y, set)| (*x, *y) == (a, b) && matches!(set, touch::TouchSet::Segments(_)));
                PrincipalContact {
                    fixed: a,
                    moving: b,
                    kind: ContactKind::of(a, b, along_segment),
                }
            })
            .collect();
        contacts.sort();
        let depth = self.penetration_depth(moving_to_fixed);
        // Within the contact tolerance, overlap is touching (rounding of the placement).
        let penetration = if depth > tol { depth } else { 0.0 };
        ContactReport {
            contacts,
            penetration,
            min_gap,
            tolerance: tol,
        }
    }
}

/// One contact as written in JSON outputs.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct ContactRecord {
    /// The kind: `f-v`, `e-e-t`, ...
    #[serde(rename = "type")]
    pub kind: ContactKind,
    /// The fixed part's element: `f3`, `e5`, `v7`.
    pub fixed: ElementId,
    /// The moving part's element.
    pub moving: ElementId,
    /// Degrees of freedom this contact leaves.
    pub dof: u8,
    /// Whether it is degenerate.
    pub degenerate: bool,
}

impl ContactRecord {
    /// The record of a contact between two parts.
    #[must_use]
    pub fn of(contact: &PrincipalContact, fixed: &Part, moving: &Part) -> ContactRecord {
        ContactRecord {
            kind: contact.kind,
            fixed: contact.fixed,
            moving: contact.moving,
            dof: contact.dof(),
            degenerate: contact.degenerate(fixed, moving),
        }
    }
}

#[cfg(test)]
mod tests {
    use glam::{DMat3, DVec3};

    use super::*;
    use crate::testing::edge_between;
    use crate::tolerance::CONTACT_REL;

    /// The box's vertical edge (foot at z = 50, head at z = 150 in the box's frame) by
    /// the L-block's wall (x = 150): placed yawed 0.1 rad, leaning off the wall by a
    /// slope, its foot at a given point ([`WallEdge::placed`]); whether a state has it
    /// in the wall (f-e).
    struct WallEdge {
        parts: (Part, Part),
        edge: ElementId,
    }

    impl WallEdge {
        const FOOT: DVec3 = DVec3::new(150.0, 10.0, 50.0);

        fn new() -> WallEdge {
            let parts = crate::examples::l_block_and_box();
            let edge = edge_between(&parts.1, Self::FOOT, DVec3::new(150.0, 10.0, 150.0));
            WallEdge { parts, edge }
        }

        /// The scene and the contact tolerance.
        fn scene(&self) -> (ContactScene<'_>, f64) {
            let scene = ContactScene::new(&self.parts.0, &self.parts.1);
            let tol = CONTACT_REL * scene.scale();
            (scene, tol)
        }

        fn placed(slope: f64, foot_at: DVec3) -> DAffine3 {
            let r = DMat3::from_rotation_y(-slope.atan()) * DMat3::from_rotation_z(0.1);
            DAffine3::from_mat3_translation(r, foot_at - r * Self::FOOT)
        }

        fn on_wall(&self, contacts: &[PrincipalContact]) -> bool {
            contacts
                .iter()
                .any(|pc| pc.moving == self.edge && pc.kind == ContactKind::FaceEdge)
        }
    }

    /// The wall edge's foot 40 below the wall's top rim (z = 150) and its head 60 above
    /// it: read from end to end it lies in the wall only upright; read over the overlap,
    /// also while its stretch over the wall stays within the tolerance, however far its
    /// head beyond the rim is.
    #[test]
    fn an_edge_over_a_walls_rim_lies_in_the_wall_read_over_the_overlap() {
        let wall = WallEdge::new();
        let (scene, tol) = wall.scene();
        let placed = |slope: f64| WallEdge::placed(slope, DVec3::new(150.0, 30.0, 110.0));
        let kinds = |contacts: &[PrincipalContact]| contacts.iter().map(|pc| pc.kind).collect::<Vec<_>>();
        // Upright: both readings put the edge in the wall.
        let upright = placed(0.0);
        assert!(wall.on_wall(&scene.state(&upright, CONTACT_REL).contacts));
        assert!(wall.on_wall(&scene.state_over_overlap(&upright, CONTACT_REL)));
        // Leaning by tolerance/90 per unit: the head, 100 up, is beyond the tolerance.
        let leaning = placed(tol / 90.0);
        let ends = scene.state(&leaning, CONTACT_REL).contacts;
        assert!(!wall.on_wall(&ends), "{:?}", kinds(&ends));
        assert!(wall.on_wall(&scene.state_over_overlap(&leaning, CONTACT_REL)));
        // Ten times more, the stretch over the wall leaves the plane: no reading has it.
        let steeper = placed(tol / 9.0);
        assert!(!wall.on_wall(&scene.state_over_overlap(&steeper, CONTACT_REL)));
    }

    /// The wall edge's foot just under the wall's top rim, 1.1e-6 L below it and 0.85
    /// tolerances inside the wall's plane, leaning off the wall so that the rim is
    /// crossed 0.85 tolerances outside it: its stretch over the wall has two points
    /// within the tolerance of the plane, more than the loosest reading's separation
    /// (0.99e-6 L) apart, at a tilt of 1.55e-3. DOMAIN reads such an edge lying in the
    /// wall, and so does the reading over the overlap (it did not while `FLUSH_TILT` was
    /// 1.4e-3, which left a band of poses no reading ruled out). Twice as steep, the
    /// stretch within the tolerance is shorter than the separation: not read.
    #[test]
    fn a_stretch_over_the_wall_one_separation_long_lies_in_the_wall_read_over_the_overlap() {
        let wall = WallEdge::new();
        let (scene, tol) = wall.scene();
        let below_rim = 1.1e-6 * scene.scale();
        let foot_at = DVec3::new(150.0 + 0.85 * tol, 30.0, 150.0 - below_rim);
        // The steepest stretch with both ends within the tolerance and the loosest
        // reading's separation apart is still read flat.
        let steepest = 2.0 * CONTACT_REL / crate::feasibility::LOOSE_CONTACT_REL;
        assert!(crate::tolerance::FLUSH_TILT >= steepest);
        let slope = 1.7 * tol / below_rim;
        assert!(slope > 1.4e-3 && slope < steepest);
        let read = |slope: f64| wall.on_wall(&scene.state_over_overlap(&WallEdge::placed(slope, foot_at), CONTACT_REL));
        assert!(read(slope));
        assert!(!read(2.0 * slope));
    }

    /// A witness the search found at a higher effort: the box's corner v6 on the
    /// L-block's concave corner v6, the L-block's floor edge e7 lying in the box's face
    /// f2, and the box's edge e6 from that corner crossing e7 3.4e-4 mm away at an
    /// angle of 1.8e-4 rad, because the corners are 5e-8 mm apart. Read from end to end,
    /// the corners' contact stays principal (the edge's stretch in the face stops at the
    /// crossing); read over the overlap, e6 has its end and the crossing on e7's line,
    /// so it runs along e7 (e-e-t) and the readings disagree: no witness. In exact
    /// geometry the corners coincide, the crossing is the corner, and the state is the
    /// edge in the face alone.
    #[test]
    fn an_edge_crossing_another_near_its_end_runs_along_it_read_over_the_overlap() {
        let (block, bx) = crate::examples::l_block_and_box();
        let scene = ContactScene::new(&block, &bx);
        let pose = crate::pose::Pose::from_array([
            -0.0017440112563633647,
            -0.7649061686836358,
            28.883407230713246,
            -0.30053863035103057,
            -5.736010645374471e-06,
            -1.8509079748124447e-05,
        ]);
        let placed = pose.to_affine(&DAffine3::IDENTITY);
        let id = |s: &str| -> ElementId { s.parse().unwrap() };
        let ends = scene.state(&placed, CONTACT_REL).contacts;
        let labels = |contacts: &[PrincipalContact]| contacts.iter().map(ToString::to_string).collect::<Vec<_>>();
        assert_eq!(labels(&ends), ["e-f e7 f2", "v-v v6 v6"]);
        let overlap = scene.state_over_overlap(&placed, CONTACT_REL);
        assert!(
            overlap
                .iter()
                .any(|pc| (pc.fixed, pc.moving, pc.kind) == (id("e7"), id("e6"), ContactKind::EdgeEdgeTouch)),
            "{:?}",
            labels(&overlap)
        );
    }
}
