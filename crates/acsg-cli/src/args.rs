//! The command line: the subcommands, their arguments and flags, and the checks of
//! argument values that clap cannot make (a bad value is a [`UsageError`], exit code 2).

use std::path::PathBuf;

use acsg::graph::Strategy;
use clap::{Parser, Subcommand};

/// Assembly Contact State Graphs of two polyhedral parts.
#[derive(Parser)]
#[command(name = "acsg", version, about, long_about = None)]
pub(crate) struct Cli {
    #[command(subcommand)]
    pub(crate) command: Command,
}

#[derive(Subcommand)]
pub(crate) enum Command {
    /// Show a part's B-rep (faces, edges, vertices, convexity, convex pieces); with a
    /// second part, card(PPC) of the pair (first fixed, second moving).
    Inspect {
        /// The fixed part (OFF, OBJ, STL, PLY, or STEP/IGES with planar faces).
        fixed: PathBuf,
        /// The moving part.
        moving: Option<PathBuf>,
        #[command(flatten)]
        units: UnitsFlag,
        /// Print one JSON object instead of text.
        #[arg(long)]
        json: bool,
    },
    /// The contact state P(X) at one pose of the moving part: principal contacts,
    /// penetration depth and the smallest gap between elements that do not touch.
    Contacts {
        /// The fixed part A.
        fixed: PathBuf,
        /// The moving part B.
        moving: PathBuf,
        /// The pose X = x,y,z,rx,ry,rz: p_A = G (R p_B + t), R = Rz(rz) Ry(ry) Rx(rx);
        /// angles in degrees (within ±180) unless --radians.
        #[arg(long, allow_hyphen_values = true)]
        pose: String,
        /// The assembled pose G of B in A's frame, in the same form (default: identity).
        #[arg(long, allow_hyphen_values = true)]
        assembled: Option<String>,
        /// Read the angles of --pose and --assembled in radians (within ±π), as the
        /// graph's JSON writes witnesses.
        #[arg(long, conflicts_with = "degrees")]
        radians: bool,
        /// Angles in degrees: the default, accepted for old scripts.
        #[arg(long, hide = true)]
        degrees: bool,
        #[command(flatten)]
        units: UnitsFlag,
        /// Contact tolerance relative to L, the larger bounding-box diagonal.
        #[arg(long, default_value_t = acsg::tolerance::CONTACT_REL, allow_hyphen_values = true)]
        tol: f64,
        /// Print one JSON object instead of text.
        #[arg(long)]
        json: bool,
    },
    /// Generate the contact state graph of a fixed and a moving part within bounds.
    Generate {
        /// The fixed part A.
        fixed: PathBuf,
        /// The moving part B.
        moving: PathBuf,
        /// Misalignment bounds, e.g. x=-5:5,y=-5:5,z=0:240,rx=-18:18,ry=-18:18,rz=-18:18
        /// (lengths in model units, angles in degrees; omitted components fixed at 0).
        #[arg(long, allow_hyphen_values = true)]
        bounds: String,
        /// The assembled pose G of B in A's frame, x,y,z,rx,ry,rz with angles in degrees
        /// (default: identity).
        #[arg(long, allow_hyphen_values = true)]
        assembled: Option<String>,
        #[command(flatten)]
        units: UnitsFlag,
        #[command(flatten)]
        run: RunFlags,
    },
    /// Generate the graph described by a task file (TOML: `fixed`, `moving`, an
    /// optional `units` (mm, cm, m, in), a `[bounds]` table with x, y, z, rx, ry, rz as
    /// [min, max] in those units and degrees, an optional `[options]` table with
    /// degenerate, threads, effort, strategy, work_limit, assembled).
    Run {
        /// The task file.
        task: PathBuf,
        /// The length unit, overriding the task file's `units` key.
        #[arg(long, value_name = "UNIT")]
        units: Option<acsg::units::LengthUnit>,
        /// Read STEP cylinders, cones and circles as planar facets within this chord
        /// tolerance (as `generate --facet`).
        #[arg(long, value_name = "MM", allow_hyphen_values = true)]
        facet: Option<f64>,
        #[command(flatten)]
        run: RunFlags,
    },
    /// Generate the graphs of many task files, one after the other: a manifest (TOML)
    /// lists them as `tasks = ["a.toml", ...]` (relative to the manifest), with an
    /// optional `output_dir` (default: each graph beside its task file, as `run`
    /// writes it). A task that fails is reported and skipped; a task whose output
    /// already holds its graph (same parts, bounds and options) is skipped, so a rerun
    /// does only what is left. Exit code 1 when a task failed.
    Batch {
        /// The manifest.
        manifest: PathBuf,
        /// Generate every task again, even those whose output is already written.
        #[arg(long)]
        force: bool,
        /// Worker threads of each run (as `run --threads`).
        #[arg(long)]
        threads: Option<usize>,
        /// Write zeros for the stage times (as `run --no-timings`).
        #[arg(long)]
        no_timings: bool,
        /// No progress bar and no line per task; errors are still reported.
        #[arg(short, long)]
        quiet: bool,
    },
    /// Generate the graph of the built-in example (the paper's L-block and box, each
    /// rotation within ±18°, x and y within ±5 mm, z from 0 to 240 mm): no files needed.
    Demo {
        /// Other bounds for the built-in parts, as `generate --bounds` takes them (e.g.
        /// x=-1:1,y=-1:1,z=0:5,rz=-2:2: a graph of a few states in seconds); omitted
        /// components are fixed at 0.
        #[arg(long, allow_hyphen_values = true)]
        bounds: Option<String>,
        #[command(flatten)]
        run: RunFlags,
    },
    /// Write a graph's HTML report: one self-contained file (no network needed) with
    /// the run summary, the graph, each state's witness pose in 3D and a table of states.
    Report {
        /// The graph's JSON (written by generate, run or demo).
        graph: PathBuf,
        /// The HTML file to write (default: the graph's path with extension `.html`).
        #[arg(short, long)]
        output: Option<PathBuf>,
    },
    /// Convert a graph's JSON for other tools: Graphviz DOT, GraphML (Gephi, yEd,
    /// networkx) or node-link JSON (networkx, d3); states carry their contacts, DOF and
    /// witness as attributes.
    Export {
        /// The graph's JSON (written by generate, run or demo).
        graph: PathBuf,
        /// The output format.
        #[arg(long, value_enum)]
        format: ExportFormat,
        /// The file to write (atomically); default: stdout.
        #[arg(short, long)]
        output: Option<PathBuf>,
    },
}

/// The formats of `acsg export`.
#[derive(Clone, Copy, clap::ValueEnum)]
pub(crate) enum ExportFormat {
    /// Graphviz DOT (`dot -Tsvg`).
    Dot,
    /// GraphML (Gephi, yEd, `networkx.read_graphml`).
    Graphml,
    /// Node-link JSON (`networkx.node_link_graph`, d3): numeric attributes, the
    /// witness as 6 numbers and its 4x4 matrix as nested arrays.
    NodeLink,
}

/// The length unit of a run.
#[derive(clap::Args)]
pub(crate) struct UnitsFlag {
    /// The length unit of the run: mm, cm, m or in. A mesh's numbers are taken to be in
    /// it (a mesh has no unit); a STEP or IGES part is converted to it (to mm when this
    /// is not given). Bounds and every length printed are in it.
    #[arg(long, value_name = "UNIT")]
    pub(crate) units: Option<acsg::units::LengthUnit>,
    /// Read STEP cylinders, cones and circles as planar facets: every circle becomes
    /// an inscribed polygon straying at most this far (in the run's unit) from it, the
    /// same number of sides for every circle of a file. The graph is then that of the
    /// faceted parts.
    #[arg(long, value_name = "MM", allow_hyphen_values = true)]
    pub(crate) facet: Option<f64>,
}

impl UnitsFlag {
    /// The chord tolerance, checked.
    pub(crate) fn facet(&self) -> anyhow::Result<Option<f64>> {
        check_facet(self.facet)
    }
}

/// A `--facet` tolerance must be a positive finite length.
pub(crate) fn check_facet(facet: Option<f64>) -> anyhow::Result<Option<f64>> {
    match facet {
        Some(f) if !(f.is_finite() && f > 0.0) => Err(UsageError(format!(
            "invalid --facet: {f} (give the chord tolerance as a positive length, e.g. --facet 0.05)"
        ))
        .into()),
        other => Ok(other),
    }
}

/// Options shared by the commands that generate a graph.
#[derive(clap::Args)]
pub(crate) struct RunFlags {
    /// Write the graph's JSON here (atomically). `generate` prints it to stdout without
    /// this; `run` writes `<task>.graph.json` beside the task file; `demo` writes
    /// `acsg-demo.graph.json` in the current folder.
    #[arg(short, long)]
    pub(crate) output: Option<PathBuf>,
    /// Also write the graph's HTML report here (as `acsg report` does).
    #[arg(long, value_name = "PATH")]
    pub(crate) html: Option<PathBuf>,
    /// Keep states with a degenerate contact (v-v, e-v, v-e, e-e-t between convex
    /// elements).
    #[arg(long)]
    pub(crate) degenerate: bool,
    /// Worker threads (0: one per core; at most four per core, or 256). The output does
    /// not depend on it.
    #[arg(long)]
    pub(crate) threads: Option<usize>,
    /// How hard to search and prove each candidate state before leaving it undecided:
    /// a multiple of the default budget (1). Higher finds states that hold only on
    /// slivers of the bounds and decides more candidates, at more time; from 2 the slice
    /// sweep also goes near every state found.
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=1000))]
    pub(crate) effort: Option<u32>,
    /// How to search: `full` (the default: every candidate decided, witnessed or proved
    /// infeasible where the budget allows) or `paper` (the paper's algorithm step by
    /// step, a baseline: local optimisation of every PPC, then of every topologically
    /// unique combination with a feasible PPC; it proves nothing infeasible, so its
    /// graph is never complete).
    #[arg(long, value_name = "NAME", value_parser = parse_strategy)]
    pub(crate) strategy: Option<Strategy>,
    /// Stop searching and proving once this much work is done: boxes of poses examined,
    /// a local optimisation counting as 50. The candidates met after that are reported
    /// undecided and the graph is not complete; the output still does not depend on
    /// the thread count. For parts too large to wait for (no limit by default).
    #[arg(long, value_name = "BOXES", value_parser = clap::value_parser!(u64).range(1..))]
    pub(crate) work_limit: Option<u64>,
    /// Write zeros for the stage times, so that runs give identical bytes.
    #[arg(long)]
    pub(crate) no_timings: bool,
    /// No summary and no progress bar.
    #[arg(short, long)]
    pub(crate) quiet: bool,
}

/// A `--strategy` name.
fn parse_strategy(text: &str) -> Result<Strategy, String> {
    text.parse()
        .map_err(|e: acsg::graph::strategy::UnknownStrategy| e.to_string())
}

/// A bad argument value found after parsing (exit code 2, like clap's own errors).
#[derive(Debug)]
pub(crate) struct UsageError(pub(crate) String);

impl std::fmt::Display for UsageError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for UsageError {}
