//! Every `refract` command of the README's code blocks, run as a newcomer
//! runs it: in a fresh clone of the repository, each must succeed and
//! leave `git status` clean. The full set takes minutes (the figures'
//! scene files at full size), so it is ignored by default and run by CI:
//! `cargo test --release --test integration readme -- --ignored`.

use crate::common::*;
use std::path::Path;
use std::process::Command;

/// The README's shell commands that call `refract` (comments cut).
fn readme_commands() -> Vec<String> {
    let text = std::fs::read_to_string(repo("README.md")).unwrap();
    let mut out = Vec::new();
    let mut in_sh = false;
    for line in text.lines() {
        if line.starts_with("```") {
            in_sh = line == "```sh";
            continue;
        }
        let cmd = match line.find("  #") {
            Some(i) => &line[..i],
            None => line,
        }
        .trim();
        if in_sh && !cmd.starts_with('#') && (cmd.starts_with("refract ") || cmd == "refract" || cmd.contains("| refract")) {
            out.push(cmd.to_string());
        }
    }
    out
}

fn git(dir: &Path, args: &[&str]) -> String {
    let o = Command::new("git").args(args).current_dir(dir).output().expect("git");
    assert!(o.status.success(), "git {args:?}: {}", String::from_utf8_lossy(&o.stderr));
    String::from_utf8_lossy(&o.stdout).into_owned()
}

#[test]
fn the_readme_has_the_commands_it_shows() {
    let cmds = readme_commands();
    assert!(cmds.len() >= 20, "{cmds:?}");
    for picture in ["css552-p4", "css552-p5", "css552-p6"] {
        assert!(cmds.iter().any(|c| c.starts_with(&format!("refract render scenes/{picture}.toml"))), "Picture {picture} is its scene file: {cmds:?}");
    }
}

#[test]
#[ignore]
fn every_readme_command_runs_in_a_fresh_clone_and_leaves_it_clean() {
    let dir = tempfile::tempdir().unwrap();
    let clone = dir.path().join("clone");
    git(dir.path(), &["clone", "--quiet", repo("").to_str().unwrap(), clone.to_str().unwrap()]);
    let bin = Path::new(env!("CARGO_BIN_EXE_refract")).parent().unwrap().to_path_buf();
    let path = format!("{}:{}", bin.display(), std::env::var("PATH").unwrap_or_default());
    for cmd in readme_commands() {
        let o = Command::new("sh").arg("-c").arg(&cmd).current_dir(&clone).env("PATH", &path).output().unwrap();
        assert!(o.status.success(), "`{cmd}`: {}", stderr(&o));
        let status = git(&clone, &["status", "--porcelain", "--untracked-files=all"]);
        assert!(status.is_empty(), "`{cmd}` left the clone changed:\n{status}");
    }
}
