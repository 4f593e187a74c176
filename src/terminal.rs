//! Progress on the terminal (indicatif) for the command line and the
//! experiment harness: the renderers report through `progress::Progress`
//! and never see this module. One live bar per run, its stages shown in
//! turn on the same line, cleared when the run ends so that only the run's
//! summary line stays; when standard error is not a terminal, a plain line
//! every few seconds instead. Rates are written for people (`rate`).

use crate::progress::Progress;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::io::IsTerminal;
use std::sync::Mutex;
use std::time::{Duration, Instant};

/// How often a plain progress line is printed when standard error is not a
/// terminal: every 5 s, or every `REFRACT_PROGRESS_SECS` seconds.
fn plain_every() -> Duration {
    let secs = std::env::var("REFRACT_PROGRESS_SECS").ok().and_then(|s| s.trim().parse::<f64>().ok()).filter(|s| s.is_finite() && *s >= 0.0);
    Duration::from_secs_f64(secs.unwrap_or(5.0).min(86_400.0))
}

pub use crate::timing::rate;

/// The unit a stage counts.
fn unit(stage: &str) -> &'static str {
    match stage {
        "light" => "photons",
        "eye" => "rows",
        _ => "steps",
    }
}

/// The stage running now.
struct Stage {
    name: &'static str,
    total: u64,
    done: u64,
    since: Instant,
}

struct State {
    stage: Option<Stage>,
    /// Wall time of each finished stage, summed over its repeats (passes).
    times: Vec<(&'static str, f64)>,
    last_plain: Instant,
    context: String,
}

/// One run's progress: a single bar on a terminal, plain lines elsewhere,
/// and the wall time of each stage.
pub struct Bars {
    bar: ProgressBar,
    plain: bool,
    every: Duration,
    state: Mutex<State>,
}

impl Bars {
    pub fn new() -> Bars {
        let terminal = std::io::stderr().is_terminal();
        let style = ProgressStyle::with_template("{prefix} [{bar:30}] {percent:>3}% {msg}").unwrap_or_else(|_| ProgressStyle::default_bar());
        let target = if terminal { ProgressDrawTarget::stderr() } else { ProgressDrawTarget::hidden() };
        let bar = ProgressBar::with_draw_target(Some(0), target).with_style(style);
        Bars {
            bar,
            plain: !terminal,
            every: plain_every(),
            state: Mutex::new(State { stage: None, times: Vec::new(), last_plain: Instant::now(), context: String::new() }),
        }
    }

    fn state(&self) -> std::sync::MutexGuard<'_, State> {
        self.state.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// What the bar is about (a figure's id and its place), shown before
    /// the stage; the stage times start afresh.
    pub fn set_context(&self, context: String) {
        let mut s = self.state();
        s.context = context;
        s.times.clear();
        s.stage = None;
    }

    /// Prints a line above the bar (or alone, off a terminal), leaving no
    /// trace of the bar in it.
    pub fn println(&self, line: &str) {
        if self.plain || self.bar.is_hidden() {
            eprintln!("{line}");
        } else {
            self.bar.println(line);
        }
    }

    /// The wall time of each stage that took time, in the order they ran.
    pub fn stage_times(&self) -> Vec<(&'static str, f64)> {
        self.state().times.clone()
    }

    /// Ends the bar, leaving nothing of it on the terminal.
    pub fn done(&self) {
        self.bar.finish_and_clear();
    }

    /// The bar's prefix: the context and the stage.
    fn describe(s: &State, st: &Stage) -> String {
        format!("{}{}", if s.context.is_empty() { String::new() } else { format!("{}: ", s.context) }, st.name)
    }
}

impl Default for Bars {
    fn default() -> Self {
        Bars::new()
    }
}

impl Drop for Bars {
    fn drop(&mut self) {
        self.bar.finish_and_clear();
    }
}

impl Progress for Bars {
    fn start(&self, stage: &'static str, total: u64) {
        let mut s = self.state();
        s.stage = Some(Stage { name: stage, total, done: 0, since: Instant::now() });
        self.bar.set_length(total.max(1));
        self.bar.set_position(0);
        let st = s.stage.as_ref().unwrap();
        self.bar.set_prefix(Self::describe(&s, st));
        self.bar.set_message(String::new());
    }

    fn advance(&self, stage: &'static str, n: u64) {
        self.bar.inc(n);
        let mut s = self.state();
        let Some(st) = s.stage.as_mut().filter(|st| st.name == stage) else { return };
        st.done += n;
        let secs = st.since.elapsed().as_secs_f64();
        // A rate once the stage has run long enough to have one.
        let msg = if secs >= 0.2 { rate(st.done as f64 / secs, unit(stage)) } else { String::new() };
        let pct = 100 * st.done / st.total.max(1);
        let done = st.done;
        if self.plain && s.last_plain.elapsed() >= self.every {
            s.last_plain = Instant::now();
            let ctx = if s.context.is_empty() { String::new() } else { format!("{}: ", s.context) };
            let r = if secs > 0.0 { format!(" ({})", rate(done as f64 / secs, unit(stage))) } else { String::new() };
            eprintln!("{ctx}{stage} {pct}%{r}, {secs:.1} s");
        } else if !self.plain {
            self.bar.set_message(msg);
        }
    }

    fn finish(&self, stage: &'static str) {
        let mut s = self.state();
        let Some(st) = s.stage.take().filter(|st| st.name == stage) else { return };
        let secs = st.since.elapsed().as_secs_f64();
        match s.times.iter_mut().find(|(n, _)| *n == stage) {
            Some((_, t)) => *t += secs,
            None => s.times.push((stage, secs)),
        }
    }
}

/// A bar that counts whole items (runs), with the current item's name
/// beside it; hidden off a terminal.
pub fn counter(len: u64, prefix: &str, unit: &str) -> ProgressBar {
    let template = format!("{{prefix}} [{{bar:40}}] {{pos}}/{{len}} {unit} {{msg}} eta {{eta}}");
    let style = ProgressStyle::with_template(&template).unwrap_or_else(|_| ProgressStyle::default_bar());
    ProgressBar::new(len).with_style(style).with_prefix(prefix.to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stages_are_timed_and_summed_over_repeats() {
        let b = Bars::new();
        for _ in 0..3 {
            b.start("light", 10);
            b.advance("light", 10);
            b.finish("light");
        }
        b.start("eye", 4);
        b.finish("eye");
        let t = b.stage_times();
        assert_eq!(t.iter().map(|s| s.0).collect::<Vec<_>>(), ["light", "eye"]);
        assert!(t.iter().all(|s| s.1 >= 0.0));
    }
}
