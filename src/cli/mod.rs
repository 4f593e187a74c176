//! The command line: clap derive structs whose doc comments are the help
//! text, turned into validated configurations and handed to the library.

pub mod param_args;

use crate::experiment::plan::Engine;
use crate::modes;
use crate::modes::glass::IorKind;
use anyhow::{bail, Context, Result};
use clap::{Args, Parser, Subcommand};
use param_args::Flags;
use std::ffi::OsString;
use std::path::PathBuf;

#[derive(Parser, Debug)]
#[command(
    name = "refract",
    version,
    about = "Rendering light through transparent objects: four student reports reproduced as an experiment harness.",
    arg_required_else_help = true
)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Command,
}

#[derive(Subcommand, Debug)]
pub enum Command {
    /// Every figure of the four reports as results/figures/<id>.png, the
    /// shipped sweeps' plots, and results/index.html (the gallery). A sweep
    /// whose runs.csv already holds every run is kept, not run again (its
    /// timings are a record of the machine that made them): its plots are
    /// redrawn from it. Delete results/<sweep>/ or run `refract sweep` to
    /// measure again.
    Figures {
        /// Smaller images and fewer photons (about 20 s on 2 cores; the full set takes about 5 minutes)
        #[arg(long)]
        quick: bool,
        /// Only these figure ids, comma-separated (then no sweeps run)
        #[arg(long, value_delimiter = ',')]
        only: Vec<String>,
        /// Results folder [default: results, or results/quick with --quick so the committed full-quality set stays]
        #[arg(long)]
        out: Option<PathBuf>,
        /// Only rewrite the gallery (index.html) from the files already in the results folder: nothing is rendered or run
        #[arg(long, conflicts_with = "only")]
        gallery_only: bool,
        /// Folder of the scene files and FIGURES.md
        #[arg(long = "scene-dir", alias = "scenes", value_name = "DIR", default_value = "scenes")]
        scenes: PathBuf,
    },
    /// Render a scene file (see scenes/*.toml) or a glTF 2.0 scene (.gltf,
    /// .glb; README: glTF scenes) to results/<id>.png or --out.
    Render {
        /// The scene file, or a glTF file
        file: PathBuf,
        /// Its [quick] settings
        #[arg(long)]
        quick: bool,
        #[arg(long, help = format!("{} (.pfm, .exr: prism scenes only) [default: results/<id>.png]", out_help(<modes::prism::Prism as modes::ModeKind>::FORMATS, "")))]
        out: Option<PathBuf>,
        /// Override a parameter of the scene file, e.g. --set photons=100000 --set size=320,120 (repeatable)
        #[arg(long, value_name = "KEY=VALUE")]
        set: Vec<String>,
    },
    /// Report 004: a point light inside a translucent OFF or OBJ mesh. With none of
    /// the report's flags (--trace ... --ior) it asks the report's 13
    /// questions on standard input.
    Interior(InteriorArgs),
    /// Write the meshes shipped in off/ (cube, colour cube, dodecahedron,
    /// icosphere, torus) into DIR.
    Meshes {
        /// Folder to write into.
        #[arg(default_value = "off")]
        dir: PathBuf,
    },
    /// The spectral photon mapper: report 000's Amici prism (amici-screen,
    /// amici-lamp), report 001's glass spheres and report 003's Cornell
    /// boxes and album cover (--scene). `refract prism trace` probes the
    /// optics ray by ray.
    Prism(PrismArgs),
    /// Run an experiment file (experiments/*.toml): a grid of runs, one CSV
    /// row each, and its plots; `refract sweep merge` joins shards.
    Sweep(SweepArgs),
    /// Spectra and colour: the CIE locus, illuminants, the accuracy report.
    Spectrum {
        #[command(subcommand)]
        which: SpectrumCommand,
    },
    /// Index of refraction of a catalogue glass by a chosen model, as CSV.
    Glass(GlassArgs),
    /// Write a built-in scene as a glTF 2.0 file (.glb or .gltf) with its
    /// glasses' dispersion (KHR_materials_dispersion), lights and camera;
    /// `refract render FILE` renders it back.
    Export {
        /// The scene: a built-in one (see `refract prism --help`, --scene) or one of the glTF examples (prism-table, sphere-box)
        scene: String,
        /// The file to write: .glb (binary) or .gltf (JSON, buffer inline)
        #[arg(long)]
        out: PathBuf,
        /// A parameter of the scene, e.g. --set glass=N-SF11 --set size=320,240 (repeatable)
        #[arg(long, value_name = "KEY=VALUE")]
        set: Vec<String>,
    },
    /// Benchmarks, measured in one run and printed as a table.
    Bench {
        #[command(subcommand)]
        which: BenchCommand,
    },
}

#[derive(Subcommand, Debug)]
pub enum BenchCommand {
    /// Rays per second per thread, BVH against the report's linear scan,
    /// on icospheres of 1280, 20480 and 81920 triangles at 640x480.
    Interior {
        /// Smaller images and fewer repeats (a smoke run, not a measurement).
        #[arg(long)]
        quick: bool,
    },
    /// Photons per second per thread, bytes per photon, and the rainbow
    /// strip's error against time for each photon map and filter
    /// (single-prism anchor scene; CSV and plot in --out).
    Prism {
        /// Fewer, smaller runs (a smoke run, not a measurement).
        #[arg(long)]
        quick: bool,
        /// Folder for the CSV and the plot [default: results/bench, or
        /// results/quick/bench with --quick, so that a smoke run leaves
        /// the recorded measurement alone]
        #[arg(long)]
        out: Option<PathBuf>,
        /// Render the same scene in a peer renderer in the same run and
        /// print each method's time over the peer's (Mitsuba 3's particle
        /// tracer; its environment made by `bash scripts/mitsuba-venv`).
        /// Without it, or if the peer is not installed, no ratio is printed
        #[arg(long, value_parser = ["mitsuba"])]
        peer: Option<String>,
        /// The peer's Python environment
        #[arg(long, default_value = crate::bench::mitsuba::DEFAULT_VENV, requires = "peer")]
        peer_venv: PathBuf,
        /// Light tracing onto the film (the default method) alone: no photon
        /// maps, no progressive runs, no hue along the strip (a shorter run)
        #[arg(long)]
        film_only: bool,
        /// Redraw the chart in --out from its CSV and its about file (when,
        /// at which commit, at what load); nothing is measured
        #[arg(long, conflicts_with_all = ["peer", "film_only"])]
        redraw: bool,
    },
    /// The k-nearest gather far from a compact cluster of photons:
    /// single-prism with --no-dispersion (every photon in the beam's
    /// spot), --map kdtree --k 50, the eye pass on 1 thread at 100k and
    /// 2 M photons (medians of 3).
    Knn {
        /// 20k and 100k photons, one run each (a smoke run).
        #[arg(long)]
        quick: bool,
    },
    /// Whether the photograph-like figures have converged: each rendered
    /// at two seeds, the relative RMSE of luminance between them (target
    /// under 2 %) and the render time.
    Figures {
        /// The scene files' quick parameters
        #[arg(long)]
        quick: bool,
        /// Only these figures (comma-separated ids)
        #[arg(long, value_delimiter = ',')]
        only: Vec<String>,
        /// Folder of the scene files
        #[arg(long = "scene-dir", alias = "scenes", value_name = "DIR", default_value = "scenes")]
        scenes: PathBuf,
    },
}

#[derive(Args, Debug)]
#[command(args_conflicts_with_subcommands = true)]
pub struct PrismArgs {
    #[command(subcommand)]
    pub probe: Option<PrismCommand>,
    #[command(flatten)]
    pub params: Flags<param_args::Prism>,
    #[arg(long, default_value = "results/prism.png", help_heading = "Output", help = out_help(<modes::prism::Prism as modes::ModeKind>::FORMATS, ""))]
    pub out: PathBuf,
    /// Append one timing row to this CSV
    #[arg(long, value_name = "FILE", help_heading = "Output")]
    pub timing_csv: Option<PathBuf>,
    /// A quick look: unless given, a tenth of the photons, 1 sample per
    /// pixel and half the size (not for measurements)
    #[arg(long, help_heading = "Output")]
    pub quick: bool,
}

#[derive(Subcommand, Debug)]
pub enum PrismCommand {
    /// One ray per wavelength through the scene's prism with the renderer's
    /// own optics: CSV of wavelength_nm, exit direction x,y,z, deviation_deg
    /// (counter-clockwise positive, toward the crown apices), transmittance;
    /// a ray totally reflected inside leaves the direction cells empty.
    Trace {
        #[command(flatten)]
        scene: Flags<param_args::PrismScene>,
        /// Wavelengths in nm, comma-separated
        #[arg(long, value_delimiter = ',', value_parser = parse_visible_nm, default_value = "486.1327,587.5618,656.2725")]
        wavelengths: Vec<f64>,
    },
}

/// The help of an output flag, from the formats the mode writes (the
/// extensions `image_io::check_output` accepts; "" = no default to show).
fn out_help(formats: &[crate::image_io::ImageFormat], default: &str) -> String {
    use crate::image_io::ImageFormat;
    let list: Vec<String> = formats
        .iter()
        .map(|f| match f {
            ImageFormat::Png => ".png".to_string(),
            ImageFormat::Ppm => ".ppm (binary P6)".into(),
            ImageFormat::Pfm => ".pfm (linear sRGB floats)".into(),
            ImageFormat::Exr => ".exr (OpenEXR: linear sRGB and XYZ, see --exr)".into(),
        })
        .collect();
    let default = if default.is_empty() { String::new() } else { format!(" [default: {default}]") };
    format!("Output image, by its extension: {}; any other is refused{default}", list.join(", "))
}

fn parse_visible_nm(s: &str) -> Result<f64, String> {
    let v: f64 = s.trim().parse().map_err(|_| format!("`{s}` is not a wavelength in nm"))?;
    if !(360.0..=830.0).contains(&v) {
        return Err(format!("{v} nm is outside 360-830 nm"));
    }
    Ok(v)
}

#[derive(Args, Debug)]
#[command(args_conflicts_with_subcommands = true, subcommand_precedence_over_arg = true)]
pub struct SweepArgs {
    #[command(subcommand)]
    pub merge: Option<SweepCommand>,
    /// The experiment file
    #[arg(required = true)]
    pub file: Option<PathBuf>,
    /// The file's [quick] settings: a small, fast version of the experiment
    #[arg(long)]
    pub quick: bool,
    /// Keep the rows already in runs.csv and run only the missing ones
    #[arg(long, conflicts_with = "fresh")]
    pub resume: bool,
    /// Start anew: move the folder's record aside (runs.csv.N, images.N, reference.png.N) first
    #[arg(long)]
    pub fresh: bool,
    /// Runs at once (each then gets its share of the cores; timings are fairest with 1)
    #[arg(long, default_value_t = 1)]
    pub jobs: usize,
    /// Output folder [default: results/NAME, or results/quick/NAME with --quick so the committed record stays]
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Remove the output folder's lock whoever holds it (only when the sweep it names is known to be gone, e.g. on another host)
    #[arg(long)]
    pub break_lock: bool,
    /// Only shard I of N (0 <= I < N): the grid's chains of runs along its first sweep axis, balanced by estimated cost over N shards as `sweep plan` does; at most as many shards as chains. Join with `sweep merge`
    #[arg(long, value_name = "I/N", value_parser = parse_shard)]
    pub shard: Option<(usize, usize)>,
    /// Stop after this many runs (for testing interruption)
    #[arg(long, hide = true)]
    pub max_runs: Option<usize>,
}

#[derive(Subcommand, Debug)]
pub enum SweepCommand {
    /// Join the runs.csv of shard folders into one, sorted by run id.
    Merge {
        /// Shard folders
        #[arg(required = true)]
        dirs: Vec<PathBuf>,
        /// Folder for the joined runs.csv
        #[arg(long)]
        out: PathBuf,
        /// The experiment file: check the shards hold all its runs, and draw its plots
        #[arg(long)]
        experiment: Option<PathBuf>,
        /// The experiment file's [quick] settings (as the shards ran)
        #[arg(long, requires = "experiment")]
        quick: bool,
        /// Run here the runs no shard holds, instead of refusing
        #[arg(long, requires = "experiment")]
        resume: bool,
        /// Move a record already in the output folder aside (runs.csv.N) instead of refusing
        #[arg(long)]
        fresh: bool,
        /// Remove the output folder's lock whoever holds it (only when the sweep it names is known to be gone)
        #[arg(long)]
        break_lock: bool,
    },
    /// Write a script that runs the sweep's shards on GNU parallel or as a
    /// Slurm job array, then merges them into the folder an unsharded
    /// `refract sweep FILE` would fill.
    Plan(PlanArgs),
}

#[derive(Args, Debug)]
pub struct PlanArgs {
    /// The experiment file
    pub file: PathBuf,
    /// What runs the shards
    #[arg(long, value_parser = param_args::named::<Engine>(), ignore_case = true)]
    pub engine: Engine,
    /// Number of shards (balanced by estimated cost; each holds whole chains along the first sweep axis, so at most as many shards as chains) [default: 4, or the chains if fewer]
    #[arg(long)]
    pub shards: Option<usize>,
    /// Folder for the plan, the shards (in shards/I) and the merged results [default: results/NAME, or results/quick/NAME with --quick]
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// The file's [quick] settings
    #[arg(long)]
    pub quick: bool,
    /// Slurm partition [default: the cluster's default]
    #[arg(long, help_heading = "Slurm")]
    pub partition: Option<String>,
    /// Slurm time limit per shard, as sbatch takes it (e.g. 1:00:00) [default: 4x the estimate, at least 10 min]
    #[arg(long, help_heading = "Slurm")]
    pub time: Option<String>,
    /// CPUs per shard
    #[arg(long, default_value_t = 1, help_heading = "Slurm")]
    pub cpus_per_task: usize,
    /// Memory per shard, as sbatch takes it (e.g. 2G) [default: from the estimate]
    #[arg(long, help_heading = "Slurm")]
    pub mem: Option<String>,
}

fn parse_shard(s: &str) -> Result<(usize, usize), String> {
    let bad = || format!("`{s}` is not I/N with 0 <= I < N");
    let (i, n) = s.split_once('/').ok_or_else(bad)?;
    let (i, n): (usize, usize) = (i.trim().parse().map_err(|_| bad())?, n.trim().parse().map_err(|_| bad())?);
    if n == 0 || i >= n {
        return Err(bad());
    }
    Ok((i, n))
}

#[derive(Subcommand, Debug)]
pub enum SpectrumCommand {
    /// CSV of a unit monochromatic stimulus, 380-780 nm in 5 nm steps:
    /// wavelength_nm, X, Y, Z, r_lin, g_lin, b_lin (linear sRGB, unclipped).
    Locus,
    /// XYZ, chromaticity, linear and encoded sRGB of a light normalised to
    /// Y = 1 (5 nm sum over 380-780 nm; lines integrated exactly).
    Illuminant {
        /// E, D65, FL1..FL12, FL3.1..FL3.15, blackbody:K, cfl-lines, laser:NM
        name: String,
    },
    /// Every IOR model against Sellmeier and every wavelength-to-colour map
    /// against CIE: CSVs and plots.
    Accuracy {
        /// Glass whose models are compared
        #[arg(long, default_value = "N-BK7")]
        glass: String,
        /// Output folder
        #[arg(long, default_value = "results/spectral")]
        out: PathBuf,
    },
}

#[derive(Args, Debug)]
pub struct GlassArgs {
    /// Glass name (see --list), e.g. N-BK7
    #[arg(required_unless_present = "list")]
    pub name: Option<String>,
    /// IOR model
    #[arg(long, value_parser = param_args::named::<IorKind>(), default_value = "sellmeier", ignore_case = true)]
    pub model: IorKind,
    /// Wavelengths in nm, comma-separated [default: the C, d and F lines]
    #[arg(long, value_delimiter = ',', value_parser = parse_wavelength, default_value = "656.2725,587.5618,486.1327")]
    pub wavelengths: Vec<f64>,
    /// List the catalogue: name, n_d, Abbe number, source
    #[arg(long, conflicts_with_all = ["name", "model", "wavelengths"])]
    pub list: bool,
}

fn parse_wavelength(s: &str) -> Result<f64, String> {
    let v: f64 = s.trim().parse().map_err(|_| format!("`{s}` is not a wavelength in nm"))?;
    if !(200.0..=2500.0).contains(&v) {
        return Err(format!("{v} nm is outside the models' range of 200-2500 nm"));
    }
    Ok(v)
}

/// Flags of `refract interior`. Giving any of the report's prompt flags
/// (--trace ... --ior, or --out) selects flag mode, where --off is required
/// and the rest take the report's defaults; otherwise the 13 questions are
/// asked on standard input.
#[derive(Args, Debug)]
pub struct InteriorArgs {
    #[command(flatten)]
    pub params: Flags<param_args::Interior>,
    #[arg(long, help_heading = crate::params::interior::PROMPTS, help = out_help(<modes::interior::Interior as modes::ModeKind>::FORMATS, "results/interior.png"))]
    pub out: Option<PathBuf>,
    /// Append one timing row (mode, mesh, triangles, ..., rays_per_s) to this CSV
    #[arg(long, value_name = "FILE", help_heading = "Output")]
    pub timing_csv: Option<PathBuf>,
}

impl InteriorArgs {
    /// True when any of the report's prompt flags was given.
    fn flag_mode(&self) -> bool {
        let prompt = |k: &str| crate::params::find(crate::params::interior::PARAMS, k).is_some_and(|p| p.section == crate::params::interior::PROMPTS);
        self.out.is_some() || self.params.given.iter().any(|g| prompt(g.key))
    }

    /// Flag mode: the report's fields from flags or their defaults.
    fn flag_config(&self) -> Result<<modes::interior::Interior as modes::ModeKind>::Config> {
        if !self.params.has("off") {
            let prompts = crate::params::interior::PARAMS.iter().filter(|p| p.section == crate::params::interior::PROMPTS && p.key != "off");
            let flags: Vec<String> = prompts.map(|p| format!("--{}", p.flag())).chain(["--out".to_string()]).collect();
            bail!("--off is required when any of the report's flags ({}) is given", flags.join(", "));
        }
        let mut c = self.params.config();
        match &self.out {
            Some(o) => c.out = crate::params::out_path(&o.to_string_lossy()).map_err(|e| anyhow::anyhow!("--out: {e}"))?,
            None => crate::image_io::create_folder(std::path::Path::new("results"))?,
        }
        Ok(c)
    }
}

/// The command line with the modes' old flag spellings (each row's
/// `aliases`, as `--color` for `--object-colour`) written as today's, and a
/// note for each: clap knows only today's names, so a typo hint never
/// points at an old one, and the old ones keep working.
pub fn modern_args(args: Vec<OsString>) -> (Vec<OsString>, Vec<String>) {
    fn old<C>(table: &'static [crate::params::Param<C>], name: &str) -> Option<String> {
        let n = name.replace('-', "_");
        table.iter().find(|p| p.aliases.contains(&n.as_str())).map(|p| p.flag())
    }
    let mode = args.get(1).and_then(|a| a.to_str()).unwrap_or_default().to_string();
    let mut notes = Vec::new();
    let mut out = Vec::with_capacity(args.len());
    let mut rest = false;
    for a in args {
        let text = a.to_str().filter(|t| !rest && t.starts_with("--") && t.len() > 2);
        let Some(t) = text else {
            rest |= a == "--";
            out.push(a);
            continue;
        };
        let (name, value) = match t[2..].split_once('=') {
            Some((n, v)) => (n, Some(v)),
            None => (&t[2..], None),
        };
        let new = match mode.as_str() {
            "interior" => old(crate::params::interior::PARAMS, name),
            "prism" => old(crate::params::prism::PARAMS, name),
            _ => None,
        };
        match new {
            Some(flag) => {
                notes.push(format!("--{name} is the old spelling of --{flag}"));
                out.push(OsString::from(match value {
                    Some(v) => format!("--{flag}={v}"),
                    None => format!("--{flag}"),
                }));
            }
            None => out.push(a),
        }
    }
    (out, notes)
}

/// A command line clap refused, as every error is: one line, `refract:
/// error: ...`, with clap's reason, its hint (or the nearest option when it
/// has none) and the possible values; help and version are printed as
/// they are. Returns the exit status: 0 for help and version, else 1.
pub fn parse_failure(e: clap::Error, args: &[OsString]) -> u8 {
    use clap::error::{ContextKind, ContextValue, ErrorKind};
    use clap::CommandFactory;
    match e.kind() {
        ErrorKind::DisplayHelp | ErrorKind::DisplayVersion => {
            let _ = e.print();
            return 0;
        }
        ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand => {
            let _ = e.print();
            return 1;
        }
        _ => {}
    }
    // The subcommand the error is about, for its options.
    let mut cmd = Cli::command();
    let mut path = vec!["refract".to_string()];
    for a in args.iter().skip(1).filter_map(|a| a.to_str()) {
        match cmd.find_subcommand(a) {
            Some(sub) => {
                path.push(a.to_string());
                cmd = sub.clone();
            }
            None if a.starts_with('-') => continue,
            None => break,
        }
    }
    let text = e.render().to_string();
    let mut parts: Vec<String> = Vec::new();
    for line in text.lines().map(str::trim).take_while(|l| !l.starts_with("Usage:") && !l.starts_with("For more information")) {
        let line = line.trim_start_matches("error: ").trim_start_matches("tip: ");
        match parts.last_mut() {
            _ if line.is_empty() => {}
            Some(last) if line.starts_with('[') => {
                last.push(' ');
                last.push_str(line);
            }
            _ => parts.push(line.to_string()),
        }
    }
    if e.kind() == ErrorKind::UnknownArgument && e.get(ContextKind::SuggestedArg).is_none() {
        if let Some(ContextValue::String(typed)) = e.get(ContextKind::InvalidArg) {
            let longs: Vec<String> = cmd.get_arguments().filter_map(|a| a.get_long()).map(|l| format!("--{l}")).collect();
            if let Some(near) = crate::names::nearest(typed, longs.iter().map(String::as_str)) {
                parts.push(format!("a similar argument exists: '{near}'"));
            }
        }
    }
    eprintln!("refract: error: {} (see `{} --help`)", parts.join("; "), path.join(" "));
    1
}

/// Runs the parsed command line.
pub fn run(cli: Cli) -> Result<()> {
    match cli.command {
        Command::Interior(args) => run_interior(args),
        Command::Meshes { dir } => Ok(modes::meshes::write(&dir, &mut |path| eprintln!("wrote {}", path.display()))?),
        Command::Prism(args) => run_prism(args),
        Command::Figures { quick, only, out, scenes, gallery_only } => {
            let out = out.unwrap_or_else(|| PathBuf::from(if quick { "results/quick" } else { "results" }));
            let outcome = crate::experiment::figures::run(&crate::experiment::figures::FigureOptions { quick, only, out, scenes, gallery_only })?;
            eprintln!("{outcome}");
            if !outcome.failed.is_empty() {
                bail!("{} of the figures failed (see above)", outcome.failed.len());
            }
            Ok(())
        }
        Command::Export { scene, out, set } => run_export(&scene, &out, &set),
        Command::Render { file, quick, out, set } if modes::gltf_file::is_gltf(&file) => run_gltf(file, quick, out, &set),
        Command::Render { file, quick, out, set } => {
            let mut scene = crate::experiment::scene_file::SceneFile::load(&file, quick)?;
            if quick && scene.same_values(&crate::experiment::scene_file::SceneFile::load(&file, false)?) {
                bail!("--quick: {} has no [quick] settings, so the render would be the full one; add a [quick] table or leave --quick out", file.display());
            }
            scene.set(&set)?;
            render_to(&scene, out)
        }
        Command::Sweep(args) => run_sweep(args),
        Command::Spectrum { which } => run_spectrum(which),
        Command::Glass(args) => run_glass(args),
        Command::Bench { which: BenchCommand::Interior { quick } } => write_stdout(&crate::bench::interior(quick)?),
        Command::Bench { which: BenchCommand::Prism { quick, out, peer, peer_venv, film_only, redraw } } => {
            let out = out.unwrap_or_else(|| PathBuf::from(if quick { "results/quick/bench" } else { "results/bench" }));
            if redraw {
                crate::bench::error_chart::redraw(&out)?;
                return write_stdout(&format!("redrew {}/prism-error-vs-time.{{png,svg}} from its CSV\n", out.display()));
            }
            let bench = crate::bench::PrismBench { quick, film_only, peer: peer.map(|_| peer_venv) };
            write_stdout(&crate::bench::prism(&bench, &out, &mut |line| eprintln!("{line}"))?)
        }
        Command::Bench { which: BenchCommand::Knn { quick } } => write_stdout(&crate::bench::knn(quick)?),
        Command::Bench { which: BenchCommand::Figures { quick, only, scenes } } => write_stdout(&crate::bench::figures(quick, &scenes, &only)?),
    }
}

/// `refract export`: the built-in scene, with the parameters given, as glTF.
fn run_export(name: &str, out: &std::path::Path, set: &[String]) -> Result<()> {
    use crate::experiment::scene_file::SceneFile;
    modes::export::check(name, !set.is_empty(), out)?;
    let mut params = Vec::new();
    if !modes::export::is_example(name) {
        let mut file = SceneFile::unnamed(name, modes::Mode::Prism, modes::export::scene_params(name)?);
        file.set(set)?;
        params = file.params;
    }
    eprintln!("{}", modes::export::export(name, &params, out)?);
    Ok(())
}

/// `refract render FILE.glb`: the file as a prism-mode scene, its size
/// from its camera's aspect ratio unless given; what the file holds and
/// refract does not model is said in one warning before the render.
fn run_gltf(file: PathBuf, quick: bool, out: Option<PathBuf>, set: &[String]) -> Result<()> {
    use crate::experiment::scene_file::SceneFile;
    let stem = file.file_stem().and_then(|s| s.to_str()).filter(|s| !s.is_empty()).unwrap_or("gltf");
    let id: String = stem.chars().map(|c| if c.is_ascii_alphanumeric() || "-_.".contains(c) { c } else { '-' }).collect();
    let named = modes::Mode::Prism.given_text("gltf", &file.to_string_lossy(), modes::Source::Chosen("the file to render"));
    let mut scene = SceneFile::unnamed(&id, modes::Mode::Prism, vec![named.map_err(|error| modes::ModeError::Key { key: "gltf".into(), error })?]);
    let given = |key: &str| set.iter().any(|s| s.split_once('=').is_some_and(|(k, _)| k.trim().replace('-', "_") == key));
    if quick {
        // A quick look, as `prism --quick`: fewer photons, one sample.
        for (key, value) in [("photons", 100_000), ("spp", 1)] {
            if !given(key) {
                scene.params.push(modes::Given { key, value: crate::params::Value::Count(value), from: modes::Source::Flag("quick".into()) });
            }
        }
    }
    scene.set(set)?;
    let mut cfg = modes::config::<modes::prism::Prism>(&scene.params)?;
    if !given("size") {
        modes::gltf_file::fit_frame(&mut cfg, if quick { 320 } else { 640 });
        let (w, h) = (cfg.scene.width, cfg.scene.height);
        scene.params.push(modes::Given { key: "size", value: crate::params::Value::Size([w, h]), from: modes::Source::Chosen("the camera's aspect ratio") });
    }
    if let Some(w) = modes::prism::gltf_check(&cfg)? {
        eprintln!("warning: {w}");
    }
    render_to(&scene, out)
}

/// Renders a scene file to `out` (default `results/<id>.png`), checked
/// before any work, with its progress bars and summary line.
fn render_to(scene: &crate::experiment::scene_file::SceneFile, out: Option<PathBuf>) -> Result<()> {
    let out = match out {
        Some(o) => o,
        None => {
            crate::image_io::create_folder(std::path::Path::new("results"))?;
            PathBuf::from("results").join(format!("{}.png", scene.id))
        }
    };
    crate::image_io::check_output(&out, scene.mode.formats()).map_err(|e| anyhow::anyhow!("--out: {e}"))?;
    crate::image_io::remove_stale_temps(out.parent().unwrap_or(std::path::Path::new("")));
    for w in scene.mode.warnings(&scene.params) {
        eprintln!("warning: {w}");
    }
    // The keys were checked before the output was named; one its format
    // leaves unused (the tone of a .pfm) is the scene's choice for its
    // picture, so it is pointed out, not refused.
    if let Some((g, why)) = scene.mode.first_ignored_writing(&scene.params, &out)? {
        eprintln!("warning: {}: `{}` does not change {}: {why}", scene.id, g.written_key(), out.display());
    }
    let bars = crate::terminal::Bars::new();
    let (_, summary) = scene.render_summarised(&out, &bars)?;
    bars.done();
    eprintln!("wrote {} ({summary})", out.display());
    Ok(())
}

fn run_interior(args: InteriorArgs) -> Result<()> {
    // What the flags fix is checked before any question is asked; the
    // trace count, asked first, is taken as above 0 until it is answered.
    let mut known = args.params.config();
    if !args.flag_mode() {
        known.max_trace = known.max_trace.max(1);
    }
    args.params.check_used(&known)?;
    crate::params::check_threads(args.params.config().threads).map_err(|e| anyhow::anyhow!("--threads: {e}"))?;
    if let Some(path) = &args.timing_csv {
        modes::interior::check_timing_csv(path).context("--timing-csv")?;
    }
    let cfg = if args.flag_mode() {
        // Again with the output named: a .pfm ignores the tone.
        let cfg = args.flag_config()?;
        args.params.check_used(&cfg)?;
        cfg
    } else {
        use std::io::IsTerminal;
        let stdin = std::io::stdin();
        let interactive = stdin.is_terminal();
        let mut input = stdin.lock();
        let mut out = std::io::stdout();
        let cfg = crate::params::prompts::ask_all(&mut crate::params::prompts::Prompter::new(&mut input, &mut out, interactive), args.params.config())?;
        args.params.check_used(&cfg)?;
        cfg
    };
    Ok(modes::interior::run_to_files(&cfg, args.timing_csv.as_deref(), &mut |line| eprintln!("{line}"))?)
}

/// Writes to standard output; a closed pipe (`| head`) is not an error.
fn write_stdout(text: &str) -> Result<()> {
    use std::io::Write;
    match std::io::stdout().lock().write_all(text.as_bytes()) {
        Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => Ok(()),
        r => Ok(r?),
    }
}

fn run_spectrum(which: SpectrumCommand) -> Result<()> {
    match which {
        SpectrumCommand::Locus => write_stdout(&modes::spectrum::locus()),
        SpectrumCommand::Illuminant { name } => write_stdout(&modes::spectrum::illuminant(&name)?),
        SpectrumCommand::Accuracy { glass, out } => write_stdout(&crate::experiment::spectral::write_report(&out, modes::glass::by_name(&glass)?)?),
    }
}

fn run_glass(args: GlassArgs) -> Result<()> {
    if args.list {
        return write_stdout(&modes::glass::list()?);
    }
    write_stdout(&modes::glass::indices(args.name.as_deref().unwrap_or_default(), args.model, &args.wavelengths)?)
}

fn run_prism(args: PrismArgs) -> Result<()> {
    if let Some(PrismCommand::Trace { scene, wavelengths }) = args.probe {
        scene.check_used(&scene.config())?;
        return write_stdout(&modes::trace::trace(&scene.config(), &wavelengths)?);
    }
    let mut cfg = args.params.config();
    cfg.out = args.out.clone();
    if !args.params.has("size") {
        modes::gltf_file::fit_frame(&mut cfg, 640);
    }
    if args.quick {
        modes::prism::quick(&mut cfg, |k| args.params.has(k));
    }
    args.params.check_used(&cfg)?;
    modes::check::<modes::prism::Prism>(&cfg, &args.params.given)?;
    let bars = crate::terminal::Bars::new();
    Ok(modes::prism::run_to_files(&cfg, args.timing_csv.as_deref(), &bars, &mut |line| bars.println(&line))?)
}

/// This command line as it would go on from where it stops: `--fresh`
/// dropped, `--resume` added, each word quoted for a POSIX shell if needed.
fn resume_command() -> String {
    let mut words: Vec<String> = vec!["refract".into()];
    words.extend(std::env::args().skip(1).filter(|a| a != "--fresh" && a != "--resume" && a != "--break-lock"));
    words.push("--resume".into());
    let quote = |w: &String| {
        if !w.is_empty() && w.chars().all(|c| c.is_ascii_alphanumeric() || "-_./=:,@%+".contains(c)) {
            w.clone()
        } else {
            format!("'{}'", w.replace('\'', "'\\''"))
        }
    };
    words.iter().map(quote).collect::<Vec<_>>().join(" ")
}

fn run_sweep(args: SweepArgs) -> Result<()> {
    use crate::experiment::{spec::Experiment, sweep};
    match args.merge {
        Some(SweepCommand::Merge { dirs, out, experiment, quick, resume, fresh, break_lock }) => {
            let e = experiment.map(|p| Experiment::load(&p, quick)).transpose()?;
            eprintln!("{}", sweep::merge(&dirs, &out, e.as_ref(), &sweep::MergeOptions { resume, fresh, break_lock })?);
            return Ok(());
        }
        Some(SweepCommand::Plan(p)) => {
            let e = Experiment::load(&p.file, p.quick)?;
            let refract = std::env::current_exe().context("cannot find the refract binary's path")?;
            let opts = crate::experiment::plan::PlanOptions {
                file: p.file,
                engine: p.engine,
                shards: p.shards,
                out: p.out,
                quick: p.quick,
                partition: p.partition,
                time: p.time,
                cpus_per_task: p.cpus_per_task,
                mem: p.mem,
                refract,
            };
            println!("{}", crate::experiment::plan::write(&e, &opts)?);
            return Ok(());
        }
        None => {}
    }
    let file = args.file.context("an experiment file is required")?;
    let e = Experiment::load(&file, args.quick)?;
    if args.jobs == 0 || args.jobs > 256 {
        bail!("--jobs: {} is not between 1 and 256", args.jobs);
    }
    if args.quick && e.same_runs(&Experiment::load(&file, false)?) {
        bail!("--quick: {} has no [quick] settings, so the sweep would be the full one; add a [quick] table or leave --quick out", file.display());
    }
    if let Some((i, n)) = args.shard {
        let runs = crate::experiment::grid::expand(&e)?;
        if !crate::experiment::plan::assign(&runs, n).contains(&i) {
            let chains = crate::experiment::plan::chain_count(&runs);
            bail!(
                "--shard {i}/{n}: shard {i} would run nothing: the grid holds {chains} chain(s) of runs (the runs along its first sweep axis stay in one shard); use at most {chains} shard(s)"
            );
        }
    }
    let on_record = match (args.resume, args.fresh) {
        (true, _) => sweep::OnRecord::Resume,
        (_, true) => sweep::OnRecord::Fresh,
        _ => sweep::OnRecord::Refuse,
    };
    let opts = sweep::SweepOptions {
        on_record,
        jobs: args.jobs,
        out: args.out,
        shard: args.shard,
        max_runs: args.max_runs,
        break_lock: args.break_lock,
        again: resume_command(),
    };
    let o = sweep::run(&e, &opts)?;
    match o.failure {
        // Every row is saved; the status says not all went well.
        Some(why) => bail!("{}; {why}", o.summary),
        None => {
            eprintln!("{}", o.summary);
            Ok(())
        }
    }
}
