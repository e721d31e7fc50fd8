//! Two crossing edges over a box of poses: where along each the crossing may lie, and
//! how far the box's poses move a point from where its centre puts it.

use glam::DVec3;

use super::Problem;
use crate::model::EdgeId;
use crate::pose::Bounds;
use crate::tolerance::{CONTACT_REL, scaled};

/// Two crossing edges, the fixed one in G's frame and the moving one in its part's
/// frame, and the contact tolerance they cross within.
#[derive(Clone, Copy, Debug)]
pub(super) struct EdgePair {
    pub(super) fixed: [DVec3; 2],
    pub(super) moving: [DVec3; 2],
    pub(super) tolerance: f64,
}

impl EdgePair {
    /// The least distance, at any pose of `b`, from the crossing (the contact within the
    /// tolerance) to an end of either edge; zero when nothing is known.
    pub(super) fn least_from_ends(&self, b: &Bounds) -> f64 {
        self.distances_from_ends(b)
            .iter()
            .flatten()
            .fold(f64::INFINITY, |m, &d| m.min(d))
    }

    /// The least distance, at any pose of `b`, from the crossing to each end of each edge
    /// (the fixed edge's, then the moving edge's, in their order); zero when nothing is
    /// known.
    pub(super) fn distances_from_ends(&self, b: &Bounds) -> [[f64; 2]; 2] {
        let positions = self.crossing_positions(b);
        let ends = |edge: &[DVec3; 2], range: Option<(f64, f64)>| {
            let length = edge[0].distance(edge[1]);
            range.map_or([0.0; 2], |(lo, hi)| [lo.max(0.0), (length - hi).max(0.0)])
        };
        [ends(&self.fixed, positions[0]), ends(&self.moving, positions[1])]
    }

    /// Where along each of two crossing edges (from its first end) the crossing lies at
    /// any pose of `b`, fixed edge (in G's frame) then moving edge (in its part's frame):
    /// within the tolerance, plus how far the box moves the other edge, of that edge's
    /// line at the box's centre, so |s − s_c| sin θ is at most that. `None` for an edge
    /// (nearly) parallel to the other at the centre.
    pub(super) fn crossing_positions(&self, b: &Bounds) -> [Option<(f64, f64)>; 2] {
        let (fixed, moving, tolerance) = (&self.fixed, &self.moving, self.tolerance);
        let centre = CentreMotion::of(b);
        let along = |on: &[DVec3; 2], line: [DVec3; 2], within: f64| {
            let length = on[0].distance(on[1]);
            let (d, m) = ((on[1] - on[0]) / length, (line[1] - line[0]).normalize());
            let sine = d.cross(m).length();
            if sine <= 1e-12 {
                return None;
            }
            // The closest point of `on`'s line to `line`'s.
            let r = on[0] - line[0];
            let (cosine, c, e) = (d.dot(m), d.dot(r), m.dot(r));
            let s = (cosine * e - c) / (1.0 - cosine * cosine);
            let half = within / sine;
            Some((s - half, s + half))
        };
        let placed = moving.map(|p| centre.moving_to_g(p));
        let moving_shift = placed.iter().map(|&(_, moved)| moved).fold(0.0, f64::max);
        let on_fixed = along(fixed, placed.map(|(p, _)| p), tolerance + moving_shift);
        let fixed_in_b = fixed.map(|p| centre.g_to_moving(p));
        let fixed_shift = fixed_in_b.iter().map(|&(_, moved)| moved).fold(0.0, f64::max);
        let on_moving = along(moving, fixed_in_b.map(|(p, _)| p), tolerance + fixed_shift);
        [on_fixed, on_moving]
    }
}

/// The pose at a box's centre and how far the box moves any point from where that pose
/// puts it: the translations' half diagonal, plus the half widths of the angles summed
/// times the point's distance from the centre of rotation.
pub(super) struct CentreMotion {
    rotation: glam::DMat3,
    translation: DVec3,
    shift: f64,
    turn: f64,
}

impl CentreMotion {
    pub(super) fn of(b: &Bounds) -> CentreMotion {
        let (centre, w) = (b.center(), b.width());
        CentreMotion {
            rotation: centre.rotation(),
            translation: centre.translation(),
            shift: 0.5 * DVec3::new(w[0], w[1], w[2]).length(),
            turn: 0.5 * (w[3] + w[4] + w[5]),
        }
    }

    /// A point of the moving part placed in G's frame, and how far it moves over the box.
    pub(super) fn moving_to_g(&self, p: DVec3) -> (DVec3, f64) {
        (
            self.rotation * p + self.translation,
            self.shift + self.turn * p.length(),
        )
    }

    /// A point of G's frame seen in the moving part's frame, and how far it moves there
    /// over the box.
    pub(super) fn g_to_moving(&self, p: DVec3) -> (DVec3, f64) {
        (
            self.rotation.transpose() * (p - self.translation),
            self.shift + self.turn * p.distance(self.translation),
        )
    }
}

impl Problem<'_> {
    /// A fixed and a moving edge as crossing edges ([`EdgePair`]).
    pub(super) fn edge_pair(&self, e: EdgeId, x: EdgeId) -> EdgePair {
        EdgePair {
            fixed: self.fixed.edge_points(e).map(|p| self.prover.fixed_point(p)),
            moving: self.moving.edge_points(x),
            tolerance: scaled(CONTACT_REL, self.scale),
        }
    }
}
