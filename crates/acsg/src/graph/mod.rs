//! The Assembly Contact State Graph: every contact state that some pose within the
//! bounds shows (docs/concepts.md#the-graph), each with a verified witness, and the neighbour
//! relation between them.
//!
//! The generator follows the paper's two stages, with every candidate decided
//! (`Problem::decide` in module `feasibility`): witnessed, proved
//! infeasible, or recorded as undecided:
//! 1. every single contact (each primitive principal contact, faces on faces, edges in
//!    faces, contacts in concave edges and corners) is decided on its own;
//! 2. breadth first, each state is grown by every single-contact state it does not
//!    imply; the combination is mapped by the derived rules under every outcome
//!    (module `rules`), pruned when it cannot exist or is already known, and
//!    otherwise decided with warm starts from the parent's and the addition's witnesses.
//!
//! When the growth settles, every state is also searched one contact below, from its
//! witness (descents); what they find grows again. Neighbour edges join states one
//! contact apart, and states whose touching regions meet (found by small probes from
//! each witness).
//!
//! A state's identity is P(X) at its witness: a search that lands on a pose showing
//! another state records that state (if new). Every witness is verified by the contact
//! module before the state is kept. Candidates of one breadth-first level are decided
//! in parallel and merged in a fixed order, so the output does not depend on the
//! number of threads.

pub mod document;
mod dof;
pub(crate) mod rules;

use std::collections::{BTreeSet, HashMap};
use std::time::Instant;

use glam::DAffine3;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use crate::contact::PrincipalContact;
use crate::feasibility::{
    Decided, Decision, PRIMITIVE_STARTS, Problem, SearchStats, Starts, is_primitive, single_contacts,
};
use crate::model::Part;
use crate::pose::{Bounds, Pose};

pub use document::Document;
pub(crate) use dof::state_dof;

/// How to generate a graph.
#[derive(Clone, Debug, PartialEq)]
pub struct Options {
    /// Keep states with a degenerate contact (v-v, e-v, v-e, e-e-t between convex
    /// elements), which hold only on a set any small motion leaves.
    pub degenerate: bool,
    /// G: the assembled pose of the moving part in the fixed part's frame.
    pub assembled: DAffine3,
    /// Worker threads; 0 uses rayon's default (one per core).
    pub threads: usize,
    /// How hard each candidate is searched and proved before it is left undecided: a
    /// multiple of the default budget of boxes and local searches (1).
    pub effort: u32,
}

impl Default for Options {
    fn default() -> Options {
        Options {
            degenerate: false,
            assembled: DAffine3::IDENTITY,
            threads: 0,
            effort: 1,
        }
    }
}

/// One contact state of the graph.
#[derive(Clone, Debug, PartialEq)]
pub struct State {
    /// Its index in [`Graph::states`]; 0 is free space.
    pub id: usize,
    /// P(X) at the witness: its principal contacts, sorted.
    pub contacts: Vec<PrincipalContact>,
    /// Degrees of freedom left at the witness (6 in free space).
    pub dof: u8,
    /// Whether one of its contacts is degenerate.
    pub degenerate: bool,
    /// A pose within the bounds showing exactly this state, verified. Free space has
    /// one when some probed pose in the bounds touches nothing.
    pub witness: Option<Pose>,
}

/// Counts and times of a run.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Stats {
    /// card(PPC): every primitive principal contact.
    pub ppc: usize,
    /// Single contacts decided in stage 1: the PPCs and every other contact that can
    /// hold alone (face on face, edge in face, contacts with concave elements).
    pub singles: usize,
    /// PPCs ruled out by the reach test without optimising.
    pub ppc_unreachable: usize,
    /// Feasible PPCs.
    pub feasible_ppc: usize,
    /// PPCs handed to the optimiser in stage 1 (the paper's count of optimisation
    /// procedures; each may run several local optimisations).
    pub stage1_searched: usize,
    /// Local optimisations run in stage 1.
    pub stage1_optimisations: usize,
    /// Stage-2 pairs (state, feasible PPC) considered.
    pub stage2_pairs: usize,
    /// Pairs where the state already implies the PPC.
    pub pruned_implied: usize,
    /// Pairs ruled out by topological existence.
    pub pruned_topology: usize,
    /// Candidate states left out because they hold a degenerate contact.
    pub pruned_degenerate: usize,
    /// Candidate states already known or already searched.
    pub pruned_duplicate: usize,
    /// Candidates ruled out by the reach test.
    pub pruned_unreachable: usize,
    /// Candidates searched by optimisation.
    pub stage2_candidates: usize,
    /// Candidates handed to the optimiser in stage 2, descents included (the paper's
    /// count of optimisation procedures).
    pub stage2_searched: usize,
    /// Local optimisations run in stage 2.
    pub stage2_optimisations: usize,
    /// States found while searching for another.
    pub found_on_the_way: usize,
    /// Stage-2 searches for a state one contact below a known one, started from its
    /// witness (after the breadth-first growth settles).
    pub descents: usize,
    /// States found by those searches.
    pub found_by_descent: usize,
    /// Candidates met in all (stage 1's PPCs, stage 2's combinations, descents): each
    /// ends witnessed, proved infeasible or undecided.
    pub candidates: usize,
    /// Candidates with a verified witness (the state asked for).
    pub witnessed: usize,
    /// Candidates proved infeasible: no pose in the bounds shows them.
    pub infeasible: usize,
    /// Candidates neither witnessed nor proved infeasible: the graph may lack them.
    pub undecided: usize,
    /// Boxes of poses examined by the branch and prune of the decisions.
    pub boxes: usize,
    /// States, free space included.
    pub states: usize,
    /// Neighbour edges.
    pub edges: usize,
    /// Seconds in stage 1.
    pub stage1_seconds: f64,
    /// Seconds in stage 2 (with the neighbour edges).
    pub stage2_seconds: f64,
}

/// A candidate state that was neither witnessed nor proved infeasible.
#[derive(Clone, Debug, PartialEq)]
pub struct Undecided {
    /// Its principal contacts, sorted.
    pub contacts: Vec<PrincipalContact>,
    /// The smallest box of poses the proof left open.
    pub open: Bounds,
}

/// The generated graph.
#[derive(Clone, Debug, PartialEq)]
pub struct Graph {
    /// The states; `states[0]` is free space.
    pub states: Vec<State>,
    /// Neighbour pairs of state ids, each `[smaller, larger]`, sorted.
    pub edges: Vec<[usize; 2]>,
    /// Counts and times.
    pub stats: Stats,
    /// The candidates left undecided, in the order met: empty when the graph is
    /// complete.
    pub undecided: Vec<Undecided>,
}

impl Graph {
    /// Whether every candidate the search met was witnessed or proved infeasible.
    #[must_use]
    pub fn is_complete(&self) -> bool {
        self.undecided.is_empty()
    }
}

/// Progress of a run, for progress bars.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Progress {
    /// 1 or 2.
    pub stage: u8,
    /// Searches done in this stage (or this stage-2 level).
    pub done: usize,
    /// Searches planned.
    pub total: usize,
    /// States so far.
    pub states: usize,
}

/// Generates the contact state graph of a fixed and a moving part within bounds.
///
/// ```
/// use acsg::graph::{Options, generate};
/// use acsg::pose::Bounds;
///
/// let (slab, cube) = acsg::examples::cube_and_slab();
/// // The cube over the slab's top face, free to tilt by 10 degrees, to yaw and to drop.
/// let bounds = Bounds::from_degrees(
///     [-1.0, -1.0, 0.0, -10.0, -10.0, -180.0],
///     [1.0, 1.0, 3.0, 10.0, 10.0, 180.0],
/// )
/// .unwrap();
/// let graph = generate(&slab, &cube, &bounds, &Options::default());
/// // Free space, 4 corners, 4 edges and the bottom face on the slab.
/// assert_eq!(graph.states.len(), 1 + 9);
/// ```
#[must_use]
pub fn generate(fixed: &Part, moving: &Part, bounds: &Bounds, options: &Options) -> Graph {
    generate_with_progress(fixed, moving, bounds, options, &|_| {})
}

/// [`generate`], calling `progress` from the calling thread as searches finish.
#[must_use]
pub fn generate_with_progress(
    fixed: &Part,
    moving: &Part,
    bounds: &Bounds,
    options: &Options,
    progress: &(dyn Fn(Progress) + Sync),
) -> Graph {
    let run = || Generator::new(fixed, moving, bounds, options).run(progress);
    match options.threads {
        0 => run(),
        n => match rayon::ThreadPoolBuilder::new().num_threads(n).build() {
            Ok(pool) => pool.install(run),
            Err(_) => run(),
        },
    }
}

/// Searches run in parallel per batch; progress is reported between batches.
const BATCH: usize = 64;

struct Generator<'a> {
    fixed: &'a Part,
    moving: &'a Part,
    options: &'a Options,
    problem: Problem<'a>,
    states: Vec<State>,
    index: HashMap<Vec<PrincipalContact>, usize>,
    /// Candidates decided or states known: never decided again.
    seen: BTreeSet<Vec<PrincipalContact>>,
    /// Candidates left undecided.
    undecided: Vec<Undecided>,
    /// Every single-contact state found, with its witness, in the order found: what
    /// stage 2 grows states by.
    additions: Vec<(PrincipalContact, Pose)>,
    /// Per state, how many of `additions` it has been grown by.
    grown: Vec<usize>,
    stats: Stats,
}

/// One stage-2 candidate to decide.
struct Candidate {
    target: Vec<PrincipalContact>,
    parent: usize,
    added: usize,
}

/// The step from a witness at which [`Generator::probe`] reads a neighbouring state
/// (relative to L for translations, radians for angles); the reading is confirmed a
/// tenth of the way.
const PROBE_STEP: f64 = 1e-4;

/// How many times the effort stage 1 spends on each single contact: they are few, and
/// every state grows from them.
const SINGLE_BOOST: u32 = 4;

/// Constructive starts of a stage-2 search (after the warm starts).
const GROWTH_STARTS: usize = 4;

impl<'a> Generator<'a> {
    fn new(fixed: &'a Part, moving: &'a Part, bounds: &Bounds, options: &'a Options) -> Generator<'a> {
        let mut problem = Problem::new(fixed, moving, *bounds, options.assembled);
        problem.set_effort(options.effort);
        let mut generator = Generator {
            fixed,
            moving,
            options,
            problem,
            states: Vec::new(),
            index: HashMap::new(),
            seen: BTreeSet::new(),
            undecided: Vec::new(),
            additions: Vec::new(),
            grown: Vec::new(),
            stats: Stats::default(),
        };
        let root = generator.free_pose();
        generator.states.push(State {
            id: 0,
            contacts: Vec::new(),
            dof: 6,
            degenerate: false,
            witness: root,
        });
        generator.index.insert(Vec::new(), 0);
        generator
    }

    /// A pose in the bounds where nothing touches: the centre, the faces' centres and
    /// the corners of the bounds, in that order.
    fn free_pose(&self) -> Option<Pose> {
        let bounds = self.problem.bounds();
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
            self.problem
                .clean_state(&pose)
                .is_some_and(|c| c.is_empty())
                .then_some(pose)
        })
    }

    fn is_degenerate(&self, contacts: &[PrincipalContact]) -> bool {
        contacts.iter().any(|pc| pc.degenerate(self.fixed, self.moving))
    }

    /// Adds a verified state if it is new and wanted; its id either way (`None` when
    /// left out as degenerate).
    fn add_state(&mut self, contacts: Vec<PrincipalContact>, witness: Pose) -> Option<(usize, bool)> {
        if let Some(&id) = self.index.get(&contacts) {
            return Some((id, false));
        }
        let degenerate = self.is_degenerate(&contacts);
        if degenerate && !self.options.degenerate {
            return None;
        }
        let id = self.states.len();
        let placement = witness.to_affine(&self.options.assembled);
        let dof = state_dof(
            self.fixed,
            self.moving,
            &contacts,
            &placement,
            self.problem.scene().scale(),
        );
        self.seen.insert(contacts.clone());
        self.index.insert(contacts.clone(), id);
        if let [single] = contacts[..] {
            self.additions.push((single, witness));
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

    fn run(mut self, progress: &(dyn Fn(Progress) + Sync)) -> Graph {
        let started = Instant::now();
        // Stage 1: every single contact decided (the PPCs, and the contacts that need
        // no PPC to hold: a face flat on a face when the rotation is pinned, say).
        let singles = single_contacts(self.fixed, self.moving, self.options.degenerate);
        self.stats.ppc = singles.iter().filter(|pc| is_primitive(pc)).count();
        self.stats.singles = singles.len();
        let mut results: Vec<(Decided, SearchStats)> = Vec::with_capacity(singles.len());
        for chunk in singles.chunks(BATCH) {
            results.par_extend(chunk.par_iter().map(|pc| {
                let mut stats = SearchStats::default();
                let starts = Starts {
                    warm: &[],
                    anchor: pc,
                    constructive: PRIMITIVE_STARTS,
                    boost: SINGLE_BOOST,
                };
                (self.problem.decide(&[*pc], &starts, &mut stats), stats)
            }));
            progress(Progress {
                stage: 1,
                done: results.len(),
                total: singles.len(),
                states: self.states.len(),
            });
        }
        for (pc, (decided, stats)) in singles.iter().zip(results) {
            self.stats.stage1_optimisations += stats.optimisations;
            self.stats.stage1_searched += usize::from(stats.optimisations > 0);
            self.stats.boxes += stats.boxes;
            let proved = matches!(decided.decision, Decision::Infeasible(_));
            if stats.optimisations == 0 && proved && is_primitive(pc) {
                self.stats.ppc_unreachable += 1;
            }
            if is_primitive(pc) && matches!(decided.decision, Decision::Witnessed(_)) {
                self.stats.feasible_ppc += 1;
            }
            self.record(vec![*pc], decided);
        }
        self.stats.stage1_seconds = started.elapsed().as_secs_f64();

        // Stage 2: every state grown by every single contact found, until nothing new
        // appears; then every state searched one contact below, and grown again.
        let started = Instant::now();
        loop {
            self.grow(progress);
            if self.descend() == 0 {
                break;
            }
        }
        let edges = self.neighbours();
        self.stats.states = self.states.len();
        self.stats.edges = edges.len();
        self.stats.stage2_seconds = started.elapsed().as_secs_f64();
        // A candidate left undecided whose state turned up later is witnessed.
        let index = &self.index;
        self.undecided.retain(|u| !index.contains_key(&u.contacts));
        self.stats.undecided = self.undecided.len();
        self.stats.witnessed = self.stats.candidates - self.stats.infeasible - self.stats.undecided;
        Graph {
            states: self.states,
            edges,
            stats: self.stats,
            undecided: self.undecided,
        }
    }

    /// Records the decision of a candidate and the states met on the way; how many
    /// states are new.
    fn record(&mut self, target: Vec<PrincipalContact>, decided: Decided) -> usize {
        self.stats.candidates += 1;
        self.seen.insert(target.clone());
        let mut new = 0;
        match decided.decision {
            Decision::Witnessed(pose) => new += usize::from(matches!(self.add_state(target, pose), Some((_, true)))),
            Decision::Infeasible(_) => self.stats.infeasible += 1,
            Decision::Undecided(open) => self.undecided.push(Undecided { contacts: target, open }),
        }
        for (state, pose) in decided.others {
            if let Some((_, true)) = self.add_state(state, pose) {
                self.stats.found_on_the_way += 1;
                new += 1;
            }
        }
        new
    }

    /// For every known state with several contacts, its subsets one contact smaller that
    /// are neither states nor candidates yet, each decided: first pushed apart from the
    /// state's witness, then in small boxes around it, then over the whole bounds. The
    /// new states.
    fn descend(&mut self) -> usize {
        let mut candidates = Vec::new();
        for state in &self.states {
            let Some(witness) = state.witness else { continue };
            if state.contacts.len() < 2 {
                continue;
            }
            for skip in 0..state.contacts.len() {
                let mut target = state.contacts.clone();
                target.remove(skip);
                if (!self.options.degenerate && self.is_degenerate(&target)) || !self.seen.insert(target.clone()) {
                    continue;
                }
                candidates.push((target, state.id, witness));
            }
        }
        let results: Vec<(Decided, SearchStats)> = candidates
            .par_iter()
            .map(|(target, from, witness)| {
                let mut stats = SearchStats::default();
                let above = &self.states[*from].contacts;
                let decided = self.problem.decide_below(target, above, *witness, &mut stats);
                (decided, stats)
            })
            .collect();
        let mut new = 0;
        for ((target, _, _), (decided, stats)) in candidates.into_iter().zip(results) {
            self.stats.descents += 1;
            self.stats.stage2_searched += usize::from(stats.optimisations > 0);
            self.stats.stage2_optimisations += stats.optimisations;
            self.stats.boxes += stats.boxes;
            let witnessed = matches!(decided.decision, Decision::Witnessed(_));
            let found = self.record(target, decided);
            self.stats.found_by_descent += usize::from(witnessed && found > 0);
            new += found;
        }
        new
    }

    /// Stage 2's growth: every state with every single contact found (in the order
    /// they were found; later ones grow the earlier states too), until no new state
    /// appears. Candidates of one round are decided in parallel, merged in order.
    fn grow(&mut self, progress: &(dyn Fn(Progress) + Sync)) {
        loop {
            let candidates = self.candidates();
            if candidates.is_empty() {
                return;
            }
            let mut results: Vec<(Decided, SearchStats)> = Vec::with_capacity(candidates.len());
            for chunk in candidates.chunks(BATCH) {
                results.par_extend(chunk.par_iter().map(|c| {
                    let mut stats = SearchStats::default();
                    let parent = self.states[c.parent].witness;
                    let (added, added_witness) = &self.additions[c.added];
                    let warm: Vec<Pose> = parent.into_iter().chain([*added_witness]).collect();
                    let starts = Starts {
                        warm: &warm,
                        anchor: added,
                        constructive: GROWTH_STARTS,
                        boost: 1,
                    };
                    (self.problem.decide(&c.target, &starts, &mut stats), stats)
                }));
                progress(Progress {
                    stage: 2,
                    done: results.len(),
                    total: candidates.len(),
                    states: self.states.len(),
                });
            }
            for (candidate, (decided, stats)) in candidates.into_iter().zip(results) {
                self.stats.stage2_optimisations += stats.optimisations;
                self.stats.stage2_searched += usize::from(stats.optimisations > 0);
                self.stats.boxes += stats.boxes;
                if stats.optimisations == 0 && matches!(decided.decision, Decision::Infeasible(_)) {
                    self.stats.pruned_unreachable += 1;
                }
                self.record(candidate.target, decided);
            }
        }
    }

    /// The candidates of the (state, single contact) pairs not considered yet, in a
    /// fixed order.
    fn candidates(&mut self) -> Vec<Candidate> {
        let mut out = Vec::new();
        let mut proposed = BTreeSet::new();
        for parent in 1..self.states.len() {
            let from = self.grown.get(parent).copied().unwrap_or(0);
            if from == self.additions.len() {
                continue;
            }
            let state = self.states[parent].contacts.clone();
            let implied = rules::state_primitives(self.fixed, self.moving, &state);
            for added in from..self.additions.len() {
                let pc = self.additions[added].0;
                self.stats.stage2_pairs += 1;
                let own = rules::state_primitives(self.fixed, self.moving, &[pc]);
                if state.contains(&pc) || (!own.is_empty() && own.is_subset(&implied)) {
                    self.stats.pruned_implied += 1;
                    continue;
                }
                let targets = rules::grow_every(self.fixed, self.moving, &state, pc);
                if targets.is_empty() {
                    self.stats.pruned_topology += 1;
                }
                for target in targets {
                    if target == state {
                        self.stats.pruned_implied += 1;
                    } else if !self.options.degenerate && self.is_degenerate(&target) {
                        self.stats.pruned_degenerate += 1;
                    } else if !self.seen.contains(&target) && proposed.insert(target.clone()) {
                        self.stats.stage2_candidates += 1;
                        out.push(Candidate { target, parent, added });
                    } else {
                        self.stats.pruned_duplicate += 1;
                    }
                }
            }
            if self.grown.len() <= parent {
                self.grown.resize(parent + 1, 0);
            }
            self.grown[parent] = self.additions.len();
        }
        out
    }

    /// Neighbour pairs: free space with every single-PPC state; a state with each state
    /// it grows into by one PPC (docs/concepts.md#the-graph). The PPCs tried are those some
    /// known state implies: a state grown into holds the PPC made, whether or not that
    /// PPC was found feasible alone in stage 1.
    fn neighbours(&self) -> Vec<[usize; 2]> {
        let made: BTreeSet<PrincipalContact> = self
            .states
            .iter()
            .flat_map(|s| rules::state_primitives(self.fixed, self.moving, &s.contacts))
            .collect();
        let mut edges = BTreeSet::new();
        for state in &self.states[1..] {
            if let [pc] = state.contacts[..] {
                if is_primitive(&pc) {
                    edges.insert([0, state.id]);
                }
            }
            let implied = rules::state_primitives(self.fixed, self.moving, &state.contacts);
            for ppc in made.iter().filter(|p| !implied.contains(p)) {
                for target in rules::grow_every(self.fixed, self.moving, &state.contacts, *ppc) {
                    if let Some(&other) = self.index.get(&target) {
                        // Making one PPC keeps every PPC the state had.
                        let keeps = rules::state_primitives(self.fixed, self.moving, &target).is_superset(&implied);
                        if other != state.id && keeps {
                            edges.insert([state.id.min(other), state.id.max(other)]);
                        }
                    }
                }
            }
        }
        let probed: Vec<Vec<usize>> = self.states[1..].par_iter().map(|s| self.probe(s)).collect();
        for (state, others) in self.states[1..].iter().zip(probed) {
            for other in others {
                edges.insert([state.id.min(other), state.id.max(other)]);
            }
        }
        edges.into_iter().collect()
    }

    /// The known states (free space included) whose regions touch this state's at its
    /// witness: the state read at small steps from the witness, in every direction
    /// along one or two pose components that the bounds leave free (a rotation-pinned
    /// face on a face steps straight into free space). A step counts when a step ten
    /// times smaller reads the same state, so that the other region reaches the
    /// witness itself.
    fn probe(&self, state: &State) -> Vec<usize> {
        let Some(witness) = state.witness else {
            return Vec::new();
        };
        let bounds = self.problem.bounds();
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
        let scale = self.problem.scene().scale();
        let x = witness.to_array();
        let read = |d: &[f64; 6], step: f64| {
            let pose = Pose::from_array(std::array::from_fn(|k| {
                x[k] + d[k] * step * if k < 3 { scale } else { 1.0 }
            }));
            if !bounds.contains(&pose, 0.0, 0.0) {
                return None;
            }
            self.problem.clean_state(&pose)
        };
        let mut out = BTreeSet::new();
        for d in &directions {
            let Some(far) = read(d, PROBE_STEP) else { continue };
            if far != state.contacts && read(d, 0.1 * PROBE_STEP).as_ref() == Some(&far) {
                if let Some(&other) = self.index.get(&far) {
                    out.insert(other);
                }
            }
        }
        out.into_iter().collect()
    }
}
