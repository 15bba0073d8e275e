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

// Seed modes: the built-ins by the macro's rules, a texture by its results name (`texture`).
const SEED_NAMES: &[(&str, SeedMode)] = &[
    ("static", SeedMode::Static),
    ("rotation", SeedMode::Rotation),
    ("shift", SeedMode::Shift),
    ("blue-noise", SeedMode::BlueNoise),
    ("stbn", SeedMode::Stbn),
    ("ign", SeedMode::Ign),
    ("bayer", SeedMode::Bayer),
    ("magic-square", SeedMode::MagicSquare),
    ("r2-dither", SeedMode::R2Dither),
];
const SEED_WORDS: &[(&str, SeedMode)] = &[
    ("per-pixel", SeedMode::Rotation),
    ("per-pixel seed", SeedMode::Rotation),
    ("random seed per pixel", SeedMode::Rotation),
    ("random", SeedMode::Rotation),
    ("static seed", SeedMode::Static),
    ("blue noise", SeedMode::BlueNoise),
    ("bluenoise", SeedMode::BlueNoise),
    ("spatiotemporal blue noise", SeedMode::Stbn),
    ("spatiotemporal blue-noise", SeedMode::Stbn),
    ("interleaved gradient noise", SeedMode::Ign),
    ("interleaved-gradient-noise", SeedMode::Ign),
    ("bayer4", SeedMode::Bayer),
    ("bayer 4x4", SeedMode::Bayer),
    ("magic square", SeedMode::MagicSquare),
    ("magic5", SeedMode::MagicSquare),
    ("r2 dither", SeedMode::R2Dither),
    ("r2dither", SeedMode::R2Dither),
];

impl SeedMode {
    /// Every built-in seed mode, in the order tables and listings use (textures are the user's:
    /// `load::texture` registers them).
    pub const ALL: &'static [SeedMode] = &[
        SeedMode::Static,
        SeedMode::Rotation,
        SeedMode::Shift,
        SeedMode::BlueNoise,
        SeedMode::Stbn,
        SeedMode::Ign,
        SeedMode::Bayer,
        SeedMode::MagicSquare,
        SeedMode::R2Dither,
    ];
    /// Every built-in name, in the order of `ALL`.
    pub const NAMES: &'static [&'static str] =
        &["static", "rotation", "shift", "blue-noise", "stbn", "ign", "bayer", "magic-square", "r2-dither"];

    /// The name specs, the command line and `results.csv` use; a texture's names its file as the
    /// spec wrote it, its use and its content hash: `texture:masks/x_%d.png:offset#1a2b3c4d`.
    pub fn name(self) -> &'static str {
        match self {
            SeedMode::Texture(t) => t.get().name(),
            m => SEED_NAMES.iter().find(|(_, v)| *v == m).map_or("?", |(n, _)| n),
        }
    }
}

impl FromStr for SeedMode {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        if let Some((_, m)) = SEED_NAMES.iter().find(|(n, _)| *n == s) {
            return Ok(*m);
        }
        if let Some(t) = super::texture::find(s) {
            return Ok(SeedMode::Texture(t));
        }
        let said = s.trim().to_lowercase();
        let meant = SEED_WORDS.iter().find(|(w, _)| *w == said).map(|(_, m)| *m);
        let s = s.escape_debug();
        let hint = meant.map_or(String::new(), |m| format!(" ('{s}' is written `{}`)", m.name()));
        let texture = if said.starts_with("texture") {
            " (a texture file is named `texture:PATH[:offset|rotation|vector]` on the command line and \
             `{ texture = \"PATH\", use = \"offset\" }` in a spec)"
        } else {
            ""
        };
        Err(format!("unknown seed mode '{s}'; valid: {}{hint}{texture}", SeedMode::NAMES.join(", ")))
    }
}

impl std::fmt::Display for SeedMode {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

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
