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

use super::grid::{expand, RunSpec};
use super::spec::Experiment;
pub use crate::modes::Cost;
use anyhow::{bail, Context, Result};
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
        c.2 += r.mode.cost(&r.params).seconds;
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
    let reference = e.reference_params().map(|p| e.mode.cost(&p));
    let mut out = vec![ShardLoad::default(); n];
    for (r, &s) in runs.iter().zip(&shard) {
        let c = r.mode.cost(&r.params);
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

/// Writes the plan's script into its folder; returns what to tell the user.
pub fn write(e: &Experiment, o: &PlanOptions) -> Result<String> {
    // A shard with no run would be a job doing nothing: at most as many
    // shards as the grid has chains (each chain stays in one shard).
    let runs = expand(e);
    let chains = chain_count(&runs).max(1);
    let n = match o.shards {
        None => DEFAULT_SHARDS.min(chains),
        Some(n) if n == 0 || n > MAX_SHARDS => bail!("--shards: {n} is not between 1 and {MAX_SHARDS}"),
        Some(n) if n > chains => bail!(
            "--shards: {n} is more than the {} this grid holds (the runs along its first sweep axis stay in one shard); at most {chains}",
            plural(chains, "chain of runs", "chains of runs")
        ),
        Some(n) => n,
    };
    if o.cpus_per_task == 0 || o.cpus_per_task > 1024 {
        bail!("--cpus-per-task: {} is not between 1 and 1024", o.cpus_per_task);
    }
    let dir = o.out.clone().unwrap_or_else(|| e.default_folder());
    crate::image_io::create_folder(&dir)?;
    let dir = absolute(&dir)?;
    let file = absolute(&o.file)?;
    let workdir = std::env::current_dir().context("cannot read the current folder")?;
    let loads = loads(e, &runs, n);
    let quick = if o.quick { " --quick" } else { "" };
    let busiest = loads.iter().map(|l| l.seconds).fold(0.0, f64::max);
    let head = |what: &str| {
        let mut s = String::new();
        let _ = writeln!(s, "#!/usr/bin/env bash");
        let _ = writeln!(s, "# Written by `refract sweep plan --engine {}` for {} ({n} shards): {what}", o.engine.name(), e.name);
        let _ = writeln!(s, "set -euo pipefail");
        let _ = writeln!(s, "built={}", shell_quote(&o.refract));
        let _ = writeln!(s, "REFRACT=\"${{REFRACT:-$built}}\"  # another binary: REFRACT=/path/to/refract bash ...");
        let _ = writeln!(s, "FILE={}", shell_quote(&file));
        let _ = writeln!(s, "OUT={}", shell_quote(&dir));
        let _ = writeln!(s, "N={n}");
        let _ = writeln!(s, "# Paths in the experiment file are relative to the folder the plan was made in.");
        let _ = writeln!(s, "cd {}", shell_quote(&workdir));
        s
    };
    let mut shard = head("runs shard $1 of 0..N-1 into $OUT/shards/$1 (again with --resume, it finishes a shard that stopped)");
    let _ = writeln!(shard, "i=\"${{1:?usage: shard.sh I [--resume]}}\"");
    let _ = writeln!(shard, "shift");
    let _ = writeln!(shard, "exec \"$REFRACT\" sweep \"$FILE\"{quick} --shard \"$i/$N\" --out \"$OUT/shards/$i\" \"$@\"");
    let mut merge = head("joins the shards into $OUT/runs.csv and draws the plots");
    let _ = writeln!(merge, "shards=()");
    let _ = writeln!(merge, "for i in $(seq 0 $((N - 1))); do shards+=(\"$OUT/shards/$i\"); done");
    let _ = writeln!(merge, "exec \"$REFRACT\" sweep merge \"${{shards[@]}}\" --out \"$OUT\" --experiment \"$FILE\"{quick} \"$@\"");
    let (script, how, s) = match o.engine {
        Engine::Parallel => {
            let mut s = head(&format!("the shards through GNU parallel, then the merge (busiest shard about {busiest:.1} s on one core)"));
            let _ = writeln!(s, "# Extra arguments go to GNU parallel (e.g. --sshloginfile FILE, -j 1). Over");
            let _ = writeln!(s, "# ssh, every host must see $REFRACT and $OUT at the same paths.");
            let _ = writeln!(s, "mkdir -p \"$OUT/logs\"");
            let _ = writeln!(
                s,
                "parallel --will-cite --halt now,fail=1 --joblog \"$OUT/logs/parallel.log\" \"$@\" bash \"$OUT/shard.sh\" {{}} ::: $(seq 0 $((N - 1)))"
            );
            let _ = writeln!(s, "bash \"$OUT/merge.sh\"");
            ("run-parallel.sh", "bash {script} [GNU parallel options, e.g. --sshloginfile hosts]", s)
        }
        Engine::Slurm => {
            let time = o.time.clone().unwrap_or_else(|| slurm_time(busiest));
            let mem_mb = loads.iter().map(|l| l.bytes).fold(0.0, f64::max) / (1u64 << 20) as f64;
            let mem = o.mem.clone().unwrap_or_else(|| format!("{}M", (256.0 + 1.5 * mem_mb).ceil() as u64));
            let partition = o.partition.as_ref().map_or(String::new(), |p| format!(" --partition={}", shell_word(p)));
            let mut s = head(&format!(
                "a job array of the shards ({time} and {mem} each, from the estimate: busiest shard about {busiest:.1} s on one core) and a merge job after them"
            ));
            let _ = writeln!(s, "# With --wait, returns when the merge job has ended, with its exit code.");
            let _ = writeln!(s, "wait_flag=()");
            let _ = writeln!(s, "if [ \"${{1:-}}\" = \"--wait\" ]; then wait_flag=(--wait); fi");
            let _ = writeln!(s, "mkdir -p \"$OUT/logs\"");
            let _ = writeln!(
                s,
                "array=$(sbatch --parsable --job-name={name}-shards --array=0-$((N - 1)){partition} --time={time} --cpus-per-task={cpus} --mem={mem} \\\n  --output=\"$OUT/logs/shard-%a.out\" --wrap=\"bash '$OUT/shard.sh' \\$SLURM_ARRAY_TASK_ID\")",
                name = shell_word(&e.name),
                time = shell_word(&time),
                cpus = o.cpus_per_task,
                mem = shell_word(&mem),
            );
            let _ = writeln!(s, "array=${{array%%;*}}");
            let _ = writeln!(s, "echo \"submitted the shards: job array $array ($N tasks)\"");
            let _ = writeln!(s, "echo \"merged results will be in $OUT/runs.csv (log: $OUT/logs/merge.out)\"");
            let _ = writeln!(
                s,
                "sbatch --parsable \"${{wait_flag[@]}}\" --job-name={name}-merge --dependency=afterok:$array --kill-on-invalid-dep=yes{partition} --time=0-00:30:00 --cpus-per-task=1 --mem={mem} \\\n  --output=\"$OUT/logs/merge.out\" --wrap=\"bash '$OUT/merge.sh'\"",
                name = shell_word(&e.name),
                mem = shell_word(&mem),
            );
            ("submit-slurm.sh", "bash {script} [--wait]", s)
        }
    };
    let path = dir.join(script);
    for (name, text) in [("shard.sh", &shard), ("merge.sh", &merge), (script, &s)] {
        let p = dir.join(name);
        crate::image_io::atomic_write(&p, |f| {
            use std::io::Write;
            f.write_all(text.as_bytes())?;
            Ok(())
        })?;
        #[cfg(unix)]
        {
            use std::os::unix::fs::PermissionsExt;
            std::fs::set_permissions(&p, std::fs::Permissions::from_mode(0o755))?;
        }
    }
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
    Ok(msg)
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
    std::path::absolute(p).with_context(|| format!("cannot resolve {}", p.display()))
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
        RunSpec {
            id,
            mode: Mode::Interior,
            case: String::new(),
            repeat: 0,
            params: vec![("trace".into(), toml::Value::Integer(trace)), ("size".into(), toml::Value::Array(vec![size.into(), size.into()]))],
            at,
        }
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
    fn slurm_times_read_as_slurm_writes_them() {
        assert_eq!(slurm_time(1.0), "0-00:10:00");
        assert_eq!(slurm_time(900.0), "0-01:00:00");
        assert_eq!(slurm_time(86400.0), "4-00:00:00");
        assert_eq!(shell_word("a b;c"), "a_b_c");
        assert_eq!(shell_quote(Path::new("/x/it's")), "'/x/it'\\''s'");
    }
}
