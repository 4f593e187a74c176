//! Report 004's input format: thirteen answers on standard input, asked in
//! the report's order. A bad answer is asked again with a one-line reason;
//! input that ends early is an error naming the unanswered prompt. Each
//! answer is checked by its parameter's row in `interior::PARAMS`, so a
//! prompt accepts exactly what the flag and the scene files accept.

use super::interior::PARAMS;
use super::{channel, find, parse_real, Param};
use crate::interior::config::InteriorConfig;
use crate::mesh::source::MeshSource;
use std::io::{BufRead, Write};

#[derive(Debug, thiserror::Error)]
pub enum PromptError {
    #[error("input ended before an answer to \"{0}\"")]
    EndOfInput(String),
    #[error("the answer to \"{0}\" is longer than 4096 bytes")]
    TooLong(String),
    #[error("reading standard input: {0}")]
    Io(#[from] std::io::Error),
}

/// The longest answer read from one line.
const MAX_ANSWER: u64 = 4096;

/// Asks one prompt until `parse` accepts the answer.
fn ask<T>(input: &mut dyn BufRead, out: &mut dyn Write, prompt: &str, parse: impl Fn(&str) -> Result<T, String>) -> Result<T, PromptError> {
    loop {
        write!(out, "{prompt}: ")?;
        out.flush()?;
        let mut line = String::new();
        // At most MAX_ANSWER bytes of a line: endless input is not an answer.
        let n = std::io::Read::take(&mut *input, MAX_ANSWER).read_line(&mut line)?;
        if n as u64 == MAX_ANSWER && !line.ends_with('\n') {
            return Err(PromptError::TooLong(prompt.to_string()));
        }
        if n == 0 {
            writeln!(out)?;
            return Err(PromptError::EndOfInput(prompt.to_string()));
        }
        match parse(line.trim_end_matches(['\n', '\r'])) {
            Ok(v) => return Ok(v),
            Err(reason) => writeln!(out, "\n{prompt}: {reason}; please answer again")?,
        }
    }
}

fn row(key: &str) -> &'static Param<InteriorConfig> {
    find(PARAMS, key).unwrap_or(&PARAMS[0])
}

/// Asks for the value of parameter `key` and sets it on `c`.
fn ask_param(input: &mut dyn BufRead, out: &mut dyn Write, prompt: &str, key: &str, c: &mut InteriorConfig) -> Result<(), PromptError> {
    let p = row(key);
    let v = ask(input, out, prompt, |s| p.kind.parse_text(s))?;
    (p.set)(c, &v);
    Ok(())
}

/// The report's "0 = No, 1 = Yes".
fn yes_no(s: &str) -> Result<bool, String> {
    match s.trim() {
        "0" => Ok(false),
        "1" => Ok(true),
        o => Err(format!("`{o}` is not 0 (no) or 1 (yes)")),
    }
}

/// Fills the report's thirteen fields of `base` from the answers; the other
/// settings (shininess, size, ...) stay as `base` has them.
pub fn ask_all(input: &mut dyn BufRead, out: &mut dyn Write, base: InteriorConfig) -> Result<InteriorConfig, PromptError> {
    let mut c = base;
    ask_param(input, out, "Maximum ray trace count", "trace", &mut c)?;
    ask_param(input, out, "Opacity of object (0-100)", "opacity", &mut c)?;
    writeln!(out, "RGB color of object, int in [0,255]")?;
    let r = ask(input, out, "R", channel)?;
    let g = ask(input, out, "G", channel)?;
    let b = ask(input, out, "B", channel)?;
    c.color = [r, g, b];
    c.out = ask(input, out, "File name of output file", super::out_path)?;
    c.off = ask(input, out, "File name of .off file", |s| super::in_path(s).map(MeshSource::File))?;
    c.coff = ask(input, out, "Is entered .off file in color off format? (0 = No, 1 = Yes)", yes_no)?;
    ask_param(input, out, "Scale Factor", "scale", &mut c)?;
    let x = ask(input, out, "X rotation (degrees)", parse_real)?;
    let y = ask(input, out, "Y rotation (degrees)", parse_real)?;
    let z = ask(input, out, "Z rotation (degrees)", parse_real)?;
    c.rot = glam::DVec3::new(x, y, z).as_vec3();
    ask_param(input, out, "Refractive Index", "ior", &mut c)?;
    Ok(c)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn base() -> InteriorConfig {
        crate::params::interior::defaults()
    }

    #[test]
    fn reasks_bad_answers_and_reports_early_end() {
        let off = concat!(env!("CARGO_MANIFEST_DIR"), "/off/cube.off");
        let text = format!("x\n-2\n3\n150\n25\n255\n999\n0\n0\nout.ppm\n/no/such.off\n{off}\n2\n1\n0\n1.5\n10\n20\n-30\nzero\n1.4\n");
        let mut out = Vec::new();
        let c = ask_all(&mut text.as_bytes(), &mut out, base()).unwrap();
        assert_eq!((c.max_trace, c.opacity, c.color, c.coff), (3, 25.0, [255, 0, 0], true));
        assert_eq!((c.scale, c.rot, c.ior), (1.5, glam::Vec3::new(10.0, 20.0, -30.0), 1.4));
        let shown = String::from_utf8(out).unwrap();
        for reason in [
            "`x` is not a whole number",
            "150 is not between 0 and 100",
            "999 is outside 0-255",
            "no such file",
            "`2` is not 0 (no) or 1 (yes)",
            "0 is not greater than 0",
            "`zero` is not a number",
        ] {
            assert!(shown.contains(reason), "missing `{reason}` in:\n{shown}");
        }
        let e = ask_all(&mut "0\n25\n".as_bytes(), &mut Vec::new(), base()).unwrap_err();
        assert_eq!(e.to_string(), "input ended before an answer to \"R\"");
    }
}
