//! Deciding a candidate state: a verified witness, a proof that no pose in the bounds
//! shows it, or an honest "undecided" with the smallest box of poses left open.
//!
//! The decision is a branch and prune over boxes of poses. Every box is first tested
//! by conservative exclusions (each sound: it only drops a box when no pose in it can
//! show the state):
//! - the orientation test over the box's rotations;
//! - interval constraint propagation ([`super::prover`]), which narrows the box's
//!   translations and may empty it;
//! - two Lipschitz tests at the box's centre: every point of the moving part moves by
//!   at most `δ = |Δt| + ρ Σ|Δθ|` over the box (ρ the farthest vertex from the moving
//!   part's origin), so a contact whose elements are more than `δ` apart at the centre,
//!   or a pair of convex pieces penetrating by more than `δ` there (the penetration
//!   depth is 1-Lipschitz in that displacement), rules the whole box out;
//! - in a box whose `δ` is below the separation tolerance, a pair of elements that no
//!   contact of the target holds and that stays closer than that tolerance all over
//!   the box: every pose there either shows more than the target or is too close to
//!   read the same with every tolerance, so none is a (robust) witness. The limits of
//!   larger states (a corner balanced on a corner, with edges along the rim) end here.
//!   A box small in rotation only (a face sliding along a face) gets the same rule
//!   with the pair's distance taken at the corners of its translations (the distance
//!   between convex elements is convex in the translation), and with a face lying
//!   within the loosest tolerance of another's plane over an overlap of their
//!   interiors (a looser checker reads them on each other).
//!
//! A box that survives is searched by a local optimisation from its centre, within the
//! box, at every few levels of depth, and split in two. The search ends with a witness,
//! with every box excluded (proved infeasible), or when the budget runs out
//! (undecided).

use std::collections::BTreeSet;

use super::prover::Links;
use super::turns::Turns;
use super::{Problem, SearchStats};
use crate::contact::PrincipalContact;
use crate::model::{ElementId, Part};
use crate::pose::{Bounds, Pose};
use crate::tolerance::{CONTACT_REL, NEAR_REL, scaled};

/// A rule that excluded boxes of poses.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Rule {
    /// Two contacts' points are too far apart on one part and too close on the other,
    /// whatever the pose.
    RigidDistance,
    /// Two point contacts' normals are an angle apart on one part that the other
    /// part's elements cannot match, under any rotation (a box corner in a
    /// right-angled groove, for one): a last proof, once every search is done.
    NormalAngles,
    /// A corner of one part on a face of the other, and another contact's point in a
    /// convex face at that corner and on the same plane: the face would lie flush or
    /// cross the plane at the corner (`feasibility::hinge`); a last proof.
    FaceHinge,
    /// A vertex at a reflex corner of one of its own part's faces on a face of the
    /// other part (`feasibility::reflex`): along one of the corner's edges, or along
    /// its continuation into the face, the vertex's part never rises off the other
    /// face, so the parts penetrate or touch elsewhere; a last proof.
    ReflexCorner,
    /// A vertex on a face, held on the plane of a face next to it by another contact
    /// (an edge from it lying there): it lies on their common edge's line, too near the
    /// face's rim or off it (`feasibility::fold`); a last proof.
    OnTheFold,
    /// Two contacts hold two points of one edge on a face's plane, and no contact lists
    /// the edge on that face (`feasibility::two_points`): in exact geometry the edge
    /// would lie on the face. The witness check makes the same test, so the decisions
    /// make it before any search.
    EdgeOnTwoPoints,
    /// The chord between two contacts' points lies on one part's boundary and inside
    /// the other, or inside both, and no edge or face of each can carry it (a face it
    /// runs through would have to lie flush), whatever the pose
    /// (`feasibility::two_points`): in exact geometry the parts penetrate. Tested by
    /// the witness check too, and before any search.
    ChordOffTheBoundary,
    /// A crossing whose edge stays parallel to a face at the other edge under every
    /// rotation of the bounds (`feasibility::parallel`): the edge lies in that face
    /// wherever it crosses, which implies the crossing. Tested before any search.
    CrossingInAFace,
    /// A crossing of two edges that stay parallel under every rotation the candidate
    /// allows (the bounds', or the turns about a flush face's normal;
    /// `feasibility::parallel`): parallel edges that meet run together or touch at an
    /// end, never cross. Tested before any search.
    ParallelCrossing,
    /// No rotation in the box puts each part on the outer side of the other's face.
    Orientation,
    /// Interval constraint propagation of the contacts and of non-penetration of
    /// vertices emptied the box.
    Propagation,
    /// The elements of a contact are farther apart at the box's centre than any point
    /// can move within the box.
    Distance,
    /// The parts penetrate at the box's centre by more than any point can move within
    /// the box.
    Penetration,
    /// The box is smaller than the separation tolerance, and a pair of elements that no
    /// contact of the target holds stays closer than that tolerance over all of it: at
    /// every pose there, the pair either touches (another state) or is too close for a
    /// witness (docs/concepts.md#tolerances), so no pose in the box shows the target
    /// robustly.
    Robustness,
}

/// A proof that no pose in the bounds shows a candidate: the rules that excluded the
/// boxes, and how many boxes were examined.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Proof {
    /// Every rule that excluded some box.
    pub rules: BTreeSet<Rule>,
    /// Boxes examined.
    pub boxes: usize,
}

impl Proof {
    /// The proof of a rule that rules a candidate out whatever the pose.
    fn outright(rule: Rule) -> Proof {
        Proof {
            rules: BTreeSet::from([rule]),
            boxes: 1,
        }
    }

    /// Whether the proof may lean on other pairs of elements keeping apart (the pairs
    /// a witness keeps apart, in propagation; the robustness rule; a reflex corner on
    /// a face, which shows that a pair no contact lists touches or penetrates): then
    /// it rules out the candidate alone, not the states holding it with more contacts.
    #[must_use]
    pub fn leans_on_others_apart(&self) -> bool {
        [Rule::Propagation, Rule::Robustness, Rule::ReflexCorner]
            .iter()
            .any(|rule| self.rules.contains(rule))
    }
}

/// How the decision of one candidate ended.
#[derive(Clone, Debug, PartialEq)]
pub enum Decision {
    /// A verified witness of the candidate.
    Witnessed(Pose),
    /// No pose in the bounds shows it.
    Infeasible(Proof),
    /// Neither: the budget ran out. The smallest box of poses still open.
    Undecided(Bounds),
}

/// A decision and the other states met on the way (verified, with their witnesses).
#[derive(Clone, Debug, PartialEq)]
pub struct Decided {
    /// How the candidate ended.
    pub decision: Decision,
    /// Other states whose witnesses the search met.
    pub others: Vec<(Vec<PrincipalContact>, Pose)>,
    /// When a branch and prune over the whole bounds left the candidate undecided with
    /// few boxes open, every one of them (their union holds every pose it could not
    /// exclude); empty otherwise. The last proofs go on from them.
    pub rest: Vec<Bounds>,
}

impl Decided {
    /// The decision as a [`super::Search`] (a proof counted in `stats.pruned`).
    pub(crate) fn into_search(self, stats: &mut SearchStats) -> super::Search {
        match self.decision {
            Decision::Witnessed(pose) => super::Search::Found(pose),
            Decision::Infeasible(_) => {
                stats.pruned += 1;
                super::Search::Unreachable
            }
            Decision::Undecided(_) => super::Search::NotFound { others: self.others },
        }
    }
}

/// Boxes examined before the first optimisation: cheap proofs come first.
const QUICK_PRUNE_BUDGET: usize = 32;
/// Boxes examined by the cheap proofs in all, before the searches inside boxes.
const PRUNE_BUDGET: usize = 256;
/// Boxes the last proofs' conditions examine over the whole bounds in a decision, once
/// its starts have failed: most candidates that hold only in the limit of a larger
/// state fall in a few (two on the built-in example), where the decision's own
/// conditions spent their whole budget in vain.
const EARLY_LAST_BUDGET: usize = 32;
/// Boxes the last proofs' conditions examine over the whole bounds before the starts:
/// nearly every candidate they rule out after the starts on the built-in example (59
/// of 77) falls in the first three, and a candidate that holds pays no more than these
/// before its search.
const FIRST_LAST_BUDGET: usize = 4;
/// Boxes of rotations examined while searching inside them, per unit of effort.
const SEARCH_BUDGET: usize = 256;
/// Boxes examined by the last proofs, split in every component, per unit of effort.
const PROOF_BUDGET: usize = 256;
/// Boxes the last proofs ([`Problem::prove_last`]) examine, split in every component,
/// per unit of effort, beyond the decision's own budget: few candidates are left then,
/// and the screen has passed them.
const LAST_PROOF_BUDGET: usize = 256;
/// Boxes the last proofs examine when they go on from the boxes a decision left open,
/// split in every component, per unit of effort; they do so only when at most a
/// quarter of it is open.
const CONTINUED_PROOF_BUDGET: usize = 512;
/// Boxes the last proofs' screen examines in the box a decision left open, per unit of
/// effort.
const SCREEN_BUDGET: usize = 64;
/// Boxes the proof by halving ([`Problem::prove_by_halving`]) examines, per unit of
/// effort, once the branch and prune has failed: the built-in example's candidates it
/// proves take from a few hundred boxes to about 5,000, and most it cannot prove meet
/// the floor within a few dozen.
const HALVING_BUDGET: usize = 24576;
/// Boxes [`Problem::sliver_rotations`] halves, per unit of effort: a search, not a
/// proof, so a budget that runs out costs only the slivers past it (the turned peg's
/// takes 33 boxes).
const SLIVER_HALVING_BUDGET: usize = 2048;
/// Boxes left open at the floor that [`Problem::sliver_rotations`] looks inside, at most.
const SLIVER_BOXES: usize = 8;
/// Boxes of rotations it splits inside each, at most.
const SLIVER_SPLITS: usize = 1024;
/// Rotations it takes from each, at most.
const SLIVER_TURNS: usize = 8;
/// The proof by halving gives up at the first box this narrow (relative to L, rotations
/// as the arc they sweep) that it cannot exclude, trimmed: the limit poses of larger states that
/// leave a candidate undecided stay open however small the box.
const HALVING_FLOOR_REL: f64 = 4e-4;
/// Slabs [`Problem::trim`] tries from each end of an angle's range, at most.
const TRIM_STEPS: usize = 24;
/// The thinnest slab [`Problem::trim`] tries, as a share of what is left.
const TRIM_LEAST: f64 = 1.0 / 4096.0;
/// A box of rotations that survives is searched by optimisation every this many
/// levels of depth (three: each angle halved once).
const SEARCH_EVERY: u32 = 3;
/// Local optimisations inside boxes, at most, per candidate and unit of effort.
const BOX_SEARCHES: usize = 16;

/// Where a search from the warm and constructive starts begins.
pub(crate) struct Starts<'s> {
    /// Witnesses of related states (the parent's, the added contact's).
    pub warm: &'s [Pose],
    /// The contact whose points the constructive starts put together.
    pub anchor: &'s PrincipalContact,
    /// How many constructive starts.
    pub constructive: usize,
    /// How many times the problem's effort this decision may spend (single contacts,
    /// few and the seeds of everything, get more).
    pub boost: u32,
}

/// What a target's boxes are tested against.
pub(crate) struct Conditions {
    /// The contacts and the pairs kept apart, for propagation.
    links: Links,
    /// The rotation-only conditions.
    turns: Turns,
}

/// How a branch and prune splits its boxes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Mode {
    /// In rotation only: the constraints are linear in the translation once the
    /// rotation is enclosed, so propagation narrows the translation directly.
    Rotations,
    /// In every component, with the Lipschitz tests.
    All,
}

/// The boxes still open, depth first.
struct Branching {
    /// Open boxes with their depths, shallow first (breadth first: every region is
    /// searched at one depth before any is searched deeper).
    open: std::collections::VecDeque<(Bounds, u32)>,
    examined: usize,
    rules: BTreeSet<Rule>,
    /// Boxes left open because they could not be split further (below the slack).
    leaves: Vec<Bounds>,
}

impl Problem<'_> {
    /// Decides a candidate state (contacts sorted) over the whole bounds: the starts
    /// first, then a branch and prune that searches inside the boxes it cannot exclude.
    pub(crate) fn decide(&self, target: &[PrincipalContact], starts: &Starts, stats: &mut SearchStats) -> Decided {
        let mut others = Vec::new();
        let mut rest = Vec::new();
        let decision = self.decide_within(target, starts, &self.bounds, &mut others, Some(&mut rest), stats);
        Decided { decision, others, rest }
    }

    /// The cheap proofs alone, on the whole bounds as one box, with no split and no
    /// search: infeasible, or undecided with the box they narrowed it to. What a
    /// candidate met after the run's work limit gets
    /// ([`crate::graph::Options::work_limit`]): nearly every candidate those proofs rule
    /// out falls in that first box, and splitting costs each one left several times as
    /// much again (on the round peg, 85% of a screen split 32 boxes deep).
    pub(crate) fn screen(&self, target: &[PrincipalContact], stats: &mut SearchStats) -> Decided {
        let decision = match self.conditions(target) {
            Err(rule) => Decision::Infeasible(Proof::outright(rule)),
            Ok(conditions) => {
                stats.boxes += 1;
                match self.exclude(target, &conditions, Mode::Rotations, &self.bounds, true) {
                    Err(rule) => Decision::Infeasible(Proof::outright(rule)),
                    Ok(open) => Decision::Undecided(open),
                }
            }
        };
        Decided {
            decision,
            others: Vec::new(),
            rest: Vec::new(),
        }
    }

    /// The rule that proves, on its own, that no pose in `bounds` shows `target` (the
    /// contacts sorted), tried as the decision tries each box: rigid distances, the
    /// rotation conditions, propagation, and the Lipschitz tests. `None` when none
    /// does. Every rule is sound: a box around a verified witness is never excluded.
    #[must_use]
    pub fn exclusion(&self, target: &[PrincipalContact], bounds: &Bounds) -> Option<Rule> {
        self.excluded_by(target, self.conditions(target), bounds)
    }

    /// [`Problem::exclusion`] with the last proofs' conditions ([`Problem::prove_last`]):
    /// a face and a corner of the other part kept apart unless a contact holds both,
    /// and the contacts along a segment or over an area asked to meet together with
    /// the other linearised conditions. As sound: a box around a verified witness is
    /// never excluded.
    #[must_use]
    pub fn last_exclusion(&self, target: &[PrincipalContact], bounds: &Bounds) -> Option<Rule> {
        self.excluded_by(target, self.last_conditions(target), bounds)
    }

    /// The rule of `conditions` that excludes `bounds` on its own, if one does.
    fn excluded_by(
        &self,
        target: &[PrincipalContact],
        conditions: Result<Conditions, Rule>,
        bounds: &Bounds,
    ) -> Option<Rule> {
        match conditions {
            Ok(conditions) => self.exclude(target, &conditions, Mode::All, bounds, true).err(),
            Err(rule) => Some(rule),
        }
    }

    /// What a target's boxes are tested against; the rule that already rules the
    /// target out whatever the pose, if one does.
    fn conditions(&self, target: &[PrincipalContact]) -> Result<Conditions, Rule> {
        self.conditions_from(target, |target| self.prover.links(target), |target| self.turns(target))
    }

    /// [`Problem::conditions`] for the last proofs ([`super::prover::Prover::last_links`]),
    /// with the contacts' normals compared first ([`super::normals`]). A decision
    /// tries them for a few boxes only before its starts ([`FIRST_LAST_BUDGET`]), and
    /// at more length after them, although they are cheap and sound from the start:
    /// the searches of candidates that hold only in the limit of a larger state (a
    /// corner in a groove, its edge nearly along it) land on the slivers next to that
    /// state, states no other search finds (the built-in example's bottom edge on the
    /// floor with an upright edge on the wall and the top edges crossing).
    fn last_conditions(&self, target: &[PrincipalContact]) -> Result<Conditions, Rule> {
        self.last_conditions_with(target, |target| self.strict_turns(target))
    }

    /// [`Problem::last_conditions`] with the rotation conditions `turns` gives.
    fn last_conditions_with(
        &self,
        target: &[PrincipalContact],
        turns: impl FnOnce(&[PrincipalContact]) -> Turns,
    ) -> Result<Conditions, Rule> {
        if !super::normals::normals_compatible(self.fixed, self.moving, target) {
            return Err(Rule::NormalAngles);
        }
        if super::hinge::hinged(self.fixed, self.moving, target, self.scale, |fixed, a, b| {
            self.scene.distance_within(fixed, a, b)
        }) {
            return Err(Rule::FaceHinge);
        }
        if super::reflex::corner_on_a_face(self.fixed, self.moving, target) {
            return Err(Rule::ReflexCorner);
        }
        if super::fold::on_the_fold(self.fixed, self.moving, target, self.scale) {
            return Err(Rule::OnTheFold);
        }
        self.conditions_from(target, |target| self.prover.last_links(target), turns)
    }

    fn conditions_from(
        &self,
        target: &[PrincipalContact],
        links: impl FnOnce(&[PrincipalContact]) -> Option<super::prover::Links>,
        turns: impl FnOnce(&[PrincipalContact]) -> Turns,
    ) -> Result<Conditions, Rule> {
        if !self.rigidly_compatible(target) {
            return Err(Rule::RigidDistance);
        }
        if super::two_points::edge_on_two_points(self.fixed, self.moving, target) {
            return Err(Rule::EdgeOnTwoPoints);
        }
        if super::two_points::chord_off_the_boundary(self.fixed, self.moving, target) {
            return Err(Rule::ChordOffTheBoundary);
        }
        if let Some(crossings) =
            super::parallel::Crossings::of(self.fixed, self.moving, &self.bounds, self.assembled.matrix3, target)
        {
            if crossings.held_in_a_face() {
                return Err(Rule::CrossingInAFace);
            }
            if crossings.of_parallel_edges() {
                return Err(Rule::ParallelCrossing);
            }
        }
        let links = links(target).ok_or(Rule::Propagation)?;
        Ok(Conditions {
            links,
            turns: turns(target),
        })
    }

    /// Decides `target`, one contact below a known `state` with witness `witness`:
    /// first by pushing the other contact apart from the witness, then within small
    /// boxes around it (a state whose neighbours hold only next to it, at a bound),
    /// then over the whole bounds from the witness.
    pub(crate) fn decide_below(
        &self,
        target: &[PrincipalContact],
        state: &[PrincipalContact],
        witness: Pose,
        stats: &mut SearchStats,
    ) -> Decided {
        let mut decided = self.retry_below(target, state, witness, stats);
        if !matches!(decided.decision, Decision::Undecided(_)) {
            return decided;
        }
        let Some(anchor) = target.first() else {
            decided.decision = Decision::Infeasible(Proof {
                rules: BTreeSet::new(),
                boxes: 0,
            });
            return decided;
        };
        let starts = Starts {
            warm: &[witness],
            anchor,
            constructive: 2,
            boost: 1,
        };
        decided.decision = self.decide_within(
            target,
            &starts,
            &self.bounds,
            &mut decided.others,
            Some(&mut decided.rest),
            stats,
        );
        decided
    }

    /// [`Problem::decide_below`] without the search over the whole bounds, for a
    /// candidate that one left undecided already: a witness next to the state's, or
    /// undecided (with the whole bounds open).
    pub(crate) fn retry_below(
        &self,
        target: &[PrincipalContact],
        state: &[PrincipalContact],
        witness: Pose,
        stats: &mut SearchStats,
    ) -> Decided {
        let mut others = Vec::new();
        let decision = match self.witness_below(target, state, witness, &mut others, stats) {
            Some(pose) => Decision::Witnessed(pose),
            None => Decision::Undecided(self.bounds),
        };
        Decided {
            decision,
            others,
            rest: Vec::new(),
        }
    }

    /// [`Problem::find_below`] as a decision: the witness, or undecided (with the whole
    /// bounds open) for a candidate met before.
    pub(crate) fn release_below(
        &self,
        target: &[PrincipalContact],
        state: &[PrincipalContact],
        witness: Pose,
        stats: &mut SearchStats,
    ) -> Decided {
        match self.find_below(target, state, witness, stats) {
            super::Search::Found(pose) => Decided {
                decision: Decision::Witnessed(pose),
                others: Vec::new(),
                rest: Vec::new(),
            },
            super::Search::NotFound { others } => Decided {
                decision: Decision::Undecided(self.bounds),
                others,
                rest: Vec::new(),
            },
            super::Search::Unreachable => Decided {
                decision: Decision::Undecided(self.bounds),
                others: Vec::new(),
                rest: Vec::new(),
            },
        }
    }

    /// A witness of `target`, one contact below a known `state` with witness
    /// `witness`, found next to that witness: by pushing the other contact apart, then
    /// within small boxes around it. What a candidate left undecided over the whole
    /// bounds is searched again with once a state above it turns up: where a state
    /// holds, the states one contact below it hold beside it (the contacts' conditions
    /// are independent there), often in a sliver the search over the bounds misses.
    pub(crate) fn witness_below(
        &self,
        target: &[PrincipalContact],
        state: &[PrincipalContact],
        witness: Pose,
        others: &mut Vec<(Vec<PrincipalContact>, Pose)>,
        stats: &mut SearchStats,
    ) -> Option<Pose> {
        let anchor = target.first()?;
        match self.find_below(target, state, witness, stats) {
            super::Search::Found(pose) => return Some(pose),
            super::Search::NotFound { others: seen } => others.extend(seen),
            super::Search::Unreachable => {}
        }
        let starts = Starts {
            warm: &[witness],
            anchor,
            constructive: 2,
            boost: 1,
        };
        self.decide_near(target, &starts, witness, others, stats)
    }

    /// A witness of `target` within small boxes around `pose`: 1e-4 then a hundred
    /// times that (translations relative to L, angles in radians), clipped to the
    /// bounds.
    pub(crate) fn decide_near(
        &self,
        target: &[PrincipalContact],
        starts: &Starts,
        pose: Pose,
        others: &mut Vec<(Vec<PrincipalContact>, Pose)>,
        stats: &mut SearchStats,
    ) -> Option<Pose> {
        for size in [NEAR_REL, 100.0 * NEAR_REL] {
            let x = pose.to_array();
            let (lo, hi) = (self.bounds.min.to_array(), self.bounds.max.to_array());
            let reach = |k: usize| if k < 3 { size * self.scale } else { size };
            let local_lo: [f64; 6] = std::array::from_fn(|k| (x[k] - reach(k)).max(lo[k]));
            let local_hi: [f64; 6] = std::array::from_fn(|k| (x[k] + reach(k)).min(hi[k]));
            let Ok(local) = Bounds::try_new(local_lo, local_hi) else {
                continue;
            };
            if let Decision::Witnessed(found) = self.decide_within(target, starts, &local, others, None, stats) {
                return Some(found);
            }
        }
        None
    }

    /// Whether no pose in the bounds has `target`'s contacts holding (robustly, inside
    /// their elements), whatever other pairs touch: the cheap proofs only (rigid
    /// distances, the rotation conditions, propagation without the pairs a witness
    /// keeps apart), split in rotation within the first budget of boxes. False when
    /// they do not settle it.
    pub(crate) fn never_holds(&self, target: &[PrincipalContact], stats: &mut SearchStats) -> bool {
        let conditions = match self.conditions(target) {
            Ok(conditions) => Conditions {
                links: conditions.links.without_apart(),
                turns: conditions.turns,
            },
            Err(_) => return true,
        };
        let mut branching = Branching::new(&[self.bounds]);
        let mut others = Vec::new();
        matches!(
            self.branch(
                target,
                &conditions,
                Mode::Rotations,
                &mut branching,
                PRUNE_BUDGET,
                None,
                &mut others,
                stats,
            ),
            Some(Decision::Infeasible(_))
        )
    }

    /// A proof by halving alone over the whole bounds, depth first: each box tested
    /// once with the last proofs' conditions (no look-ahead) and halved where it is
    /// widest, rotations weighed as the arc they sweep, the half holding `toward` (the
    /// centre of the box the branch and prune left open) first.
    /// The box left open once `budget` boxes are examined (the next one) or a box no
    /// wider than `floor` stays open, its angles trimmed too ([`Problem::trim`]): the branch and prune's
    /// look-ahead weighs the halves' propagation, which near a limit pose of a larger
    /// state keeps splitting translations that the halving leaves whole, while a
    /// rotation slice of a few milliradians would fall to propagation outright.
    fn prove_by_halving(
        &self,
        target: &[PrincipalContact],
        conditions: &Conditions,
        toward: Pose,
        budget: usize,
        floor: f64,
        stats: &mut SearchStats,
    ) -> Result<Proof, Bounds> {
        let depth = Depth {
            budget,
            floor,
            most_open: 1,
        };
        let halving = self.halve(target, conditions, toward, depth, stats);
        match halving.open.first() {
            Some(open) => Err(*open),
            None => Ok(Proof {
                rules: halving.rules,
                boxes: halving.boxes,
            }),
        }
    }

    /// Halves the bounds, depth first from the half holding `toward`, as far as `depth`
    /// goes (each box at its floor trimmed and tried once more): the rules that
    /// excluded boxes, and the boxes left open (the box it stopped at, when the budget
    /// ran out).
    fn halve(
        &self,
        target: &[PrincipalContact],
        conditions: &Conditions,
        toward: Pose,
        depth: Depth,
        stats: &mut SearchStats,
    ) -> Halving {
        let Depth {
            budget,
            floor,
            most_open,
        } = depth;
        let mut stack = vec![self.bounds];
        let mut halving = Halving::default();
        while let Some(b) = stack.pop() {
            if halving.boxes >= budget {
                halving.open.push(b);
                break;
            }
            halving.boxes += 1;
            stats.boxes += 1;
            match self.exclude(target, conditions, Mode::All, &b, true) {
                Err(rule) => {
                    halving.rules.insert(rule);
                }
                Ok(narrowed) => {
                    let Some(k) = self.prover.widest_above(&narrowed, 0..6, floor) else {
                        // At the floor, a last try: the angles cut down to where the
                        // tests leave them open, a thin slab the box's own tests miss.
                        let trimmed = self.trim(target, conditions, &narrowed);
                        match self.exclude(target, conditions, Mode::All, &trimmed, true) {
                            Err(rule) => {
                                halving.rules.insert(rule);
                            }
                            Ok(_) => {
                                halving.open.push(trimmed);
                                if halving.open.len() >= most_open {
                                    break;
                                }
                            }
                        }
                        continue;
                    };
                    // The half holding `toward` is examined first: a box that stays
                    // open is found early where there is one.
                    let mut split = narrowed.halves(k);
                    let t = toward.to_array()[k];
                    split.sort_by_key(|h| h.min.to_array()[k] <= t && t <= h.max.to_array()[k]);
                    stack.extend(split);
                }
            }
        }
        halving
    }

    /// Rotations at which `target`, left open by the last proofs, may show as a
    /// checker reads it, for slices to look there ([`Problem::states_in_slivers`]):
    /// the bounds halved as the last proofs do, with the rotation conditions read
    /// tightly ([`Problem::readable_turns`]), and inside each box left open at the
    /// floor (a few), rotations that meet those conditions exactly. A state may hold
    /// only on a sliver narrower than the floor, by the grace of the tolerance: the
    /// turned peg's edge lying in the hole's wall (its tilt within the contact
    /// tolerance over its length) while its bottom corner's edge rises off the
    /// chamfer by more than the loose tolerance, one product of two turns small, each
    /// turn not; no search lands there, and the last proofs (sound, so looser) cannot
    /// close the boxes next to it.
    pub(crate) fn sliver_rotations(&self, target: &[PrincipalContact]) -> Vec<[f64; 3]> {
        let Ok(conditions) = self.last_conditions_with(target, |target| self.readable_turns(target)) else {
            return Vec::new();
        };
        let floor = scaled(HALVING_FLOOR_REL, self.scale);
        let mut stats = SearchStats::default();
        let depth = Depth {
            budget: SLIVER_HALVING_BUDGET * self.effort as usize,
            floor,
            most_open: SLIVER_BOXES,
        };
        let halving = self.halve(target, &conditions, self.bounds.center(), depth, &mut stats);
        let mut rotations: Vec<[f64; 3]> = Vec::new();
        for open in &halving.open {
            for r in conditions.turns.rotations_meeting(open, SLIVER_SPLITS, SLIVER_TURNS) {
                if !rotations.contains(&r) {
                    rotations.push(r);
                }
            }
        }
        rotations
    }

    /// The box with slabs of its angles cut off from either end where the exclusion
    /// tests rule them out, each half of what is left, then thinner ones (as
    /// [`Turns::shave`] does with the rotation conditions alone). Each slab is cut at
    /// most to half of what is left, so something is always left.
    fn trim(&self, target: &[PrincipalContact], conditions: &Conditions, b: &Bounds) -> Bounds {
        let (lo, hi) = super::turns::shave_angles(b, TRIM_STEPS, TRIM_LEAST, |lo, hi| {
            Bounds::try_new(*lo, *hi).is_ok_and(|s| self.exclude(target, conditions, Mode::All, &s, true).is_err())
        });
        Bounds::try_new(lo, hi).unwrap_or(*b)
    }

    /// Boxes the last proofs examine when they go on from the boxes a decision left
    /// open.
    fn continued_proof_budget(&self) -> usize {
        CONTINUED_PROOF_BUDGET * self.effort as usize
    }

    /// The last proof of a candidate left undecided once every search and sweep is
    /// done, with the strongest conditions ([`super::prover::Prover::last_links`]) and
    /// no search in between. First a screen: the box its decision left open (`open`),
    /// split in every component within [`SCREEN_BUDGET`] boxes; a candidate whose open
    /// box stays open there is left undecided at that cost. Then the branch and prune
    /// goes on from every box the decision left open (`rest`, when it gave them), in
    /// every component; without them, over the whole bounds, rotations first, then
    /// every component. Where that fails (the screen included), a proof by halving
    /// alone over the whole bounds ([`Problem::prove_by_halving`]). The proof, or
    /// the box the halving left open: where the candidate may still hold, for the
    /// report.
    pub(crate) fn prove_last(
        &self,
        target: &[PrincipalContact],
        open: &Bounds,
        rest: &[Bounds],
        stats: &mut SearchStats,
    ) -> Result<Proof, Bounds> {
        let conditions = match self.last_conditions(target) {
            Ok(conditions) => conditions,
            Err(rule) => {
                return Ok(Proof::outright(rule));
            }
        };
        let proved = |from: &[Bounds], phases: &[(Mode, usize)], stats: &mut SearchStats| {
            let mut branching = Branching::new(from);
            let mut others = Vec::new();
            for &(mode, budget) in phases {
                branching.open.extend(branching.leaves.drain(..).map(|b| (b, 0)));
                match self.branch(
                    target,
                    &conditions,
                    mode,
                    &mut branching,
                    budget,
                    None,
                    &mut others,
                    stats,
                ) {
                    Some(Decision::Infeasible(proof)) => return Some(proof),
                    Some(_) => return None,
                    None => {}
                }
            }
            None
        };
        let effort = self.effort as usize;
        let standard = |stats: &mut SearchStats| {
            proved(&[*open], &[(Mode::All, SCREEN_BUDGET * effort)], stats)?;
            // Few boxes left open (the decision hands on at most a quarter of the budget):
            // going on from them reaches deeper than starting again. Many (a decision that
            // split wide regions it could not exclude): the stronger conditions exclude
            // more from the whole bounds, at coarse levels.
            if !rest.is_empty() {
                return proved(rest, &[(Mode::All, self.continued_proof_budget())], stats);
            }
            let rotations = PRUNE_BUDGET + SEARCH_BUDGET * effort;
            let all = rotations + (PROOF_BUDGET + LAST_PROOF_BUDGET) * effort;
            proved(&[self.bounds], &[(Mode::Rotations, rotations), (Mode::All, all)], stats)
        };
        standard(stats).ok_or(()).or_else(|()| {
            let floor = scaled(HALVING_FLOOR_REL, self.scale);
            self.prove_by_halving(
                target,
                &conditions,
                open.center(),
                HALVING_BUDGET * effort,
                floor,
                stats,
            )
        })
    }

    /// The states met where `target`'s contacts hold with others touching too: local
    /// optimisations of its contacts alone (other pairs may touch), from `count`
    /// constructive starts, each pose read by the contact module and kept when it is a
    /// clean witness of a state holding every contact of `target`. A contact that never
    /// holds alone, because others come with it wherever it holds (faces at the same
    /// clearance, two feet on one floor), occurs only in such states: the decision of
    /// the contact on its own, which proves that no pose shows it alone, says nothing
    /// of them.
    pub(crate) fn states_containing(
        &self,
        target: &[PrincipalContact],
        count: usize,
        stats: &mut SearchStats,
    ) -> Vec<(Vec<PrincipalContact>, Pose)> {
        let mut found: Vec<(Vec<PrincipalContact>, Pose)> = Vec::new();
        if target.is_empty() {
            return found;
        }
        let anchors: Vec<PrincipalContact> = target.to_vec();
        for (i, start) in self.starts(&anchors, count, &self.bounds).into_iter().enumerate() {
            let start = self.probed(target, &anchors[i % anchors.len()], start, &self.bounds);
            let pose = self.solve_from(target, start, &self.bounds, stats);
            let Some(state) = self.verify(&pose) else { continue };
            let holds = target.iter().all(|pc| state.binary_search(pc).is_ok());
            if holds && !found.iter().any(|(known, _)| *known == state) {
                found.push((state, pose));
            }
        }
        found
    }

    pub(crate) fn decide_within(
        &self,
        target: &[PrincipalContact],
        starts: &Starts,
        bounds: &Bounds,
        others: &mut Vec<(Vec<PrincipalContact>, Pose)>,
        rest: Option<&mut Vec<Bounds>>,
        stats: &mut SearchStats,
    ) -> Decision {
        let conditions = match self.conditions(target) {
            Ok(conditions) => conditions,
            Err(rule) => {
                return Decision::Infeasible(Proof::outright(rule));
            }
        };
        let links = &conditions;
        let mut branching = Branching::new(&[*bounds]);
        // Cheap proofs first, split in rotation only: given the rotation, the contacts
        // are linear in the translation, which propagation narrows directly. A few
        // boxes before the starts (nearly every candidate these proofs rule out falls in
        // one), the rest after them: a candidate that holds is mostly witnessed by a
        // start, and the boxes would all be spent on it in vain.
        let prune = |budget: usize, branching: &mut Branching, others: &mut Vec<_>, stats: &mut SearchStats| {
            self.branch(target, links, Mode::Rotations, branching, budget, None, others, stats)
        };
        if let Some(decision) = prune(QUICK_PRUNE_BUDGET, &mut branching, others, stats) {
            return decision;
        }
        // The last proofs' stronger conditions, very briefly: the candidates they rule
        // out at all fall in a few boxes, mostly, and then need no search.
        let last = self.last_conditions(target);
        if let Some(proof) = self.proved_early(target, &last, FIRST_LAST_BUDGET, stats) {
            return Decision::Infeasible(proof);
        }
        // The warm starts and the constructive starts.
        // The anchor first, then the target's other contacts in turn.
        let anchors: Vec<PrincipalContact> = std::iter::once(*starts.anchor)
            .chain(target.iter().copied().filter(|pc| pc != starts.anchor))
            .collect();
        let constructive = self.starts(&anchors, starts.constructive, bounds);
        let probed = constructive
            .into_iter()
            .enumerate()
            .map(|(i, start)| self.probed(target, &anchors[i % anchors.len()], start, bounds));
        for start in starts.warm.iter().copied().chain(probed) {
            if let Some(pose) = self.search_from(target, start, bounds, others, stats) {
                return Decision::Witnessed(pose);
            }
        }
        // Again, longer: after the starts, whose searches meet the states next to the
        // candidate, and before the rest of the cheap proofs, the searches inside boxes
        // and the long branch and prune.
        if let Some(proof) = self.proved_early(target, &last, EARLY_LAST_BUDGET, stats) {
            return Decision::Infeasible(proof);
        }
        if let Some(decision) = prune(PRUNE_BUDGET, &mut branching, others, stats) {
            return decision;
        }
        // Point contacts that pin the translation to a line: a search over the rotation.
        if let Some(pose) = self.slide_search(target, bounds, true, others) {
            return Decision::Witnessed(pose);
        }
        // Then inside the boxes of rotations that stay open, level by level (the local
        // searches left counted down).
        let effort = (self.effort * starts.boost.max(1)) as usize;
        let mut searches = BOX_SEARCHES * effort;
        let budget = PRUNE_BUDGET + SEARCH_BUDGET * effort;
        if let Some(decision) = self.branch(
            target,
            links,
            Mode::Rotations,
            &mut branching,
            budget,
            Some(&mut searches),
            others,
            stats,
        ) {
            return decision;
        }
        // Last, proofs that need the translations split too (non-penetration, the
        // Lipschitz tests), from the boxes left.
        branching.open.extend(branching.leaves.drain(..).map(|b| (b, 0)));
        let decision = self
            .branch(
                target,
                links,
                Mode::All,
                &mut branching,
                budget + PROOF_BUDGET * effort,
                Some(&mut searches),
                others,
                stats,
            )
            .unwrap_or_else(|| Decision::Undecided(branching.open().unwrap_or(*bounds)));
        if let (Decision::Undecided(_), Some(rest)) = (&decision, rest) {
            // Handed on only when few enough for the last proofs to go on from.
            if branching.open.len() + branching.leaves.len() <= self.continued_proof_budget() / 4 {
                *rest = branching.rest();
            }
        }
        decision
    }

    /// The proof of the last proofs' conditions ([`Problem::last_conditions`]) over the
    /// whole bounds within `budget` boxes per unit of effort, if they find one.
    fn proved_early(
        &self,
        target: &[PrincipalContact],
        last: &Result<Conditions, Rule>,
        budget: usize,
        stats: &mut SearchStats,
    ) -> Option<Proof> {
        match last {
            Ok(conditions) => self.proof_within(target, conditions, budget * self.effort as usize, stats),
            Err(rule) => Some(Proof::outright(*rule)),
        }
    }

    /// The proof, split in every component with no search, that no pose of the whole
    /// bounds meets `conditions`, if `budget` boxes find one.
    fn proof_within(
        &self,
        target: &[PrincipalContact],
        conditions: &Conditions,
        budget: usize,
        stats: &mut SearchStats,
    ) -> Option<Proof> {
        let mut branching = Branching::new(&[self.bounds]);
        match self.branch(
            target,
            conditions,
            Mode::All,
            &mut branching,
            budget,
            None,
            &mut Vec::new(),
            stats,
        ) {
            Some(Decision::Infeasible(proof)) => Some(proof),
            _ => None,
        }
    }

    /// Examines boxes until none is left open (proof), a witness is found, a box
    /// cannot be split, or `budget` boxes have been examined in all (`None`: the
    /// boxes left stay open). With `searches`, boxes that survive are searched
    /// by optimisation every [`SEARCH_EVERY`] levels.
    #[allow(clippy::too_many_arguments)]
    fn branch(
        &self,
        target: &[PrincipalContact],
        links: &Conditions,
        mode: Mode,
        branching: &mut Branching,
        budget: usize,
        mut searches: Option<&mut usize>,
        others: &mut Vec<(Vec<PrincipalContact>, Pose)>,
        stats: &mut SearchStats,
    ) -> Option<Decision> {
        while branching.examined < budget {
            let Some((b, depth)) = branching.open.pop_front() else {
                if let Some(&leaf) = branching.leaves.first() {
                    // A box split to the end in rotation may still fall to translation
                    // splits.
                    return (mode == Mode::All).then_some(Decision::Undecided(leaf));
                }
                return Some(Decision::Infeasible(Proof {
                    rules: std::mem::take(&mut branching.rules),
                    boxes: branching.examined,
                }));
            };
            branching.examined += 1;
            stats.boxes += 1;
            let narrowed = match self.exclude(target, links, mode, &b, true) {
                Err(rule) => {
                    branching.rules.insert(rule);
                    continue;
                }
                Ok(narrowed) => narrowed,
            };
            if let Some(left) = searches.as_deref_mut() {
                // Sliding is cheap (one sweep of the pieces along a line): every box
                // that survives gets it at its central rotation.
                let c = narrowed.center().to_array();
                if let Some(pose) = self.slide(target, [c[3], c[4], c[5]], &narrowed, others) {
                    return Some(Decision::Witnessed(pose));
                }
                if depth > 0 && depth % SEARCH_EVERY == 0 && *left > 0 {
                    *left -= 1;
                    if let Some(pose) = self.slide_search(target, &narrowed, false, others) {
                        return Some(Decision::Witnessed(pose));
                    }
                    let start = self.box_start(target, &narrowed, *left);
                    if let Some(pose) = self.search_from(target, start, &narrowed, others, stats) {
                        return Some(Decision::Witnessed(pose));
                    }
                }
            }
            let split = self.look_ahead(target, links, mode, &narrowed);
            match split {
                Some(Split { component, excluded }) => {
                    // The halves the look-ahead excluded count as examined here.
                    for (half, rule) in narrowed.halves(component).into_iter().zip(excluded) {
                        match rule {
                            Some(rule) => {
                                branching.examined += 1;
                                stats.boxes += 1;
                                branching.rules.insert(rule);
                            }
                            None => branching.open.push_back((half, depth + 1)),
                        }
                    }
                }
                None if mode == Mode::Rotations => branching.leaves.push(narrowed),
                None => {
                    // Below the slack and not excluded: a last search from its centre,
                    // then it stays open.
                    if let Some(pose) = self.slide_within(target, &narrowed, others) {
                        return Some(Decision::Witnessed(pose));
                    }
                    if let Some(pose) = self.search_from(target, narrowed.center(), &narrowed, others, stats) {
                        return Some(Decision::Witnessed(pose));
                    }
                    branching.leaves.push(narrowed);
                }
            }
        }
        None
    }

    /// The component to split a box along (angles only in [`Mode::Rotations`]): the
    /// one whose halves the tests exclude the most of. On a tie, among rotations, the
    /// angle the undecided rotation conditions change the most (a turn about a face's
    /// normal then stays whole), else the mean share of the translation widths left
    /// after propagation, then the widest. With it, the rule that excluded each half.
    fn look_ahead(&self, target: &[PrincipalContact], links: &Conditions, mode: Mode, b: &Bounds) -> Option<Split> {
        let components = match mode {
            Mode::Rotations => 3..6,
            Mode::All => 0..6,
        };
        let widest = self.prover.split_among(b, components.clone())?;
        let parent = b.width();
        let score = |k: usize| -> (usize, f64, Vec<Option<Rule>>) {
            let mut excluded = 0;
            let mut left = 0.0;
            let mut by = Vec::new();
            for half in b.halves(k) {
                let verdict = self.exclude(target, links, mode, &half, false);
                by.push(verdict.as_ref().err().copied());
                match verdict {
                    Err(_) => excluded += 1,
                    Ok(narrowed) => {
                        let w = narrowed.width();
                        left += (0..3)
                            .map(|j| if parent[j] > 0.0 { w[j] / parent[j] } else { 1.0 })
                            .sum::<f64>()
                            / 3.0;
                    }
                }
            }
            (excluded, left, by)
        };
        // A component whose halves are both excluded is the first one with the most
        // (no component has more): the rest need not be scored.
        let mut scores = Vec::new();
        for k in components.filter(|&k| self.prover.split_among(b, k..k + 1).is_some()) {
            let scored = score(k);
            let both = scored.0 == 2;
            scores.push((k, scored));
            if both {
                break;
            }
        }
        let split = |component: usize| Split {
            component,
            excluded: scores
                .iter()
                .find(|(k, _)| *k == component)
                .map_or_else(Vec::new, |(_, (_, _, by))| by.clone()),
        };
        let hinted = links.turns.split(b);
        let most = scores.iter().map(|(_, (e, _, _))| *e).max()?;
        if most > 0 {
            return scores.iter().find(|(_, (e, _, _))| *e == most).map(|(k, _)| split(*k));
        }
        if let Some(k) = hinted.filter(|k| scores.iter().any(|(j, _)| j == k)) {
            return Some(split(k));
        }
        let least = scores.iter().map(|(_, (_, l, _))| *l).fold(f64::INFINITY, f64::min);
        if scores.iter().all(|(_, (_, l, _))| *l == least) {
            return Some(split(widest));
        }
        scores.iter().find(|(_, (_, l, _))| *l == least).map(|(k, _)| split(*k))
    }

    /// The exclusion tests of one box: the box narrowed by propagation when none
    /// excludes it.
    ///
    /// With `shave`, the box's angles are first cut down to where the rotation
    /// conditions may hold ([`Turns::shave`]); the look-ahead's trial halves only test
    /// them.
    fn exclude(
        &self,
        target: &[PrincipalContact],
        links: &Conditions,
        mode: Mode,
        b: &Bounds,
        shave: bool,
    ) -> Result<Bounds, Rule> {
        let shaved;
        let b = if shave {
            shaved = links.turns.shave(b).ok_or(Rule::Orientation)?;
            &shaved
        } else if links.turns.may_hold(b) {
            b
        } else {
            return Err(Rule::Orientation);
        };
        let narrowed = self.prover.narrow(&links.links, b).ok_or(Rule::Propagation)?;
        if mode == Mode::Rotations {
            // The Lipschitz tests need small translation boxes too.
            return Ok(narrowed);
        }
        let reach = self.reach_within(&narrowed);
        let slack = scaled(10.0 * CONTACT_REL, self.scale);
        let placement = self.placement(&narrowed.center());
        if target
            .iter()
            .any(|pc| self.scene.element_distance(&placement, pc.fixed, pc.moving) > reach + slack)
        {
            return Err(Rule::Distance);
        }
        if self.scene.penetrates_beyond(&placement, reach + slack) {
            return Err(Rule::Penetration);
        }
        let within = self.separation() - reach - slack;
        if within > 0.0 && self.holds_other_pair(target, &placement, within) {
            return Err(Rule::Robustness);
        }
        if self.keeps_other_pair_close(target, &narrowed) {
            return Err(Rule::Robustness);
        }
        Ok(narrowed)
    }

    /// The robustness rule for a box that is small in rotation but not in translation
    /// (a face sliding along a face): a pair of convex elements held by no contact of
    /// the target that stays closer than the separation tolerance over the whole box.
    /// At a fixed rotation the distance between two convex sets is a convex function of
    /// the translation, so its largest value over the box's translations is at one of
    /// their eight corners; turning within the box moves no point of the moving part
    /// by more than `ρ Σ|Δθ|`.
    fn keeps_other_pair_close(&self, target: &[PrincipalContact], b: &Bounds) -> bool {
        let w = b.width();
        let turn = self.moving_radius * (3..6).map(|k| 0.5 * w[k]).sum::<f64>();
        let slack = scaled(10.0 * CONTACT_REL, self.scale);
        let within = self.separation() - turn - slack;
        // A face on a face is read with its plane distances enclosed over the whole
        // box (not the centre's turned by `turn`), so a tall box thin in its angles
        // still tells a face within the loose tolerance of another's plane.
        let loose = scaled(super::LOOSE_CONTACT_REL, self.scale) - slack;
        // A face stays within `d` of a plane over the box's translations only if the
        // box is thinner than `2 d` in some component (the distance is affine in the
        // translation, its range as wide as Σ |n_k| w_k ≥ min w_k): below, the faces
        // are only tried within the separation, the convex elements within `within`.
        if within <= 0.0 && (0..3).all(|k| w[k] >= 2.0 * self.separation()) {
            return false;
        }
        let centre = b.center();
        let (lo, hi) = (b.min.to_array(), b.max.to_array());
        let corners: Vec<glam::DAffine3> = (0..8u32)
            .map(|c| {
                let pick = |k: usize| if (c >> k) & 1 == 0 { lo[k] } else { hi[k] };
                self.placement(&Pose {
                    x: pick(0),
                    y: pick(1),
                    z: pick(2),
                    ..centre
                })
            })
            .collect();
        let convex = |part: &Part, e: ElementId| match e {
            ElementId::Face(f) => part.face(f).loops.len() == 1 && !part.face_outline_is_nonconvex(f),
            _ => true,
        };
        let motion = self.reach_within(b);
        let rotations = super::interval::rotation_enclosure(b);
        let stay_close = |f, g, plane_within: f64, whole: bool| {
            let near_plane = |s: glam::DVec3| self.plane_distance_over(f, s, b, &rotations) < plane_within;
            self.faces_stay_close(f, g, &corners, &near_plane, (motion, turn), whole)
        };
        self.scene
            .pairs_within(&self.placement(&centre), within.max(loose))
            .into_iter()
            .any(|(x, y)| match (x, y) {
                (ElementId::Face(f), ElementId::Face(g)) if self.held(target, x, y) => {
                    // Touching elsewhere through a contact of the target is allowed; the
                    // whole face lying within the loosest tolerance of the other's plane,
                    // over it, is not: a looser checker reads the faces on each other.
                    let target_pair = target.iter().any(|pc| pc.fixed == x && pc.moving == y);
                    !target_pair && stay_close(f, g, loose, true)
                }
                _ if self.held(target, x, y) => false,
                _ if within <= 0.0 => false,
                _ if convex(self.fixed, x) && convex(self.moving, y) => corners
                    .iter()
                    .all(|placement| self.scene.element_distance(placement, x, y) < within),
                (ElementId::Face(f), ElementId::Face(g)) => stay_close(f, g, self.separation() - slack, false),
                _ => false,
            })
    }

    /// Whether a point well inside the moving face `g` stays within `within` of the
    /// fixed face `f`'s plane at every corner placement (the distance to a plane is
    /// affine in the translation, so at every translation between them) and inside `f`
    /// all over the box: then at every pose of the box the two faces either touch in
    /// both their interiors (a contact of that pair, whatever the target holds) or are
    /// too close for a witness.
    ///
    /// Inside `f` all over the box: `motion` (how far any point moves within the box)
    /// deep inside it at the first corner; or, with the rotation at the box's centre,
    /// deeper than `turn` (how far the box's turns move any point) at every corner of
    /// the translations, in a convex face or in one triangle of it (the depth in a
    /// convex polygon is concave, so its least over a box of translations is at a
    /// corner). The second sees a face sliding along a face the whole length of the
    /// box's translations.
    fn faces_stay_close(
        &self,
        f: crate::model::FaceId,
        g: crate::model::FaceId,
        corners: &[glam::DAffine3],
        near_plane: &dyn Fn(glam::DVec3) -> bool,
        (motion, turn): (f64, f64),
        whole: bool,
    ) -> bool {
        let (fixed, moving) = (&self.fixed_faces[f.index()], &self.moving_faces[g.index()]);
        if whole && !moving.loops.iter().flatten().all(|&v| near_plane(v)) {
            return false;
        }
        // Inside both faces by more than the contact tolerance: a touch there is read
        // as a contact of these two faces.
        let keep = scaled(10.0 * CONTACT_REL, self.scale);
        let convex = fixed.loops.len() == 1 && !self.fixed.face_outline_is_nonconvex(f);
        let deep_at_every_corner = |p: glam::DVec3, depth: &dyn Fn(glam::DVec3) -> f64| {
            corners.iter().all(|c| depth(c.transform_point3(p)) > turn + keep)
        };
        // Points of `g` (in its part's frame): its samples, and per pair of triangles
        // the centre of their overlap at the first corner (a thin overlap holds no
        // sample), and the centre of the part of it that stays in `f`'s triangle at
        // every corner, with that triangle (counter-clockwise).
        let to_moving = corners[0].inverse();
        // The other corners' translations from the first (a box flat in a component
        // repeats them; the first itself moves nothing).
        let mut shifts: Vec<glam::DVec3> = Vec::new();
        for c in &corners[1..] {
            let shift = c.translation - corners[0].translation;
            if shift != glam::DVec3::ZERO && !shifts.contains(&shift) {
                shifts.push(shift);
            }
        }
        // `f`'s triangle with its corners counter-clockwise around its normal.
        let ccw = |t: [glam::DVec3; 3]| {
            if (t[1] - t[0]).cross(t[2] - t[0]).dot(fixed.normal) >= 0.0 {
                t
            } else {
                [t[0], t[2], t[1]]
            }
        };
        let centre = |poly: &[glam::DVec3]| poly.iter().copied().sum::<glam::DVec3>() / poly.len() as f64;
        let mut points: Vec<(glam::DVec3, Option<[glam::DVec3; 3]>)> =
            moving.samples.iter().map(|&s| (s, None)).collect();
        for t in &fixed.triangles {
            for u in &moving.triangles {
                let [a, b, c] = u.map(|p| {
                    let q = corners[0].transform_point3(p);
                    q - fixed.normal * (fixed.normal.dot(q) - fixed.offset)
                });
                let mut poly = t.to_vec();
                for (x, y) in [(a, c), (c, b), (b, a)] {
                    poly = clip_outside(&poly, x, y, fixed.normal, glam::DVec3::ZERO);
                }
                if poly.len() < 3 {
                    continue;
                }
                points.push((to_moving.transform_point3(centre(&poly)), None));
                // Where the triangle of `f` is, seen from the first corner, when the
                // translation is at another.
                let [ta, tb, tc] = ccw(*t);
                for &shift in &shifts {
                    for (x, y) in [(ta, tb), (tb, tc), (tc, ta)] {
                        poly = clip_outside(&poly, x, y, fixed.normal, -shift);
                    }
                }
                if poly.len() >= 3 {
                    points.push((to_moving.transform_point3(centre(&poly)), Some(ccw(*t))));
                }
            }
        }
        // The depth of a point in a counter-clockwise triangle of `f`.
        let in_triangle = |t: [glam::DVec3; 3]| {
            move |p: glam::DVec3| {
                [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])]
                    .iter()
                    .map(|&(x, y)| fixed.normal.cross(y - x).normalize_or_zero().dot(p - x))
                    .fold(f64::INFINITY, f64::min)
            }
        };
        points.iter().any(|&(s, triangle)| {
            if !(moving.inside_depth(s) > keep && near_plane(s)) {
                return false;
            }
            fixed.inside_depth(corners[0].transform_point3(s)) > 2.0 * motion + keep
                || (convex && deep_at_every_corner(s, &|p| fixed.inside_depth(p)))
                || triangle.is_some_and(|t| deep_at_every_corner(s, &in_triangle(t)))
        })
    }

    /// The largest distance of the moving part's point `s` from the fixed face `f`'s
    /// plane over the box `b` (`rotations` encloses its rotations): `n · G (R s + t)`
    /// in interval arithmetic, plus a round-off allowance.
    fn plane_distance_over(
        &self,
        f: crate::model::FaceId,
        s: glam::DVec3,
        b: &Bounds,
        rotations: &super::interval::IntervalMat,
    ) -> f64 {
        use super::interval::{Interval, turned_value};
        let face = &self.fixed_faces[f.index()];
        // n · G q = m · q + n · G's translation, with m = G's linear part transposed n.
        let m = self.assembled.matrix3.transpose() * face.normal;
        let (lo, hi) = (b.min.to_array(), b.max.to_array());
        let moved = (0..3).fold(Interval::point(0.0), |acc, k| {
            acc.add(Interval::new(lo[k], hi[k]).mul(Interval::point(m[k])))
        });
        let d = turned_value(rotations, m, s).add(moved).add(Interval::point(
            face.normal.dot(self.assembled.translation) - face.offset,
        ));
        d.lo.abs().max(d.hi.abs()) + scaled(crate::tolerance::ROUNDOFF_REL, self.scale)
    }

    /// Whether two elements `within` of each other at `placement` are held by none of
    /// the target's contacts. Where two elements touch, the point lies on a contact of
    /// the state, in the closures of both the pair's and the contact's elements, so a
    /// held pair shares a vertex with the contact's element on each part.
    fn holds_other_pair(&self, target: &[PrincipalContact], placement: &glam::DAffine3, within: f64) -> bool {
        self.scene
            .pairs_within(placement, within)
            .into_iter()
            .any(|(x, y)| !self.held(target, x, y))
    }

    /// Whether a contact of the target holds the pair of a fixed element `x` and a
    /// moving element `y` (see [`Problem::holds_other_pair`]).
    fn held(&self, target: &[PrincipalContact], x: ElementId, y: ElementId) -> bool {
        target
            .iter()
            .any(|pc| self.fixed.share_a_vertex(x, pc.fixed) && self.moving.share_a_vertex(y, pc.moving))
    }

    /// A witness found by sliding ([`Problem::slide`]) at the centres of a box's eight
    /// octants of rotation (its centre was slid when the box was examined).
    fn slide_within(
        &self,
        target: &[PrincipalContact],
        b: &Bounds,
        others: &mut Vec<(Vec<PrincipalContact>, Pose)>,
    ) -> Option<Pose> {
        let (lo, hi) = (b.min.to_array(), b.max.to_array());
        let at = |w: [f64; 3]| -> [f64; 3] { std::array::from_fn(|k| lo[3 + k] + (hi[3 + k] - lo[3 + k]) * w[k]) };
        let quarter = |bit: u32| 0.25 + 0.5 * f64::from(bit);
        (0..8u32)
            .map(|c| [quarter(c & 1), quarter((c >> 1) & 1), quarter((c >> 2) & 1)])
            .find_map(|w| self.slide(target, at(w), b, others))
    }

    /// A start inside a box for its `k`-th search: at the box's central rotation, the
    /// translation that puts the points of one of the target's contacts together (the
    /// contact and the points chosen by `k`), clamped to the box. The box's centre
    /// alone rarely shows a contact: a thin region of poses needs the contact placed.
    fn box_start(&self, target: &[PrincipalContact], b: &Bounds, k: usize) -> Pose {
        let c = b.center().to_array();
        match target.get(k % target.len().max(1)) {
            Some(anchor) => {
                let placed = self.placed(anchor, k / target.len(), [c[3], c[4], c[5]], b);
                self.probed(target, anchor, placed, b)
            }
            None => b.center(),
        }
    }

    /// How far any point of the moving part can move between a box's centre and any
    /// pose in the box: the translation's half-diagonal plus, for each angle, its
    /// half-width times the farthest vertex from the moving part's origin (an
    /// elementary rotation by α moves a point at radius ρ by at most ρ |α|).
    fn reach_within(&self, b: &Bounds) -> f64 {
        let w = b.width();
        let translation = (0..3).map(|k| (0.5 * w[k]).powi(2)).sum::<f64>().sqrt();
        let turn: f64 = (3..6).map(|k| 0.5 * w[k]).sum();
        translation + self.moving_radius * turn
    }

    /// One local optimisation from `start` within `bounds`; the witness when the pose
    /// it reaches (or a pose pushed from there) shows the target. Other clean states
    /// met are added to `others`.
    fn search_from(
        &self,
        target: &[PrincipalContact],
        start: Pose,
        bounds: &Bounds,
        others: &mut Vec<(Vec<PrincipalContact>, Pose)>,
        stats: &mut SearchStats,
    ) -> Option<Pose> {
        let pose = self.solve_from(target, start, bounds, stats);
        self.settle(target, pose, bounds, others, stats)
    }
}

/// The part of a convex polygon (in a plane of normal `n`) on the inner side of the
/// line from `x + shift` to `y + shift`, a side of a polygon counter-clockwise around
/// `n`.
fn clip_outside(
    poly: &[glam::DVec3],
    x: glam::DVec3,
    y: glam::DVec3,
    n: glam::DVec3,
    shift: glam::DVec3,
) -> Vec<glam::DVec3> {
    if poly.len() < 3 {
        return Vec::new();
    }
    let outward = (y - x).cross(n).normalize_or_zero();
    crate::geometry::clip_convex(poly, outward, outward.dot(x + shift))
}

/// Where the look-ahead splits a box, and the rule that excluded each half (in the
/// order of [`Bounds::halves`]; none for a half that stays open).
struct Split {
    component: usize,
    excluded: Vec<Option<Rule>>,
}

/// How far [`Problem::halve`] goes: at most `budget` boxes, none split below `floor`,
/// stopping at the `most_open`-th box left open.
#[derive(Clone, Copy)]
struct Depth {
    budget: usize,
    floor: f64,
    most_open: usize,
}

/// What [`Problem::halve`] found.
#[derive(Default)]
struct Halving {
    rules: BTreeSet<Rule>,
    boxes: usize,
    open: Vec<Bounds>,
}

impl Branching {
    /// A branch and prune that starts from the whole of each box of `boxes`.
    fn new(boxes: &[Bounds]) -> Branching {
        Branching {
            open: boxes.iter().map(|&b| (b, 0)).collect(),
            examined: 0,
            rules: BTreeSet::new(),
            leaves: Vec::new(),
        }
    }

    /// Every box still open: the queue's, then those below the slack.
    fn rest(&self) -> Vec<Bounds> {
        self.open
            .iter()
            .map(|&(b, _)| b)
            .chain(self.leaves.iter().copied())
            .collect()
    }

    /// The smallest box still open: a box below the slack, else the deepest in the
    /// queue.
    fn open(&self) -> Option<Bounds> {
        self.leaves
            .first()
            .copied()
            .or_else(|| self.open.back().map(|(b, _)| *b))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contact::ContactKind as K;
    use crate::testing::{contact, fixture};

    /// `f` of the built-in example's problem.
    fn with_the_example<T>(f: impl FnOnce(&Problem<'_>) -> T) -> T {
        let (block, cuboid) = crate::examples::l_block_and_box();
        let bounds = crate::examples::paper_bounds();
        f(&Problem::new(&block, &cuboid, bounds, glam::DAffine3::IDENTITY))
    }

    /// The proof by halving of `target` (sorted here) with the last proofs' conditions.
    fn halving(problem: &Problem<'_>, target: &mut [PrincipalContact], budget: usize) -> Option<Proof> {
        target.sort();
        let conditions = match problem.last_conditions(target) {
            Ok(conditions) => conditions,
            // Ruled out whatever the pose: a proof too.
            Err(rule) => return Some(Proof::outright(rule)),
        };
        let floor = scaled(HALVING_FLOOR_REL, problem.scale);
        let toward = problem.bounds.center();
        problem
            .prove_by_halving(target, &conditions, toward, budget, floor, &mut SearchStats::default())
            .ok()
    }

    #[test]
    fn halving_proves_a_corner_on_the_wall_with_the_step_edge_crossing() {
        // The box's corner v6 on the wall f5 while the step's front edge e4 crosses the
        // box's bottom edge e1: the branch and prune's look-ahead leaves it open; halved
        // where widest, every box falls within a few hundred.
        let mut target = [contact("f5", "v6", K::FaceVertex), contact("e4", "e1", K::EdgeEdge)];
        with_the_example(|problem| {
            let proof = halving(problem, &mut target, HALVING_BUDGET);
            assert!(
                proof.as_ref().is_some_and(|p| p.boxes > 50 && p.boxes < 1000),
                "{proof:?}"
            );
            // With too few boxes it gives up rather than claim a proof.
            assert!(halving(problem, &mut target, 50).is_none());
        });
        // With the back edge e7 crossing the bottom edge e9 instead (the built-in
        // example's graph listed it undecided until the halving came, which then took a
        // few hundred boxes), the dips of the crossing rule out the whole bounds at once:
        // the corner's edges rise off the wall only where e7 descends under the bottom.
        let mut target = [contact("f5", "v6", K::FaceVertex), contact("e7", "e9", K::EdgeEdge)];
        with_the_example(|problem| {
            let proof = halving(problem, &mut target, HALVING_BUDGET);
            assert!(proof.as_ref().is_some_and(|p| p.boxes == 1), "{proof:?}");
        });
    }

    #[test]
    fn a_box_at_the_halving_floor_falls_once_its_angles_are_trimmed() {
        // The chamfered hole's corner v7 on the peg's upright edge e0, the peg turned
        // about y and z: a box the halving reached at its floor. The corner runs rule
        // it out whole; without them the tests leave it open whole, slabs of its
        // angles fall one by one, and what is left falls too.
        let (hole, peg) = (fixture("block_with_chamfered_hole.off"), fixture("peg.off"));
        let bounds = crate::testing::turned_peg_bounds();
        let problem = Problem::new(&hole, &peg, bounds, glam::DAffine3::IDENTITY);
        let target = [contact("v7", "e0", K::VertexEdge)];
        let Ok(conditions) = problem.last_conditions(&target) else {
            panic!("no outright rule");
        };
        let floor = Bounds::try_new(
            [
                -0.6837896054557115,
                -0.9624535893588331,
                33.74478398444296,
                0.0,
                -0.033952108105202196,
                -0.0011801980912892925,
            ],
            [
                -0.6763566519841359,
                -0.9579094659003552,
                33.788479605438134,
                0.0,
                -0.03381575425739014,
                -0.0010530315658486289,
            ],
        )
        .unwrap();
        assert!(problem.exclude(&target, &conditions, Mode::All, &floor, true).is_err());
        let conditions = Conditions {
            turns: conditions.turns.without_corner_runs(),
            ..conditions
        };
        assert!(problem.exclude(&target, &conditions, Mode::All, &floor, true).is_ok());
        let trimmed = problem.trim(&target, &conditions, &floor);
        let (before, after) = (floor.width(), trimmed.width());
        assert!((4..6).any(|k| after[k] < 0.5 * before[k]), "{trimmed:?}");
        assert!(
            problem
                .exclude(&target, &conditions, Mode::All, &trimmed, true)
                .is_err()
        );
    }

    #[test]
    fn a_face_within_the_loose_tolerance_of_the_wall_over_a_box_thin_in_its_angles_is_excluded() {
        // The box's back bottom edge on the L-block's step, its top right edge crossing
        // the wall's top edge, turned -1.75e-6 rad about z: its right face lies within
        // 2e-4 mm of the wall's plane, which the loose reading (2.7e-4 mm) reads as face
        // on face. Over this box, thin in x and in its angles (the halving's floor),
        // each angle still moves the box's corners by up to 0.02 mm, so only the plane
        // distances enclosed over the box (not the centre's turned) see that.
        let (a, b) = crate::examples::l_block_and_box();
        let problem = Problem::new(&a, &b, crate::examples::paper_bounds(), glam::DAffine3::IDENTITY);
        let mut target = [contact("f3", "e6", K::FaceEdge), contact("e10", "e10", K::EdgeEdge)];
        target.sort();
        let b = Bounds::try_new(
            [
                -2.18e-4,
                -2.265625,
                10.341212839421077,
                -0.11179429790744266,
                -2.7e-8,
                -1.801e-6,
            ],
            [
                -1.50e-4,
                -2.1875,
                10.355796013224646,
                -0.11167491434695674,
                2.7e-8,
                -1.690e-6,
            ],
        )
        .unwrap();
        assert!(problem.keeps_other_pair_close(&target, &b));
        // The loose reading has the faces on each other at every corner of the box.
        let (lo, hi) = (b.min.to_array(), b.max.to_array());
        let wall_on_side = contact("f5", "f5", K::FaceFace);
        for c in 0..64u32 {
            let corner: [f64; 6] = std::array::from_fn(|k| if (c >> k) & 1 == 0 { lo[k] } else { hi[k] });
            let placement = problem.placement(&Pose::from_array(corner));
            let loose = problem
                .scene
                .state(&placement, super::super::LOOSE_CONTACT_REL)
                .contacts;
            assert!(loose.contains(&wall_on_side), "corner {c}: {loose:?}");
        }
    }

    #[test]
    fn halving_never_proves_a_witnessed_state() {
        // The box's other top corner v5 on the wall with the same edges crossing holds:
        // the contact module reads it at this pose, robustly.
        let witness = Pose::from_array([
            -0.7121164752204439,
            5.0,
            12.561846310422034,
            -0.001712805816945965,
            0.08214562990854982,
            0.31415913155484626,
        ]);
        let mut target = [contact("f5", "v5", K::FaceVertex), contact("e7", "e9", K::EdgeEdge)];
        with_the_example(|problem| {
            let state = problem.verify(&witness).expect("a clean witness");
            assert!(target.iter().all(|pc| state.contains(pc)), "{state:?}");
            assert!(halving(problem, &mut target, HALVING_BUDGET).is_none());
            // The box it stops at, which the report lists: inside the bounds, small,
            // and not ruled out by the last proofs' own test run on it again.
            let conditions = problem.last_conditions(&target).expect("conditions");
            let floor = scaled(HALVING_FLOOR_REL, problem.scale);
            let open = problem
                .prove_by_halving(
                    &target,
                    &conditions,
                    problem.bounds.center(),
                    HALVING_BUDGET,
                    floor,
                    &mut SearchStats::default(),
                )
                .expect_err("left open");
            let (lo, hi) = (open.min.to_array(), open.max.to_array());
            let (blo, bhi) = (problem.bounds.min.to_array(), problem.bounds.max.to_array());
            assert!((0..6).all(|k| blo[k] <= lo[k] && hi[k] <= bhi[k]), "{open:?}");
            assert!((0..3).all(|k| hi[k] - lo[k] <= floor), "{open:?}");
            assert_eq!(problem.last_exclusion(&target, &open), None);
        });
    }

    #[test]
    fn the_last_proofs_close_what_the_decisions_own_conditions_leave_open() {
        // The hole's rim edge e11 on the peg's bottom face f2, the peg tilted about y
        // by −0.002 to −0.004 rad, x near −1 (where the bottom may reach past the rim):
        // past the rim the bottom dips into the top face, so no pose here shows the
        // contact alone (see the prover's test of the same box). The decision's own
        // conditions leave it open; the last proofs' close it, in the decision (within
        // their few boxes before the searches, so none runs), and from what it would
        // hand on.
        let (hole, peg) = (fixture("block_with_hole.off"), fixture("peg.off"));
        let bounds = Bounds::try_new(
            [-1.0, 0.0, 39.8, 0.0, -0.004, 0.0],
            [-0.95, 1.0, 40.0, 0.0, -0.002, 0.0],
        )
        .unwrap();
        let problem = Problem::new(&hole, &peg, bounds, glam::DAffine3::IDENTITY);
        let target = [contact("e11", "f2", K::EdgeFace)];
        let conditions = problem.conditions(&target).expect("conditions");
        let mut stats = SearchStats::default();
        let budget = PRUNE_BUDGET + SEARCH_BUDGET + PROOF_BUDGET;
        assert!(problem.proof_within(&target, &conditions, budget, &mut stats).is_none());
        let starts = Starts {
            warm: &[],
            anchor: &target[0],
            constructive: 2,
            boost: 1,
        };
        let decided = problem.decide(&target, &starts, &mut stats);
        let Decision::Infeasible(proof) = decided.decision else {
            panic!("the decision should prove it: {:?}", decided.decision);
        };
        assert!(proof.boxes <= FIRST_LAST_BUDGET, "{} boxes", proof.boxes);
        assert_eq!(stats.optimisations, 0, "proved before the searches");
        // With no boxes handed on, the last proofs start again from the whole bounds.
        let open = bounds;
        assert!(problem.prove_last(&target, &open, &[], &mut stats).is_ok());
        // Handed boxes that cover the poses left open (here the two halves of the
        // bounds), they go on from those.
        let (lo, hi) = (bounds.min.to_array(), bounds.max.to_array());
        let mut middle = lo;
        middle[0] = 0.5 * (lo[0] + hi[0]);
        let mut upper = hi;
        upper[0] = middle[0];
        let halves = [
            Bounds::try_new(lo, upper).unwrap(),
            Bounds::try_new(middle, hi).unwrap(),
        ];
        assert!(problem.prove_last(&target, &open, &halves, &mut stats).is_ok());
    }
}
