//! Progress of long runs (the steps of a junction, the cases of a report): a bar with an ETA on a
//! terminal, a few plain lines otherwise (logs and CI keep no escape codes and no stream of redraws).

use std::io::IsTerminal;
use std::sync::atomic::{AtomicU64, Ordering};

use indicatif::{ProgressBar, ProgressStyle};

/// A progress bar over a count of `unit`s, shared between threads.
#[derive(Debug)]
pub struct Bar {
    bar: Option<ProgressBar>,
    name: String,
    done: AtomicU64,
    total: AtomicU64,
    /// Last tenth reported when not on a terminal.
    logged: AtomicU64,
}

impl Bar {
    /// A bar named `name`; hidden when standard error is not a terminal (then every tenth is logged).
    pub fn new(name: &str, unit: &str) -> Self {
        let bar = std::io::stderr().is_terminal().then(|| {
            let b = ProgressBar::new(0);
            let template = format!(
                "{name} [{{bar:40}}] {{pos}}/{{len}} {unit} ({{percent}} %, {{elapsed_precise}}, ETA {{eta}})"
            );
            if let Ok(style) = ProgressStyle::with_template(&template) {
                b.set_style(style.progress_chars("=> "));
            }
            b.enable_steady_tick(std::time::Duration::from_millis(500));
            b
        });
        Bar {
            bar,
            name: name.into(),
            done: AtomicU64::new(0),
            total: AtomicU64::new(0),
            logged: AtomicU64::new(0),
        }
    }

    /// `done` of `total`. A first call with `done > 0` (a resumed run, cached cases) starts the ETA
    /// from there, so the work already done does not make the rest look fast.
    pub fn update(&self, done: u64, total: u64) {
        let first = self.total.swap(total, Ordering::Relaxed) == 0;
        self.done.store(done, Ordering::Relaxed);
        match &self.bar {
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
                    tracing::info!("{}: {} %", self.name, 10 * tenth);
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
        if let Some(b) = &self.bar {
            b.finish_and_clear();
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
}
