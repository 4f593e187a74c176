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

/// Asserts a failed run, no panic, `needle` in stderr's one line (every
/// error, a bad command line's too, is one line and exit status 1).
pub fn assert_clean_failure(o: &Output, needle: &str) {
    let err = stderr(o);
    assert!(!o.status.success(), "expected failure, got success; stderr: {err}");
    assert!(!err.contains("panicked"), "panic: {err}");
    let first = err.lines().next().unwrap_or("");
    assert!(first.contains(needle), "expected `{needle}` in the first line of: {err}");
    assert!(first.starts_with("refract: error: "), "one style: {err}");
    assert_eq!(o.status.code(), Some(1), "exit status: {err}");
    assert_eq!(err.trim_end().lines().count(), 1, "error should be one line: {err}");
}

/// A P6 image read back: (width, height, bytes).
pub fn ppm(path: &Path) -> (usize, usize, Vec<u8>) {
    refract::image_io::read_ppm(path).unwrap()
}

/// Every file under `dir` with its bytes, sorted: two snapshots are equal
/// when a run changed, added and removed nothing.
pub fn snapshot(dir: &Path) -> Vec<(PathBuf, Vec<u8>)> {
    let mut out = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).unwrap().flatten() {
            let p = e.path();
            if p.is_dir() {
                stack.push(p);
            } else {
                out.push((p.strip_prefix(dir).unwrap().to_path_buf(), std::fs::read(&p).unwrap_or_default()));
            }
        }
    }
    out.sort();
    out
}

/// Asserts a failed run whose stderr's first line is exactly `first`, with
/// exit code `code`.
pub fn assert_fails_with(o: &Output, code: i32, first: &str) {
    let err = stderr(o);
    assert!(!err.contains("panicked"), "panic: {err}");
    assert_eq!(o.status.code(), Some(code), "exit code; stderr: {err}");
    assert_eq!(err.lines().next().unwrap_or(""), first, "first line of stderr: {err}");
}
