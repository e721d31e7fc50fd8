//! From a parsed command line to the library: one function per subcommand, each
//! loading its parts, checking the values clap cannot check, and handing over to the
//! printing or the generation.

use std::io::Write;
use std::path::{Path, PathBuf};

use acsg::export::GraphFile;
use acsg::graph::Options;
use acsg::model::{Inspection, Part};
use acsg::pose::Pose;
use acsg::task::Task;
use acsg::units::LengthUnit;
use anyhow::Context;
use glam::DAffine3;

use crate::args::{Cli, Command, ExportFormat, RunFlags, UnitsFlag, UsageError};
use crate::batch::{BatchFlags, run_batch};
use crate::generate::{Job, generate_and_write, load_pair, run_task, units_label};
use crate::print::{ContactsAtPose, Shown, print_contacts, print_inspection};

/// Runs one command line.
pub(crate) fn run(cli: Cli) -> anyhow::Result<()> {
    match cli.command {
        Command::Inspect {
            fixed,
            moving,
            units,
            json,
        } => inspect(&fixed, moving.as_deref(), &units, json),
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
            let angles = if radians { Angles::Radians } else { Angles::Degrees };
            let pose = parse_pose("--pose", &pose, angles)?;
            let assembled = assembled
                .map(|text| parse_pose("--assembled", &text, angles))
                .transpose()?
                .unwrap_or(Pose::IDENTITY);
            contacts([&fixed, &moving], &pose, &assembled, &units, Shown::checked(tol, json)?)
        }
        Command::Generate {
            fixed,
            moving,
            bounds,
            assembled,
            units,
            run,
        } => generate([&fixed, &moving], &bounds, assembled.as_deref(), &units, run),
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
        Command::Demo { bounds, run } => demo(bounds.as_deref(), run),
        Command::Report { graph, output } => report(&graph, output),
        Command::Export { graph, format, output } => export(&graph, format, output.as_deref()),
    }
}

/// How the angles of a pose given on the command line are read.
#[derive(Clone, Copy)]
enum Angles {
    Degrees,
    Radians,
}

/// A pose argument (`x,y,z,rx,ry,rz`), checked; a bad one is a usage error.
fn parse_pose(flag: &str, text: &str, angles: Angles) -> anyhow::Result<Pose> {
    let degrees = matches!(angles, Angles::Degrees);
    Pose::parse_checked(text, degrees).map_err(|e| UsageError(format!("invalid {flag}: {e}")).into())
}

/// `acsg inspect`: one part's B-rep, or two parts' and their card(PPC).
fn inspect(fixed: &Path, moving: Option<&Path>, units: &UnitsFlag, json: bool) -> anyhow::Result<()> {
    let (unit, facet) = (units.units, units.facet()?);
    let (fixed, fixed_format) = Part::from_path_with(fixed, unit, facet)?;
    let moving = moving.map(|m| Part::from_path_with(m, unit, facet)).transpose()?;
    let formats = [Some(fixed_format), moving.as_ref().map(|m| m.1)];
    let mut report = Inspection::of(&fixed, moving.as_ref().map(|m| &m.0));
    report.units = units_label(unit, &formats);
    report.facet = facet;
    print_inspection(&report, json)
}

/// `acsg contacts`: P(X) at one pose.
fn contacts(paths: [&Path; 2], pose: &Pose, assembled: &Pose, units: &UnitsFlag, shown: Shown) -> anyhow::Result<()> {
    let ((fixed, moving), length) = load_pair(paths, units.units, units.facet()?)?;
    let g = assembled.to_affine(&DAffine3::IDENTITY);
    let placement = pose.to_affine(&g);
    let scene = acsg::contact::ContactScene::new(&fixed, &moving);
    let report = scene.evaluate(&placement, shown.tol);
    // Robustness is defined at the contact tolerance, whatever --tol shows.
    let at_contact_tolerance;
    let read = if shown.tol == acsg::tolerance::CONTACT_REL {
        &report
    } else {
        at_contact_tolerance = scene.evaluate(&placement, acsg::tolerance::CONTACT_REL);
        &at_contact_tolerance
    };
    let flaw = acsg::feasibility::witness_flaw(&scene, &placement, read);
    let at = ContactsAtPose {
        fixed: &fixed,
        moving: &moving,
        pose,
        assembled: &g,
        report: &report,
        flaw: flaw.as_ref(),
    };
    print_contacts(&at, &Shown { length, ..shown })
}

/// `acsg generate`: the graph of two part files within bounds given as text.
fn generate(
    paths: [&Path; 2],
    bounds: &str,
    assembled: Option<&str>,
    units: &UnitsFlag,
    run: RunFlags,
) -> anyhow::Result<()> {
    let bounds = acsg::task::bounds_from_spec(bounds).map_err(|e| UsageError(e.to_string()))?;
    let mut options = Options::default();
    if let Some(text) = assembled {
        let g = parse_pose("--assembled", text, Angles::Degrees)?;
        options.assembled = g.to_affine(&DAffine3::IDENTITY);
    }
    let names = paths.map(|p| p.display().to_string());
    let facet = units.facet()?;
    let (parts, length) = load_pair(paths, units.units, facet)?;
    let job = Job {
        names,
        bounds,
        options,
        length,
        facet,
    };
    generate_and_write(parts, job, run, None)
}

/// `acsg demo`: the paper's example, built in, within its bounds or those given.
fn demo(bounds: Option<&str>, run: RunFlags) -> anyhow::Result<()> {
    let bounds = match bounds {
        Some(spec) => acsg::task::bounds_from_spec(spec).map_err(|e| UsageError(e.to_string()))?,
        None => acsg::examples::paper_bounds(),
    };
    let parts = acsg::examples::l_block_and_box();
    let job = Job {
        names: ["builtin:l_block.off".to_string(), "builtin:box.off".to_string()],
        bounds,
        options: Options::default(),
        length: LengthUnit::Mm.symbol().to_string(),
        facet: None,
    };
    let output = Some(PathBuf::from("acsg-demo.graph.json"));
    generate_and_write(parts, job, run, output)
}

/// `acsg report`: a graph file's HTML report.
fn report(graph: &Path, output: Option<PathBuf>) -> anyhow::Result<()> {
    let file = GraphFile::from_path(graph)?;
    let output = output.unwrap_or_else(|| graph.with_extension("html"));
    let page = acsg::export::html::to_html(&file);
    acsg::io::write_atomic(&output, page.as_bytes())
        .with_context(|| format!("writing the report {}", output.display()))?;
    writeln!(std::io::stdout().lock(), "wrote {}", output.display())?;
    Ok(())
}

/// `acsg export`: a graph file in another tool's format.
fn export(graph: &Path, format: ExportFormat, output: Option<&Path>) -> anyhow::Result<()> {
    let file = GraphFile::from_path(graph)?;
    let text = match format {
        ExportFormat::Dot => acsg::export::dot::to_dot(&file),
        ExportFormat::Graphml => acsg::export::graphml::to_graphml(&file),
        ExportFormat::NodeLink => acsg::export::node_link::to_node_link(&file),
    };
    match output {
        Some(path) => {
            acsg::io::write_atomic(path, text.as_bytes()).with_context(|| format!("writing {}", path.display()))?
        }
        None => std::io::stdout().lock().write_all(text.as_bytes())?,
    }
    Ok(())
}
