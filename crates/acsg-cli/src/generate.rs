//! Generating a graph for the commands that do (`generate`, `run`, `batch`, `demo`):
//! the run's flags applied to its options, the generation under a progress bar, and
//! the graph written with its summary.

use std::io::Write;
use std::path::{Path, PathBuf};

use acsg::export::GraphFile;
use acsg::graph::{Document, Graph, Options, generate_with_progress};
use acsg::model::Part;
use acsg::pose::Bounds;
use acsg::task::Task;
use acsg::units::LengthUnit;
use anyhow::Context;

use crate::args::{RunFlags, UsageError, check_facet};
use crate::print::summary;
use crate::progress::GenerationBar;

/// What a run is about, apart from its parts and flags.
pub(crate) struct Job {
    /// The parts' paths as the user gave them.
    pub(crate) names: [String; 2],
    pub(crate) bounds: Bounds,
    pub(crate) options: Options,
    /// The label of lengths (`mm`, ..., or "model units").
    pub(crate) length: String,
    /// The chord tolerance STEP curved faces were faceted with, if any.
    pub(crate) facet: Option<f64>,
}

/// Generates a graph, prints its summary and writes its JSON (to `flags.output`, else
/// `default_output`, else stdout).
pub(crate) fn generate_and_write(
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
    apply_flags(&mut options, &flags)?;
    let bar = GenerationBar::new(!flags.quiet);
    let mut graph = generate_with_progress(&fixed, &moving, &bounds, &options, &|p| bar.report(&p));
    bar.finish();
    if flags.no_timings {
        graph.stats.stage1_seconds = 0.0;
        graph.stats.stage2_seconds = 0.0;
    }
    let mut document = Document::new(&graph, &fixed, &moving, &bounds, &options, [&names[0], &names[1]]);
    document.units.length.clone_from(&length);
    document.facet = facet;
    let output = flags.output.clone().or(default_output);
    // Results first, messages after: a closed stdout must not cost a result file.
    let mut messages = String::new();
    if !flags.quiet {
        messages.push_str(&run_summary(&graph, &names, &bounds, &length, facet));
    }
    messages.push_str(&write_outputs(&document, output.as_ref(), flags.html.as_ref())?);
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

/// The flags of a run that change its options (`--degenerate`, `--threads`,
/// `--effort`, `--strategy`, `--work-limit`), checked.
fn apply_flags(options: &mut Options, flags: &RunFlags) -> anyhow::Result<()> {
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
    if let Some(limit) = flags.work_limit {
        options.work_limit = Some(limit);
    }
    Ok(())
}

/// The summary printed after a run, with a first line when the parts were faceted.
fn run_summary(graph: &Graph, names: &[String; 2], bounds: &Bounds, length: &str, facet: Option<f64>) -> String {
    let mut text = String::new();
    if let Some(f) = facet {
        text.push_str(&format!(
            "facets STEP cylinders, cones and circles read as planar facets (chord tolerance {f} {length}): \
             the graph is of the faceted parts\n"
        ));
    }
    text.push_str(&summary(graph, names, bounds, length));
    text
}

/// Writes the graph's JSON (to `output`, else stdout) and its HTML report (to `html`,
/// when asked); returns a line per file written.
fn write_outputs(document: &Document, output: Option<&PathBuf>, html: Option<&PathBuf>) -> anyhow::Result<String> {
    let json = document.to_json();
    let mut messages = String::new();
    match output {
        Some(path) => {
            acsg::io::write_atomic(path, json.as_bytes()).with_context(|| "writing the graph")?;
            messages.push_str(&format!("wrote {}\n", path.display()));
        }
        None => std::io::stdout().lock().write_all(json.as_bytes())?,
    }
    if let Some(path) = html {
        let page = acsg::export::html::to_html(&GraphFile::from_document(document));
        acsg::io::write_atomic(path, page.as_bytes())
            .with_context(|| format!("writing the report {}", path.display()))?;
        messages.push_str(&format!("wrote {}\n", path.display()));
    }
    Ok(messages)
}

/// Both parts of a run, read in `unit` (STEP curves faceted within `facet`), and the
/// label of the run's lengths.
pub(crate) fn load_pair(
    paths: [&Path; 2],
    unit: Option<LengthUnit>,
    facet: Option<f64>,
) -> anyhow::Result<((Part, Part), String)> {
    let (fixed, fixed_format) = Part::from_path_with(paths[0], unit, facet)?;
    let (moving, moving_format) = Part::from_path_with(paths[1], unit, facet)?;
    let length = units_label(unit, &[Some(fixed_format), Some(moving_format)]);
    Ok(((fixed, moving), length))
}

/// Generates the graph of a task read from its file and writes it (`acsg run`, and
/// each task of `acsg batch`).
pub(crate) fn run_task(
    job: Task,
    units: Option<LengthUnit>,
    facet: Option<f64>,
    run: RunFlags,
    default_output: PathBuf,
) -> anyhow::Result<()> {
    let unit = units.or(job.units);
    let facet = check_facet(facet.or(job.facet))?;
    let (parts, length) = load_pair([&job.fixed, &job.moving], unit, facet)?;
    let run_job = Job {
        names: [job.fixed_given, job.moving_given],
        bounds: job.bounds,
        options: job.options,
        length,
        facet,
    };
    generate_and_write(parts, run_job, run, Some(default_output))
}

/// The label of a run's lengths: the unit given, else `mm` when every part is a CAD
/// file (read in millimetres), else "model units".
pub(crate) fn units_label(unit: Option<LengthUnit>, formats: &[Option<acsg::io::Format>]) -> String {
    match unit {
        Some(unit) => unit.symbol().to_string(),
        None if formats.iter().flatten().all(|f| f.is_cad()) => LengthUnit::Mm.symbol().to_string(),
        None => acsg::units::UNSPECIFIED.to_string(),
    }
}
