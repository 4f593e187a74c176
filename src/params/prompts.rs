//! Report 004's input format: thirteen answers on standard input, asked in
//! the report's order and read as the report's C++ `cin >>` reads them:
//! whitespace-separated tokens, any number to a line, blank lines skipped
//! (so a file of answers one per line, or all on one line, replays alike).
//! At a terminal a bad answer is asked again with a one-line reason (the
//! rest of its line is dropped); from a pipe or file the first bad answer
//! stops the run, naming its line, the question and the answer (a later
//! answer would otherwise land on the wrong question). The mesh is read
//! when it is named, so a file that is not a mesh is caught there. Input
//! that ends early is an error naming the unanswered prompt. Each
//! answer is checked by its parameter's row in `interior::PARAMS`, so a
//! prompt accepts exactly what the flag and the scene files accept (a
//! file name holds no space, as with `cin >>`).

use super::given::{Given, Source};
use super::interior::PARAMS;
use super::{channel, find, parse_real, Param, Value, ValueError};
use crate::interior::config::InteriorConfig;
use crate::mesh::source::MeshSource;
use std::io::{BufRead, Write};
use std::path::PathBuf;

#[derive(Debug, thiserror::Error)]
pub enum PromptError {
    #[error("input ended before an answer to \"{0}\"")]
    EndOfInput(String),
    #[error("the answer to \"{0}\" is longer than 4096 bytes")]
    TooLong(String),
    #[error("more than 4096 blank lines before an answer to \"{0}\"")]
    Blank(String),
    #[error("line {line} of standard input: `{answer}` is no answer to \"{prompt}\": {reason}")]
    BadAnswer { line: usize, prompt: String, answer: String, reason: String },
    // No `#[from]`: as a source the reason would be printed twice.
    #[error("reading standard input: {0}")]
    Io(std::io::Error),
}

impl From<std::io::Error> for PromptError {
    fn from(e: std::io::Error) -> Self {
        PromptError::Io(e)
    }
}

/// Where the answers come from: the input, where the questions go, the
/// line being read, and whether a person is answering (then a bad answer
/// is asked again).
pub struct Prompter<'a> {
    pub input: &'a mut dyn BufRead,
    pub out: &'a mut dyn Write,
    pub interactive: bool,
    /// The line the pending tokens came from.
    line: usize,
    /// Answers read but not yet taken, in order.
    pending: std::collections::VecDeque<String>,
}

impl<'a> Prompter<'a> {
    pub fn new(input: &'a mut dyn BufRead, out: &'a mut dyn Write, interactive: bool) -> Self {
        Prompter { input, out, interactive, line: 0, pending: Default::default() }
    }

    /// The next answer: the next token of the current line, else of the
    /// next line that has one. `None` at the end of the input.
    fn token(&mut self, prompt: &str) -> Result<Option<String>, PromptError> {
        let mut blank = 0;
        while self.pending.is_empty() {
            let mut line = String::new();
            // At most MAX_ANSWER bytes of a line: endless input is not an answer.
            let n = std::io::Read::take(&mut *self.input, MAX_ANSWER).read_line(&mut line)?;
            if n as u64 == MAX_ANSWER && !line.ends_with('\n') {
                return Err(PromptError::TooLong(prompt.to_string()));
            }
            if n == 0 {
                return Ok(None);
            }
            self.line += 1;
            blank += 1;
            if blank > MAX_ANSWER {
                return Err(PromptError::Blank(prompt.to_string()));
            }
            self.pending.extend(line.split_whitespace().map(str::to_string));
        }
        Ok(self.pending.pop_front())
    }
}

/// The longest answer read from one line.
const MAX_ANSWER: u64 = 4096;

/// Asks one prompt until `parse` accepts the answer (at a terminal), or
/// once (from a pipe or file).
fn ask<T, E: std::fmt::Display>(p: &mut Prompter, prompt: &str, parse: impl Fn(&str) -> Result<T, E>) -> Result<T, PromptError> {
    loop {
        write!(p.out, "{prompt}: ")?;
        p.out.flush()?;
        let Some(answer) = p.token(prompt)? else {
            writeln!(p.out)?;
            return Err(PromptError::EndOfInput(prompt.to_string()));
        };
        let answer = answer.as_str();
        match parse(answer) {
            Ok(v) => return Ok(v),
            Err(reason) if p.interactive => {
                // The rest of a bad line is dropped: it was meant to follow it.
                p.pending.clear();
                writeln!(p.out, "\n{prompt}: {reason}; please answer again")?
            }
            Err(reason) => {
                writeln!(p.out)?;
                return Err(PromptError::BadAnswer { line: p.line, prompt: prompt.to_string(), answer: answer.to_string(), reason: reason.to_string() });
            }
        }
    }
}

fn row(key: &str) -> &'static Param<InteriorConfig> {
    find(PARAMS, key).unwrap_or(&PARAMS[0])
}

/// Asks for the value of parameter `key`: a value given at its prompt.
fn ask_param(p: &mut Prompter, prompt: &'static str, key: &str) -> Result<Given, PromptError> {
    let r = row(key);
    let value = ask(p, prompt, |s| r.kind.parse_text(s))?;
    Ok(Given { key: r.key, value, from: Source::Prompt(prompt) })
}

/// A mesh file that exists and reads as a mesh (read here, when it is
/// named, so a wrong file is caught at its own question).
fn mesh(s: &str) -> Result<MeshSource, MeshAnswerError> {
    let source = super::in_path(s).map(MeshSource::File)?;
    source.load()?;
    Ok(source)
}

/// Why a mesh named at its prompt is refused: no such file, or not a mesh.
#[derive(Debug, thiserror::Error)]
enum MeshAnswerError {
    #[error(transparent)]
    Name(#[from] ValueError),
    #[error(transparent)]
    Mesh(#[from] crate::mesh::MeshError),
}

/// The report's "0 = No, 1 = Yes".
fn yes_no(s: &str) -> Result<bool, ValueError> {
    match s.trim() {
        "0" => Ok(false),
        "1" => Ok(true),
        o => Err(ValueError::NotYesNo(o.into())),
    }
}

/// The report's thirteen answers: each field a value given at its
/// question, and the output image's name.
pub struct Answers {
    pub given: Vec<Given>,
    pub out: PathBuf,
}

/// Asks the report's thirteen questions, in its order.
pub fn answers(p: &mut Prompter) -> Result<Answers, PromptError> {
    let mut given = vec![ask_param(p, "Maximum ray trace count", "trace")?, ask_param(p, "Opacity of object (0-100)", "opacity")?];
    const COLOUR: &str = "RGB color of object, int in [0,255]";
    writeln!(p.out, "{COLOUR}")?;
    let rgb = [ask(p, "R", channel)?, ask(p, "G", channel)?, ask(p, "B", channel)?];
    given.push(Given { key: "object_colour", value: Value::Rgb(rgb), from: Source::Prompt(COLOUR) });
    let out = ask(p, "File name of output file", super::out_path)?;
    const OFF: &str = "File name of .off file";
    let off = ask(p, OFF, mesh)?;
    given.push(Given { key: "off", value: Value::Text(off.to_string()), from: Source::Prompt(OFF) });
    const COFF: &str = "Is entered .off file in color off format? (0 = No, 1 = Yes)";
    given.push(Given { key: "coff", value: Value::Flag(ask(p, COFF, yes_no)?), from: Source::Prompt(COFF) });
    given.push(ask_param(p, "Scale Factor", "scale")?);
    let rot = [ask(p, "X rotation (degrees)", parse_real)?, ask(p, "Y rotation (degrees)", parse_real)?, ask(p, "Z rotation (degrees)", parse_real)?];
    given.push(Given { key: "rot", value: Value::Triple(rot), from: Source::Prompt("X, Y and Z rotation (degrees)") });
    given.push(ask_param(p, "Refractive Index", "ior")?);
    Ok(Answers { given, out })
}

/// Fills the report's thirteen fields of `base` from the answers; the other
/// settings (shininess, size, ...) stay as `base` has them.
pub fn ask_all(p: &mut Prompter, base: InteriorConfig) -> Result<InteriorConfig, PromptError> {
    let a = answers(p)?;
    let mut c = base;
    super::given::apply(PARAMS, &mut c, &a.given);
    c.out = a.out;
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
        let c = ask_all(&mut Prompter::new(&mut text.as_bytes(), &mut out, true), base()).unwrap();
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
        let e = ask_all(&mut Prompter::new(&mut "0\n25\n".as_bytes(), &mut Vec::new(), true), base()).unwrap_err();
        assert_eq!(e.to_string(), "input ended before an answer to \"R\"");
    }

    /// From a pipe, the first bad answer stops the run, naming its line,
    /// the question and the answer; a file that is not a mesh is caught at
    /// the mesh's own question.
    #[test]
    fn piped_answers_stop_at_the_first_bad_one() {
        let e = ask_all(&mut Prompter::new(&mut "0\n25\n255\n999\n0\n".as_bytes(), &mut Vec::new(), false), base()).unwrap_err();
        assert_eq!(e.to_string(), "line 4 of standard input: `999` is no answer to \"G\": 999 is outside 0-255");
        let readme = concat!(env!("CARGO_MANIFEST_DIR"), "/README.md");
        let text = format!("0\n25\n255\n255\n255\nout.png\n{readme}\n0\n1\n0\n0\n0\n1.4\n");
        let e = ask_all(&mut Prompter::new(&mut text.as_bytes(), &mut Vec::new(), false), base()).unwrap_err().to_string();
        assert!(e.starts_with(&format!("line 7 of standard input: `{readme}` is no answer to \"File name of .off file\": {readme}:")), "{e}");
        // Tokens as `cin >>` reads them: several to a line, blank lines
        // skipped; an error names the line the bad token is on.
        let off = concat!(env!("CARGO_MANIFEST_DIR"), "/off/cube.off");
        let lines = format!("0\n25\n255\n255\n255\nout.png\n{off}\n0\n1\n0\n0\n0\n1.4\n");
        let tokens = format!("\n  0 25\t255 255 255\n\nout.png {off} 0 1\n0 0 0 1.4");
        let a = ask_all(&mut Prompter::new(&mut lines.as_bytes(), &mut Vec::new(), false), base()).unwrap();
        let b = ask_all(&mut Prompter::new(&mut tokens.as_bytes(), &mut Vec::new(), false), base()).unwrap();
        assert_eq!(a, b);
        let e = ask_all(&mut Prompter::new(&mut "\n0 25\n\n255 999 0".as_bytes(), &mut Vec::new(), false), base()).unwrap_err();
        assert_eq!(e.to_string(), "line 4 of standard input: `999` is no answer to \"G\": 999 is outside 0-255");
        let e = ask_all(&mut Prompter::new(&mut "\n".repeat(5000).as_bytes(), &mut Vec::new(), false), base()).unwrap_err();
        assert_eq!(e.to_string(), "more than 4096 blank lines before an answer to \"Maximum ray trace count\"");
        // Unreadable input: the reason once, as the program prints errors.
        let e = ask_all(&mut Prompter::new(&mut &b"\xff\xfe\n"[..], &mut Vec::new(), false), base()).unwrap_err();
        assert_eq!(e.to_string(), "reading standard input: stream did not contain valid UTF-8");
        assert!(std::error::Error::source(&e).is_none(), "a source would print the reason again");
    }

    /// Each answer is a value given at its question, checked by its row.
    #[test]
    fn each_answer_is_a_value_given_at_its_question() {
        let off = concat!(env!("CARGO_MANIFEST_DIR"), "/off/cube.off");
        let text = format!("3 25 255 0 0 out.png {off} 0 1.5 10 20 30 1.4\n");
        let a = answers(&mut Prompter::new(&mut text.as_bytes(), &mut Vec::new(), false)).unwrap();
        let by = |k: &str| a.given.iter().find(|g| g.key == k).unwrap();
        assert_eq!(by("opacity").at(), "the answer to \"Opacity of object (0-100)\"");
        assert_eq!((by("trace").value.count(), by("ior").value.real()), (3, 1.4));
        assert_eq!(by("object_colour").value, Value::Rgb([255, 0, 0]));
        assert_eq!(by("rot").value, Value::Triple([10.0, 20.0, 30.0]));
        assert_eq!((a.given.len(), a.out), (8, PathBuf::from("out.png")));
    }
}
