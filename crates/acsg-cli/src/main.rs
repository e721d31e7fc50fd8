//! `acsg`: the command-line interface. It parses and validates arguments, calls the
//! library, prints, and maps errors to exit codes (0 success, 1 bad input or failed
//! job, 2 bad usage).

use std::io::{IsTerminal, Write};
use std::path::PathBuf;
use std::process::ExitCode;

use acsg::contact::{ContactRecord, ContactReport, ContactScene};
use acsg::export::GraphFile;
use acsg::graph::{Document, Graph, Options, Progress, Strategy, generate_with_progress};
use acsg::model::{ElementId, Inspection, Part, PartElements};
use acsg::pose::{Bounds, Pose};
use acsg::task::Task;
use anyhow::Context;
use clap::{Parser, Subcommand};
use glam::{DAffine3, DVec3};

/// Assembly Contact State Graphs of two polyhedral parts.
#[derive(Parser)]
#[command(name = "acsg", version, about, long_about = None)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
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
    /// degenerate, threads, effort, assembled).
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
enum ExportFormat {
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
struct UnitsFlag {
    /// The length unit of the run: mm, cm, m or in. A mesh's numbers are taken to be in
    /// it (a mesh has no unit); a STEP or IGES part is converted to it (to mm when this
    /// is not given). Bounds and every length printed are in it.
    #[arg(long, value_name = "UNIT")]
    units: Option<acsg::units::LengthUnit>,
    /// Read STEP cylinders, cones and circles as planar facets: every circle becomes
    /// an inscribed polygon straying at most this far (in the run's unit) from it, the
    /// same number of sides for every circle of a file. The graph is then that of the
    /// faceted parts.
    #[arg(long, value_name = "MM", allow_hyphen_values = true)]
    facet: Option<f64>,
}

impl UnitsFlag {
    /// The chord tolerance, checked.
    fn facet(&self) -> anyhow::Result<Option<f64>> {
        check_facet(self.facet)
    }
}

/// A `--facet` tolerance must be a positive finite length.
fn check_facet(facet: Option<f64>) -> anyhow::Result<Option<f64>> {
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
struct RunFlags {
    /// Write the graph's JSON here (atomically). `generate` prints it to stdout without
    /// this; `run` writes `<task>.graph.json` beside the task file; `demo` writes
    /// `acsg-demo.graph.json` in the current folder.
    #[arg(short, long)]
    output: Option<PathBuf>,
    /// Also write the graph's HTML report here (as `acsg report` does).
    #[arg(long, value_name = "PATH")]
    html: Option<PathBuf>,
    /// Keep states with a degenerate contact (v-v, e-v, v-e, e-e-t between convex
    /// elements).
    #[arg(long)]
    degenerate: bool,
    /// Worker threads (0: one per core; at most four per core, or 256). The output does
    /// not depend on it.
    #[arg(long)]
    threads: Option<usize>,
    /// How hard to search and prove each candidate state before leaving it undecided:
    /// a multiple of the default budget (1). Higher finds states that hold only on
    /// slivers of the bounds and decides more candidates, at more time.
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=1000))]
    effort: Option<u32>,
    /// How to search: `full` (the default: every candidate decided, witnessed or proved
    /// infeasible where the budget allows) or `paper` (the paper's algorithm step by
    /// step, a baseline: local optimisation of every PPC, then of every topologically
    /// unique combination with a feasible PPC; it proves nothing infeasible, so its
    /// graph is never complete).
    #[arg(long, value_name = "NAME", value_parser = parse_strategy)]
    strategy: Option<Strategy>,
    /// Write zeros for the stage times, so that runs give identical bytes.
    #[arg(long)]
    no_timings: bool,
    /// No summary and no progress bar.
    #[arg(short, long)]
    quiet: bool,
}

/// A `--strategy` name.
fn parse_strategy(text: &str) -> Result<Strategy, String> {
    text.parse()
        .map_err(|e: acsg::graph::strategy::UnknownStrategy| e.to_string())
}

/// A bad argument value found after parsing (exit code 2, like clap's own errors).
#[derive(Debug)]
struct UsageError(String);

impl std::fmt::Display for UsageError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for UsageError {}

fn main() -> ExitCode {
    let cli = Cli::parse();
    match run(cli) {
        Ok(()) => ExitCode::SUCCESS,
        Err(err) if err.downcast_ref::<UsageError>().is_some() => {
            eprintln!("error: {err:#}");
            ExitCode::from(2)
        }
        Err(err) => {
            // A closed pipe (`acsg ... | head`) is not an error worth a message.
            if is_broken_pipe(&err) {
                return ExitCode::SUCCESS;
            }
            eprintln!("error: {err:#}");
            ExitCode::from(1)
        }
    }
}

fn is_broken_pipe(err: &anyhow::Error) -> bool {
    err.chain().any(|cause| {
        let io_kind = cause
            .downcast_ref::<std::io::Error>()
            .map(std::io::Error::kind)
            .or_else(|| {
                cause
                    .downcast_ref::<serde_json::Error>()
                    .and_then(serde_json::Error::io_error_kind)
            });
        io_kind == Some(std::io::ErrorKind::BrokenPipe)
    })
}

fn run(cli: Cli) -> anyhow::Result<()> {
    match cli.command {
        Command::Inspect {
            fixed,
            moving,
            units,
            json,
        } => {
            let (unit, facet) = (units.units, units.facet()?);
            let (fixed, fixed_format) = Part::from_path_with(&fixed, unit, facet)?;
            let moving = moving.map(|m| Part::from_path_with(&m, unit, facet)).transpose()?;
            let formats = [Some(fixed_format), moving.as_ref().map(|m| m.1)];
            let mut report = Inspection::of(&fixed, moving.as_ref().map(|m| &m.0));
            report.units = units_label(unit, &formats);
            report.facet = facet;
            print_inspection(&report, json)
        }
        Command::Contacts {
            fixed,
            moving,
            pose,
            assembled,
            radians,
            degrees: _,
            units,
            tol,
            json,
        } => {
            let usage = |what: &str, e: &dyn std::fmt::Display| UsageError(format!("invalid {what}: {e}"));
            let pose = Pose::parse_checked(&pose, !radians).map_err(|e| usage("--pose", &e))?;
            let assembled = match assembled {
                Some(text) => Pose::parse_checked(&text, !radians).map_err(|e| usage("--assembled", &e))?,
                None => Pose::IDENTITY,
            };
            if !(tol.is_finite() && tol > 0.0 && tol < 1.0) {
                return Err(UsageError(format!(
                    "invalid --tol: {tol} (give a relative tolerance between 0 and 1, e.g. 1e-9)"
                ))
                .into());
            }
            let (unit, facet) = (units.units, units.facet()?);
            let (fixed, fixed_format) = Part::from_path_with(&fixed, unit, facet)?;
            let (moving, moving_format) = Part::from_path_with(&moving, unit, facet)?;
            let length = units_label(unit, &[Some(fixed_format), Some(moving_format)]);
            let g = assembled.to_affine(&DAffine3::IDENTITY);
            let placement = pose.to_affine(&g);
            let report = ContactScene::new(&fixed, &moving).evaluate(&placement, tol);
            let shown = Shown { tol, json, length };
            print_contacts(&fixed, &moving, &pose, &g, &report, &shown)
        }
        Command::Generate {
            fixed,
            moving,
            bounds,
            assembled,
            units,
            run,
        } => {
            let bounds = acsg::task::bounds_from_spec(&bounds).map_err(|e| UsageError(e.to_string()))?;
            let mut options = Options::default();
            if let Some(text) = assembled {
                let g =
                    Pose::parse_checked(&text, true).map_err(|e| UsageError(format!("invalid --assembled: {e}")))?;
                options.assembled = g.to_affine(&DAffine3::IDENTITY);
            }
            let names = [fixed.display().to_string(), moving.display().to_string()];
            let (unit, facet) = (units.units, units.facet()?);
            let (fixed, fixed_format) = Part::from_path_with(&fixed, unit, facet)?;
            let (moving, moving_format) = Part::from_path_with(&moving, unit, facet)?;
            let length = units_label(unit, &[Some(fixed_format), Some(moving_format)]);
            let job = Job {
                names,
                bounds,
                options,
                length,
                facet,
            };
            generate_and_write((fixed, moving), job, run, None)
        }
        Command::Run {
            task,
            units,
            facet,
            run,
        } => {
            let job = Task::from_path(&task)?;
            let default_output = task.with_extension("graph.json");
            run_task(job, units, facet, run, default_output)
        }
        Command::Batch {
            manifest,
            force,
            threads,
            no_timings,
            quiet,
        } => {
            let flags = BatchFlags {
                force,
                threads,
                no_timings,
                quiet,
            };
            run_batch(&manifest, &flags)
        }
        Command::Demo { run } => {
            let parts = acsg::examples::l_block_and_box();
            let job = Job {
                names: ["builtin:l_block.off".to_string(), "builtin:box.off".to_string()],
                bounds: acsg::examples::paper_bounds(),
                options: Options::default(),
                length: acsg::units::LengthUnit::Mm.symbol().to_string(),
                facet: None,
            };
            let output = Some(PathBuf::from("acsg-demo.graph.json"));
            generate_and_write(parts, job, run, output)
        }
        Command::Report { graph, output } => {
            let file = GraphFile::from_path(&graph)?;
            let output = output.unwrap_or_else(|| graph.with_extension("html"));
            let page = acsg::export::html::to_html(&file);
            acsg::io::write_atomic(&output, page.as_bytes())
                .with_context(|| format!("writing the report {}", output.display()))?;
            writeln!(std::io::stdout().lock(), "wrote {}", output.display())?;
            Ok(())
        }
        Command::Export { graph, format, output } => {
            let file = GraphFile::from_path(&graph)?;
            let text = match format {
                ExportFormat::Dot => acsg::export::dot::to_dot(&file),
                ExportFormat::Graphml => acsg::export::graphml::to_graphml(&file),
                ExportFormat::NodeLink => acsg::export::node_link::to_node_link(&file),
            };
            match output {
                Some(path) => acsg::io::write_atomic(&path, text.as_bytes())
                    .with_context(|| format!("writing {}", path.display()))?,
                None => std::io::stdout().lock().write_all(text.as_bytes())?,
            }
            Ok(())
        }
    }
}

/// Generates the graph of a task read from its file and writes it (`acsg run`).
fn run_task(
    job: Task,
    units: Option<acsg::units::LengthUnit>,
    facet: Option<f64>,
    run: RunFlags,
    default_output: PathBuf,
) -> anyhow::Result<()> {
    let unit = units.or(job.units);
    let facet = check_facet(facet.or(job.facet))?;
    let (fixed, fixed_format) = Part::from_path_with(&job.fixed, unit, facet)?;
    let (moving, moving_format) = Part::from_path_with(&job.moving, unit, facet)?;
    let length = units_label(unit, &[Some(fixed_format), Some(moving_format)]);
    let run_job = Job {
        names: [job.fixed_given, job.moving_given],
        bounds: job.bounds,
        options: job.options,
        length,
        facet,
    };
    generate_and_write((fixed, moving), run_job, run, Some(default_output))
}

/// The options of `acsg batch`.
struct BatchFlags {
    force: bool,
    threads: Option<usize>,
    no_timings: bool,
    quiet: bool,
}

/// The manifest of `acsg batch`.
#[derive(serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct Manifest {
    /// Task files, relative to the manifest.
    tasks: Vec<PathBuf>,
    /// Where the graphs go, relative to the manifest (default: beside each task file).
    #[serde(default)]
    output_dir: Option<PathBuf>,
}

/// What became of one task of a batch.
enum Outcome {
    /// Generated and written.
    Wrote(PathBuf),
    /// Its output already held its graph.
    Skipped(PathBuf),
}

/// `acsg batch`: every task of the manifest, in order; a failed task is reported and
/// the others still run.
fn run_batch(manifest: &std::path::Path, flags: &BatchFlags) -> anyhow::Result<()> {
    let text = std::fs::read_to_string(manifest)
        .with_context(|| format!("{}: cannot read the manifest (check the path)", manifest.display()))?;
    let list: Manifest = toml::from_str(text.strip_prefix('\u{feff}').unwrap_or(&text)).map_err(|e| {
        anyhow::anyhow!(
            "{}: {} (a manifest is `tasks = [\"a.toml\", \"b.toml\"]` and an optional `output_dir = \"graphs\"`)",
            manifest.display(),
            e.message().trim()
        )
    })?;
    if let Some(threads) = flags.threads {
        acsg::task::check_threads(threads).map_err(|m| UsageError(format!("invalid --threads: {m}")))?;
    }
    let folder = manifest.parent().unwrap_or(std::path::Path::new(""));
    let outputs: Vec<PathBuf> = list
        .tasks
        .iter()
        .map(|task| {
            let beside = folder.join(task).with_extension("graph.json");
            match (&list.output_dir, beside.file_name()) {
                (Some(dir), Some(name)) => folder.join(dir).join(name),
                _ => beside,
            }
        })
        .collect();
    for (k, output) in outputs.iter().enumerate() {
        if let Some(j) = outputs[..k].iter().position(|o| o == output) {
            anyhow::bail!(
                "{}: tasks {} and {} would both write {} (rename one task file, or drop output_dir)",
                manifest.display(),
                j + 1,
                k + 1,
                output.display()
            );
        }
    }
    if let Some(dir) = &list.output_dir {
        let dir = folder.join(dir);
        std::fs::create_dir_all(&dir).with_context(|| format!("creating {}", dir.display()))?;
    }
    let bar = (!flags.quiet && std::io::stderr().is_terminal()).then(|| {
        let bar = indicatif::ProgressBar::new(list.tasks.len() as u64);
        bar.set_style(
            indicatif::ProgressStyle::with_template("batch {elapsed:>4} [{bar:20}] {pos}/{len} tasks, {msg}")
                .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
        );
        bar
    });
    let say = |line: String| match &bar {
        Some(bar) => bar.println(line),
        None => println!("{line}"),
    };
    let (mut wrote, mut skipped, mut failed) = (0, 0, 0);
    for (task, output) in list.tasks.iter().zip(&outputs) {
        let path = folder.join(task);
        if let Some(bar) = &bar {
            bar.set_message(path.display().to_string());
        }
        match batch_task(&path, output, flags) {
            Ok(Outcome::Wrote(out)) => {
                wrote += 1;
                if !flags.quiet {
                    say(format!("wrote   {} ({})", out.display(), describe_graph(&out)));
                }
            }
            Ok(Outcome::Skipped(out)) => {
                skipped += 1;
                if !flags.quiet {
                    say(format!(
                        "skipped {} (already written: {})",
                        path.display(),
                        out.display()
                    ));
                }
            }
            Err(err) => {
                failed += 1;
                let line = format!("error   {}: {err:#}", path.display());
                match &bar {
                    Some(bar) => bar.suspend(|| eprintln!("{line}")),
                    None => eprintln!("{line}"),
                }
            }
        }
        if let Some(bar) = &bar {
            bar.inc(1);
        }
    }
    if let Some(bar) = bar {
        bar.finish_and_clear();
    }
    if !flags.quiet {
        println!("batch   {wrote} generated, {skipped} skipped (already written), {failed} failed");
    }
    if failed > 0 {
        anyhow::bail!("{failed} of {} tasks failed (see above)", list.tasks.len());
    }
    Ok(())
}

/// One task of a batch: skipped when `output` already holds its graph, else generated.
fn batch_task(task: &std::path::Path, output: &std::path::Path, flags: &BatchFlags) -> anyhow::Result<Outcome> {
    let job = Task::from_path(task)?;
    if !flags.force && holds_graph_of(output, &job) {
        return Ok(Outcome::Skipped(output.to_path_buf()));
    }
    let run = RunFlags {
        output: Some(output.to_path_buf()),
        html: None,
        degenerate: false,
        threads: flags.threads,
        effort: None,
        strategy: None,
        no_timings: flags.no_timings,
        quiet: true,
    };
    run_task(job, None, None, run, output.to_path_buf())?;
    Ok(Outcome::Wrote(output.to_path_buf()))
}

/// Whether `output` is a graph file of `job`: the same parts (as named in the task
/// file), bounds and options. Outputs are written atomically, so one that reads is
/// whole.
fn holds_graph_of(output: &std::path::Path, job: &Task) -> bool {
    if !output.is_file() {
        return false;
    }
    let Ok(file) = GraphFile::from_path(output) else {
        return false;
    };
    // Numbers read back from JSON may differ from the task's in the last digit.
    let close = |a: &[f64], b: &[f64]| {
        a.len() == b.len()
            && a.iter()
                .zip(b)
                .all(|(x, y)| (x - y).abs() <= 1e-12 * x.abs().max(y.abs()).max(1.0))
    };
    let g = acsg::pose::Pose::IDENTITY.matrix(&job.options.assembled);
    file.fixed.path == job.fixed_given
        && file.moving.path == job.moving_given
        && close(&file.bounds.min, &job.bounds.min.to_array())
        && close(&file.bounds.max, &job.bounds.max.to_array())
        && file.options.degenerate == job.options.degenerate
        && file.options.strategy == job.options.strategy
        && close(file.assembled.as_flattened(), g.as_flattened())
}

/// "122 states, 444 edges, complete" of a graph file just written.
fn describe_graph(path: &std::path::Path) -> String {
    match GraphFile::from_path(path) {
        Ok(g) => format!(
            "{} states, {} edges, {}",
            g.states.len(),
            g.edges.len(),
            if g.complete {
                "complete".to_string()
            } else {
                format!("{} undecided", g.undecided.len())
            }
        ),
        Err(e) => e.to_string(),
    }
}

/// One progress bar for a whole run: stage 1 and each stage-2 level report their own
/// searches done and planned; the bar adds each finished batch to what came before, so
/// it never restarts (its length grows as levels are planned, and the ETA is for the
/// searches planned so far).
#[derive(Debug, Default)]
struct RunProgress {
    /// Searches of the finished batches.
    base: u64,
    /// The last report: stage, done, planned.
    last: Option<(u8, usize, usize)>,
}

impl RunProgress {
    /// The bar's position and length after a report.
    fn update(&mut self, p: &Progress) -> (u64, u64) {
        if let Some((stage, done, total)) = self.last {
            let new_batch = stage != p.stage || done >= total || p.done < done || p.total != total;
            if new_batch {
                self.base += total as u64;
            }
        }
        self.last = Some((p.stage, p.done, p.total));
        (self.base + p.done as u64, self.base + p.total as u64)
    }
}

/// The label of a run's lengths: the unit given, else `mm` when every part is a CAD
/// file (read in millimetres), else "model units".
fn units_label(unit: Option<acsg::units::LengthUnit>, formats: &[Option<acsg::io::Format>]) -> String {
    match unit {
        Some(unit) => unit.symbol().to_string(),
        None if formats.iter().flatten().all(|f| f.is_cad()) => acsg::units::LengthUnit::Mm.symbol().to_string(),
        None => acsg::units::UNSPECIFIED.to_string(),
    }
}

/// What a run is about, apart from its parts and flags.
struct Job {
    /// The parts' paths as the user gave them.
    names: [String; 2],
    bounds: Bounds,
    options: Options,
    /// The label of lengths (`mm`, ..., or "model units").
    length: String,
    /// The chord tolerance STEP curved faces were faceted with, if any.
    facet: Option<f64>,
}

/// Generates a graph, prints its summary and writes its JSON (to `flags.output`, else
/// `default_output`, else stdout).
fn generate_and_write(
    (fixed, moving): (Part, Part),
    job: Job,
    flags: RunFlags,
    default_output: Option<PathBuf>,
) -> anyhow::Result<()> {
    let Job {
        names,
        bounds,
        mut options,
        length,
        facet,
    } = job;
    options.degenerate |= flags.degenerate;
    if let Some(threads) = flags.threads {
        acsg::task::check_threads(threads).map_err(|m| UsageError(format!("invalid --threads: {m}")))?;
        options.threads = threads;
    }
    if let Some(effort) = flags.effort {
        options.effort = effort;
    }
    if let Some(strategy) = flags.strategy {
        options.strategy = strategy;
    }
    let bar = (!flags.quiet && std::io::stderr().is_terminal()).then(|| {
        let bar = indicatif::ProgressBar::new(0);
        bar.set_style(
            indicatif::ProgressStyle::with_template(
                // The length grows as stage-2 levels are planned: the ETA is a lower bound.
                "{prefix} {elapsed:>4} [{bar:20}] {pos}/{len} searches, {msg}, ETA ≥ {eta}",
            )
            .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
        );
        bar
    });
    let tally = std::sync::Mutex::new(RunProgress::default());
    let progress = |p: Progress| {
        if let Some(bar) = &bar {
            let (position, length) = match tally.lock() {
                Ok(mut tally) => tally.update(&p),
                Err(_) => return,
            };
            bar.set_prefix(format!("stage {}", p.stage));
            bar.set_length(length);
            bar.set_position(position);
            bar.set_message(format!("{} states", p.states));
        }
    };
    let mut graph = generate_with_progress(&fixed, &moving, &bounds, &options, &progress);
    if let Some(bar) = bar {
        bar.finish_and_clear();
    }
    if flags.no_timings {
        graph.stats.stage1_seconds = 0.0;
        graph.stats.stage2_seconds = 0.0;
    }
    let mut document = Document::new(&graph, &fixed, &moving, &bounds, &options, [&names[0], &names[1]]);
    document.units.length.clone_from(&length);
    document.facet = facet;
    let json = document.to_json();
    let output = flags.output.or(default_output);
    // Results first, messages after: a closed stdout must not cost a result file.
    let mut messages = String::new();
    if !flags.quiet {
        messages.push_str(&summary(&graph, &names, &bounds, &length));
        if let Some(f) = facet {
            messages.insert_str(
                0,
                &format!(
                    "facets STEP cylinders, cones and circles read as planar facets (chord tolerance {f} {length}): \
                     the graph is of the faceted parts\n"
                ),
            );
        }
    }
    match &output {
        Some(path) => {
            acsg::io::write_atomic(path, json.as_bytes()).with_context(|| "writing the graph")?;
            messages.push_str(&format!("wrote {}\n", path.display()));
        }
        None => std::io::stdout().lock().write_all(json.as_bytes())?,
    }
    if let Some(path) = &flags.html {
        let page = acsg::export::html::to_html(&GraphFile::from_document(&document));
        acsg::io::write_atomic(path, page.as_bytes())
            .with_context(|| format!("writing the report {}", path.display()))?;
        messages.push_str(&format!("wrote {}\n", path.display()));
    }
    if !flags.quiet {
        // Keep stdout for the JSON when it goes there.
        if output.is_none() {
            std::io::stderr().lock().write_all(messages.as_bytes())?;
        } else {
            std::io::stdout().lock().write_all(messages.as_bytes())?;
        }
    }
    Ok(())
}

/// The run summary: parts, bounds, stages, and states by number of contacts and DOF.
fn summary(graph: &Graph, names: &[String; 2], bounds: &Bounds, length: &str) -> String {
    use std::fmt::Write as _;
    let s = &graph.stats;
    let mut out = String::new();
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
    match graph.strategy {
        // The default's summary reads as before.
        Strategy::Full => {}
        Strategy::Paper => {
            let _ = writeln!(
                out,
                "search paper: the paper's algorithm, a baseline (local optimisations from fixed starts; no \
                 proofs, warm starts or descents)"
            );
        }
    }
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
    out
}

fn print_inspection(report: &Inspection, json: bool) -> anyhow::Result<()> {
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
    parts: PartsDocument<'a>,
}

#[derive(serde::Serialize)]
struct PartsDocument<'a> {
    fixed: &'a PartElements,
    moving: &'a PartElements,
}

/// How `acsg contacts` prints.
struct Shown {
    /// The relative contact tolerance used.
    tol: f64,
    /// JSON instead of text.
    json: bool,
    /// The label of lengths.
    length: String,
}

fn print_contacts(
    fixed: &Part,
    moving: &Part,
    pose: &Pose,
    assembled: &DAffine3,
    report: &ContactReport,
    shown: &Shown,
) -> anyhow::Result<()> {
    let Shown { tol, json, length } = shown;
    let (tol, json) = (*tol, *json);
    let records: Vec<ContactRecord> = report
        .contacts
        .iter()
        .map(|c| ContactRecord::of(c, fixed, moving))
        .collect();
    let mut out = std::io::stdout().lock();
    if json {
        let doc = ContactsDocument {
            convention: acsg::pose::CONVENTION,
            units: acsg::graph::document::Units {
                length: length.clone(),
                angle: "radians".into(),
            },
            pose: pose.to_array(),
            matrix: pose.matrix(assembled),
            tolerance: tol,
            contacts: records,
            penetration: report.penetration,
            min_gap: report.min_gap,
            parts: PartsDocument {
                fixed: &PartElements::of(fixed),
                moving: &PartElements::of(moving),
            },
        };
        serde_json::to_writer_pretty(&mut out, &doc).context("writing JSON")?;
        writeln!(out)?;
        return Ok(());
    }
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
            acsg::tolerance::GAP_SEARCH_REL * fixed.bounds().diagonal().max(moving.bounds().diagonal())
        )?,
    }
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

#[cfg(test)]
mod tests {
    use super::*;

    fn report(stage: u8, done: usize, total: usize) -> Progress {
        Progress {
            stage,
            done,
            total,
            states: 0,
        }
    }

    /// Stage 1 (10 searches), then two stage-2 levels (4, then 6): one bar whose
    /// position never goes back and whose length is the sum planned so far.
    #[test]
    fn the_progress_bar_runs_once_through_all_levels() {
        let mut tally = RunProgress::default();
        let reports = [
            (report(1, 5, 10), (5, 10)),
            (report(1, 10, 10), (10, 10)),
            (report(2, 2, 4), (12, 14)),
            (report(2, 4, 4), (14, 14)),
            (report(2, 3, 6), (17, 20)),
            (report(2, 6, 6), (20, 20)),
        ];
        let mut last = 0;
        for (p, expected) in reports {
            let got = tally.update(&p);
            assert_eq!(got, expected, "{p:?}");
            assert!(got.0 >= last);
            last = got.0;
        }
    }
}
