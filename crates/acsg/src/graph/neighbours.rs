//! The neighbour relation of a finished set of states (DOMAIN.md section 4): two states
//! are neighbours when their regions of poses touch. Found two ways, whatever strategy
//! found the states: one PPC apart under the mapping rules, and by reading the state
//! at small steps from each witness.

use std::collections::{BTreeSet, HashMap};

use glam::{DMat3, DVec3};
use rayon::prelude::*;

use super::{State, rules};
use crate::contact::{ContactKind, PrincipalContact};
use crate::feasibility::lp::{self, Row, VARS};
use crate::feasibility::{Problem, is_primitive};
use crate::model::{ElementId, Part};
use crate::pose::Pose;

/// The step from a witness at which [`probe`] reads a neighbouring state (relative to
/// L for translations, radians for angles); the reading is confirmed a tenth of the
/// way.
const PROBE_STEP: f64 = 1e-4;

/// Neighbour pairs of state ids, each `[smaller, larger]`, sorted: free space with every
/// single-PPC state; a state with each state it grows into by one PPC. The PPCs tried
/// are those some known state implies: a state grown into holds the PPC made, whether
/// or not that PPC was found feasible alone. Then the pairs the probes find.
pub(crate) fn neighbours(
    fixed: &Part,
    moving: &Part,
    states: &[State],
    index: &HashMap<Vec<PrincipalContact>, usize>,
    problem: &Problem<'_>,
) -> Vec<[usize; 2]> {
    let made: BTreeSet<PrincipalContact> = states
        .iter()
        .flat_map(|s| rules::state_primitives(fixed, moving, &s.contacts))
        .collect();
    let mut edges = BTreeSet::new();
    for state in &states[1..] {
        if let [pc] = state.contacts[..] {
            if is_primitive(&pc) {
                edges.insert([0, state.id]);
            }
        }
        let implied = rules::state_primitives(fixed, moving, &state.contacts);
        for ppc in made.iter().filter(|p| !implied.contains(p)) {
            for target in rules::grow_every(fixed, moving, &state.contacts, *ppc) {
                if let Some(&other) = index.get(&target) {
                    // Making one PPC keeps every PPC the state had.
                    let keeps = rules::state_primitives(fixed, moving, &target).is_superset(&implied);
                    if other != state.id && keeps {
                        edges.insert([state.id.min(other), state.id.max(other)]);
                    }
                }
            }
        }
    }
    let probed: Vec<Vec<usize>> = states[1..]
        .par_iter()
        .map(|s| probe(fixed, moving, s, index, problem))
        .collect();
    for (state, others) in states[1..].iter().zip(probed) {
        for other in others {
            edges.insert([state.id.min(other), state.id.max(other)]);
        }
    }
    edges.into_iter().collect()
}

/// The known states (free space included) whose regions touch this state's at its
/// witness: the state read at small steps from the witness, in every direction along
/// one or two pose components that the bounds leave free (a rotation-pinned face on a
/// face steps straight into free space). A step counts when a step ten times smaller
/// reads the same state, so that the other region reaches the witness itself.
fn probe(
    fixed: &Part,
    moving: &Part,
    state: &State,
    index: &HashMap<Vec<PrincipalContact>, usize>,
    problem: &Problem<'_>,
) -> Vec<usize> {
    let Some(witness) = state.witness else {
        return Vec::new();
    };
    let bounds = problem.bounds();
    let width = bounds.width();
    let free: Vec<usize> = (0..6).filter(|&k| width[k] > 0.0).collect();
    let mut directions: Vec<[f64; 6]> = Vec::new();
    for (i, &k) in free.iter().enumerate() {
        for sign in [1.0, -1.0] {
            let mut d = [0.0; 6];
            d[k] = sign;
            directions.push(d);
        }
        for &j in &free[i + 1..] {
            for (a, b) in [(1.0, 1.0), (1.0, -1.0), (-1.0, 1.0), (-1.0, -1.0)] {
                let mut d = [0.0; 6];
                d[k] = a;
                d[j] = b;
                directions.push(d);
            }
        }
    }
    directions.extend(sliding_directions(fixed, moving, state, &witness, problem));
    let scale = problem.scene().scale();
    let x = witness.to_array();
    let read = |d: &[f64; 6], step: f64| {
        let pose = Pose::from_array(std::array::from_fn(|k| {
            x[k] + d[k] * step * if k < 3 { scale } else { 1.0 }
        }));
        // Outside the bounds it reads nothing, with the same round-off allowed as at a
        // witness (a pinned angle at -1e-22 rad).
        problem.clean_state(&pose)
    };
    let mut out = BTreeSet::new();
    for d in &directions {
        let Some(far) = read(d, PROBE_STEP) else { continue };
        if far != state.contacts && read(d, 0.1 * PROBE_STEP).as_ref() == Some(&far) {
            if let Some(&other) = index.get(&far) {
                out.insert(other);
            }
        }
    }
    out.into_iter().collect()
}

/// How fast, per unit of translation, a broken contact's gap must open along a sliding
/// direction: at the probe's smaller step (a tenth of [`PROBE_STEP`]) the gap is then
/// five times the separation the witness check asks for
/// ([`crate::tolerance::SEPARATION_REL`]).
const OPENING_RATE: f64 = 0.5;

/// Translations from a witness that break chosen contacts of the state and keep the
/// others exactly (each plane contact's normal orthogonal to the move), one for each
/// nonempty set of contacts broken that some translation within the bounds breaks:
/// the regions of the states one or more contacts below that touch this one, reached
/// whatever pose components the witness happens to sit at (an edge lying on a tilted
/// wall lifts off along the wall's normal, which no single axis need follow). Empty
/// when a contact has no single separating normal (a vertex or edge on an edge, a
/// vertex on a vertex).
fn sliding_directions(
    fixed: &Part,
    moving: &Part,
    state: &State,
    witness: &Pose,
    problem: &Problem<'_>,
) -> Vec<[f64; 6]> {
    const MOST_CONTACTS: usize = 6;
    let contacts = &state.contacts;
    if contacts.is_empty() || contacts.len() > MOST_CONTACTS {
        return Vec::new();
    }
    let rotation = problem.placement(witness).matrix3;
    let Some(normals) = contacts
        .iter()
        .map(|pc| separating_normal(fixed, moving, &rotation, pc))
        .collect::<Option<Vec<DVec3>>>()
    else {
        return Vec::new();
    };
    // The translation's box: a component at its bound moves inward only, a pinned
    // one not at all; the angles stay.
    let (bounds, x) = (problem.bounds(), witness.to_array());
    let (min, max) = (bounds.min.to_array(), bounds.max.to_array());
    let step = PROBE_STEP * problem.scene().scale();
    let mut lo = [0.0; VARS];
    let mut hi = [0.0; VARS];
    for k in 0..3 {
        lo[k] = if x[k] - step >= min[k] { -1.0 } else { 0.0 };
        hi[k] = if x[k] + step <= max[k] { 1.0 } else { 0.0 };
    }
    let row = |n: DVec3, lo: f64, hi: f64| Row {
        a: [n.x, n.y, n.z, 0.0, 0.0, 0.0],
        lo,
        hi,
    };
    let mut out = Vec::new();
    for broken in 1..(1usize << contacts.len()) {
        let rows: Vec<Row> = normals
            .iter()
            .enumerate()
            .map(|(i, &n)| {
                if broken & (1 << i) != 0 {
                    row(n, OPENING_RATE, f64::INFINITY)
                } else {
                    row(n, 0.0, 0.0)
                }
            })
            .collect();
        let meets = |t: DVec3| {
            let a = t.to_array();
            (0..3).all(|k| a[k] >= lo[k] - 1e-12 && a[k] <= hi[k] + 1e-12)
                && rows.iter().all(|r| {
                    let v = r.a[0] * a[0] + r.a[1] * a[1] + r.a[2] * a[2];
                    v >= r.lo - 1e-9 && v <= r.hi + 1e-9
                })
        };
        // The broken normals' sum off the kept ones first: the most direct way out;
        // else any translation the linear programme finds.
        let direct = straight_out(&normals, broken).filter(|&t| meets(t));
        let found = direct.or_else(|| match lp::solve(&rows, &lo, &hi) {
            lp::Outcome::Point(t) => Some(DVec3::new(t[0], t[1], t[2])),
            _ => None,
        });
        if let Some(t) = found {
            out.push([t.x, t.y, t.z, 0.0, 0.0, 0.0]);
        }
    }
    out
}

/// The sum of the normals of the contacts in the set `broken`, with the parts along
/// the other contacts' normals taken out, scaled to a largest component of one; `None`
/// when nothing is left.
fn straight_out(normals: &[DVec3], broken: usize) -> Option<DVec3> {
    let mut kept: Vec<DVec3> = Vec::new();
    for (i, &n) in normals.iter().enumerate() {
        if broken & (1 << i) == 0 {
            let rest = kept.iter().fold(n, |v, k| v - k * v.dot(*k));
            if let Some(unit) = rest.try_normalize().filter(|_| rest.length() > 1e-9) {
                kept.push(unit);
            }
        }
    }
    let sum: DVec3 = normals
        .iter()
        .enumerate()
        .filter(|(i, _)| broken & (1 << i) != 0)
        .map(|(_, &n)| n)
        .sum();
    let t = kept.iter().fold(sum, |v, k| v - k * v.dot(*k));
    let largest = t.abs().max_element();
    (largest > 1e-9).then(|| t / largest)
}

/// The unit normal along which translating the moving part opens a contact's gap at
/// first order, in the fixed part's frame (`rotation` turns the moving part's
/// directions there): the face's outward normal for a face of the fixed part, the
/// moving face's inward one for a face of the moving part, the common normal of two
/// crossing edges, oriented out of the fixed edge's wedge. `None` for a contact with
/// no single such normal (on an edge or a vertex, collinear edges), or crossing edges
/// whose orientation the two wedges do not agree on.
fn separating_normal(fixed: &Part, moving: &Part, rotation: &DMat3, pc: &PrincipalContact) -> Option<DVec3> {
    match (pc.kind, pc.fixed, pc.moving) {
        (ContactKind::FaceFace | ContactKind::FaceEdge | ContactKind::FaceVertex, ElementId::Face(f), _) => {
            Some(fixed.face(f).normal)
        }
        (ContactKind::EdgeFace | ContactKind::VertexFace, _, ElementId::Face(f)) => {
            Some(-(*rotation * moving.face(f).normal))
        }
        (ContactKind::EdgeEdge, ElementId::Edge(e), ElementId::Edge(x)) => {
            let n = fixed.edge_direction(e).cross(*rotation * moving.edge_direction(x));
            let n = n.try_normalize()?;
            let [f0, f1] = fixed.edge(e).faces;
            let out_of_fixed = fixed.face(f0).normal + fixed.face(f1).normal;
            let [g0, g1] = moving.edge(x).faces;
            let into_moving = -(*rotation * (moving.face(g0).normal + moving.face(g1).normal));
            let (a, b) = (n.dot(out_of_fixed), n.dot(into_moving));
            // Both wedges must say which way the gap opens.
            (a * b > 0.0).then(|| if a > 0.0 { n } else { -n })
        }
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::examples::builtin;
    use crate::pose::Bounds;

    #[test]
    fn straight_out_breaks_the_chosen_contacts_and_keeps_the_others() {
        // A wall facing -x, and a face tilted 0.19° off +y that an edge lies in.
        let wall = DVec3::new(-1.0, 0.0, 0.0);
        let tilted = DVec3::new(0.0, -0.999_994_73, 0.003_246_54).normalize();
        let off_the_tilted = straight_out(&[wall, tilted], 0b10).expect("a way out");
        assert_eq!(off_the_tilted.dot(wall), 0.0);
        assert!(off_the_tilted.dot(tilted) > 0.99);
        let off_both = straight_out(&[wall, tilted], 0b11).expect("a way out");
        assert!(off_both.dot(wall) > 0.99 && off_both.dot(tilted) > 0.99);
        // Two opposite walls: no translation leaves one and keeps the other.
        assert!(straight_out(&[wall, -wall], 0b01).is_none());
    }

    /// The plain hole's peg against its wall (x at its bound) with the rim's edge lying
    /// in its tilted side face, at a witness the search found: the pinned yaw came out
    /// at -4.8e-22 rad. Stepping off the side face, off the wall, and off both reads the
    /// wall alone, the edge alone and free space (by hand: each contact's normal is
    /// known, and the nearest other pair is 0.065 mm away).
    #[test]
    fn probes_read_past_the_round_off_of_a_pinned_angle() {
        let fixed = builtin(
            "block_with_hole.off",
            include_str!("../../../../fixtures/block_with_hole.off"),
        );
        let moving = builtin("peg.off", include_str!("../../../../fixtures/peg.off"));
        let bounds =
            Bounds::from_degrees([-1.0, -1.0, 0.0, -1.0, -1.0, 0.0], [1.0, 1.0, 85.0, 1.0, 1.0, 0.0]).expect("bounds");
        let problem = Problem::new(&fixed, &moving, bounds, glam::DAffine3::IDENTITY);
        let witness = Pose::from_array([
            1.0,
            0.902_583_644_844_690_7,
            20.097_828_363_539_428,
            -0.003_246_544_503_272_309,
            1.773_607_582_211_699_8e-19,
            -4.807_405_699_096_272e-22,
        ]);
        let contacts = problem.clean_state(&witness).expect("a robust witness");
        let kinds: Vec<ContactKind> = contacts.iter().map(|pc| pc.kind).collect();
        assert_eq!(kinds, [ContactKind::FaceFace, ContactKind::EdgeFace]);
        let alone = |kind| {
            contacts
                .iter()
                .filter(|pc| pc.kind == kind)
                .copied()
                .collect::<Vec<_>>()
        };
        let index: HashMap<Vec<PrincipalContact>, usize> = [
            (Vec::new(), 0),
            (contacts.clone(), 1),
            (alone(ContactKind::FaceFace), 2),
            (alone(ContactKind::EdgeFace), 3),
        ]
        .into_iter()
        .collect();
        let state = State {
            id: 1,
            contacts,
            dof: 3,
            degenerate: false,
            witness: Some(witness),
        };
        assert_eq!(probe(&fixed, &moving, &state, &index, &problem), [0, 2, 3]);
    }
}
