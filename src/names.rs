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

    /// The value of a name (ASCII case-insensitive).
    fn from_name(s: &str) -> Option<Self> {
        Self::VALUES.iter().find(|v| v.1.eq_ignore_ascii_case(s.trim())).map(|v| v.0)
    }

    /// Names and descriptions, for help texts and error messages.
    fn choices() -> Vec<(&'static str, &'static str)> {
        Self::VALUES.iter().map(|v| (v.1, v.2)).collect()
    }
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
    use super::Named;

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
        assert_eq!(Fruit::choices(), vec![("apple", "Red and round."), ("banana", "Long and yellow; two doc lines.")]);
    }
}
