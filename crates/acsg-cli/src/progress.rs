//! The progress bars on a terminal: one for a whole generation (stage 1 and every
//! stage-2 level on one bar), one for a batch.

use std::io::IsTerminal;
use std::sync::Mutex;

use acsg::graph::Progress;

/// One progress bar for a whole run: stage 1 and each stage-2 level report their own
/// searches done and planned; the bar adds each finished batch to what came before, so
/// it never restarts (its length grows as levels are planned, and the ETA is for the
/// searches planned so far).
#[derive(Debug, Default)]
pub(crate) struct RunProgress {
    /// Searches of the finished batches.
    base: u64,
    /// The last report: stage, done, planned.
    last: Option<(u8, usize, usize)>,
}

impl RunProgress {
    /// The bar's position and length after a report.
    pub(crate) fn update(&mut self, p: &Progress) -> (u64, u64) {
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

/// The bar of one generation, drawn on stderr when it is a terminal and the run is
/// not quiet.
pub(crate) struct GenerationBar {
    bar: Option<indicatif::ProgressBar>,
    tally: Mutex<RunProgress>,
}

impl GenerationBar {
    /// A bar, or nothing to draw when `shown` is false or stderr is not a terminal.
    pub(crate) fn new(shown: bool) -> Self {
        let bar = (shown && std::io::stderr().is_terminal()).then(|| {
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
        Self {
            bar,
            tally: Mutex::new(RunProgress::default()),
        }
    }

    /// Shows one report of the generator.
    pub(crate) fn report(&self, p: &Progress) {
        if let Some(bar) = &self.bar {
            let (position, length) = match self.tally.lock() {
                Ok(mut tally) => tally.update(p),
                Err(_) => return,
            };
            bar.set_prefix(format!("stage {}", p.stage));
            bar.set_length(length);
            bar.set_position(position);
            bar.set_message(format!("{} states", p.states));
        }
    }

    /// Clears the bar once the graph is generated.
    pub(crate) fn finish(self) {
        if let Some(bar) = self.bar {
            bar.finish_and_clear();
        }
    }
}

/// The bar of a batch (one step per task), drawn as [`GenerationBar`] is.
pub(crate) fn batch_bar(shown: bool, tasks: usize) -> Option<indicatif::ProgressBar> {
    (shown && std::io::stderr().is_terminal()).then(|| {
        let bar = indicatif::ProgressBar::new(tasks as u64);
        bar.set_style(
            indicatif::ProgressStyle::with_template("batch {elapsed:>4} [{bar:20}] {pos}/{len} tasks, {msg}")
                .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
        );
        bar
    })
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
