//! The default strategy ([`super::Strategy::Full`]): the paper's two stages widened so
//! that every candidate is decided ([`Problem::decide`]): witnessed, proved infeasible,
//! or recorded as undecided:
//! 1. every single contact (each primitive principal contact, faces on faces, edges in
//!    faces, contacts in concave edges and corners) is decided on its own; one that
//!    does not hold alone may still hold with others touching too (three parallel
//!    walls at the same clearance), so unless the cheap proofs show that it never
//!    holds at all, the states holding it are searched for;
//! 2. breadth first, each state is grown by every single-contact state it does not
//!    imply, and by every state holding a contact that does not hold alone (its
//!    contacts one after the other); the combination is mapped by the derived rules
//!    under every outcome ([`rules::grow_every`]), pruned when it cannot exist or is
//!    already known, and otherwise decided with warm starts from the parent's and the
//!    addition's witnesses.
//!
//! When the growth settles, every state is also searched one contact below, from its
//! witness (descents); what they find grows again. When that settles too, the slice
//! sweep reads the states at several hundred fixed rotations off the Minkowski
//! differences of the convex pieces ([`Problem::states_in_slices`]), and then at a few
//! rotations inside each box the undecided candidates' decisions left open, carried
//! onto the alignments their contacts need and turned along them
//! ([`Problem::states_in_open_box`]); what it finds grows and descends again. Last, the
//! candidates still undecided are proved once more with stronger conditions
//! ([`Problem::prove_last`]); those still open are sliced at the rotations where they
//! may hold on a sliver narrower than the proofs' floor ([`Problem::states_in_slivers`]),
//! and what that finds grows, descends and is proved again. A search that lands on a pose
//! showing another state records that state (if new). Candidates of one round are
//! decided in parallel and merged in a fixed order, so the output does not depend on
//! the number of threads.
//!
//! With a work limit ([`crate::graph::Options::work_limit`]), checked between batches,
//! the candidates met once it is reached get the cheap proofs alone
//! ([`Problem::screen`]), and the coupled searches, sweeps and last proofs are skipped.

use std::collections::{BTreeMap, BTreeSet};

use rayon::prelude::*;

use super::BATCH;
use crate::contact::PrincipalContact;
use crate::feasibility::{
    Decided, Decision, Density, PRIMITIVE_STARTS, Problem, SearchStats, SliceFinds, Starts, is_primitive,
    lies_strictly_below, single_contacts,
};
use crate::graph::Progress;
use crate::graph::rules;
use crate::graph::store::{Store, work};
use crate::model::Part;
use crate::pose::{Bounds, Pose};

/// How many times the effort stage 1 spends on each single contact: they are few, and
/// every state grows from them.
const SINGLE_BOOST: u32 = 4;

/// Searches for the states holding a single contact that does not hold alone.
const COUPLED_STARTS: usize = 4;

/// Constructive starts of a stage-2 search (after the warm starts).
const GROWTH_STARTS: usize = 4;
/// Candidates decided in parallel between two progress reports when the run has no
/// work limit: four times [`BATCH`], so that a core waits less often at a batch's end
/// for another's long candidate (the built-in example: 0.86× the wall time).
const WIDE_BATCH: usize = 4 * BATCH;

/// How a candidate below a state is searched.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Below {
    /// Met for the first time, one contact below: decided next to the state's witness,
    /// then over the whole bounds.
    New,
    /// Left undecided before, one contact below: searched next to the witness again.
    Again,
    /// Left undecided before, further below: the other contacts pushed apart from the
    /// witness.
    Released,
}

/// One stage-2 candidate to decide.
struct Candidate {
    target: Vec<PrincipalContact>,
    parent: usize,
    added: usize,
}

/// Runs both stages, then descents, until nothing new appears.
pub(super) fn run(store: &mut Store<'_>, problem: &Problem<'_>, progress: &(dyn Fn(Progress) + Sync)) {
    decide_singles(store, problem, progress);
    store.end_stage1();
    let mut searched = Searched::default();
    let mut proved_last = BTreeSet::new();
    let mut slivered = BTreeSet::new();
    loop {
        search(store, problem, &mut searched, progress);
        if store.work_limit_reached(0) {
            // The candidates left stay undecided: the graph says it is not complete.
            break;
        }
        prove_last(store, problem, &mut proved_last);
        // What the last proofs leave open may hold on a sliver no search lands on:
        // slices there; what they find grows, and is decided, again.
        if sweep_slivers(store, problem, &mut slivered) == 0 {
            break;
        }
    }
}

/// What the searches have done so far, so that a second round goes on from there.
#[derive(Default)]
struct Searched {
    /// The states grown so far, by index.
    grown: Vec<usize>,
    /// The candidates below each state searched again.
    retried: BTreeSet<(Vec<PrincipalContact>, usize)>,
    /// The undecided candidates whose open boxes were sliced.
    swept: BTreeSet<Vec<PrincipalContact>>,
    /// Whether the wide slice sweep has run.
    sliced: bool,
    /// The states whose neighbourhoods were sliced.
    seeded: usize,
}

/// Stage 2: every state grown by every single contact found, until nothing new
/// appears; then every state searched one contact below, and grown again; then the
/// sweeps, each of which may find more to grow.
fn search(store: &mut Store<'_>, problem: &Problem<'_>, searched: &mut Searched, progress: &(dyn Fn(Progress) + Sync)) {
    loop {
        grow(store, problem, &mut searched.grown, progress);
        if descend(store, problem, &mut searched.retried) > 0 {
            continue;
        }
        if store.work_limit_reached(0) {
            return;
        }
        // When the searches settle, the slice sweep: last, so that every state the
        // searches find keeps its witness whatever the sweep finds (the sweep only
        // adds), and so that it counts what they missed.
        if !std::mem::replace(&mut searched.sliced, true) && sweep_slices(store, problem) > 0 {
            continue;
        }
        // Near every state found: at a higher effort only (it costs as much again as the
        // rest on parts of many pieces).
        if store.options().effort >= crate::feasibility::THOROUGH_EFFORT
            && sweep_near(store, problem, &mut searched.seeded) > 0
        {
            continue;
        }
        if sweep_undecided(store, problem, &mut searched.swept) == 0 {
            break;
        }
    }
}

/// The candidates still undecided, proved with the strongest conditions
/// ([`Problem::prove_last`]) once nothing more turns up: the sweeps have read the boxes
/// their decisions left open by then. In parallel, recorded in a fixed order.
fn prove_last(store: &mut Store<'_>, problem: &Problem<'_>, proved_last: &mut BTreeSet<Vec<PrincipalContact>>) {
    let mut left = store.undecided_to_prove();
    // Each candidate once: one left open stays so until a state of it turns up.
    left.retain(|(target, _, _)| proved_last.insert(target.clone()));
    let results: Vec<(Result<(), Bounds>, SearchStats)> = left
        .par_iter()
        .map(|(target, open, rest)| {
            let mut stats = SearchStats::default();
            (problem.prove_last(target, open, rest, &mut stats).map(|_| ()), stats)
        })
        .collect();
    let mut proved = BTreeSet::new();
    let mut still_open = BTreeMap::new();
    for ((target, _, _), (outcome, stats)) in left.into_iter().zip(results) {
        store.stats.boxes += stats.boxes;
        match outcome {
            Ok(()) => {
                proved.insert(target);
            }
            Err(open) => {
                still_open.insert(target, open);
            }
        }
    }
    store.proved_last(&proved, &still_open);
}

/// Stage 1: every single contact decided (the PPCs, and the contacts that need no PPC
/// to hold: a face flat on a face when the rotation is pinned, say).
fn decide_singles(store: &mut Store<'_>, problem: &Problem<'_>, progress: &(dyn Fn(Progress) + Sync)) {
    let singles = single_contacts(store.fixed(), store.moving(), store.options().degenerate);
    store.stats.ppc = singles.iter().filter(|pc| is_primitive(pc)).count();
    store.stats.singles = singles.len();
    let (results, pending) = decide_in_batches(
        store,
        problem,
        &singles,
        std::slice::from_ref,
        |_, pc, stats| {
            let starts = Starts {
                warm: &[],
                anchor: pc,
                constructive: PRIMITIVE_STARTS,
                boost: SINGLE_BOOST,
            };
            problem.decide(&[*pc], &starts, stats)
        },
        |store, done| {
            progress(Progress {
                stage: 1,
                done,
                total: singles.len(),
                states: store.states().len(),
            });
        },
    );
    let (units, stats) = if store.work_limit_reached(pending) {
        (Vec::new(), SearchStats::default())
    } else {
        coupled_units(problem, &singles, &results)
    };
    store.stats.stage1_optimisations += stats.optimisations;
    store.stats.boxes += stats.boxes;
    for (pc, (decided, stats)) in singles.iter().zip(results) {
        let counts = &mut store.stats;
        counts.stage1_optimisations += stats.optimisations;
        counts.stage1_searched += usize::from(stats.optimisations > 0);
        counts.boxes += stats.boxes;
        let proved = matches!(decided.decision, Decision::Infeasible(_));
        if stats.optimisations == 0 && proved && is_primitive(pc) {
            counts.ppc_unreachable += 1;
        }
        if is_primitive(pc) && matches!(decided.decision, Decision::Witnessed(_)) {
            counts.feasible_ppc += 1;
        }
        store.record(vec![*pc], decided, problem);
    }
    for (state, pose) in units {
        if store.add_unit(state, pose, problem) {
            store.stats.found_on_the_way += 1;
        }
    }
}

/// The states that show at the slice sweep's rotations ([`Problem::states_in_slices`])
/// over the whole bounds: those on slivers of the bounds that no local search reaches,
/// found without optimising. They grow and descend as every other state does. The new
/// states.
fn sweep_slices(store: &mut Store<'_>, problem: &Problem<'_>) -> usize {
    let finds = problem.states_in_slices(problem.bounds(), Density::WIDE, store.options().degenerate);
    add_sliced(store, problem, finds)
}

/// The states that show at rotations close to the witnesses of the states found since
/// the last call (`seeded` of them were swept before): a state that holds only on a
/// sliver next to a known one (an edge lying in a face while a face lies on a face)
/// shows there. The new states.
fn sweep_near(store: &mut Store<'_>, problem: &Problem<'_>, seeded: &mut usize) -> usize {
    let seeds: Vec<Pose> = store.states()[*seeded..].iter().filter_map(|s| s.witness).collect();
    *seeded = store.states().len();
    if seeds.is_empty() {
        return 0;
    }
    let finds = problem.states_near(&seeds, store.options().degenerate);
    add_sliced(store, problem, finds)
}

/// Adds the states a sweep found; how many are new.
fn add_sliced(store: &mut Store<'_>, problem: &Problem<'_>, finds: SliceFinds) -> usize {
    store.stats.slices += finds.slices;
    store.stats.slice_samples += finds.samples;
    let mut new = 0;
    for (state, pose) in finds.states {
        if store.add_met(state, pose, problem) {
            store.stats.found_by_slices += 1;
            new += 1;
        }
    }
    new
}

/// Slices at the rotations where the candidates the last proofs left open may hold on
/// a sliver ([`Problem::states_in_slivers`]), each candidate once (`slivered`). The new
/// states.
fn sweep_slivers(
    store: &mut Store<'_>,
    problem: &Problem<'_>,
    slivered: &mut BTreeSet<Vec<PrincipalContact>>,
) -> usize {
    let targets: Vec<Vec<PrincipalContact>> = store
        .still_undecided()
        .into_iter()
        .filter(|contacts| slivered.insert(contacts.clone()))
        .collect();
    if targets.is_empty() {
        return 0;
    }
    let finds = problem.states_in_slivers(&targets, store.options().degenerate);
    finds.into_iter().map(|found| add_sliced(store, problem, found)).sum()
}

/// Slices through the boxes of poses that the decisions of the candidates still
/// undecided left open, each candidate once (`swept`), and along the alignments the
/// candidate's contacts need from there ([`Problem::states_in_open_box`]): where a
/// state holds only on a sliver, the box the prover could not close holds its poses or
/// lies next to them. The new states.
fn sweep_undecided(store: &mut Store<'_>, problem: &Problem<'_>, swept: &mut BTreeSet<Vec<PrincipalContact>>) -> usize {
    let boxes: Vec<(Vec<PrincipalContact>, Bounds)> = store
        .undecided_open()
        .into_iter()
        .filter(|(contacts, _)| swept.insert(contacts.clone()))
        .collect();
    let degenerate = store.options().degenerate;
    let finds = problem.states_in_open_boxes(&boxes, degenerate);
    finds.into_iter().map(|found| add_sliced(store, problem, found)).sum()
}

/// A state met or searched for.
type Met = (Vec<PrincipalContact>, Pose);

/// Decides `items` (each candidate's contacts given by `target`) in batches: in
/// parallel within a batch, in order across them, with `progress` told how many are
/// done after each (from the calling thread, where a Python caller's Ctrl-C is seen).
///
/// With a work limit, batches of [`BATCH`]: once the limit is reached (checked between
/// batches, so the output does not depend on the thread count), the rest get the
/// cheap proofs alone ([`Problem::screen`]). Without one, batches of [`WIDE_BATCH`]:
/// fewer barriers where a core waits for another's long candidate. The outcomes, and
/// the work they did, which the store has not recorded yet.
fn decide_in_batches<T: Sync>(
    store: &mut Store<'_>,
    problem: &Problem<'_>,
    items: &[T],
    target: impl Fn(&T) -> &[PrincipalContact] + Sync,
    decide: impl Fn(&Store<'_>, &T, &mut SearchStats) -> Decided + Sync,
    progress: impl Fn(&Store<'_>, usize),
) -> (Vec<(Decided, SearchStats)>, u64) {
    let batch = if store.options().work_limit.is_some() {
        BATCH
    } else {
        WIDE_BATCH
    };
    let mut results: Vec<(Decided, SearchStats)> = Vec::with_capacity(items.len());
    let mut pending = 0;
    for chunk in items.chunks(batch) {
        let screen = store.work_limit_reached(pending);
        let first = results.len();
        let store = &*store;
        results.par_extend(chunk.par_iter().map(|item| {
            let mut stats = SearchStats::default();
            let decided = if screen {
                problem.screen(target(item), &mut stats)
            } else {
                decide(store, item, &mut stats)
            };
            (decided, stats)
        }));
        pending += results[first..].iter().map(|(_, stats)| work(stats)).sum::<u64>();
        progress(store, results.len());
    }
    (results, pending)
}

/// The states holding a single contact that was proved not to hold alone by a proof
/// leaning on other pairs keeping apart (or left undecided): a contact may hold only
/// with others touching too, and such states then grow the others as single
/// contacts do. The states met by the decisions and by a search for each
/// ([`Problem::states_containing`], unless its cheap proofs show that it never
/// holds), in the order of the singles, with the work done.
fn coupled_units(
    problem: &Problem<'_>,
    singles: &[PrincipalContact],
    results: &[(Decided, SearchStats)],
) -> (Vec<Met>, SearchStats) {
    let coupled: Vec<(usize, Vec<Met>, SearchStats)> = singles
        .par_iter()
        .zip(results)
        .enumerate()
        .filter(|(_, (_, (decided, _)))| may_hold_with_others(decided))
        .map(|(i, (pc, _))| {
            let mut stats = SearchStats::default();
            let found = if problem.never_holds(&[*pc], &mut stats) {
                Vec::new()
            } else {
                problem.states_containing(&[*pc], COUPLED_STARTS, &mut stats)
            };
            (i, found, stats)
        })
        .collect();
    let mut units: Vec<Met> = Vec::new();
    let mut work = SearchStats::default();
    for (i, found, stats) in coupled {
        work.optimisations += stats.optimisations;
        work.boxes += stats.boxes;
        let held = results[i]
            .0
            .others
            .iter()
            .filter(|(state, _)| state.contains(&singles[i]));
        for (state, pose) in found.iter().chain(held) {
            if !units.iter().any(|(u, _)| u == state) {
                units.push((state.clone(), *pose));
            }
        }
    }
    (units, work)
}

/// Whether a single contact's decision leaves open that it holds with other contacts
/// (see [`Problem::states_containing`]): it was not witnessed, and either nothing
/// proved it infeasible or the proof leans on other pairs keeping apart.
fn may_hold_with_others(decided: &Decided) -> bool {
    match &decided.decision {
        Decision::Witnessed(_) => false,
        Decision::Infeasible(proof) => proof.leans_on_others_apart(),
        Decision::Undecided(_) => true,
    }
}

/// For every known state with several contacts, its subsets one contact smaller that
/// are neither states nor candidates yet, each decided: first pushed apart from the
/// state's witness, then in small boxes around it, then over the whole bounds. Subsets
/// left undecided before are searched again next to each state above them (`retried`
/// holds the pairs of subset and state tried). The new states.
fn descend(
    store: &mut Store<'_>,
    problem: &Problem<'_>,
    retried: &mut BTreeSet<(Vec<PrincipalContact>, usize)>,
) -> usize {
    let mut candidates = Vec::new();
    for s in 0..store.states().len() {
        let state = &store.states()[s];
        let Some(witness) = state.witness else { continue };
        if state.contacts.len() < 2 {
            continue;
        }
        let (id, contacts) = (state.id, state.contacts.clone());
        for skip in 0..contacts.len() {
            let mut target = contacts.clone();
            target.remove(skip);
            if store.leaves_out(&target) {
                continue;
            }
            if store.take_up(&target) {
                candidates.push((target, id, witness, Below::New));
            } else if store.is_undecided(&target) && retried.insert((target.clone(), id)) {
                candidates.push((target, id, witness, Below::Again));
            }
        }
    }
    // A state less a whole group of contacts that hold only together (a unit of
    // growth): where the group's members cannot part one at a time, the state's
    // subsets one contact below do not hold, but the rest without the group may.
    for s in 0..store.states().len() {
        let state = &store.states()[s];
        let Some(witness) = state.witness else { continue };
        let (id, contacts) = (state.id, state.contacts.clone());
        let groups: Vec<Vec<PrincipalContact>> = store
            .units()
            .iter()
            .map(|(unit, _)| unit.clone())
            .filter(|unit| {
                unit.len() > 1
                    && unit.len() < contacts.len()
                    && unit.iter().all(|pc| contacts.binary_search(pc).is_ok())
            })
            .collect();
        for group in groups {
            let target: Vec<PrincipalContact> = contacts.iter().filter(|pc| !group.contains(pc)).copied().collect();
            if !store.leaves_out(&target) && store.take_up(&target) {
                candidates.push((target, id, witness, Below::New));
            }
        }
    }
    // Undecided candidates further below a state: pushed apart from its witness once.
    // Where contacts come in groups (faces at one clearance), a candidate holds only
    // beside the states that hold its group, not beside those one contact above. So
    // too a candidate that holds a part of one of the state's contacts (a vertex of an
    // edge lying in a face), whose region may be a sliver along the state's.
    let undecided = store.still_undecided();
    let (fixed, moving) = (store.fixed(), store.moving());
    for state in store.states() {
        let Some(witness) = state.witness else { continue };
        for target in &undecided {
            let deeper = target.len() + 1 < state.contacts.len()
                && target.iter().all(|pc| state.contacts.binary_search(pc).is_ok());
            if (deeper || lies_strictly_below(fixed, moving, target, &state.contacts))
                && retried.insert((target.clone(), state.id))
            {
                candidates.push((target.clone(), state.id, witness, Below::Released));
            }
        }
    }
    let (results, _) = decide_in_batches(
        store,
        problem,
        &candidates,
        |(target, ..)| &target[..],
        |store, (target, from, witness, below), stats| {
            let above = &store.states()[*from].contacts;
            match below {
                Below::New => problem.decide_below(target, above, *witness, stats),
                Below::Again => problem.retry_below(target, above, *witness, stats),
                Below::Released => problem.release_below(target, above, *witness, stats),
            }
        },
        |_, _| {},
    );
    let mut new = 0;
    for ((target, _, _, below), (decided, stats)) in candidates.into_iter().zip(results) {
        let again = below != Below::New;
        let counts = &mut store.stats;
        counts.descents += 1;
        // A retried candidate was counted as searched when it was first decided.
        counts.stage2_searched += usize::from(stats.optimisations > 0 && !again);
        counts.stage2_optimisations += stats.optimisations;
        counts.boxes += stats.boxes;
        let recorded = if again {
            store.record_again(target, decided, problem)
        } else {
            store.record(target, decided, problem)
        };
        store.stats.found_by_descent += usize::from(recorded.witnessed && recorded.new > 0);
        new += recorded.new;
    }
    new
}

/// Stage 2's growth: every state with every single contact found (in the order they
/// were found; later ones grow the earlier states too), until no new state appears.
/// Candidates of one round are decided in parallel, merged in order. `grown` holds, per
/// state, how many of the single-contact states it has been grown by.
fn grow(store: &mut Store<'_>, problem: &Problem<'_>, grown: &mut Vec<usize>, progress: &(dyn Fn(Progress) + Sync)) {
    loop {
        let candidates = candidates(store, grown);
        if candidates.is_empty() {
            return;
        }
        let (results, _) = decide_in_batches(
            store,
            problem,
            &candidates,
            |c| &c.target[..],
            |store, c, stats| {
                let parent = store.states()[c.parent].witness;
                let (added, added_witness) = &store.units()[c.added];
                let warm: Vec<Pose> = parent.into_iter().chain([*added_witness]).collect();
                let starts = Starts {
                    warm: &warm,
                    anchor: &added[0],
                    constructive: GROWTH_STARTS,
                    boost: 1,
                };
                problem.decide(&c.target, &starts, stats)
            },
            |store, done| {
                progress(Progress {
                    stage: 2,
                    done,
                    total: candidates.len(),
                    states: store.states().len(),
                });
            },
        );
        for (candidate, (decided, stats)) in candidates.into_iter().zip(results) {
            let counts = &mut store.stats;
            counts.stage2_optimisations += stats.optimisations;
            counts.stage2_searched += usize::from(stats.optimisations > 0);
            counts.boxes += stats.boxes;
            if stats.optimisations == 0 && matches!(decided.decision, Decision::Infeasible(_)) {
                counts.pruned_unreachable += 1;
            }
            store.record(candidate.target, decided, problem);
        }
    }
}

/// The candidates of the (state, single contact) pairs not considered yet, in a fixed
/// order.
fn candidates(store: &mut Store<'_>, grown: &mut Vec<usize>) -> Vec<Candidate> {
    let (fixed, moving) = (store.fixed(), store.moving());
    let mut out = Vec::new();
    let mut proposed = BTreeSet::new();
    for parent in 1..store.states().len() {
        let from = grown.get(parent).copied().unwrap_or(0);
        let units = store.units().len();
        if from == units {
            continue;
        }
        let state = store.states()[parent].contacts.clone();
        let implied = rules::state_primitives(fixed, moving, &state);
        for added in from..units {
            let unit = store.units()[added].0.clone();
            store.stats.stage2_pairs += 1;
            let own = rules::state_primitives(fixed, moving, &unit);
            if unit.iter().all(|pc| state.contains(pc)) || (!own.is_empty() && own.is_subset(&implied)) {
                store.stats.pruned_implied += 1;
                continue;
            }
            let targets = grow_by(fixed, moving, &state, &unit);
            if targets.is_empty() {
                store.stats.pruned_topology += 1;
            }
            for target in targets {
                if store.admit(&target, &state, &mut proposed) {
                    out.push(Candidate { target, parent, added });
                }
            }
        }
        if grown.len() <= parent {
            grown.resize(parent + 1, 0);
        }
        grown[parent] = units;
    }
    out
}

/// Every state a state grown by a unit (its contacts one after the other) can map to.
fn grow_by(
    fixed: &Part,
    moving: &Part,
    state: &[PrincipalContact],
    unit: &[PrincipalContact],
) -> Vec<Vec<PrincipalContact>> {
    let mut targets = vec![state.to_vec()];
    for &pc in unit {
        let mut next: Vec<Vec<PrincipalContact>> = Vec::new();
        for t in targets {
            let grown = if t.contains(&pc) {
                vec![t]
            } else {
                rules::grow_every(fixed, moving, &t, pc)
            };
            for g in grown {
                if !next.contains(&g) {
                    next.push(g);
                }
            }
        }
        targets = next;
    }
    targets
}
