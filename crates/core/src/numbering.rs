//! How steps and components are numbered wherever a person or a script sees
//! them (text, JSON, command-line arguments): from 1. Inside the solver they
//! are indices from 0; [`StepNo`] and [`ComponentNo`] are the one place the
//! two meet.

macro_rules! number {
    ($(#[$doc:meta])* $name:ident) => {
        $(#[$doc])*
        #[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
        pub struct $name(usize);

        impl $name {
            /// The number of the item at 0-based `index`.
            pub fn of_index(index: usize) -> Self {
                $name(index)
            }
            /// The 0-based index.
            pub fn index(self) -> usize {
                self.0
            }
            /// The number as people count: `index + 1`.
            pub fn number(self) -> usize {
                self.0 + 1
            }
            /// Read a number as people count (1, 2, …); `None` for 0 or a non-number.
            pub fn parse(text: &str) -> Option<Self> {
                text.trim().parse::<usize>().ok().and_then(|n| n.checked_sub(1)).map($name)
            }
        }

        impl std::fmt::Display for $name {
            fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                write!(f, "{}", self.number())
            }
        }

        #[cfg(feature = "serde")]
        impl serde::Serialize for $name {
            fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
                s.serialize_u64(self.number() as u64)
            }
        }

        #[cfg(feature = "serde")]
        impl schemars::JsonSchema for $name {
            fn schema_name() -> std::borrow::Cow<'static, str> {
                stringify!($name).into()
            }
            fn json_schema(_: &mut schemars::SchemaGenerator) -> schemars::Schema {
                schemars::json_schema!({ "type": "integer", "minimum": 1 })
            }
        }
    };
}

number!(
    /// A construction step as numbered for people: step 1 is index 0.
    StepNo
);
number!(
    /// A component as numbered for people: component 1 is index 0.
    ComponentNo
);
number!(
    /// A bar or body of the scene file as numbered for people (in file order, from 1).
    ItemNo
);

/// Serialize a 0-based step index as its number (`serialize_with`).
#[cfg(feature = "serde")]
pub(crate) fn step_number<S: serde::Serializer>(index: &usize, s: S) -> Result<S::Ok, S::Error> {
    serde::Serialize::serialize(&StepNo::of_index(*index), s)
}

/// Serialize a 0-based bar or body index as its number (`serialize_with`).
#[cfg(feature = "serde")]
pub(crate) fn item_number<S: serde::Serializer>(index: &usize, s: S) -> Result<S::Ok, S::Error> {
    serde::Serialize::serialize(&ItemNo::of_index(*index), s)
}
