//! What the commands print: the run summary, a part's inspection and the contacts at
//! a pose, as text or JSON.

use std::io::Write;

use acsg::contact::{ContactRecord, ContactReport};
use acsg::feasibility::WitnessFlaw;
use acsg::graph::{Graph, Stats, Strategy};
use acsg::model::{ElementId, Inspection, Part, PartElements};
use acsg::pose::{Bounds, Pose};
use anyhow::Context;
use glam::{DAffine3, DVec3};

use crate::args::UsageError;

/// The run summary: parts, bounds, stages, and states by number of contacts and DOF.
pub(crate) fn summary(graph: &Graph, names: &[String; 2], bounds: &Bounds, length: &str) -> String {
    let mut out = String::new();
    write_run_header(&mut out, names, bounds, length);
    write_strategy(&mut out, graph.strategy);
    write_stages(&mut out, &graph.stats);
    write_outcome(&mut out, graph);
    out
}

/// The summary's first lines: the parts, the units and the bounds.
fn write_run_header(out: &mut String, names: &[String; 2], bounds: &Bounds, length: &str) {
    use std::fmt::Write as _;
    let _ = writeln!(out, "fixed  {}\nmoving {}", names[0], names[1]);
    let _ = writeln!(
        out,
        "units  lengths in {length}, angles in degrees (radians in the JSON)"
    );
    let (lo, hi) = (bounds.min.to_array(), bounds.max.to_array());
    let ranges: Vec<String> = ["x", "y", "z", "rx", "ry", "rz"]
        .iter()
        .enumerate()
        .map(|(k, n)| {
            if k < 3 {
                format!("{n} [{}, {}]", lo[k], hi[k])
            } else {
                format!("{n} [{:.4}°, {:.4}°]", lo[k].to_degrees(), hi[k].to_degrees())
            }
        })
        .collect();
    let _ = writeln!(out, "bounds {}", ranges.join("  "));
}

/// The line naming a strategy other than the default (whose summary reads as before).
fn write_strategy(out: &mut String, strategy: Strategy) {
    use std::fmt::Write as _;
    match strategy {
        Strategy::Full => {}
        Strategy::Paper => {
            let _ = writeln!(
                out,
                "search paper: the paper's algorithm, a baseline (local optimisations from fixed starts; no \
                 proofs, warm starts or descents)"
            );
        }
    }
}

/// The summary's account of stage 1 and stage 2, counter by counter.
fn write_stages(out: &mut String, s: &Stats) {
    use std::fmt::Write as _;
    let _ = writeln!(
        out,
        "stage 1  card(PPC) {}, {} ruled out without optimising, {} searched by optimisation ({} local runs), \
         {} feasible, {:.3} s",
        s.ppc, s.ppc_unreachable, s.stage1_searched, s.stage1_optimisations, s.feasible_ppc, s.stage1_seconds
    );
    // A pair gives one outcome per case of the mapping rules, and each outcome is
    // counted once: the counts below add up to more than the pairs.
    let _ = writeln!(
        out,
        "stage 2  {} pairs (a known state and a single contact to add); each pair gives one outcome per case \
         of the mapping rules, so the counts below add up to more than the pairs:",
        s.stage2_pairs
    );
    let _ = writeln!(
        out,
        "           {:>8} implied (the state already holds the contact, or an outcome is the state itself)",
        s.pruned_implied
    );
    let _ = writeln!(
        out,
        "           {:>8} pairs with no outcome (ruled out by topological existence)",
        s.pruned_topology
    );
    let _ = writeln!(
        out,
        "           {:>8} outcomes left out as degenerate (keep them with --degenerate)",
        s.pruned_degenerate
    );
    let _ = writeln!(
        out,
        "           {:>8} outcomes already known or already proposed",
        s.pruned_duplicate
    );
    let _ = writeln!(
        out,
        "           {:>8} new candidates, each decided:",
        s.stage2_candidates
    );
    let _ = writeln!(
        out,
        "           {:>8} ruled out without optimising (sound exclusion tests)",
        s.pruned_unreachable
    );
    let _ = writeln!(
        out,
        "           {:>8} searched by optimisation ({} local runs; descents included)",
        s.stage2_searched, s.stage2_optimisations
    );
    let _ = writeln!(
        out,
        "           {:>8} descents (searches one contact below a known state, from its witness)",
        s.descents
    );
    let _ = writeln!(
        out,
        "           {:>8} states found while searching for another, {} found by descents; {:.3} s",
        s.found_on_the_way, s.found_by_descent, s.stage2_seconds
    );
    let _ = writeln!(
        out,
        "slices   {} rotations, {} translations read off the pieces' Minkowski differences: {} states no \
         search had found",
        s.slices, s.slice_samples, s.found_by_slices
    );
    let _ = writeln!(
        out,
        "proofs   {} candidates still undecided after the searches and sweeps proved infeasible by the last, \
         strongest proofs",
        s.proved_last
    );
}

/// The summary's last lines: the graph's size, whether it is complete, and its states
/// by number of contacts and DOF.
fn write_outcome(out: &mut String, graph: &Graph) {
    use std::fmt::Write as _;
    let s = &graph.stats;
    let _ = writeln!(
        out,
        "graph    {} states (free space included), {} edges",
        s.states, s.edges
    );
    let _ = writeln!(
        out,
        "complete {}",
        if !graph.strategy.proves() {
            format!(
                "NO: the {} strategy proves nothing infeasible; {} of {} candidates were not witnessed (listed \
                 under \"undecided\" in the JSON)",
                graph.strategy, s.undecided, s.candidates
            )
        } else if graph.is_complete() {
            format!(
                "yes: each of the {} candidates met was witnessed ({}) or proved infeasible ({})",
                s.candidates, s.witnessed, s.infeasible
            )
        } else if s.work_limit_reached {
            format!(
                "NO: the work limit was reached; {} of {} candidates undecided (the ones met after it were not \
                 searched, and the sweeps and last proofs did not run: the graph may lack these states and \
                 states beyond them; a higher --work-limit, or none, goes further)",
                s.undecided, s.candidates
            )
        } else {
            format!(
                "NO: {} of {} candidates undecided (neither witnessed nor proved infeasible; the graph may lack \
                 these states, listed under \"undecided\" in the JSON)",
                s.undecided, s.candidates
            )
        }
    );
    let mut table: std::collections::BTreeMap<(usize, u8), usize> = std::collections::BTreeMap::new();
    for state in &graph.states {
        *table.entry((state.contacts.len(), state.dof)).or_default() += 1;
    }
    let _ = writeln!(out, "\n  contacts  dof  states");
    for ((contacts, dof), count) in table {
        let _ = writeln!(out, "  {contacts:>8}  {dof:>3}  {count:>6}");
    }
}

pub(crate) fn print_inspection(report: &Inspection, json: bool) -> anyhow::Result<()> {
    let mut out = std::io::stdout().lock();
    if json {
        serde_json::to_writer_pretty(&mut out, report).context("writing JSON")?;
        writeln!(out)?;
        return Ok(());
    }
    writeln!(out, "units  {} (lengths, volumes in cubic {0})", report.units)?;
    if let Some(f) = report.facet {
        writeln!(
            out,
            "facets STEP cylinders, cones and circles read as planar facets (chord tolerance {f} {}): the counts \
             are of the faceted parts",
            report.units
        )?;
    }
    for (i, p) in report.parts.iter().enumerate() {
        let role = match (i, report.parts.len()) {
            (_, 1) => "",
            (0, _) => " (fixed)",
            _ => " (moving)",
        };
        writeln!(out, "{}{role}", p.path)?;
        writeln!(
            out,
            "  faces          {:>6}  ({} with holes, {} non-convex)",
            p.faces, p.faces_with_holes, p.nonconvex_faces
        )?;
        writeln!(
            out,
            "  vertices       {:>6}  ({} convex, {} non-convex)",
            p.vertices,
            p.convex_vertices,
            p.vertices - p.convex_vertices
        )?;
        writeln!(
            out,
            "  edges          {:>6}  ({} convex, {} concave)",
            p.edges, p.convex_edges, p.concave_edges
        )?;
        writeln!(out, "  convex pieces  {:>6}", p.convex_pieces)?;
        writeln!(out, "  volume         {}", p.volume)?;
        let [min, max] = p.bounds;
        writeln!(
            out,
            "  bounds         ({}, {}, {}) .. ({}, {}, {})",
            min[0], min[1], min[2], max[0], max[1], max[2]
        )?;
    }
    if let Some(ppc) = report.ppc {
        writeln!(
            out,
            "card(PPC) = {}  (f-v {}, e-e {}, v-f {})",
            ppc.total, ppc.f_v, ppc.e_e, ppc.v_f
        )?;
    }
    Ok(())
}

/// The JSON document of `acsg contacts`.
#[derive(serde::Serialize)]
struct ContactsDocument<'a> {
    convention: &'static str,
    units: acsg::graph::document::Units,
    pose: [f64; 6],
    matrix: [[f64; 4]; 4],
    tolerance: f64,
    contacts: Vec<ContactRecord>,
    penetration: f64,
    min_gap: Option<f64>,
    /// Whether the pose is a robust witness of the state read at the contact tolerance
    /// (bounds aside): every checker whose tolerance lies between 1e-9 L and 1e-6 L
    /// reads that state.
    robust: bool,
    /// Why not, in words (`null` when robust).
    not_robust_because: Option<String>,
    parts: PartsDocument<'a>,
}

#[derive(serde::Serialize)]
struct PartsDocument<'a> {
    fixed: &'a PartElements,
    moving: &'a PartElements,
}

/// How `acsg contacts` prints.
pub(crate) struct Shown {
    /// The relative contact tolerance used.
    pub(crate) tol: f64,
    /// JSON instead of text.
    pub(crate) json: bool,
    /// The label of lengths.
    pub(crate) length: String,
}

impl Shown {
    /// How to print with the relative tolerance `tol`, checked (the length label is
    /// set once the parts are read).
    pub(crate) fn checked(tol: f64, json: bool) -> anyhow::Result<Self> {
        if !(tol.is_finite() && tol > 0.0 && tol < 1.0) {
            return Err(UsageError(format!(
                "invalid --tol: {tol} (give a relative tolerance between 0 and 1, e.g. 1e-9)"
            ))
            .into());
        }
        Ok(Self {
            tol,
            json,
            length: String::new(),
        })
    }
}

/// The contacts at one pose, as `acsg contacts` found them.
pub(crate) struct ContactsAtPose<'a> {
    pub(crate) fixed: &'a Part,
    pub(crate) moving: &'a Part,
    pub(crate) pose: &'a Pose,
    /// The assembled pose G.
    pub(crate) assembled: &'a DAffine3,
    pub(crate) report: &'a ContactReport,
    /// Why the pose is no robust witness of the state read at the contact tolerance.
    pub(crate) flaw: Option<&'a WitnessFlaw>,
}

/// A witness flaw in words.
fn flaw_text(flaw: &WitnessFlaw) -> String {
    let state = |contacts: &[acsg::contact::PrincipalContact]| {
        if contacts.is_empty() {
            "no contact".to_owned()
        } else {
            contacts.iter().map(ToString::to_string).collect::<Vec<_>>().join(", ")
        }
    };
    match flaw {
        WitnessFlaw::Penetration(depth) => format!("the parts penetrate by {depth}"),
        WitnessFlaw::TooClose(gap) => {
            format!("two elements that do not touch are {gap} apart, closer than the separation tolerance (1e-6 L)")
        }
        WitnessFlaw::EdgeOnTwoPoints => {
            "two contacts hold two points of one edge on a face's plane that no contact lists the edge on".to_owned()
        }
        WitnessFlaw::ChordOffTheBoundary => {
            "the chord between two contacts' points lies on one part's boundary and inside the other, or inside both, on no face or edge they share lying flush".to_owned()
        }
        WitnessFlaw::LooseReading(contacts) => {
            format!(
                "read with a tolerance just under 1e-6 L the state is {}",
                state(contacts)
            )
        }
        WitnessFlaw::OverlapReading(contacts) => format!("read over the overlap the state is {}", state(contacts)),
    }
}

/// Prints the contacts at one pose, their elements' coordinates, the penetration and
/// the smallest gap.
pub(crate) fn print_contacts(at: &ContactsAtPose<'_>, shown: &Shown) -> anyhow::Result<()> {
    let ContactsAtPose {
        fixed,
        moving,
        pose,
        assembled,
        report,
        flaw,
    } = *at;
    let records: Vec<ContactRecord> = report
        .contacts
        .iter()
        .map(|c| ContactRecord::of(c, fixed, moving))
        .collect();
    if shown.json {
        return print_contacts_json(at, records, shown);
    }
    let length = &shown.length;
    let mut out = std::io::stdout().lock();
    let placement = pose.to_affine(assembled);
    let [x, y, z, rx, ry, rz] = pose.to_array();
    let deg = |a: f64| a.to_degrees();
    writeln!(
        out,
        "pose         x={x} y={y} z={z} ({length}) rx={}° ry={}° rz={}°",
        deg(rx),
        deg(ry),
        deg(rz)
    )?;
    writeln!(
        out,
        "contacts     {} (coordinates in the fixed part's frame)",
        records.len()
    )?;
    for r in &records {
        let flag = if r.degenerate { ", degenerate" } else { "" };
        writeln!(
            out,
            "  {:<5} {}  x  {}   ({} DOF{flag})",
            r.kind.label(),
            r.fixed,
            r.moving,
            r.dof
        )?;
        writeln!(out, "        fixed  {}", describe(fixed, r.fixed, &DAffine3::IDENTITY))?;
        writeln!(out, "        moving {}", describe(moving, r.moving, &placement))?;
    }
    let verdict = if report.penetration > 0.0 {
        "  (the parts penetrate)"
    } else {
        ""
    };
    writeln!(out, "penetration  {}{verdict}", report.penetration)?;
    match report.min_gap {
        Some(gap) => writeln!(out, "min gap      {gap}  (closest pair of elements that do not touch)")?,
        None => writeln!(
            out,
            "min gap      >= {} (1% of L)",
            acsg::tolerance::GAP_SEARCH_REL * acsg::model::length_scale(fixed, moving)
        )?,
    }
    match flaw {
        None => writeln!(
            out,
            "witness      robust: every checker with a tolerance between 1e-9 L and 1e-6 L reads this state"
        )?,
        Some(flaw) => writeln!(out, "witness      not robust: {}", flaw_text(flaw))?,
    }
    Ok(())
}

/// [`print_contacts`] as one JSON object.
fn print_contacts_json(at: &ContactsAtPose<'_>, records: Vec<ContactRecord>, shown: &Shown) -> anyhow::Result<()> {
    let doc = ContactsDocument {
        convention: acsg::pose::CONVENTION,
        units: acsg::graph::document::Units {
            length: shown.length.clone(),
            angle: "radians".into(),
        },
        pose: at.pose.to_array(),
        matrix: at.pose.matrix(at.assembled),
        tolerance: shown.tol,
        contacts: records,
        penetration: at.report.penetration,
        min_gap: at.report.min_gap,
        robust: at.flaw.is_none(),
        not_robust_because: at.flaw.map(flaw_text),
        parts: PartsDocument {
            fixed: &PartElements::of(at.fixed),
            moving: &PartElements::of(at.moving),
        },
    };
    let mut out = std::io::stdout().lock();
    serde_json::to_writer_pretty(&mut out, &doc).context("writing JSON")?;
    writeln!(out)?;
    Ok(())
}

/// An element's coordinates after `placement`.
fn describe(part: &Part, element: ElementId, placement: &DAffine3) -> String {
    let p = |v: DVec3| {
        let q = placement.transform_point3(v);
        format!("({}, {}, {})", q.x, q.y, q.z)
    };
    match element {
        ElementId::Vertex(v) => format!("vertex at {}", p(part.vertex(v).position)),
        ElementId::Edge(e) => {
            let [a, b] = part.edge_points(e);
            format!("edge {} - {}", p(a), p(b))
        }
        ElementId::Face(f) => {
            let face = part.face(f);
            let n = placement.transform_vector3(face.normal).normalize();
            let corners: Vec<String> = face
                .outer()
                .vertices
                .iter()
                .map(|&v| p(part.vertex(v).position))
                .collect();
            format!(
                "face, normal ({}, {}, {}), corners {}",
                n.x,
                n.y,
                n.z,
                corners.join(" ")
            )
        }
    }
}
