//! Progress of long runs (the steps of a junction, the cases of a report): a bar with an ETA on a
//! terminal, a few plain lines otherwise (logs and CI keep no escape codes and no stream of redraws).
//!
//! Log lines and bars share standard error: every line is written through [`LogWriter`], which
//! lifts the bars while it writes, so neither overwrites the other. Two log targets carry progress
//! and are shown without `-v` (see `main::init_logs`): [`TARGET`], a bar's plain lines off a
//! terminal, and `stage`, the periodic lines of the library's long stages that have no bar (a
//! relaxation's phases, a patch test's strain and stress, a calibration's iterations).

use std::io::{IsTerminal, Write};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{LazyLock, OnceLock};

use indicatif::{MultiProgress, ProgressBar, ProgressStyle};

/// The log target of a bar's plain lines when standard error is not a terminal.
pub const TARGET: &str = "progress";

/// Every bar on the terminal, drawn together below the log lines.
static BARS: LazyLock<MultiProgress> = LazyLock::new(MultiProgress::new);

/// Standard error for the log: each line is written with the bars lifted.
#[derive(Debug, Clone, Copy, Default)]
pub struct LogWriter;

impl Write for LogWriter {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        BARS.suspend(|| std::io::stderr().write(buf))
    }

    fn write_all(&mut self, buf: &[u8]) -> std::io::Result<()> {
        BARS.suspend(|| std::io::stderr().write_all(buf))
    }

    fn flush(&mut self) -> std::io::Result<()> {
        std::io::stderr().flush()
    }
}

/// A progress bar over a count of `unit`s, shared between threads.
#[derive(Debug)]
pub struct Bar {
    /// The terminal's bar, made at the first update (so that a stage that runs before the counted
    /// one, such as a sliding run's strength tests, does not sit under an empty bar), or None off a
    /// terminal.
    bar: OnceLock<Option<ProgressBar>>,
    name: String,
    unit: String,
    done: AtomicU64,
    total: AtomicU64,
    /// Last tenth reported when not on a terminal.
    logged: AtomicU64,
}

impl Bar {
    /// A bar named `name`, drawn on a terminal; off a terminal every tenth is a log line.
    pub fn new(name: &str, unit: &str) -> Self {
        Bar {
            bar: OnceLock::new(),
            name: name.into(),
            unit: unit.into(),
            done: AtomicU64::new(0),
            total: AtomicU64::new(0),
            logged: AtomicU64::new(0),
        }
    }

    /// The terminal's bar, made over `total` at the first call.
    fn drawn(&self, total: u64) -> Option<&ProgressBar> {
        self.bar
            .get_or_init(|| {
                std::io::stderr().is_terminal().then(|| {
                    let b = BARS.add(ProgressBar::new(total));
                    let template = format!(
                        "{} [{{bar:40}}] {{pos}}/{{len}} {} ({{percent}} %, {{elapsed_precise}}, ETA {{eta}})",
                        self.name, self.unit
                    );
                    if let Ok(style) = ProgressStyle::with_template(&template) {
                        b.set_style(style.progress_chars("=> "));
                    }
                    b.enable_steady_tick(std::time::Duration::from_millis(500));
                    b
                })
            })
            .as_ref()
    }

    /// `done` of `total`. A first call with `done > 0` (a resumed run, cached cases) starts the ETA
    /// from there, so the work already done does not make the rest look fast.
    pub fn update(&self, done: u64, total: u64) {
        let first = self.total.swap(total, Ordering::Relaxed) == 0;
        self.done.store(done, Ordering::Relaxed);
        match self.drawn(total) {
            Some(b) => {
                b.set_length(total);
                b.set_position(done);
                if first {
                    b.reset_eta();
                }
            }
            None => {
                let tenth = (10 * done).checked_div(total).unwrap_or(10);
                if tenth > self.logged.fetch_max(tenth, Ordering::Relaxed) {
                    tracing::info!(target: TARGET, "{}: {} % ({done} of {total} {})", self.name, 10 * tenth, self.unit);
                }
            }
        }
    }

    /// One more unit done.
    pub fn inc(&self) {
        let done = self.done.fetch_add(1, Ordering::Relaxed) + 1;
        self.update(done, self.total.load(Ordering::Relaxed));
    }

    /// Removes the bar.
    pub fn finish(&self) {
        if let Some(Some(b)) = self.bar.get() {
            b.finish_and_clear();
            BARS.remove(b);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_survive_updates_and_increments_from_threads() {
        let bar = Bar::new("cases", "cases");
        bar.update(3, 10);
        std::thread::scope(|s| {
            for _ in 0..2 {
                s.spawn(|| {
                    for _ in 0..3 {
                        bar.inc();
                    }
                });
            }
        });
        assert_eq!(bar.done.load(Ordering::Relaxed), 9);
        assert_eq!(bar.total.load(Ordering::Relaxed), 10);
        assert_eq!(bar.logged.load(Ordering::Relaxed), 9);
        bar.finish();
    }

    #[test]
    fn a_bar_is_made_at_its_first_update_not_before() {
        let bar = Bar::new("steps", "steps");
        assert!(bar.bar.get().is_none());
        bar.update(0, 5);
        assert!(bar.bar.get().is_some());
        bar.finish();
    }
}
