//! The graph being built, apart from how it is searched: the states found (free space
//! first), their canonical index, every candidate met and how it ended (the completeness
//! record), the single-contact states that growth adds, and the counts. A search
//! strategy ([`super::strategy`]) drives it through [`Store::record`] and reads it back;
//! [`Store::finish`] adds the neighbour edges and hands over the [`Graph`].
//!
//! Every state enters through a verified witness: a strategy records a
//! [`Decided`], whose witnesses the feasibility module has checked.

use std::collections::{BTreeMap, BTreeSet, HashMap};
use std::time::Instant;

use super::{Graph, Options, SEARCH_WORK, State, Stats, Undecided, neighbours, state_dof};
use crate::contact::PrincipalContact;
use crate::feasibility::{Decided, Decision, Problem, SearchStats};
use crate::model::Part;
use crate::pose::{Bounds, Pose};

/// The work a decision did, as [`Options::work_limit`] counts it: its boxes, and
/// [`SEARCH_WORK`] per local optimisation.
pub(crate) fn work(stats: &SearchStats) -> u64 {
    stats.boxes as u64 + SEARCH_WORK * stats.optimisations as u64
}

/// The graph being built.
pub(crate) struct Store<'a> {
    fixed: &'a Part,
    moving: &'a Part,
    options: &'a Options,
    states: Vec<State>,
    index: HashMap<Vec<PrincipalContact>, usize>,
    /// Candidates decided or states known: never decided again.
    seen: BTreeSet<Vec<PrincipalContact>>,
    /// Candidates left undecided.
    undecided: Vec<Undecided>,
    /// Every box a decision over the whole bounds left open, per undecided candidate
    /// that has them: where the last proofs go on.
    rests: HashMap<Vec<PrincipalContact>, Vec<Bounds>>,
    /// Every single-contact state found, with its witness, in the order found: what
    /// growth adds to states.
    units: Vec<(Vec<PrincipalContact>, Pose)>,
    /// Counts: the store keeps those of the graph and the completeness record, the
    /// strategy adds those of its own work.
    pub stats: Stats,
    /// When the current stage began.
    clock: Instant,
}

impl<'a> Store<'a> {
    /// A graph holding free space alone, with a witness when some probed pose in the
    /// bounds touches nothing.
    pub fn new(fixed: &'a Part, moving: &'a Part, options: &'a Options, problem: &Problem<'_>) -> Store<'a> {
        let root = free_pose(problem);
        let mut store = Store {
            fixed,
            moving,
            options,
            states: Vec::new(),
            index: HashMap::new(),
            seen: BTreeSet::new(),
            undecided: Vec::new(),
            rests: HashMap::new(),
            units: Vec::new(),
            stats: Stats::default(),
            clock: Instant::now(),
        };
        store.states.push(State {
            id: 0,
            contacts: Vec::new(),
            dof: 6,
            degenerate: false,
            witness: root,
        });
        store.index.insert(Vec::new(), 0);
        store
    }

    /// The fixed part.
    pub fn fixed(&self) -> &'a Part {
        self.fixed
    }

    /// The moving part.
    pub fn moving(&self) -> &'a Part {
        self.moving
    }

    /// The options of the run.
    pub fn options(&self) -> &'a Options {
        self.options
    }

    /// Whether the run has reached its work limit ([`Options::work_limit`]), counting
    /// the work recorded so far and `pending` more ([`work`]) not recorded yet. Once
    /// reached, it stays so, and [`Stats::work_limit_reached`] says so.
    pub fn work_limit_reached(&mut self, pending: u64) -> bool {
        let Some(limit) = self.options.work_limit else {
            return false;
        };
        let s = &self.stats;
        let recorded = s.boxes as u64 + SEARCH_WORK * (s.stage1_optimisations + s.stage2_optimisations) as u64;
        self.stats.work_limit_reached |= recorded + pending >= limit;
        self.stats.work_limit_reached
    }

    /// The states so far; `states()[0]` is free space.
    pub fn states(&self) -> &[State] {
        &self.states
    }

    /// What states are grown by, with their witnesses, in the order found: every
    /// single-contact state, and every state holding a contact that never holds
    /// alone (see [`Store::add_unit`]).
    pub fn units(&self) -> &[(Vec<PrincipalContact>, Pose)] {
        &self.units
    }

    /// Adds a verified state as a unit of growth: a state found holding a single
    /// contact that no pose shows alone (faces at the same clearance come together),
    /// so that the states holding it are grown from it as from a single contact.
    /// Whether it was new as a state.
    pub fn add_unit(&mut self, contacts: Vec<PrincipalContact>, witness: Pose, problem: &Problem<'_>) -> bool {
        let Some((id, new)) = self.add_state(contacts, witness, problem) else {
            return false;
        };
        let state = &self.states[id];
        if state.contacts.len() > 1 && !self.units.iter().any(|(u, _)| *u == state.contacts) {
            self.units
                .push((state.contacts.clone(), state.witness.unwrap_or(witness)));
        }
        new
    }

    /// Adds a verified state met outside the search for any candidate (by the slice
    /// sweep); whether it was new.
    pub fn add_met(&mut self, contacts: Vec<PrincipalContact>, witness: Pose, problem: &Problem<'_>) -> bool {
        matches!(self.add_state(contacts, witness, problem), Some((_, true)))
    }

    /// Whether a candidate was decided already or is a known state.
    pub fn is_seen(&self, contacts: &[PrincipalContact]) -> bool {
        self.seen.contains(contacts)
    }

    /// Marks a candidate as taken up by the strategy (it will be recorded); false when
    /// it was decided already or is a known state.
    pub fn take_up(&mut self, contacts: &[PrincipalContact]) -> bool {
        self.seen.insert(contacts.to_vec())
    }

    /// The candidates left undecided so far whose states have not turned up since, in
    /// the order they were met.
    pub fn still_undecided(&self) -> Vec<Vec<PrincipalContact>> {
        self.undecided_open()
            .into_iter()
            .map(|(contacts, _)| contacts)
            .collect()
    }

    /// The candidates still undecided, with the boxes of poses their decisions left
    /// open, in the order they were met.
    pub fn undecided_open(&self) -> Vec<(Vec<PrincipalContact>, Bounds)> {
        self.undecided
            .iter()
            .filter(|u| !self.index.contains_key(&u.contacts))
            .map(|u| (u.contacts.clone(), u.open))
            .collect()
    }

    /// [`Store::undecided_open`] with every box each decision over the whole bounds
    /// left open (empty when none did), for the last proofs; the store keeps them no
    /// longer.
    pub fn undecided_to_prove(&mut self) -> Vec<(Vec<PrincipalContact>, Bounds, Vec<Bounds>)> {
        let mut rests = std::mem::take(&mut self.rests);
        self.undecided_open()
            .into_iter()
            .map(|(contacts, open)| {
                let rest = rests.remove(&contacts).unwrap_or_default();
                (contacts, open, rest)
            })
            .collect()
    }

    /// Whether a candidate was left undecided (and no state of it has turned up since).
    pub fn is_undecided(&self, contacts: &[PrincipalContact]) -> bool {
        !self.index.contains_key(contacts) && self.undecided.iter().any(|u| u.contacts == contacts)
    }

    /// Records what a second search for a candidate left undecided found (not
    /// counted as a candidate again): a witness makes it a state (it leaves the
    /// undecided list when the graph is finished); any other end leaves the first
    /// record as it was. The states met on the way are added. How many states are new.
    pub fn record_again(&mut self, target: Vec<PrincipalContact>, decided: Decided, problem: &Problem<'_>) -> Recorded {
        let mut recorded = Recorded::default();
        if let Decision::Witnessed(pose) = decided.decision {
            recorded.witnessed = true;
            recorded.new += usize::from(matches!(self.add_state(target, pose, problem), Some((_, true))));
        }
        self.record_others(recorded, decided.others, problem)
    }

    /// Adds the states met on the way to `recorded`'s count.
    fn record_others(
        &mut self,
        mut recorded: Recorded,
        others: Vec<(Vec<PrincipalContact>, Pose)>,
        problem: &Problem<'_>,
    ) -> Recorded {
        for (state, pose) in others {
            if let Some((_, true)) = self.add_state(state, pose, problem) {
                self.stats.found_on_the_way += 1;
                recorded.new += 1;
            }
        }
        recorded
    }

    /// Whether a state holds a degenerate contact.
    pub fn is_degenerate(&self, contacts: &[PrincipalContact]) -> bool {
        contacts.iter().any(|pc| pc.degenerate(self.fixed, self.moving))
    }

    /// Counts one outcome of growing `state` by a contact and whether it is a new
    /// candidate to decide: not the state itself, not left out as degenerate, neither
    /// known nor already proposed in this round (`proposed` gains it).
    pub fn admit(
        &mut self,
        target: &[PrincipalContact],
        state: &[PrincipalContact],
        proposed: &mut BTreeSet<Vec<PrincipalContact>>,
    ) -> bool {
        if target == state {
            self.stats.pruned_implied += 1;
        } else if self.leaves_out(target) {
            self.stats.pruned_degenerate += 1;
        } else if !self.is_seen(target) && proposed.insert(target.to_vec()) {
            self.stats.stage2_candidates += 1;
            return true;
        } else {
            self.stats.pruned_duplicate += 1;
        }
        false
    }

    /// Whether the run leaves a state out for holding a degenerate contact.
    pub fn leaves_out(&self, contacts: &[PrincipalContact]) -> bool {
        !self.options.degenerate && self.is_degenerate(contacts)
    }

    /// Adds a verified state if it is new and wanted; its id and whether it is new
    /// (`None` when left out as degenerate).
    fn add_state(
        &mut self,
        contacts: Vec<PrincipalContact>,
        witness: Pose,
        problem: &Problem<'_>,
    ) -> Option<(usize, bool)> {
        if let Some(&id) = self.index.get(&contacts) {
            return Some((id, false));
        }
        let degenerate = self.is_degenerate(&contacts);
        if degenerate && !self.options.degenerate {
            return None;
        }
        let id = self.states.len();
        let placement = witness.to_affine(&self.options.assembled);
        let dof = state_dof(self.fixed, self.moving, &contacts, &placement, problem.scene().scale());
        self.seen.insert(contacts.clone());
        self.index.insert(contacts.clone(), id);
        if contacts.len() == 1 {
            self.units.push((contacts.clone(), witness));
        }
        self.states.push(State {
            id,
            contacts,
            dof,
            degenerate,
            witness: Some(witness),
        });
        Some((id, true))
    }

    /// Records how a candidate ended and the states met on the way (each with a
    /// verified witness); how many states are new. The candidate counts as met once
    /// here, whatever strategy decided it.
    pub fn record(&mut self, target: Vec<PrincipalContact>, decided: Decided, problem: &Problem<'_>) -> Recorded {
        self.stats.candidates += 1;
        self.seen.insert(target.clone());
        let mut recorded = Recorded::default();
        match decided.decision {
            Decision::Witnessed(pose) => {
                recorded.witnessed = true;
                recorded.new += usize::from(matches!(self.add_state(target, pose, problem), Some((_, true))));
            }
            Decision::Infeasible(_) => self.stats.infeasible += 1,
            Decision::Undecided(open) => {
                if !decided.rest.is_empty() {
                    self.rests.insert(target.clone(), decided.rest);
                }
                self.undecided.push(Undecided { contacts: target, open });
            }
        }
        self.record_others(recorded, decided.others, problem)
    }

    /// Takes candidates left undecided off the list: the last proofs proved them
    /// infeasible.
    /// The others keep the box the last proofs left open (`open`), where the candidate
    /// may still hold.
    pub fn proved_last(
        &mut self,
        proved: &BTreeSet<Vec<PrincipalContact>>,
        open: &BTreeMap<Vec<PrincipalContact>, Bounds>,
    ) {
        let before = self.undecided.len();
        self.undecided.retain(|u| !proved.contains(&u.contacts));
        for u in &mut self.undecided {
            if let Some(b) = open.get(&u.contacts) {
                u.open = *b;
            }
        }
        let taken = before - self.undecided.len();
        self.stats.infeasible += taken;
        self.stats.proved_last += taken;
    }

    /// Ends stage 1: its time is taken, and stage 2's begins.
    pub fn end_stage1(&mut self) {
        self.stats.stage1_seconds = self.clock.elapsed().as_secs_f64();
        self.clock = Instant::now();
    }

    /// The finished graph: the neighbour edges added, the counts completed (stage 2's
    /// time includes the edges), and the candidates left undecided whose states turned
    /// up later counted as witnessed.
    pub fn finish(mut self, problem: &Problem<'_>) -> Graph {
        let edges = neighbours::neighbours(self.fixed, self.moving, &self.states, &self.index, problem);
        self.stats.states = self.states.len();
        self.stats.edges = edges.len();
        self.stats.stage2_seconds = self.clock.elapsed().as_secs_f64();
        let index = &self.index;
        self.undecided.retain(|u| !index.contains_key(&u.contacts));
        self.stats.undecided = self.undecided.len();
        self.stats.witnessed = self.stats.candidates - self.stats.infeasible - self.stats.undecided;
        Graph {
            states: self.states,
            edges,
            stats: self.stats,
            undecided: self.undecided,
            strategy: self.options.strategy,
        }
    }
}

/// What recording one candidate changed.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) struct Recorded {
    /// Whether the candidate itself was witnessed.
    pub witnessed: bool,
    /// New states, the candidate's and those met on the way.
    pub new: usize,
}

/// A pose in the bounds where nothing touches: the centre, the faces' centres and the
/// corners of the bounds, in that order.
fn free_pose(problem: &Problem<'_>) -> Option<Pose> {
    let bounds = problem.bounds();
    let (lo, hi) = (bounds.min.to_array(), bounds.max.to_array());
    let mut probes = vec![[0.5; 6]];
    for k in 0..6 {
        for end in [0.0, 1.0] {
            let mut w = [0.5; 6];
            w[k] = end;
            probes.push(w);
        }
    }
    for corner in 0..64u32 {
        probes.push(std::array::from_fn(|k| f64::from((corner >> k) & 1)));
    }
    probes.into_iter().find_map(|w| {
        let pose = Pose::from_array(std::array::from_fn(|k| lo[k] + (hi[k] - lo[k]) * w[k]));
        problem.clean_state(&pose).is_some_and(|c| c.is_empty()).then_some(pose)
    })
}
