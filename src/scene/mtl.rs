//! The one thing of a Wavefront material library (`.mtl`, named by an OBJ's `mtllib`) that changes
//! AO: `map_d`, the dissolve texture, used as an alpha *mask* (Sponza's plants and chains carry their
//! cut-outs this way). Everything else is shading and ignored, including the scalar `d` and `Tr`:
//! they blend (a half-transparent glass pane), they cut nothing out, and exporters write `d 0` on
//! solid materials often enough that honouring it would hollow scenes out.
//!
//! A `map_d` texel is opaque iff its value (after `-mm base gain`: base + gain × value) is at least
//! 0.5 — the glTF default `alphaCutoff`, as OBJ has no cutoff of its own; the value is `-imfchan`'s
//! channel, or the alpha channel of an image that has one, else its luminance. Options follow the
//! MTL specification (Wavefront's "MTL material format", Lee 1995): `-o` and `-s` move and scale the
//! texture coordinates, `-clamp on` clamps them instead of repeating; `-blendu`, `-blendv`, `-boost`,
//! `-texres`, `-cc` and `-bm` change nothing a nearest-texel mask reads and are accepted; `-t`
//! (turbulence) is refused.

use super::alpha::Channel;

/// A material's `map_d` as the library states it.
#[derive(Debug, Clone, PartialEq)]
pub struct MapD {
    /// The texture file, relative to the library (`\` read as `/`).
    pub file: String,
    /// The `map_d` line in the library.
    pub line: usize,
    pub channel: Option<Channel>,
    pub clamp: bool,
    /// `-o u v`, `-s u v` (texture coordinates become uv × scale + offset).
    pub offset: [f32; 2],
    pub scale: [f32; 2],
    /// `-mm base gain`.
    pub base: f32,
    pub gain: f32,
}

/// A `newmtl` and its mask, if it has one.
#[derive(Debug, Clone, PartialEq)]
pub struct Material {
    pub name: String,
    pub map_d: Option<MapD>,
}

/// Reads a library's text; the error says where (line) and what.
pub fn parse(text: &str) -> Result<Vec<Material>, String> {
    let mut out: Vec<Material> = Vec::new();
    for (no, line) in text.lines().enumerate() {
        let line_no = no + 1;
        let content = line.split('#').next().unwrap_or_default().trim();
        let Some(keyword) = content.split_whitespace().next() else { continue };
        let rest = content[keyword.len()..].trim();
        match keyword {
            "newmtl" => {
                if rest.is_empty() {
                    return Err(format!("line {line_no}: `newmtl` needs a material name"));
                }
                out.push(Material { name: rest.to_string(), map_d: None });
            }
            "map_d" => {
                let Some(m) = out.last_mut() else {
                    return Err(format!("line {line_no}: `map_d` before any `newmtl`"));
                };
                m.map_d = Some(map_d(rest, line_no)?);
            }
            _ => {}
        }
    }
    Ok(out)
}

/// The options and file name of a `map_d` statement.
fn map_d(rest: &str, line_no: usize) -> Result<MapD, String> {
    let mut m = MapD {
        file: String::new(),
        line: line_no,
        channel: None,
        clamp: false,
        offset: [0.0; 2],
        scale: [1.0; 2],
        base: 0.0,
        gain: 1.0,
    };
    let words: Vec<&str> = rest.split_whitespace().collect();
    let mut k = 0;
    // The numbers after an option (up to `max`, at least `min`).
    let numbers = |k: &mut usize, option: &str, min: usize, max: usize| -> Result<Vec<f32>, String> {
        let mut v = Vec::new();
        while v.len() < max && *k < words.len() {
            match words[*k].parse::<f32>() {
                Ok(x) if x.is_finite() => v.push(x),
                _ => break,
            }
            *k += 1;
        }
        if v.len() < min {
            return Err(format!("line {line_no}: map_d option {option} needs {min} number(s)"));
        }
        Ok(v)
    };
    let on_off = |k: &mut usize, option: &str| -> Result<bool, String> {
        let v = words.get(*k).copied();
        *k += 1;
        match v {
            Some("on") => Ok(true),
            Some("off") => Ok(false),
            _ => Err(format!("line {line_no}: map_d option {option} takes on or off")),
        }
    };
    while k < words.len() && words[k].starts_with('-') {
        let option = words[k];
        k += 1;
        match option {
            "-clamp" => m.clamp = on_off(&mut k, option)?,
            "-blendu" | "-blendv" | "-cc" => {
                on_off(&mut k, option)?;
            }
            "-boost" | "-texres" | "-bm" => {
                numbers(&mut k, option, 1, 1)?;
            }
            "-o" | "-s" => {
                let v = numbers(&mut k, option, 1, 3)?;
                let target = if option == "-o" { &mut m.offset } else { &mut m.scale };
                target[0] = v[0];
                if let Some(&y) = v.get(1) {
                    target[1] = y;
                }
            }
            "-mm" => {
                let v = numbers(&mut k, option, 2, 2)?;
                (m.base, m.gain) = (v[0], v[1]);
            }
            "-imfchan" => {
                let c = words.get(k).copied();
                k += 1;
                m.channel = Some(match c {
                    Some("r") => Channel::Red,
                    Some("g") => Channel::Green,
                    Some("b") => Channel::Blue,
                    Some("m") => Channel::Alpha,
                    Some("l") => Channel::Luminance,
                    _ => {
                        return Err(format!(
                            "line {line_no}: map_d -imfchan takes r, g, b, m (matte: alpha) or l (luminance), \
                             found '{}'",
                            c.unwrap_or_default()
                        ));
                    }
                });
            }
            "-t" => {
                return Err(format!(
                    "line {line_no}: map_d option -t (turbulence) is not supported: a mask is read at the \
                     texture coordinates as written"
                ));
            }
            _ => {
                return Err(format!(
                    "line {line_no}: map_d option '{option}' is not one hemilab knows (it reads -clamp, -imfchan, \
                     -o, -s, -mm, and accepts -blendu, -blendv, -boost, -texres, -cc, -bm)"
                ));
            }
        }
    }
    // The file name is the rest (it may contain spaces); Windows exporters write `\`.
    m.file = words[k.min(words.len())..].join(" ").replace('\\', "/");
    if m.file.is_empty() {
        return Err(format!("line {line_no}: map_d needs a texture file name"));
    }
    Ok(m)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn materials_and_their_masks() {
        let text = "# two\nnewmtl leaf green\nKd 0 1 0\nd 0\nmap_d -clamp on -imfchan r -o 0.5 0.25 -s 2 -mm 0.1 0.8 \
                    -boost 2 textures\\leaf mask.png\n\nnewmtl bark\nmap_Kd bark.png\n";
        let m = parse(text).unwrap();
        assert_eq!(m.len(), 2);
        assert_eq!((m[0].name.as_str(), m[1].name.as_str(), &m[1].map_d), ("leaf green", "bark", &None));
        let d = m[0].map_d.clone().unwrap();
        assert_eq!(
            (d.file.as_str(), d.line, d.channel, d.clamp),
            ("textures/leaf mask.png", 5, Some(Channel::Red), true)
        );
        assert_eq!((d.offset, d.scale, d.base, d.gain), ([0.5, 0.25], [2.0, 1.0], 0.1, 0.8));
    }

    #[test]
    fn faults_name_their_line() {
        for (text, want) in [
            ("map_d a.png\n", "line 1: `map_d` before any `newmtl`"),
            ("newmtl\n", "line 1: `newmtl` needs a material name"),
            ("newmtl a\nmap_d -clamp\n", "line 2: map_d option -clamp takes on or off"),
            ("newmtl a\nmap_d -t 1 1 a.png\n", "line 2: map_d option -t (turbulence) is not supported"),
            ("newmtl a\nmap_d -foo a.png\n", "line 2: map_d option '-foo' is not one hemilab knows"),
            ("newmtl a\nmap_d -imfchan z a.png\n", "line 2: map_d -imfchan takes r, g, b, m"),
            ("newmtl a\nmap_d -mm 1 a.png\n", "line 2: map_d option -mm needs 2 number(s)"),
            ("newmtl a\nmap_d -s 2\n", "line 2: map_d needs a texture file name"),
        ] {
            let e = parse(text).err().unwrap_or_default();
            assert!(e.starts_with(want), "{text:?}: want '{want}', got '{e}'");
        }
    }
}
