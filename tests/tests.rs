//! Whole-program tests: each module runs the built `refract` binary or the
//! library as the binary does.

// Helpers: run the binary, temp folders, read images.
mod common;

// Report 004's stdin prompts against the same run by flags.
mod cli_prompts;
// Malformed OFF files and impossible parameters: one line, non-zero, no output.
mod bad_input;
// A given value's refusal names where it was given: file line, flag, --set, prompt.
mod given_sources;
// The BVH and the report's linear scan give the same pixels.
mod bvh_vs_linear;
// Same seed, same image, whatever the thread count.
mod determinism;
// The rendered image against closed-form optics (the TIR circle).
mod interior_optics;
// Random and mutated OFF text never panics the reader.
mod off_fuzz;
// The spectral core against the CIE and glass reference tables.
mod spectral_oracles;
// Prism scenes against closed-form deviation and the Amici oracle.
mod prism_optics;
// Reports 001 and 003: the ball lens, the Cornell laser.
mod scene_optics;
// The contrasting figures differ where their captions say.
mod figure_content;
// Whole prism renders: energy, landing points, chroma, the CFL's line images.
mod prism_render;
// The exact reference of beam-and-screen scenes; progressive photon mapping.
mod exact_reference;
// Every real flag with arbitrary f64 bit patterns: a finite image or a clear error.
mod float_flags;
// The experiment runner: rows, plots, resume, shards, failures as rows.
mod sweep;
// Saved work is never lost: records, reruns, interruptions, locks.
mod sweep_record;
// Checks made before any work: output folders, bounds, empty meshes.
mod prework_checks;
// Wavefront OBJ input: messages name OBJ, the file and the line; soups are warned of.
mod obj_input;
// The committed timing charts: medians with error bars, fits where claimed.
mod committed_charts;
// Sweeps through GNU parallel and Slurm (ignored unless the engines are there).
mod scale_out;
// The figures of the four reports and their gallery; scene files.
mod figures;
// The modules import only downward (docs/architecture.md).
mod layers;
// Citations of docs/physics.md point at sections that exist.
mod docs;
// A matte scene through a dispersive wedge against the sum of its
// monochromatic renders.
mod wedge;
// Paths in scene and experiment files are from the file's folder.
mod file_paths;
// Flags, keys and axes that cannot change the image are refused.
mod ignored_flags;
// Every shipped scene kind at its defaults is neither black nor white.
mod default_scenes;
// The help against what the program does.
mod help_text;
// One vocabulary: names, hints, one error style.
mod names;
// The README's commands, from a fresh clone (ignored: CI runs it).
mod readme;
// Progress lines, rates and the summary line.
mod progress;
// `--out x.exr`: OpenEXR's channels against the PFM and the film's XYZ.
mod openexr_out;
// `bench prism` without its peer prints no ratio.
mod bench_peer;
// glTF in and out: round trip, glass, lights, warnings, bad files.
mod gltf;
