//! Where a key stands in a scene or experiment file: its line, from the
//! TOML parser's own spans (`toml::de::DeTable`), so an error names the
//! exact line of the key, in a `[section]`, a `[[section]]` entry, an
//! inline table (`fixed = { trace = 2 }`) or a dotted key alike.

use toml::de::{DeTable, DeValue};
use toml::Spanned;

/// A parsed file's keys and their places.
pub struct KeyLines<'t> {
    text: &'t str,
    root: Option<Spanned<DeTable<'t>>>,
}

impl<'t> KeyLines<'t> {
    /// The keys of `text` (a file that does not parse has none: its syntax
    /// error is reported, with its line, before any key is looked at).
    pub fn new(text: &'t str) -> KeyLines<'t> {
        KeyLines { text, root: DeTable::parse(text).ok() }
    }

    /// The 1-based line of `key` in table `section` (dotted, `""` for the
    /// top level; where a part is an array of tables, its `nth` entry,
    /// counted from 0). A key that is not there: the line of the deepest
    /// table of `section` that is (a missing key is reported where it
    /// belongs); a file that did not parse: line 1.
    pub fn line(&self, section: &str, nth: usize, key: &str) -> usize {
        let (key_at, table_at) = self.find(section, nth, key);
        self.line_at(key_at.unwrap_or(table_at))
    }

    /// The byte where `key` of table `section` (as for `line`) is written,
    /// if it is: to keep keys in the file's order.
    pub fn offset(&self, section: &str, nth: usize, key: &str) -> Option<usize> {
        self.find(section, nth, key).0
    }

    /// Where `key` is written, if it is, and where the deepest table of
    /// `section` that is written starts.
    fn find(&self, section: &str, nth: usize, key: &str) -> (Option<usize>, usize) {
        let Some(root) = &self.root else { return (None, 0) };
        let mut at = 0;
        let mut table: &DeTable = root.get_ref();
        for part in section.split('.').filter(|p| !p.is_empty()) {
            let Some(v) = entry(table, part) else { return (None, at) };
            let v = match v.get_ref() {
                DeValue::Array(items) => match items.get(nth) {
                    Some(item) => item,
                    None => return (None, v.span().start),
                },
                _ => v,
            };
            at = v.span().start;
            match v.get_ref() {
                DeValue::Table(t) => table = t,
                _ => return (None, at),
            }
        }
        (table.iter().find(|(k, _)| k.get_ref() == key).map(|(k, _)| k.span().start), at)
    }

    fn line_at(&self, byte: usize) -> usize {
        1 + self.text.as_bytes()[..byte.min(self.text.len())].iter().filter(|&&b| b == b'\n').count()
    }
}

fn entry<'a, 't>(table: &'a DeTable<'t>, key: &str) -> Option<&'a Spanned<DeValue<'t>>> {
    table.iter().find(|(k, _)| k.get_ref() == key).map(|(_, v)| v)
}

#[cfg(test)]
mod tests {
    use super::*;

    const FILE: &str = "\
name = \"a\"   # line 1
fixed = { trace = 2,
  opacity = 50 }
[sweep]
# a comment with trace = 9 in it
trace = [1, 2]
[[case]]
name = \"one\"
[[case]]
name = \"two\"
params.opacity = 3
[outputs]
images = true
[[outputs.plot]]
x = \"trace\"
[[outputs.plot]]
y = \"seconds\"
";

    #[test]
    fn keys_are_found_by_their_spans_wherever_they_are_written() {
        let k = KeyLines::new(FILE);
        assert_eq!(k.line("", 0, "name"), 1);
        assert_eq!(k.line("fixed", 0, "opacity"), 3, "inside an inline table");
        assert_eq!(k.line("sweep", 0, "trace"), 6, "not the comment above it");
        assert_eq!(k.line("case", 1, "name"), 10, "the second [[case]]");
        assert_eq!(k.line("case.params", 1, "opacity"), 11, "a dotted key");
        assert_eq!(k.line("outputs.plot", 1, "y"), 17);
        assert_eq!(k.line("outputs", 0, "images"), 13);
    }

    #[test]
    fn a_missing_key_is_placed_at_its_table() {
        let k = KeyLines::new(FILE);
        assert_eq!(k.line("case", 0, "mode"), 7, "the first [[case]] has no mode");
        assert_eq!(k.line("outputs.plot", 0, "y"), 14);
        assert_eq!(k.line("nowhere", 0, "x"), 1);
        assert_eq!(KeyLines::new("a = [").line("", 0, "a"), 1, "a file that does not parse");
    }
}
