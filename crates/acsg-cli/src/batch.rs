//! `acsg batch`: the graphs of many task files, one after the other, skipping those
//! whose output already holds their graph.

use std::path::{Path, PathBuf};

use acsg::export::GraphFile;
use acsg::task::Task;
use anyhow::Context;

use crate::args::{RunFlags, UsageError};
use crate::generate::run_task;
use crate::progress::batch_bar;

/// The options of `acsg batch`.
pub(crate) struct BatchFlags {
    pub(crate) force: bool,
    pub(crate) threads: Option<usize>,
    pub(crate) no_timings: bool,
    pub(crate) quiet: bool,
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
pub(crate) fn run_batch(manifest: &Path, flags: &BatchFlags) -> anyhow::Result<()> {
    let list = read_manifest(manifest)?;
    if let Some(threads) = flags.threads {
        acsg::task::check_threads(threads).map_err(|m| UsageError(format!("invalid --threads: {m}")))?;
    }
    let folder = manifest.parent().unwrap_or(Path::new(""));
    let outputs = output_paths(manifest, &list)?;
    if let Some(dir) = &list.output_dir {
        let dir = folder.join(dir);
        std::fs::create_dir_all(&dir).with_context(|| format!("creating {}", dir.display()))?;
    }
    let bar = batch_bar(!flags.quiet, list.tasks.len());
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

/// The manifest, read and parsed.
fn read_manifest(manifest: &Path) -> anyhow::Result<Manifest> {
    let text = std::fs::read_to_string(manifest)
        .with_context(|| format!("{}: cannot read the manifest (check the path)", manifest.display()))?;
    toml::from_str(text.strip_prefix('\u{feff}').unwrap_or(&text)).map_err(|e| {
        anyhow::anyhow!(
            "{}: {} (a manifest is `tasks = [\"a.toml\", \"b.toml\"]` and an optional `output_dir = \"graphs\"`)",
            manifest.display(),
            e.message().trim()
        )
    })
}

/// Where each task's graph goes; an error when two tasks would write the same file.
fn output_paths(manifest: &Path, list: &Manifest) -> anyhow::Result<Vec<PathBuf>> {
    let folder = manifest.parent().unwrap_or(Path::new(""));
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
    Ok(outputs)
}

/// One task of a batch: skipped when `output` already holds its graph, else generated.
fn batch_task(task: &Path, output: &Path, flags: &BatchFlags) -> anyhow::Result<Outcome> {
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
        work_limit: None,
        no_timings: flags.no_timings,
        quiet: true,
    };
    run_task(job, None, None, run, output.to_path_buf())?;
    Ok(Outcome::Wrote(output.to_path_buf()))
}

/// Whether `output` is a graph file of `job`: the same parts (as named in the task
/// file), bounds and options. Outputs are written atomically, so one that reads is
/// whole.
fn holds_graph_of(output: &Path, job: &Task) -> bool {
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
        && file.options.work_limit == job.options.work_limit
        && close(file.assembled.as_flattened(), g.as_flattened())
}

/// "122 states, 444 edges, complete" of a graph file just written.
fn describe_graph(path: &Path) -> String {
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
