//! The help is what the program does: every default it prints is accepted
//! as typed and gives the same bytes as leaving the flag out; defaults are
//! printed as the table writes them; each extension `--out` lists is
//! written and any other refused; what it says is required is.

use crate::common::*;

/// `(flag, default)` for every flag whose long help shows `[default: X]`.
fn defaults(help: &str) -> Vec<(String, String)> {
    let mut out = Vec::new();
    let mut flag = None;
    for line in help.lines() {
        let t = line.trim();
        if line.starts_with("      --") || line.starts_with("  -") {
            flag = t.split_whitespace().find(|w| w.starts_with("--")).map(|w| w.trim_end_matches(',').to_string());
        } else if let (Some(f), Some(d)) = (&flag, t.strip_prefix("[default: ").and_then(|r| r.strip_suffix(']'))) {
            out.push((f.clone(), d.to_string()));
        }
    }
    out
}

fn help(cmd: &str) -> String {
    let o = run(&[cmd, "--help"], "", std::path::Path::new("."));
    assert!(o.status.success());
    String::from_utf8(o.stdout).unwrap()
}

/// Runs `base` with `--out a.EXT`, then with every printed default added
/// (except `skip`): the same bytes.
fn printed_defaults_are_the_defaults(cmd: &str, base: &[&str], skip: &[&str], ext: &str) {
    let shown = defaults(&help(cmd));
    assert!(shown.len() > 10, "{cmd}: {shown:?}");
    for (f, d) in &shown {
        assert!(!d.contains("0000000") && !d.contains("9999999"), "{cmd} {f}: the default {d} is not as written");
    }
    let dir = tempfile::tempdir().unwrap();
    let a = format!("a.{ext}");
    let mut plain: Vec<&str> = vec![cmd];
    plain.extend(base);
    plain.extend(["--out", &a]);
    let o = run(&plain, "", dir.path());
    assert!(o.status.success(), "{}", stderr(&o));
    let b = format!("b.{ext}");
    let mut full: Vec<&str> = vec![cmd];
    full.extend(base);
    full.extend(["--out", &b]);
    for (f, d) in &shown {
        if !skip.contains(&f.as_str()) && !base.contains(&f.as_str()) {
            full.extend([f.as_str(), d.as_str()]);
        }
    }
    let o = run(&full, "", dir.path());
    assert!(o.status.success(), "{full:?}: {}", stderr(&o));
    assert_eq!(std::fs::read(dir.path().join(&a)).unwrap(), std::fs::read(dir.path().join(&b)).unwrap(), "{full:?}");
}

#[test]
fn interior_defaults_as_printed_are_the_defaults() {
    let cube = repo("off/cube.off");
    printed_defaults_are_the_defaults("interior", &["--off", cube.to_str().unwrap(), "--size", "24,24"], &["--out"], "ppm");
    let h = help("interior");
    assert!(h.contains("[default: 1.4]") && h.contains("[default: 0.0001]"), "{h}");
}

#[test]
fn prism_defaults_as_printed_are_the_defaults() {
    printed_defaults_are_the_defaults("prism", &["--scene", "single-prism", "--size", "32,24", "--photons", "20000"], &["--out", "--scene"], "png");
}

#[test]
fn out_extensions_as_printed_work_and_no_other() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let cube = repo("off/cube.off");
    for (cmd, base) in [
        ("interior", vec!["--off", cube.to_str().unwrap(), "--size", "8,8"]),
        ("prism", vec!["--scene", "single-prism", "--size", "16,12", "--photons", "2000"]),
    ] {
        let h = help(cmd);
        let line = h.lines().skip_while(|l| !l.trim_start().starts_with("--out ")).nth(1).unwrap().to_string();
        let exts: Vec<String> =
            line.split(|c: char| c.is_whitespace() || c == ',' || c == ';').filter(|w| w.starts_with('.') && w.len() > 1).map(str::to_string).collect();
        assert!(exts.len() >= 2, "{cmd}: {line}");
        for e in &exts {
            let out = format!("x{e}");
            let mut args = vec![cmd];
            args.extend(&base);
            args.extend(["--out", &out]);
            let o = run(&args, "", d);
            assert!(o.status.success(), "{cmd} --out {out}: {}", stderr(&o));
            assert!(d.join(&out).is_file());
        }
        let mut args = vec![cmd];
        args.extend(&base);
        args.extend(["--out", "x.jpg"]);
        let before = snapshot(d);
        let o = run(&args, "", d);
        let listed = exts.join(", ");
        assert_fails_with(&o, 1, &format!("refract: error: --out: `x.jpg` does not end in an image extension refract writes here ({listed})"));
        assert_eq!(snapshot(d), before);
    }
}

#[test]
fn what_the_help_says_is_required_is() {
    let h = help("interior");
    assert!(h.contains("[required with any of the report's flags; otherwise asked]") && !h.contains("[default: off/cube.off]"), "{h}");
    let dir = tempfile::tempdir().unwrap();
    let o = run(&["interior", "--ior", "1.5"], "", dir.path());
    assert_fails_with(
        &o,
        1,
        "refract: error: --off is required when any of the report's flags (--trace, --opacity, --object-colour, --coff, --scale, --rot, --ior, --out) is given",
    );
    assert!(snapshot(dir.path()).is_empty());
    let s = help("sweep");
    assert!(s.contains("chains of runs along its first sweep axis") && !s.contains("modulo"), "{s}");
}
