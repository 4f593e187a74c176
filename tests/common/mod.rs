use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};

pub fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_refract"))
}

pub fn repo(path: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(path)
}

/// Runs `refract ARGS` with `stdin` piped in.
pub fn run(args: &[&str], stdin: &str, dir: &Path) -> Output {
    use std::io::Write;
    let mut child = bin().args(args).current_dir(dir).stdin(Stdio::piped()).stdout(Stdio::piped()).stderr(Stdio::piped()).spawn().expect("spawn refract");
    // A program may stop reading early (a capped answer): a closed pipe is fine.
    match child.stdin.take().unwrap().write_all(stdin.as_bytes()) {
        Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => {}
        r => r.unwrap(),
    }
    child.wait_with_output().unwrap()
}

pub fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// Asserts a failed run, no panic, `needle` in the first line of stderr. A
/// domain error (exit 1) is that one line; a bad command line (exit 2) is
/// clap's message, which ends with the `--help` hint.
pub fn assert_clean_failure(o: &Output, needle: &str) {
    let err = stderr(o);
    assert!(!o.status.success(), "expected failure, got success; stderr: {err}");
    assert!(!err.contains("panicked"), "panic: {err}");
    let first = err.lines().next().unwrap_or("");
    assert!(first.contains(needle), "expected `{needle}` in the first line of: {err}");
    match o.status.code() {
        Some(1) => assert_eq!(err.trim_end().lines().count(), 1, "error should be one line: {err}"),
        Some(2) => assert!(err.trim_end().ends_with("For more information, try '--help'."), "clap's hint is kept: {err}"),
        c => panic!("exit code {c:?}: {err}"),
    }
}

/// A P6 image read back: (width, height, bytes).
pub fn ppm(path: &Path) -> (usize, usize, Vec<u8>) {
    refract::image_io::read_ppm(path).unwrap()
}
