//! Progress bars on the terminal (indicatif) for the command line and the
//! experiment harness: the renderers report through `progress::Progress`
//! and never see this module.

use crate::progress::Progress;
use indicatif::{MultiProgress, ProgressBar, ProgressStyle};
use std::sync::Mutex;

/// One bar per stage, drawn on standard error while the stage runs.
pub struct Bars {
    multi: MultiProgress,
    bars: Mutex<Vec<(&'static str, ProgressBar)>>,
}

impl Bars {
    pub fn new() -> Bars {
        Bars { multi: MultiProgress::new(), bars: Mutex::new(Vec::new()) }
    }

    fn with(&self, stage: &'static str, f: impl FnOnce(&ProgressBar)) {
        let bars = self.bars.lock().unwrap_or_else(|e| e.into_inner());
        if let Some((_, b)) = bars.iter().find(|(s, _)| *s == stage) {
            f(b);
        }
    }
}

impl Default for Bars {
    fn default() -> Self {
        Bars::new()
    }
}

/// A bar that counts whole items (figures, runs), with the current item's
/// name beside it.
pub fn counter(len: u64, prefix: &str, unit: &str) -> ProgressBar {
    let template = format!("{{prefix}} [{{bar:40}}] {{pos}}/{{len}} {unit} {{msg}} eta {{eta}}");
    let style = ProgressStyle::with_template(&template).unwrap_or_else(|_| ProgressStyle::default_bar());
    ProgressBar::new(len).with_style(style).with_prefix(prefix.to_string())
}

/// The unit a stage counts, for the rate shown beside its bar.
fn unit(stage: &str) -> &'static str {
    match stage {
        "light" => "photons/s",
        "eye" => "rows/s",
        _ => "/s",
    }
}

impl Progress for Bars {
    fn start(&self, stage: &'static str, total: u64) {
        let template = format!("{{prefix:>6}} [{{bar:40}}] {{percent:>3}}% {{per_sec:.0}} ({}) eta {{eta}}", unit(stage));
        let style = ProgressStyle::with_template(&template).unwrap_or_else(|_| ProgressStyle::default_bar());
        let bar = self.multi.add(ProgressBar::new(total).with_style(style).with_prefix(stage));
        self.bars.lock().unwrap_or_else(|e| e.into_inner()).push((stage, bar));
    }

    fn advance(&self, stage: &'static str, n: u64) {
        self.with(stage, |b| b.inc(n));
    }

    fn finish(&self, stage: &'static str) {
        let mut bars = self.bars.lock().unwrap_or_else(|e| e.into_inner());
        if let Some(i) = bars.iter().position(|(s, _)| *s == stage) {
            bars.remove(i).1.finish_and_clear();
        }
    }
}
