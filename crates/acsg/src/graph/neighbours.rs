//! The neighbour relation of a finished set of states (DOMAIN.md section 4): two states
//! are neighbours when their regions of poses touch. Found two ways, whatever strategy
//! found the states: one PPC apart under the mapping rules, and by reading the state
//! at small steps from each witness.

use std::collections::{BTreeSet, HashMap};

use rayon::prelude::*;

use super::{State, rules};
use crate::contact::PrincipalContact;
use crate::feasibility::{Problem, is_primitive};
use crate::model::Part;
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
    let probed: Vec<Vec<usize>> = states[1..].par_iter().map(|s| probe(s, index, problem)).collect();
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
fn probe(state: &State, index: &HashMap<Vec<PrincipalContact>, usize>, problem: &Problem<'_>) -> Vec<usize> {
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
    let scale = problem.scene().scale();
    let x = witness.to_array();
    let read = |d: &[f64; 6], step: f64| {
        let pose = Pose::from_array(std::array::from_fn(|k| {
            x[k] + d[k] * step * if k < 3 { scale } else { 1.0 }
        }));
        if !bounds.contains(&pose, 0.0, 0.0) {
            return None;
        }
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
