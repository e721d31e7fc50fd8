//! `acsg`: the command-line interface. It parses and validates arguments
//! ([`args`]), calls the library ([`dispatch`], [`generate`], [`batch`]), prints
//! ([`print`], [`progress`]), and maps errors to exit codes (0 success, 1 bad input or
//! failed job, 2 bad usage).

mod args;
mod batch;
mod dispatch;
mod generate;
mod print;
mod progress;

use std::process::ExitCode;

use clap::Parser;

use crate::args::{Cli, UsageError};

/// mimalloc rather than the system's allocator: a decision builds and drops many small
/// vectors per box of poses (rows of linear programmes, cases, pieces' hulls).
#[global_allocator]
static ALLOCATOR: mimalloc::MiMalloc = mimalloc::MiMalloc;

fn main() -> ExitCode {
    let cli = Cli::parse();
    match dispatch::run(cli) {
        Ok(()) => ExitCode::SUCCESS,
        Err(err) if err.downcast_ref::<UsageError>().is_some() => {
            eprintln!("error: {}", message(&err));
            ExitCode::from(2)
        }
        Err(err) => {
            // A closed pipe (`acsg ... | head`) is not an error worth a message.
            if is_broken_pipe(&err) {
                return ExitCode::SUCCESS;
            }
            eprintln!("error: {}", message(&err));
            ExitCode::from(1)
        }
    }
}

/// An error with its causes, each after a colon, but a cause whose words the message
/// already holds (a library error that names its source in its own text) only once.
fn message(err: &anyhow::Error) -> String {
    let mut text = err.to_string();
    for cause in err.chain().skip(1) {
        let cause = cause.to_string();
        if !text.contains(&cause) {
            text.push_str(": ");
            text.push_str(&cause);
        }
    }
    text
}

/// Whether an error comes from writing to a closed pipe.
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
