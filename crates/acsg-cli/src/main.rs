//! `acsg`: the command-line interface. It parses and validates arguments, calls the
//! library, prints, and maps errors to exit codes (0 success, 1 bad input or failed
//! job, 2 bad usage).

use std::io::Write;
use std::path::PathBuf;
use std::process::ExitCode;

use acsg::model::{Inspection, Part};
use anyhow::Context;
use clap::{Parser, Subcommand};

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
        /// The fixed part (OFF, OBJ, STL or PLY).
        fixed: PathBuf,
        /// The moving part.
        moving: Option<PathBuf>,
        /// Print one JSON object instead of text.
        #[arg(long)]
        json: bool,
    },
    /// Run on the built-in example (the paper's L-block and box): no files needed.
    Demo {
        /// Print one JSON object instead of text.
        #[arg(long)]
        json: bool,
    },
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    match run(cli) {
        Ok(()) => ExitCode::SUCCESS,
        Err(err) => {
            // A closed pipe (`acsg ... | head`) is not an error worth a message.
            if err
                .downcast_ref::<std::io::Error>()
                .is_some_and(|e| e.kind() == std::io::ErrorKind::BrokenPipe)
            {
                return ExitCode::SUCCESS;
            }
            eprintln!("error: {err:#}");
            ExitCode::from(1)
        }
    }
}

fn run(cli: Cli) -> anyhow::Result<()> {
    match cli.command {
        Command::Inspect { fixed, moving, json } => {
            let fixed = Part::from_path(&fixed)?;
            let moving = moving.map(|m| Part::from_path(&m)).transpose()?;
            print_inspection(&Inspection::of(&fixed, moving.as_ref()), json)
        }
        Command::Demo { json } => {
            let (fixed, moving) = acsg::examples::l_block_and_box();
            print_inspection(&Inspection::of(&fixed, Some(&moving)), json)
        }
    }
}

fn print_inspection(report: &Inspection, json: bool) -> anyhow::Result<()> {
    let mut out = std::io::stdout().lock();
    if json {
        serde_json::to_writer_pretty(&mut out, report).context("writing JSON")?;
        writeln!(out)?;
        return Ok(());
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
