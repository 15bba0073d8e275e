//! The names the paper (and the CLI and spec files) use for each choice, in one place; the
//! sequences' names are their registry entries' (`registry::SequenceInfo`).

use super::{Distribution, Schedule, SeedMode};
use std::str::FromStr;

macro_rules! named {
    ($ty:ty, $what:literal, [$($variant:ident => $name:literal),+ $(,)?],
     words [$($word:literal => $meant:ident),* $(,)?]) => {
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
                    _ => {
                        // The report's words (`spec::Row::name`) are not values, but say which is meant.
                        let said = s.trim().to_lowercase();
                        let meant: Option<$ty> = match said.as_str() {
                            $($word => Some(<$ty>::$meant),)*
                            _ => None,
                        };
                        // Escaped (a newline in a TOML string would split the one-line error).
                        let s = s.escape_debug();
                        let hint = meant.map_or(String::new(), |m| format!(" ('{s}' is written `{}`)", m.name()));
                        Err(format!("unknown {} '{}'; valid: {}{hint}", $what, s, <$ty>::NAMES.join(", ")))
                    }
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
], words [
    "cosine" => SineCosine,
    "cosine-weighted" => SineCosine,
    "sinecosine" => SineCosine,
    "sine cosine" => SineCosine,
    "concentric" => ConcentricCosine,
]);

named!(SeedMode, "seed mode", [
    Static => "static",
    Rotation => "rotation",
    Shift => "shift",
    BlueNoise => "blue-noise",
    Stbn => "stbn",
], words [
    "per-pixel" => Rotation,
    "per-pixel seed" => Rotation,
    "random seed per pixel" => Rotation,
    "random" => Rotation,
    "static seed" => Static,
    "blue noise" => BlueNoise,
    "bluenoise" => BlueNoise,
    "spatiotemporal blue noise" => Stbn,
    "spatiotemporal blue-noise" => Stbn,
]);

named!(Schedule, "schedule", [
    Independent => "independent",
    R1 => "r1",
], words [
    "golden" => R1,
    "golden-ratio" => R1,
    "r2" => R1,
    "per-frame" => Independent,
]);

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::Sequence;

    #[test]
    fn names_round_trip_and_unknown_lists_choices() {
        for d in Distribution::ALL {
            assert_eq!(d.name().parse::<Distribution>().unwrap(), *d);
        }
        for s in Schedule::ALL {
            assert_eq!(s.name().parse::<Schedule>().unwrap(), *s);
        }
        assert!("golden".parse::<Schedule>().unwrap_err().ends_with("is written `r1`)"));
        let e = "cosine".parse::<Distribution>().unwrap_err();
        assert!(e.contains("sine-cosine") && e.contains("'cosine'"), "{e}");
        // The report's words point at the value they name.
        let e = "per-pixel".parse::<SeedMode>().unwrap_err();
        assert!(e.ends_with("('per-pixel' is written `rotation`)"), "{e}");
        let e = "Pseudo-random".parse::<Sequence>().unwrap_err();
        assert!(e.ends_with("('Pseudo-random' is written `random`)"), "{e}");
        assert!(!"gauss".parse::<Distribution>().unwrap_err().contains("written"));
    }
}
