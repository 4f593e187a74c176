//! Spreading a sweep over machines: which shard runs which run (balanced
//! by estimated cost), and `refract sweep plan`, which writes a script for
//! GNU parallel or a Slurm job array that runs the shards and merges them.
//!
//! A shard holds whole chains: the runs that differ only along the first
//! sweep axis (same case, repeat and other axes). `changed_px` compares a
//! run with the one before it on that axis, so a chain must stay together
//! for the merged CSV to equal the unsharded one. Chains go, most costly
//! first, to the shard with the least estimated work (longest processing
//! time first); the assignment depends only on the experiment file, so any
//! engine and any machine agree on it.

use super::error::{ExperimentError, Result};
use super::grid::{expand, RunSpec};
use super::spec::Experiment;
pub use crate::modes::Cost;
use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// What stays fixed along a chain (the runs along the first sweep axis,
/// which go together: each run's changed_px compares it with the one before).
type ChainKey = (String, u32, Vec<usize>);

fn chain_key(r: &RunSpec) -> ChainKey {
    (r.case.clone(), r.repeat, r.at.iter().skip(1).copied().collect())
}

/// How many chains the grid holds: the most shards that all have work.
pub fn chain_count(runs: &[RunSpec]) -> usize {
    runs.iter().map(chain_key).collect::<std::collections::BTreeSet<_>>().len()
}

/// The shard (0..n) of every run, by run id.
pub fn assign(runs: &[RunSpec], n: usize) -> Vec<usize> {
    let n = n.max(1);
    // Chains, keyed by what stays fixed along the first axis: (first run
    // id, run ids, estimated seconds).
    let mut chains: BTreeMap<ChainKey, (usize, Vec<usize>, f64)> = BTreeMap::new();
    for r in runs {
        let c = chains.entry(chain_key(r)).or_insert((r.id, Vec::new(), 0.0));
        c.1.push(r.id);
        c.2 += r.mode.cost(&r.given).seconds;
    }
    let mut chains: Vec<(usize, Vec<usize>, f64)> = chains.into_values().collect();
    // Most costly first; equal costs in run order.
    chains.sort_by(|a, b| b.2.total_cmp(&a.2).then(a.0.cmp(&b.0)));
    let mut load = vec![0.0f64; n];
    let mut shard = vec![0; runs.len()];
    for (_, ids, c) in chains {
        let s = (0..n).min_by(|&a, &b| load[a].total_cmp(&load[b]).then(a.cmp(&b))).unwrap_or(0);
        load[s] += c;
        for id in ids {
            shard[id] = s;
        }
    }
    shard
}

crate::named_enum! {
    /// What runs the shards.
    pub enum Engine {
        /// GNU parallel, on this machine or over ssh (`--sshloginfile`).
        Parallel = "parallel",
        /// A Slurm job array and a dependent merge job (`sbatch`).
        Slurm = "slurm",
    }
}

/// What `refract sweep plan` was asked for.
#[derive(Clone, Debug)]
pub struct PlanOptions {
    pub file: PathBuf,
    pub engine: Engine,
    /// `None`: `DEFAULT_SHARDS`, or the grid's chains if fewer.
    pub shards: Option<usize>,
    pub out: Option<PathBuf>,
    pub quick: bool,
    /// Slurm: partition, time limit (as sbatch takes it), CPUs and memory
    /// per shard; estimated from the experiment where not given.
    pub partition: Option<String>,
    pub time: Option<String>,
    pub cpus_per_task: usize,
    pub mem: Option<String>,
    /// The refract binary the script runs.
    pub refract: PathBuf,
}

/// `n` and its noun, singular or plural.
fn plural(n: usize, one: &str, many: &str) -> String {
    format!("{n} {}", if n == 1 { one } else { many })
}

/// Shards when `--shards` is not given.
pub const DEFAULT_SHARDS: usize = 4;

/// The most shards a plan makes (a job array larger than this is a typo).
pub const MAX_SHARDS: usize = 10_000;

/// Estimated work of each shard: runs, seconds on one core (with the
/// reference run, which every shard renders for its metrics), peak bytes.
#[derive(Clone, Debug, Default)]
pub struct ShardLoad {
    pub runs: usize,
    pub seconds: f64,
    pub bytes: f64,
}

/// The loads of `n` shards of `runs`, the grid of `e`.
pub fn loads(e: &Experiment, runs: &[RunSpec], n: usize) -> Vec<ShardLoad> {
    let shard = assign(runs, n);
    let reference = e.reference_given().and_then(Result::ok).map(|p| e.mode.cost(&p));
    let mut out = vec![ShardLoad::default(); n];
    for (r, &s) in runs.iter().zip(&shard) {
        let c = r.mode.cost(&r.given);
        out[s].runs += 1;
        out[s].seconds += c.seconds;
        out[s].bytes = out[s].bytes.max(c.bytes);
    }
    for l in &mut out {
        if let Some(c) = reference {
            l.seconds += c.seconds;
            l.bytes = l.bytes.max(c.bytes);
        }
    }
    out
}

/// The scripts' text: the head every script starts with, and the body of
/// each (placeholders `{{key}}`, filled by `fill`).
const HEAD: &str = include_str!("plan_scripts/head.sh");
const SHARD: &str = include_str!("plan_scripts/shard.sh");
const MERGE: &str = include_str!("plan_scripts/merge.sh");
const PARALLEL: &str = include_str!("plan_scripts/run-parallel.sh");
const SLURM: &str = include_str!("plan_scripts/submit-slurm.sh");

/// `template` with every `{{key}}` replaced by its value in `values`, in one
/// pass (a value holding `{{` is left as it is).
fn fill(template: &str, values: &[(&str, &str)]) -> String {
    let mut out = String::with_capacity(template.len());
    let mut rest = template;
    while let Some(start) = rest.find("{{") {
        out.push_str(&rest[..start]);
        let after = &rest[start + 2..];
        match after.find("}}").and_then(|end| values.iter().find(|(k, _)| *k == &after[..end]).map(|(_, v)| (end, v))) {
            Some((end, v)) => {
                out.push_str(v);
                rest = &after[end + 2..];
            }
            None => {
                out.push_str("{{");
                rest = after;
            }
        }
    }
    out.push_str(rest);
    out
}

/// How many shards to make: as asked, or `DEFAULT_SHARDS`, never more than
/// the grid's chains (a shard with no run would be a job doing nothing).
fn shard_count(runs: &[RunSpec], asked: Option<usize>) -> Result<usize> {
    let chains = chain_count(runs).max(1);
    Ok(match asked {
        None => DEFAULT_SHARDS.min(chains),
        Some(n) if n == 0 || n > MAX_SHARDS => return Err(ExperimentError::flag("--shards", format!("{n} is not between 1 and {MAX_SHARDS}"))),
        Some(n) if n > chains => {
            let why = format!(
                "{n} is more than the {} this grid holds (the runs along its first sweep axis stay in one shard); at most {chains}",
                plural(chains, "chain of runs", "chains of runs")
            );
            return Err(ExperimentError::flag("--shards", why));
        }
        Some(n) => n,
    })
}

/// The three scripts of a plan, by file name: shard.sh, merge.sh and the
/// engine's script; and how to run the last (`{script}` for its path).
struct Scripts {
    files: [(&'static str, String); 3],
    how: &'static str,
}

/// The plan's scripts for `n` shards of `e` with `loads`, writing into `dir`
/// and running from `workdir`.
fn scripts(e: &Experiment, o: &PlanOptions, n: usize, loads: &[ShardLoad], dir: &Path, file: &Path, workdir: &Path) -> Scripts {
    let n_text = n.to_string();
    let (refract, file, out, workdir) = (shell_quote(&o.refract), shell_quote(file), shell_quote(dir), shell_quote(workdir));
    let head = |what: &str| {
        fill(
            HEAD,
            &[
                ("engine", o.engine.name()),
                ("name", &e.name),
                ("n", &n_text),
                ("what", what),
                ("refract", &refract),
                ("file", &file),
                ("out", &out),
                ("workdir", &workdir),
            ],
        )
    };
    let quick = [("quick", if o.quick { " --quick" } else { "" })];
    let shard = head("runs shard $1 of 0..N-1 into $OUT/shards/$1 (again with --resume, it finishes a shard that stopped)") + &fill(SHARD, &quick);
    let merge = head("joins the shards into $OUT/runs.csv and draws the plots") + &fill(MERGE, &quick);
    let busiest = loads.iter().map(|l| l.seconds).fold(0.0, f64::max);
    let (script, how, text) = match o.engine {
        Engine::Parallel => (
            "run-parallel.sh",
            "bash {script} [GNU parallel options, e.g. --sshloginfile hosts]",
            head(&format!("the shards through GNU parallel, then the merge (busiest shard about {busiest:.1} s on one core)")) + PARALLEL,
        ),
        Engine::Slurm => {
            let time = o.time.clone().unwrap_or_else(|| slurm_time(busiest));
            let mem_mb = loads.iter().map(|l| l.bytes).fold(0.0, f64::max) / (1u64 << 20) as f64;
            let mem = o.mem.clone().unwrap_or_else(|| format!("{}M", (256.0 + 1.5 * mem_mb).ceil() as u64));
            let partition = o.partition.as_ref().map_or(String::new(), |p| format!(" --partition={}", shell_word(p)));
            let what = format!(
                "a job array of the shards ({time} and {mem} each, from the estimate: busiest shard about {busiest:.1} s on one core) and a merge job after them"
            );
            let body = fill(
                SLURM,
                &[
                    ("job", &shell_word(&e.name)),
                    ("partition", &partition),
                    ("time", &shell_word(&time)),
                    ("cpus", &o.cpus_per_task.to_string()),
                    ("mem", &shell_word(&mem)),
                ],
            );
            ("submit-slurm.sh", "bash {script} [--wait]", head(&what) + &body)
        }
    };
    Scripts { files: [("shard.sh", shard), ("merge.sh", merge), (script, text)], how }
}

/// Writes `text` to `path` (through a temp file), executable on Unix.
fn write_script(path: &Path, text: &str) -> Result<()> {
    crate::image_io::atomic_write(path, |f| {
        use std::io::Write;
        f.write_all(text.as_bytes())?;
        Ok(())
    })?;
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        std::fs::set_permissions(path, std::fs::Permissions::from_mode(0o755))?;
    }
    Ok(())
}

/// What to tell the user: the shards' estimated loads, the script written
/// at `path`, how to run it and where the merged results go.
fn summary(e: &Experiment, n: usize, loads: &[ShardLoad], path: &Path, how: &str, dir: &Path) -> String {
    let mut msg = String::new();
    let _ = writeln!(
        msg,
        "{}: {} in {} (estimated seconds on one core, with the reference run each shard renders):",
        e.name,
        plural(loads.iter().map(|l| l.runs).sum::<usize>(), "run", "runs"),
        plural(n, "shard", "shards")
    );
    for (i, l) in loads.iter().enumerate() {
        let _ = writeln!(msg, "  shard {i}: {} runs, about {:.1} s, {:.1} MB", l.runs, l.seconds, l.bytes / 1e6);
    }
    let _ = writeln!(msg, "wrote {} (with shard.sh and merge.sh beside it)", path.display());
    let _ = writeln!(msg, "run it: {}", how.replace("{script}", &path.display().to_string()));
    let _ = write!(msg, "merged results: {}/runs.csv and the plots beside it", dir.display());
    msg
}

/// Writes the plan's script into its folder; returns what to tell the user.
pub fn write(e: &Experiment, o: &PlanOptions) -> Result<String> {
    let runs = expand(e)?;
    let n = shard_count(&runs, o.shards)?;
    if o.cpus_per_task == 0 || o.cpus_per_task > 1024 {
        return Err(ExperimentError::flag("--cpus-per-task", format!("{} is not between 1 and 1024", o.cpus_per_task)));
    }
    let dir = o.out.clone().unwrap_or_else(|| e.default_folder());
    crate::image_io::create_folder(&dir)?;
    let dir = absolute(&dir)?;
    let file = absolute(&o.file)?;
    let workdir = std::env::current_dir().map_err(ExperimentError::io("cannot read the current folder"))?;
    let loads = loads(e, &runs, n);
    let s = scripts(e, o, n, &loads, &dir, &file, &workdir);
    for (name, text) in &s.files {
        write_script(&dir.join(name), text)?;
    }
    let path = dir.join(s.files[2].0);
    Ok(summary(e, n, &loads, &path, s.how, &dir))
}

/// A Slurm time limit for a shard estimated at `seconds`: four times the
/// estimate (machines differ), at least 10 minutes, as D-HH:MM:SS.
fn slurm_time(seconds: f64) -> String {
    let seconds = if seconds.is_finite() { seconds } else { 0.0 };
    let s = (4.0 * seconds).clamp(600.0, 365.0 * 86400.0).ceil() as u64;
    let m = s.div_ceil(60);
    format!("{}-{:02}:{:02}:00", m / 1440, (m / 60) % 24, m % 60)
}

fn absolute(p: &Path) -> Result<PathBuf> {
    std::path::absolute(p).map_err(ExperimentError::io(format!("cannot resolve {}", p.display())))
}

/// A path in single quotes for bash.
fn shell_quote(p: &Path) -> String {
    format!("'{}'", p.display().to_string().replace('\'', "'\\''"))
}

/// A word that needs no quoting (names, times, memory), or an error-free
/// stand-in: anything outside [A-Za-z0-9._:-] becomes '_'.
fn shell_word(s: &str) -> String {
    s.chars().map(|c| if c.is_ascii_alphanumeric() || "._:-".contains(c) { c } else { '_' }).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::modes::Mode;

    fn run(id: usize, at: Vec<usize>, trace: i64, size: i64) -> RunSpec {
        let params = vec![("trace".into(), toml::Value::Integer(trace)), ("size".into(), toml::Value::Array(vec![size.into(), size.into()]))];
        let given = Mode::Interior.typed(&params, |_| crate::modes::Source::Set).unwrap();
        RunSpec { id, mode: Mode::Interior, case: String::new(), repeat: 0, params, given, at }
    }

    #[test]
    fn chains_stay_together_and_costly_chains_spread() {
        // Axis 0: trace 0, 10; axis 1: four chains, chain 3 sixteen times
        // the pixels.
        let mut runs = Vec::new();
        for (a0, t) in [(0, 0), (1, 10)] {
            for a1 in 0..4 {
                let size = if a1 == 3 { 400 } else { 100 };
                runs.push(run(runs.len(), vec![a0, a1], t, size));
            }
        }
        let s = assign(&runs, 2);
        for a1 in 0..4 {
            assert_eq!(s[a1], s[4 + a1], "chain {a1} split");
        }
        // The dear chain alone in one shard, the three cheap ones in the other.
        assert!((0..3).all(|a1| s[a1] != s[3]), "{s:?}");
        // One shard: everything in it; more shards than chains: some empty.
        assert!(assign(&runs, 1).iter().all(|&x| x == 0));
        let s8 = assign(&runs, 8);
        assert_eq!(s8.iter().collect::<std::collections::HashSet<_>>().len(), 4);
    }

    #[test]
    fn templates_are_filled_in_one_pass() {
        assert_eq!(fill("a {{x}} b {{y}}{{x}}", &[("x", "1"), ("y", "{{x}}")]), "a 1 b {{x}}1");
        assert_eq!(fill("${a} {{unknown}} {{x", &[("x", "1")]), "${a} {{unknown}} {{x");
    }

    /// Every placeholder of every script is filled, for both engines.
    #[test]
    fn scripts_leave_no_placeholder() {
        let file = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/experiments/lab-trace.toml"));
        let e = Experiment::load(file, true).unwrap();
        let runs = expand(&e).unwrap();
        for engine in [Engine::Parallel, Engine::Slurm] {
            let o = PlanOptions {
                file: file.into(),
                engine,
                shards: None,
                out: None,
                quick: true,
                partition: Some("p".into()),
                time: None,
                cpus_per_task: 2,
                mem: None,
                refract: "/bin/refract".into(),
            };
            let s = scripts(&e, &o, 2, &loads(&e, &runs, 2), Path::new("/out"), file, Path::new("/w"));
            for (name, text) in &s.files {
                assert!(text.starts_with("#!/usr/bin/env bash\n") && text.ends_with('\n'), "{name}");
                assert!(!text.contains("{{") && !text.contains("}}"), "{name}: {text}");
                assert!(text.contains("N=2\n") && text.contains("cd '/w'\n"), "{name}");
            }
            assert!(s.files[0].1.contains(" --quick --shard"));
        }
    }

    #[test]
    fn slurm_times_read_as_slurm_writes_them() {
        assert_eq!(slurm_time(1.0), "0-00:10:00");
        assert_eq!(slurm_time(900.0), "0-01:00:00");
        assert_eq!(slurm_time(86400.0), "4-00:00:00");
        assert_eq!(shell_word("a b;c"), "a_b_c");
        assert_eq!(shell_quote(Path::new("/x/it's")), "'/x/it'\\''s'");
    }
}
