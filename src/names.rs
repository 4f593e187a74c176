//! Enums whose values have names: what a user types on the command line or
//! writes in a scene file, and a one-line description for help texts. The
//! physics defines its enums with `named_enum!`; the command line builds
//! its choices from `Named::VALUES`, so no physics type depends on clap.

/// An enum with a name and a description for each value.
pub trait Named: Copy + PartialEq + Sized + 'static {
    /// Every value with its name and description, in the order shown.
    const VALUES: &'static [(Self, &'static str, &'static str)];

    fn name(self) -> &'static str {
        Self::VALUES.iter().find(|v| v.0 == self).map_or("?", |v| v.1)
    }

    /// The value of a name, ignoring case, spaces, `-` and `_` (`key`).
    fn from_name(s: &str) -> Option<Self> {
        Self::VALUES.iter().find(|v| key(v.1) == key(s)).map(|v| v.0)
    }

    /// Names and descriptions, for help texts and error messages.
    fn choices() -> Vec<(&'static str, &'static str)> {
        Self::VALUES.iter().map(|v| (v.1, v.2)).collect()
    }
}

/// A name as it is matched: its ASCII letters and digits, lower case, so
/// `Fused Silica`, `fused-silica` and `FUSED_SILICA` are one name.
pub fn key(s: &str) -> String {
    s.chars().filter(|c| c.is_ascii_alphanumeric()).collect::<String>().to_ascii_lowercase()
}

/// Edit distance (Levenshtein) between two strings, by characters.
fn distance(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut row: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.chars().enumerate() {
        let mut prev = row[0];
        row[0] = i + 1;
        for (j, cb) in b.iter().enumerate() {
            let here = row[j + 1];
            row[j + 1] = (prev + usize::from(ca != *cb)).min(row[j] + 1).min(here + 1);
            prev = here;
        }
    }
    row[b.len()]
}

/// The candidate nearest to `typed`, for a "did you mean" hint: by edit
/// distance between keys (at most a third of the typed key, and at least
/// 2 allowed), or one key holding the other (`colour` in `object-colour`);
/// `None` when nothing is near.
pub fn nearest<'a>(typed: &str, candidates: impl IntoIterator<Item = &'a str>) -> Option<&'a str> {
    let t = key(typed);
    if t.is_empty() {
        return None;
    }
    let limit = (t.len() / 3).max(2);
    candidates
        .into_iter()
        .filter_map(|c| {
            let k = key(c);
            let d = if k.len() >= 3 && t.len() >= 3 && (k.contains(&t) || t.contains(&k)) { 1 } else { distance(&t, &k) };
            (d <= limit).then_some(((d, k.len().abs_diff(t.len())), c))
        })
        .min_by_key(|(d, _)| *d)
        .map(|(_, c)| c)
}

/// ` (did you mean `x`?)` for the nearest candidate, or nothing.
pub fn did_you_mean<'a>(typed: &str, candidates: impl IntoIterator<Item = &'a str>) -> String {
    nearest(typed, candidates).map_or(String::new(), |c| format!(" (did you mean `{c}`?)"))
}

/// Declares an enum and its `Named` table: each variant's name after `=`,
/// its doc comment as the description.
///
/// ```ignore
/// named_enum! {
///     /// Photon storage.
///     pub enum MapKind {
///         /// The report's per-object buffer.
///         Buffer = "buffer",
///     }
/// }
/// ```
#[macro_export]
macro_rules! named_enum {
    ($(#[$meta:meta])* $vis:vis enum $name:ident { $($(#[doc = $doc:literal])+ $variant:ident = $text:literal),+ $(,)? }) => {
        $(#[$meta])*
        #[derive(Copy, Clone, Debug, PartialEq, Eq)]
        $vis enum $name { $($(#[doc = $doc])+ $variant),+ }

        impl $crate::names::Named for $name {
            const VALUES: &'static [(Self, &'static str, &'static str)] = &[$(($name::$variant, $text, $crate::names::__trim(concat!($($doc),+)))),+];
        }

        impl $name {
            /// The value's name, as typed on the command line.
            pub fn name(self) -> &'static str {
                match self { $($name::$variant => $text),+ }
            }
        }
    };
}

/// Doc comments start with a space; descriptions do not.
#[doc(hidden)]
pub const fn __trim(s: &'static str) -> &'static str {
    match s.as_bytes() {
        [b' ', ..] => {
            let (_, rest) = s.split_at(1);
            rest
        }
        _ => s,
    }
}

#[cfg(test)]
mod tests {
    use super::{nearest, Named};

    #[test]
    fn nearest_names_a_close_candidate_or_none() {
        let keys = ["offset", "opacity", "object_colour", "colour_map", "trace"];
        assert_eq!(nearest("ofset", keys), Some("offset"));
        assert_eq!(nearest("colour", keys), Some("colour_map"), "the shortest key holding it");
        assert_eq!(nearest("opacty", keys), Some("opacity"));
        assert_eq!(nearest("zebra", keys), None);
        assert_eq!(nearest("fused-silica", ["N-BK7", "FUSED SILICA"]), Some("FUSED SILICA"));
        assert_eq!(nearest("nbk8", ["N-BK7", "FUSED SILICA"]), Some("N-BK7"));
    }

    crate::named_enum! {
        /// A test enum.
        pub enum Fruit {
            /// Red and round.
            Apple = "apple",
            /// Long and yellow;
            /// two doc lines.
            Banana = "banana",
        }
    }

    #[test]
    fn names_round_trip_and_describe() {
        assert_eq!(Fruit::Banana.name(), "banana");
        assert_eq!(<Fruit as Named>::name(Fruit::Apple), "apple");
        assert_eq!(Fruit::from_name(" APPLE"), Some(Fruit::Apple));
        assert_eq!(Fruit::from_name("cherry"), None);
        assert_eq!(Fruit::from_name("Ban-ana"), Some(Fruit::Banana), "case and separators aside");
        assert_eq!(Fruit::choices(), vec![("apple", "Red and round."), ("banana", "Long and yellow; two doc lines.")]);
    }
}
