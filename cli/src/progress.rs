//! Progress of long runs: a bar with an ETA on a terminal, a few plain lines otherwise (logs and CI
//! keep no escape codes and no stream of redraws).

use std::io::IsTerminal;

use indicatif::{ProgressBar, ProgressStyle};

/// A progress bar over a count of `unit`s.
#[derive(Debug)]
pub struct Bar {
    bar: Option<ProgressBar>,
    name: String,
    /// Last tenth reported when not on a terminal.
    logged: std::cell::Cell<u64>,
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
            b
        });
        Bar {
            bar,
            name: name.into(),
            logged: std::cell::Cell::new(0),
        }
    }

    /// `done` of `total`.
    pub fn update(&self, done: u64, total: u64) {
        match &self.bar {
            Some(b) => {
                b.set_length(total);
                b.set_position(done);
            }
            None => {
                let tenth = (10 * done).checked_div(total).unwrap_or(10);
                if tenth > self.logged.get() {
                    self.logged.set(tenth);
                    tracing::info!("{}: {} %", self.name, 10 * tenth);
                }
            }
        }
    }

    /// Removes the bar.
    pub fn finish(&self) {
        if let Some(b) = &self.bar {
            b.finish_and_clear();
        }
    }
}
