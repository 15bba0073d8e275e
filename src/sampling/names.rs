//! The names the paper (and the CLI and spec files) use for each choice, in one place.

use super::{Distribution, SeedMode, Sequence};
use std::str::FromStr;

macro_rules! named {
    ($ty:ty, $what:literal, [$($variant:ident => $name:literal),+ $(,)?]) => {
        impl $ty {
            /// Every variant, in the order tables and listings use.
            pub const ALL: &'static [$ty] = &[$(<$ty>::$variant),+];
            /// Every accepted name, in the order of `ALL`.
            pub const NAMES: &'static [&'static str] = &[$($name),+];

            pub fn name(self) -> &'static str {
                match self { $(<$ty>::$variant => $name),+ }
            }
        }

        impl FromStr for $ty {
            type Err = String;
            fn from_str(s: &str) -> Result<Self, String> {
                match s {
                    $($name => Ok(<$ty>::$variant),)+
                    _ => Err(format!(
                        "unknown {} '{}'; valid: {}",
                        $what,
                        s,
                        <$ty>::NAMES.join(", ")
                    )),
                }
            }
        }

        impl std::fmt::Display for $ty {
            fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                f.write_str(self.name())
            }
        }
    };
}

named!(Distribution, "distribution", [
    Uniform => "uniform",
    Sine => "sine",
    SineCosine => "sine-cosine",
    ConcentricCosine => "concentric-cosine",
]);

named!(Sequence, "sequence", [
    Random => "random",
    Fibonacci => "fibonacci",
    Stratified => "stratified",
    Sobol => "sobol",
]);

named!(SeedMode, "seed mode", [
    Static => "static",
    Rotation => "rotation",
    Shift => "shift",
    BlueNoise => "blue-noise",
]);

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip_and_unknown_lists_choices() {
        for d in Distribution::ALL {
            assert_eq!(d.name().parse::<Distribution>().unwrap(), *d);
        }
        let e = "cosine".parse::<Distribution>().unwrap_err();
        assert!(e.contains("sine-cosine") && e.contains("'cosine'"), "{e}");
    }
}
