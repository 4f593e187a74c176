//! `refract sweep`: runs an experiment file's grid of runs, one CSV row per
//! run, flushed as each finishes; `--resume` runs only what is missing,
//! `--shard I/N` the I-th of N cost-balanced shards (`plan::assign`),
//! `refract sweep merge` joins shards.
//! A run that fails is a row with its error, never a crashed sweep.

use super::error::{chain, ExperimentError, Result};
pub use super::grid::{expand, RunSpec};
use super::interrupt;
use super::lock::{FolderLock, Taken};
use super::metrics::{self, Frame};
use super::params::{cell, Mode};
pub use super::row::NO_REFERENCE;
use super::row::{Compared, RunRow, Status};
use super::spec::Experiment;
use crate::image_io::{atomic_write, write_rgb8};
use crate::modes::{Given, MeshCache, Source};
use std::collections::{HashMap, HashSet};
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};

/// What a sweep does with a record already in its folder.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum OnRecord {
    /// Refuse a record of another experiment (or file version, or quick
    /// against full), naming `--fresh`.
    #[default]
    Refuse,
    /// Keep this experiment's rows and run only the missing ones.
    Resume,
    /// Move any record aside (`runs.csv.N`) and start again.
    Fresh,
    /// Resume this experiment's rows; move another's aside (`figures`).
    ResumeOrFresh,
}

#[derive(Clone, Debug, Default)]
pub struct SweepOptions {
    pub on_record: OnRecord,
    pub jobs: usize,
    pub out: Option<PathBuf>,
    /// (I, N): run only the runs `plan::assign` gives shard I of N.
    pub shard: Option<(usize, usize)>,
    /// Stop after this many runs (to test interruption).
    pub max_runs: Option<usize>,
    /// Remove the folder's lock whoever holds it (`--break-lock`).
    pub break_lock: bool,
    /// The command that goes on from where this sweep stops (named when it
    /// is interrupted); `refract sweep FILE --resume` if empty.
    pub again: String,
}

/// How a sweep ended.
#[derive(Debug)]
pub struct Outcome {
    pub dir: PathBuf,
    /// "NAME: 20 of 20 runs in DIR/runs.csv (0 failed)".
    pub summary: String,
    /// Why the sweep must end with a non-zero status, if it must: its
    /// first failed run's error, and a failed reference run's.
    pub failure: Option<String>,
}

struct RunOutcome {
    frame: Option<Frame>,
    row: RunRow,
}

/// Renders one run; with `min_time` above 0, renders it again inside the
/// same timing until the renders together take that long, and records the
/// mean time per render (and how many renders were timed), in wall time
/// and in the process's CPU time (every thread; what a shared machine's
/// other load does not add to).
fn run_one(mode: Mode, params: &[Given], meshes: &MeshCache, min_time: f64) -> RunOutcome {
    let result = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| -> Result<RunOutcome, crate::modes::ModeError> {
        let cpu = crate::timing::process_cpu_seconds();
        let mut run = mode.render(params, &crate::progress::Silent, meshes)?;
        let (mut build, mut trace, mut render, mut n) = (run.record.build_s, run.record.trace_s, run.record.render_s, 1u32);
        // Until the render, the light pass (if the run has one) and the
        // CPU time (what a chart plots) each took min_time in all; at
        // most 20 times min_time of wall time, whatever a run's fixed
        // costs outside those.
        let cpu_so_far = || cpu.zip(crate::timing::process_cpu_seconds()).map_or(f64::INFINITY, |(a, b)| b - a);
        let has_trace = trace.is_some_and(|t| t > 0.0);
        let started = std::time::Instant::now();
        let short = |render: f64, trace: Option<f64>| render < min_time || (has_trace && trace.is_some_and(|t| t < min_time)) || cpu_so_far() < min_time;
        while min_time > 0.0 && short(render, trace) && started.elapsed().as_secs_f64() < 20.0 * min_time && n < 100_000 {
            run = mode.render(params, &crate::progress::Silent, meshes)?;
            build += run.record.build_s;
            trace = trace.map(|t| t + run.record.trace_s.unwrap_or(0.0));
            render += run.record.render_s;
            n += 1;
        }
        let per = n as f64;
        let cpu = cpu.zip(crate::timing::process_cpu_seconds()).map(|(a, b)| (b - a) / per);
        (run.record.build_s, run.record.trace_s, run.record.render_s) = (build / per, trace.map(|t| t / per), render / per);
        Ok(RunOutcome { frame: Some(run.frame()), row: RunRow::measured(&run.record, n, cpu) })
    }));
    match result {
        Ok(Ok(o)) => o,
        Ok(Err(e)) => RunOutcome { frame: None, row: RunRow::failed(chain(&e)) },
        Err(p) => {
            let msg = p.downcast_ref::<String>().cloned().or_else(|| p.downcast_ref::<&str>().map(|s| s.to_string())).unwrap_or_else(|| "panic".into());
            RunOutcome { frame: None, row: RunRow::failed(format!("internal error: {msg}")) }
        }
    }
}

/// An image's file name by its place on the sweep's axes, e.g.
/// `ior-1.4.png` or `hero_spp-4.png` (the case first where there are
/// cases): a reader knows what it shows without runs.csv.
pub fn image_name(e: &Experiment, r: &RunSpec) -> String {
    let clean = |t: &str| -> String {
        let t: String = t
            .chars()
            .map(|c| {
                if c.is_ascii_alphanumeric() || c == '.' || c == '-' {
                    c
                } else if c == ' ' {
                    'x'
                } else {
                    '-'
                }
            })
            .collect();
        t.trim_matches('-').to_string()
    };
    let mut parts: Vec<String> = Vec::new();
    if !r.case.is_empty() {
        parts.push(clean(&r.case));
    }
    let case_params = e.cases.iter().find(|c| c.name == r.case).map_or(&[][..], |c| &c.params[..]);
    for ((k, vals), &i) in e.axes_for(case_params).zip(&r.at) {
        if vals.len() > 1 || e.sweep.len() == 1 {
            parts.push(format!("{}-{}", clean(k), clean(&cell(&vals[i]))));
        }
    }
    if parts.is_empty() {
        parts.push(format!("run-{}", r.id));
    }
    format!("{}.png", parts.join("_"))
}

/// Complete rows of an existing runs.csv (a torn last line is dropped).
fn read_rows(path: &Path, header: &[String]) -> Result<Vec<Vec<String>>> {
    let text = match std::fs::read_to_string(path) {
        Ok(t) => t,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(Vec::new()),
        Err(e) => return Err(ExperimentError::io(format!("cannot read {}", path.display()))(e)),
    };
    let complete = match text.rfind('\n') {
        Some(i) => &text[..=i],
        None => "",
    };
    let mut r = csv::ReaderBuilder::new().flexible(true).from_reader(complete.as_bytes());
    let h: Vec<String> = r.headers()?.iter().map(str::to_string).collect();
    if !h.is_empty() && h != header {
        return Err(ExperimentError::Record { path: path.into(), why: "its columns differ from this experiment's; use another --out or delete it".into() });
    }
    Ok(r.records().filter_map(|x| x.ok()).map(|x| x.iter().map(str::to_string).collect::<Vec<_>>()).filter(|x: &Vec<String>| x.len() == header.len()).collect())
}

fn write_rows(path: &Path, header: &[String], rows: &[Vec<String>]) -> Result<()> {
    Ok(atomic_write(path, |f| {
        let mut w = csv::Writer::from_writer(f);
        w.write_record(header)?;
        for r in rows {
            w.write_record(r)?;
        }
        w.flush()
    })?)
}

/// A sweep under way: what every run shares.
struct Sweep<'a> {
    e: &'a Experiment,
    dir: PathBuf,
    header: Vec<String>,
    names: Vec<String>,
    all: Vec<RunSpec>,
    /// Run ids by (case, repeat, place on the axes), for predecessors.
    by_place: HashMap<(String, u32, Vec<usize>), usize>,
    meshes: MeshCache,
    reference: Option<Frame>,
    /// The reference run's error, if it failed.
    reference_error: Option<String>,
    /// Frames of finished runs, for the next run's `changed_px`.
    frames: Mutex<HashMap<usize, Frame>>,
    /// runs.csv, open for appending one row per run.
    file: Arc<Mutex<std::fs::File>>,
    errors: Mutex<Vec<ExperimentError>>,
}

/// Takes `dir`'s lock (`lock::FolderLock`) for this command, saying so
/// when it took over a lock whose owner was gone or broke one.
fn take_lock(dir: &Path, break_lock: bool) -> Result<FolderLock> {
    let command = std::env::args().collect::<Vec<_>>().join(" ");
    let (lock, taken) = FolderLock::take(dir, &command, break_lock)?;
    match taken {
        Taken::Fresh => {}
        Taken::Stale(who) => eprintln!("note: {}: took over the lock of {who}, which is gone", lock.path().display()),
        Taken::Broken(who) => eprintln!("note: {}: broke the lock of {who} (--break-lock)", lock.path().display()),
    }
    Ok(lock)
}

/// Runs the experiment; returns the output folder and a summary line.
pub fn run(e: &Experiment, opts: &SweepOptions) -> Result<Outcome> {
    let dir = opts.out.clone().unwrap_or_else(|| e.default_folder());
    if dir.exists() && !dir.is_dir() {
        return Err(ExperimentError::flag("--out", format!("{} is not a folder; a sweep writes a folder of results", dir.display())));
    }
    crate::image_io::create_folder(&dir)?;
    let lock = Arc::new(take_lock(&dir, opts.break_lock)?);
    // What a sweep killed while writing left behind.
    crate::image_io::remove_stale_temps(&dir);
    crate::image_io::remove_stale_temps(&dir.join("images"));
    let header = e.columns();
    let csv_path = dir.join("runs.csv");
    let all = expand(e)?;
    let existing = keep_or_move(e, &dir, &header, opts.on_record)?;
    // Start the file afresh with the kept rows only.
    write_rows(&csv_path, &header, &existing)?;
    let done: HashSet<usize> = existing.iter().filter_map(|r| r[0].parse().ok()).collect();
    let shard_of = opts.shard.map(|(_, n)| super::plan::assign(&all, n));
    let ours = |r: &&RunSpec| match (opts.shard, &shard_of) {
        (Some((i, _)), Some(s)) => s[r.id] == i,
        _ => true,
    };
    let wanted = all.iter().filter(ours).count();
    let mine: Vec<usize> = all.iter().filter(ours).filter(|r| !done.contains(&r.id)).take(opts.max_runs.unwrap_or(usize::MAX)).map(|r| r.id).collect();
    let file = Arc::new(Mutex::new(std::fs::OpenOptions::new().append(true).open(&csv_path)?));
    let again = if opts.again.is_empty() { format!("refract sweep {} --resume --out {}", e.name, dir.display()) } else { opts.again.clone() };
    let _interrupt = interrupt::Guard::new(on_interrupt(&dir, Arc::clone(&lock), Arc::clone(&file), wanted, again));
    let meshes = MeshCache::default();
    // The reference is rendered only when a run needs it (a complete
    // record is kept without it; its charts read reference.csv).
    let shard_ids = opts.shard.map(|(_, n)| super::plan::assign(&all, n));
    let pending = all.iter().any(|r| !done.contains(&r.id) && opts.shard.is_none_or(|(i, _)| shard_ids.as_ref().is_some_and(|s| s[r.id] == i)));
    let reference_runs = pending || !dir.join("reference.csv").is_file();
    let reference_params = e.reference_given().transpose()?.filter(|_| reference_runs);
    warn_once(reference_params.iter().map(|p| (e.mode, &p[..])).chain(all.iter().filter(|r| mine.contains(&r.id)).map(|r| (r.mode, &r.given[..]))));
    let (reference, reference_error) = if reference_runs { reference_frame(e, &dir, &meshes)? } else { (None, None) };
    if let Some(err) = &reference_error {
        eprintln!("refract: the reference run failed: {err}; the runs go on, with rmse, psnr and rel_rmse marked `{NO_REFERENCE}`");
    }
    if e.images {
        crate::image_io::create_folder(&dir.join("images"))?;
    }
    let by_place = all.iter().map(|r| ((r.case.clone(), r.repeat, r.at.clone()), r.id)).collect();
    let sweep = Sweep {
        e,
        names: e.param_names(),
        by_place,
        all,
        meshes,
        reference,
        reference_error,
        frames: Mutex::new(HashMap::new()),
        file,
        errors: Mutex::new(Vec::new()),
        header,
        dir,
    };
    let mine: Vec<&RunSpec> = mine.iter().map(|&id| &sweep.all[id]).collect();
    sweep.run_all(&mine, opts.jobs)?;
    sweep.finish(&csv_path, opts.shard, wanted)
}

/// Tells the user, before the first run, what a run's mode would warn of
/// (`Mode::warnings`: an `obj` mesh the face hierarchy cannot narrow):
/// once for the sweep, not once a run, asking the first run of each mesh.
fn warn_once<'a>(runs: impl Iterator<Item = (Mode, &'a [Given])>) {
    let mut asked: Vec<&crate::params::Value> = Vec::new();
    for (mode, params) in runs {
        let Some(mesh) = params.iter().find(|g| g.key == "obj").map(|g| &g.value) else { continue };
        if asked.contains(&mesh) {
            continue;
        }
        asked.push(mesh);
        for w in mode.warnings(params) {
            eprintln!("warning: {w}");
        }
    }
}

/// What SIGINT or SIGTERM does during a sweep: waits for a row being
/// written (then holds runs.csv so no other is begun), discards the run
/// under way (its temporary files), releases the lock, says how many runs
/// are saved and the command that goes on, and exits.
fn on_interrupt(dir: &Path, lock: Arc<FolderLock>, file: Arc<Mutex<std::fs::File>>, wanted: usize, again: String) -> impl Fn(i32) + Send + 'static {
    let dir = dir.to_path_buf();
    move |sig| {
        let held = file.lock().unwrap_or_else(|e| e.into_inner());
        let csv = dir.join("runs.csv");
        let saved = std::fs::read_to_string(&csv).map_or(0, |t| t.matches('\n').count().saturating_sub(1));
        crate::image_io::remove_own_temps(&dir);
        crate::image_io::remove_own_temps(&dir.join("images"));
        lock.release();
        use std::io::IsTerminal;
        let fresh_line = if std::io::stderr().is_terminal() { "\n" } else { "" };
        eprintln!(
            "{fresh_line}refract: stopped by {}: {saved} of {wanted} runs saved in {} (the run under way was discarded); to finish, run: {again}",
            interrupt::name(sig),
            csv.display()
        );
        drop(held);
        std::process::exit(interrupt::status_of(sig));
    }
}

/// What a sweep keeps of the record already in `dir`, as `how` says: the
/// rows to go on from (only this experiment's, each run once), after
/// moving any other record aside. A record of another experiment, of
/// another version of its file, or of its quick version against the full
/// one (or the other way) is refused unless `how` moves it aside.
fn keep_or_move(e: &Experiment, dir: &Path, header: &[String], how: OnRecord) -> Result<Vec<Vec<String>>> {
    use super::record::{describe, inspect, move_aside, Found};
    let found = inspect(dir, header)?;
    let csv = dir.join("runs.csv");
    let fresh_hint = |what: &str| ExperimentError::Record {
        path: csv.clone(),
        why: format!("holds {what}; write elsewhere with --out, or run again with --fresh to move that record aside (to runs.csv.N, images.N) and start anew"),
    };
    let move_it = |note: &str| -> Result<Vec<Vec<String>>> {
        let to = move_aside(dir)?;
        eprintln!("note: {note}; moved it aside to {}", to.display());
        Ok(Vec::new())
    };
    match found {
        Found::Nothing => Ok(Vec::new()),
        Found::OtherColumns(n) => match how {
            OnRecord::Fresh | OnRecord::ResumeOrFresh => move_it(&format!("{} holds {n} rows with other columns", csv.display())),
            _ => Err(fresh_hint(&format!("{n} rows with other columns than this experiment's (another experiment, or another version of refract)"))),
        },
        Found::Rows { rows, fingerprints, torn } => {
            let ours = fingerprints.len() == 1 && fingerprints.contains_key(&e.fingerprint);
            match how {
                OnRecord::Fresh => move_it(&format!("{} held {}", csv.display(), describe(&fingerprints))),
                _ if !ours && how == OnRecord::ResumeOrFresh => {
                    move_it(&format!("{} held {}, not of {}", csv.display(), describe(&fingerprints), e.fingerprint))
                }
                _ if !ours => {
                    let version = if e.quick { "this experiment file's --quick version" } else { "this experiment file (full quality, not --quick)" };
                    Err(fresh_hint(&format!("{}, not of {} ({version})", describe(&fingerprints), e.fingerprint)))
                }
                OnRecord::Resume | OnRecord::ResumeOrFresh => {
                    let (kept, notes) = super::record::check_rows(&csv, rows, expand(e)?.len())?;
                    for n in notes {
                        eprintln!("note: {n}");
                    }
                    if let Some(line) = torn {
                        eprintln!("note: {}:{line}: the last line was cut off mid-write (no newline); that run runs again", csv.display());
                    }
                    Ok(kept)
                }
                OnRecord::Refuse => {
                    let total = expand(e)?.len();
                    let have = rows.iter().filter_map(|(_, r)| r[0].parse::<usize>().ok()).filter(|&id| id < total).collect::<HashSet<_>>().len();
                    Err(ExperimentError::Record {
                        path: csv.clone(),
                        why: format!("already holds {have} of the {total} runs of this experiment; run again with --resume to run only the missing ones, or with --fresh to move the record aside (to runs.csv.N) and run them all"),
                    })
                }
            }
        }
    }
}

/// The reference run's frame (the fixed parameters with the reference's
/// overrides), written as reference.png, or the reference run's error; and
/// its own noise measured and written to reference.csv: the reference
/// rendered again with another seed, the error between the two over the
/// square root of two (0 for a reference that draws nothing at random).
fn reference_frame(e: &Experiment, dir: &Path, meshes: &MeshCache) -> Result<(Option<Frame>, Option<String>)> {
    let Some(p) = e.reference_given().transpose()? else { return Ok((None, None)) };
    let t = std::time::Instant::now();
    let o = run_one(e.mode, &p, meshes, 0.0);
    let seconds = t.elapsed().as_secs_f64();
    let Some(f) = o.frame else {
        let err = if o.row.status == Status::Error { o.row.error } else { "no image".to_string() };
        return Ok((None, Some(err)));
    };
    write_rgb8(&dir.join("reference.png"), f.width, f.height, &f.display)?;
    let noise = if e.mode.ignored(&p, "seed").is_some() {
        0.0
    } else {
        let seed = p.iter().rev().find(|g| g.key == "seed").map_or(1, |g| g.value.count());
        let mut other = p.clone();
        let twin = crate::params::Value::Count(seed.wrapping_add(7919));
        crate::params::given::put(&mut other, Given { key: "seed", value: twin, from: Source::Chosen("the reference's twin, another seed") });
        let twin = run_one(e.mode, &other, meshes, 0.0).frame;
        twin.and_then(|g| metrics::relative_error(&g, &f).or_else(|| metrics::relative_rmse(&g, &f))).map_or(f64::NAN, |d| d / 2f64.sqrt())
    };
    let text = format!("what,value\nseconds,{}\nnoise,{}\n", crate::timing::cell(seconds), crate::timing::cell(noise));
    crate::image_io::write_text(&dir.join("reference.csv"), &text)?;
    Ok((Some(f), None))
}

impl Sweep<'_> {
    /// The runs, in waves along the first sweep axis, so each run's
    /// predecessor (for changed_px) is done before it; runs within a wave
    /// go in parallel with `jobs` above 1.
    fn run_all(&self, mine: &[&RunSpec], jobs: usize) -> Result<()> {
        let bar = crate::terminal::counter(mine.len() as u64, &self.e.name, "runs");
        let pool = rayon::ThreadPoolBuilder::new().num_threads(jobs.max(1)).build()?;
        let mut waves: std::collections::BTreeMap<usize, Vec<&RunSpec>> = std::collections::BTreeMap::new();
        for r in mine {
            waves.entry(r.at.first().copied().unwrap_or(0)).or_default().push(r);
        }
        let one = |r: &&RunSpec| {
            self.run_row(r);
            bar.inc(1);
        };
        for wave in waves.values() {
            use rayon::prelude::*;
            // Only this wave's predecessors are needed from here on: a
            // sweep holds at most two waves of frames, not every run's.
            let keep: HashSet<usize> = wave.iter().filter_map(|r| self.predecessor(r)).collect();
            self.frames.lock().unwrap().retain(|id, _| keep.contains(id));
            if jobs <= 1 {
                // One at a time, in order. (Not through a 1-thread pool: a
                // worker waiting on a render's own pool steals the next run,
                // so runs would overlap and their timings would be wrong.)
                wave.iter().for_each(one);
            } else {
                pool.install(|| wave.par_iter().with_max_len(1).for_each(one));
            }
        }
        bar.finish_and_clear();
        match self.errors.lock().unwrap().drain(..).next() {
            Some(err) => Err(ExperimentError::Writing { dir: self.dir.clone(), error: Box::new(err) }),
            None => Ok(()),
        }
    }

    /// The run one step earlier along the first sweep axis, for changed_px.
    fn predecessor(&self, r: &RunSpec) -> Option<usize> {
        if r.at.first().copied().unwrap_or(0) == 0 {
            return None;
        }
        let mut at = r.at.clone();
        at[0] -= 1;
        self.by_place.get(&(r.case.clone(), r.repeat, at)).copied()
    }

    /// The image metrics of a run's frame (against the reference and its
    /// predecessor), and its image if the experiment keeps them.
    fn measure(&self, r: &RunSpec, f: &Frame, row: &mut RunRow) {
        row.nan_count = Some(metrics::non_finite(f));
        row.fireflies = Some(metrics::fireflies(f));
        row.highlight_px = Some(metrics::highlight_pixels(f));
        if self.reference_error.is_some() {
            (row.rmse, row.psnr, row.rel_rmse) = (Compared::NoReference, Compared::NoReference, Compared::NoReference);
        }
        if let Some(rf) = &self.reference {
            if let Some((rmse, psnr)) = metrics::rmse_psnr(f, rf) {
                (row.rmse, row.psnr) = (Compared::Value(rmse), Compared::Value(psnr));
            }
            if let Some(rel) = metrics::relative_rmse(f, rf) {
                row.rel_rmse = Compared::Value(rel);
            }
            row.rel_error = metrics::relative_error(f, rf).map(crate::timing::Real);
        }
        let prev = self
            .predecessor(r)
            .and_then(|p| self.frames.lock().unwrap().get(&p).cloned().or_else(|| load_frame(&self.dir.join("images").join(image_name(self.e, &self.all[p])))));
        row.changed_px = prev.and_then(|p| metrics::changed_pixels(f, &p));
        // One image a place: the repeats of a run draw the same picture.
        if self.e.images && r.repeat == 0 {
            if let Err(err) = write_rgb8(&self.dir.join("images").join(image_name(self.e, r)), f.width, f.height, &f.display) {
                self.errors.lock().unwrap().push(err.into());
            }
        }
        self.frames.lock().unwrap().insert(r.id, f.clone());
    }

    /// Runs one run and appends its row to runs.csv.
    fn run_row(&self, r: &RunSpec) {
        let RunOutcome { frame, mut row } = run_one(r.mode, &r.given, &self.meshes, self.e.min_time);
        row.experiment = self.e.fingerprint.clone();
        [row.host, row.cpu, row.cores, row.load_1min] = machine();
        if let Some(f) = &frame {
            self.measure(r, f, &mut row);
        }
        let identity = [r.id.to_string(), r.mode.name().to_string(), r.case.clone(), r.repeat.to_string()];
        let params: Vec<String> = self.names.iter().map(|n| r.params.iter().find(|(k, _)| k == n).map_or(String::new(), |(_, v)| cell(v))).collect();
        let mut w = csv::WriterBuilder::new().has_headers(false).from_writer(Vec::new());
        let line =
            w.serialize((identity, params, row)).map_err(ExperimentError::from).and_then(|_| w.into_inner().map_err(|e| ExperimentError::Disk(e.into_error())));
        let written = line.and_then(|bytes| {
            let mut f = self.file.lock().unwrap();
            f.write_all(&bytes).and_then(|_| f.flush()).map_err(ExperimentError::from)
        });
        if let Err(err) = written {
            self.errors.lock().unwrap().push(err);
        }
    }

    /// Sorts the rows by run id, draws the plots, and sums up.
    /// `wanted`: how many runs this sweep (or shard) holds when complete.
    fn finish(&self, csv_path: &Path, shard: Option<(usize, usize)>, wanted: usize) -> Result<Outcome> {
        let mut rows = read_rows(csv_path, &self.header)?;
        rows.sort_by_key(|r| r[0].parse::<usize>().unwrap_or(usize::MAX));
        rows.dedup_by(|a, b| a[0] == b[0]);
        write_rows(csv_path, &self.header, &rows)?;
        let complete = rows.len() >= wanted;
        if complete || shard.is_some() {
            let why = if self.reference_error.is_some() { " (the reference run failed)" } else { "" };
            for (file, column) in super::charts::draw_all(self.e, &self.dir, &self.header, &rows)? {
                eprintln!("note: plot {file} not drawn: no run has a value of {column}{why}");
            }
        }
        let col = |name: &str| self.header.iter().position(|h| h == name).unwrap_or(0);
        // A case may declare that its runs fail (`expect = "error"`): such
        // a failure is what the experiment records, not the sweep's.
        let meant_to_fail = |r: &Vec<String>| self.e.cases.iter().any(|c| c.name == r[col("case")] && c.expect == super::spec::Expect::Error);
        let (expected, failed): (Vec<&Vec<String>>, Vec<&Vec<String>>) = rows.iter().filter(|r| r[col("failed")] == "1").partition(|r| meant_to_fail(r));
        let rendered_anyway: Vec<&Vec<String>> = rows.iter().filter(|r| r[col("failed")] != "1" && meant_to_fail(r)).collect();
        let (what, again) = match shard {
            Some((i, n)) => (format!(" of shard {i}/{n}"), "; run this shard again with --resume to finish it"),
            None => (String::new(), "; run again with --resume to finish"),
        };
        let mut failures = format!("{} failed", failed.len());
        if !expected.is_empty() {
            failures.push_str(&format!(", and {} as its case declares (expect = \"error\")", expected.len()));
        }
        if !rendered_anyway.is_empty() {
            failures.push_str(&format!("; {} meant to fail rendered", rendered_anyway.len()));
        }
        let summary =
            format!("{}: {} of {} runs{what} in {} ({failures}){}", self.e.name, rows.len(), wanted, csv_path.display(), if complete { "" } else { again });
        let mut why = Vec::new();
        if let Some(r) = failed.first() {
            let case = if r[col("case")].is_empty() { String::new() } else { format!(" ({})", r[col("case")]) };
            why.push(format!("the first failed run, {}{case}: {}", r[0], r[col("error")]));
        }
        if let Some(r) = rendered_anyway.first() {
            why.push(format!("run {} ({}) rendered, but its case declares expect = \"error\": the condition it records no longer fails", r[0], r[col("case")]));
        }
        if let Some(err) = &self.reference_error {
            why.push(format!("the reference run failed: {err} (rmse, psnr and rel_rmse are marked `{NO_REFERENCE}`)"));
        }
        Ok(Outcome { dir: self.dir.clone(), summary, failure: (!why.is_empty()).then(|| why.join("; ")) })
    }
}

/// Where a run ran, for comparing timings from several machines: host
/// name, CPU model, logical cores, and the 1-minute load average when the
/// run started (Linux's /proc; empty cells elsewhere).
fn machine() -> [String; 4] {
    let read = |p: &str| std::fs::read_to_string(p).unwrap_or_default();
    let host = read("/proc/sys/kernel/hostname").trim().to_string();
    let cpu =
        read("/proc/cpuinfo").lines().find(|l| l.starts_with("model name")).and_then(|l| l.split(':').nth(1)).map(|m| m.trim().to_string()).unwrap_or_default();
    let cores = std::thread::available_parallelism().map_or(String::new(), |n| n.get().to_string());
    let load = read("/proc/loadavg").split_whitespace().next().unwrap_or_default().to_string();
    [host, cpu, cores, load]
}

fn load_frame(path: &Path) -> Option<Frame> {
    let img = image::open(path).ok()?.to_rgb8();
    let (w, h) = img.dimensions();
    let display = img.into_raw();
    let luma = crate::spectrum::cie::SRGB_LUMA;
    let luminance = display.chunks(3).map(|c| luma.x * c[0] as f64 / 255.0 + luma.y * c[1] as f64 / 255.0 + luma.z * c[2] as f64 / 255.0).collect();
    Some(Frame { width: w as usize, height: h as usize, display, luminance, xyz: Vec::new() })
}

/// Joins the runs.csv of several shard folders into `out`/runs.csv, with
/// their run images and reference image. It refuses rows of another
/// experiment (or another version of its file, by the `experiment`
/// fingerprint; with `experiment` given, it must be that file's), a run
/// that two shards both hold, and, with `experiment` given, runs that no
/// shard holds (naming them, and how to run them) unless `resume`, which
/// runs them here.
pub fn merge(dirs: &[PathBuf], out: &Path, experiment: Option<&Experiment>, o: &MergeOptions) -> Result<String> {
    let mut header: Option<Vec<String>> = None;
    // Each row with its shard and its line there.
    let mut rows: Vec<(Vec<String>, usize)> = Vec::new();
    let mut lines: Vec<u64> = Vec::new();
    for (k, d) in dirs.iter().enumerate() {
        if dirs[..k].contains(d) {
            return Err(ExperimentError::GivenTwice(d.clone()));
        }
        for (row, line) in read_shard(d, &dirs[0], &mut header)? {
            rows.push((row, k));
            lines.push(line);
        }
    }
    let header = header.ok_or(ExperimentError::NoFolders)?;
    check_one_experiment(&header, &rows, dirs, experiment)?;
    let rows = in_run_order(rows, &lines, dirs)?;
    let missing = missing_runs(&rows, experiment, o.resume)?;
    crate::image_io::create_folder(out)?;
    {
        let _lock = take_lock(out, o.break_lock)?;
        let rows: Vec<Vec<String>> = rows.iter().map(|(r, _)| r.clone()).collect();
        write_merged(dirs, out, &header, &rows, o.fresh)?;
        if let (Some(e), true) = (experiment, missing.is_empty()) {
            for (file, column) in super::charts::draw_all(e, out, &header, &rows)? {
                eprintln!("note: plot {file} not drawn: no run has a value of {column}");
            }
        }
    }
    let merged = format!("merged {} rows from {} folders into {}", rows.len(), dirs.len(), out.join("runs.csv").display());
    match experiment {
        Some(e) if !missing.is_empty() => {
            let o = run(e, &SweepOptions { on_record: OnRecord::Resume, jobs: 1, out: Some(out.to_path_buf()), ..Default::default() })?;
            let line = format!("{merged}; ran the {} missing here: {}", missing.len(), o.summary);
            match o.failure {
                Some(why) => Err(ExperimentError::Failed { done: line, why }),
                None => Ok(line),
            }
        }
        _ => Ok(merged),
    }
}

/// A shard folder's rows, each with its line, once checked: not being
/// written, not cut off, a sweep's runs.csv with the columns of the first
/// shard's (`header`, set by the first), every row a whole run.
fn read_shard(d: &Path, first: &Path, header: &mut Option<Vec<String>>) -> Result<Vec<(Vec<String>, u64)>> {
    let mut rows = Vec::new();
    // A shard still being written is not merged.
    if let Some(holder) = FolderLock::holder(d) {
        let why = format!(
            "this shard is still being written (its lock is held by {holder}); merge when it has finished, or if that sweep is gone, delete {}",
            d.join(".lock").display()
        );
        return Err(ExperimentError::Record { path: d.to_path_buf(), why });
    }
    let p = d.join("runs.csv");
    let text = crate::data::read_input_text(&p).map_err(ExperimentError::io(format!("cannot read {}", p.display())))?;
    // A last line without its newline was cut off mid-write: its last
    // cell may be a shorter, wrong number (0.757080 read as 0.757).
    if !text.is_empty() && !text.ends_with('\n') {
        let why = format!(
            "the last line does not end in a newline (the shard was cut off while writing it); finish the shard with `refract sweep FILE --resume --shard I/N --out {}` first",
            d.display()
        );
        return Err(ExperimentError::RecordLine { path: p, line: text.matches('\n').count() as u64 + 1, why });
    }
    let mut r = csv::Reader::from_reader(text.as_bytes());
    let h: Vec<String> = r.headers().map_err(|csv| ExperimentError::Header { path: p.clone(), csv })?.iter().map(str::to_string).collect();
    if h.first().map(String::as_str) != Some("run_id") {
        let why = format!("not a sweep's runs.csv (its first column is `{}`, not run_id)", h.first().map_or("", String::as_str));
        return Err(ExperimentError::RecordLine { path: p, line: 1, why });
    }
    match header {
        Some(x) if *x != h => return Err(ExperimentError::Record { path: p, why: format!("its columns differ from {}", first.join("runs.csv").display()) }),
        _ => *header = Some(h.clone()),
    }
    // Every row is a whole run: a short or unreadable one (a shard
    // stopped mid-write) is named, not dropped.
    for record in r.records() {
        let x = record.map_err(|e| {
            let at = e.position().map_or(0, |at| at.line());
            match e.kind() {
                csv::ErrorKind::UnequalLengths { len, .. } => {
                    ExperimentError::RecordLine { path: p.clone(), line: at, why: format!("not a whole run ({len} of {} cells)", h.len()) }
                }
                _ => ExperimentError::UnreadableRow { path: p.clone(), line: at, csv: e },
            }
        })?;
        // (The reader refuses a row of another length than the header's.)
        if x[0].parse::<usize>().is_err() {
            return Err(ExperimentError::RecordLine { path: p, line: x.position().map_or(0, |at| at.line()), why: format!("`{}` is not a run id", &x[0]) });
        }
        rows.push((x.iter().map(str::to_string).collect(), x.position().map_or(0, |at| at.line())));
    }
    Ok(rows)
}

/// Refuses rows of another experiment (or another version of its file)
/// than `experiment`'s, or than the first row's without one.
fn check_one_experiment(header: &[String], rows: &[(Vec<String>, usize)], dirs: &[PathBuf], experiment: Option<&Experiment>) -> Result<()> {
    if let Some(col) = header.iter().position(|h| h == "experiment") {
        let want = match experiment {
            Some(e) => e.fingerprint.clone(),
            None => rows.first().map(|(r, _)| r[col].clone()).unwrap_or_default(),
        };
        if let Some((r, k)) = rows.iter().find(|(r, _)| r[col] != want) {
            let why = format!(
                "run {} is from experiment {}, not {} (another experiment, or another version of its file); merge only shards of one run",
                r[0], r[col], want
            );
            return Err(ExperimentError::Record { path: dirs[*k].join("runs.csv"), why });
        }
    }
    Ok(())
}

/// The rows in run order, refusing a run twice in one shard or in two.
fn in_run_order(rows: Vec<(Vec<String>, usize)>, lines: &[u64], dirs: &[PathBuf]) -> Result<Vec<(Vec<String>, usize)>> {
    let mut order: Vec<usize> = (0..rows.len()).collect();
    order.sort_by_key(|&i| (rows[i].0[0].parse::<usize>().unwrap_or(usize::MAX), i));
    if let Some(w) = order.windows(2).find(|w| rows[w[0]].0[0] == rows[w[1]].0[0]) {
        let ((a, ka), (b, kb)) = (&rows[w[0]], &rows[w[1]]);
        if ka == kb {
            let why = format!("run {} is twice (lines {} and {}); each run is one row", a[0], lines[w[0]], lines[w[1]]);
            return Err(ExperimentError::Record { path: dirs[*ka].join("runs.csv"), why });
        }
        return Err(ExperimentError::InTwoShards { id: b[0].clone(), first: dirs[*ka].clone(), second: dirs[*kb].clone() });
    }
    Ok(order.into_iter().map(|i| rows[i].clone()).collect())
}

/// The runs of `experiment` that no shard holds (none without one);
/// refused unless `resume` runs them.
fn missing_runs(rows: &[(Vec<String>, usize)], experiment: Option<&Experiment>, resume: bool) -> Result<Vec<String>> {
    let mut missing = Vec::new();
    if let Some(e) = experiment {
        let have: HashSet<usize> = rows.iter().filter_map(|(r, _)| r[0].parse().ok()).collect();
        let total = expand(e)?.len();
        missing = (0..total).filter(|id| !have.contains(id)).map(|id| id.to_string()).collect();
        if !missing.is_empty() && !resume {
            return Err(ExperimentError::InNoShard { runs: missing.join(", "), missing: missing.len(), total });
        }
    }
    Ok(missing)
}

/// Writes the merged rows into `out` with the shards' run images and
/// reference. A record already in `out` is replaced only by one that holds
/// every row of it, unchanged; else it is moved aside (`fresh`) or refused.
fn write_merged(dirs: &[PathBuf], out: &Path, header: &[String], rows: &[Vec<String>], fresh: bool) -> Result<()> {
    if let super::record::Found::Rows { rows: old, .. } = super::record::inspect(out, header)? {
        let lost = old.iter().find(|(_, r)| !rows.iter().any(|m| m == r));
        match lost {
            None => {}
            Some(_) if fresh => {
                let to = super::record::move_aside(out)?;
                eprintln!("note: moved the record in {} aside to {}", out.display(), to.display());
            }
            Some((line, r)) => {
                let why = format!(
                    "holds run {} as the merge does not (another run, or another version of the experiment); merge into another --out, or with --fresh to move that record aside (to runs.csv.N)",
                    r[0]
                );
                return Err(ExperimentError::RecordLine { path: out.join("runs.csv"), line: *line, why });
            }
        }
    }
    // The run images (named by their parameters) and the reference
    // image and its record travel with the rows.
    for d in dirs {
        let mut names: Vec<PathBuf> = std::fs::read_dir(d.join("images")).map(|rd| rd.flatten().map(|e| e.path()).collect()).unwrap_or_default();
        names.retain(|p| p.extension().is_some_and(|x| x == "png") && !p.file_name().is_some_and(|n| n.to_string_lossy().starts_with('.')));
        names.sort();
        for from in names {
            crate::image_io::create_folder(&out.join("images"))?;
            copy_into_place(&from, &out.join("images").join(from.file_name().unwrap_or_default()))?;
        }
    }
    for name in ["reference.png", "reference.csv"] {
        if let Some(reference) = dirs.iter().map(|d| d.join(name)).find(|p| p.is_file()) {
            copy_into_place(&reference, &out.join(name))?;
        }
    }
    write_rows(&out.join("runs.csv"), header, rows)
}

/// How `merge` treats the folder it writes.
#[derive(Clone, Copy, Debug, Default)]
pub struct MergeOptions {
    /// Run here the runs no shard holds.
    pub resume: bool,
    /// Move a record in the output folder aside instead of refusing.
    pub fresh: bool,
    /// Remove the output folder's lock whoever holds it.
    pub break_lock: bool,
}

/// Copies a file to a temporary sibling of `to`, then renames it there.
fn copy_into_place(from: &Path, to: &Path) -> Result<()> {
    let bytes = std::fs::read(from).map_err(ExperimentError::io(format!("cannot read {}", from.display())))?;
    Ok(atomic_write(to, |f| f.write_all(&bytes))?)
}
