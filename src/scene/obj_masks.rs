//! An OBJ file's alpha masks: its material libraries (`mtllib`) read, the materials its faces use
//! (`usemtl`) looked up, and each one with a `map_d` (`scene::mtl`) made a cutout from its texture.
//! The texture coordinates are OBJ's, whose v = 0 is the image's *bottom* row; `alpha::Cutout`
//! counts rows from the top (glTF's convention), so v is flipped: v' = 1 − v.

use super::alpha::{Cutout, SOLID, Source, Wrap};
use super::obj::{NO_TEXCOORD, Parsed};
use super::{alpha, mtl};

/// Reads a file a mesh names (a path relative to the mesh file, `/`-separated) to its bytes.
pub type Fetch<'a> = &'a mut dyn FnMut(&str) -> Result<Vec<u8>, String>;

/// A masked material: its cutout, and its `-o` offset and `-s` scale of the texture coordinates.
#[derive(Debug, Clone, Copy)]
struct Placed {
    cutout: u32,
    offset: [f32; 2],
    scale: [f32; 2],
}

/// A decoded texture: width, height, one value per texel.
type Decoded = (u32, u32, Vec<f32>);

/// What the masked materials need per triangle.
pub struct Masks {
    /// Per material of `Parsed::materials`, its mask if it has one.
    per_material: Vec<Option<Placed>>,
    pub cutouts: Vec<Cutout>,
    /// The libraries' and textures' bytes (hashed with the scene).
    pub bytes: Vec<Vec<u8>>,
}

impl Masks {
    /// Records the next kept triangle: its corners are `corners` (indices into `parsed.corners`),
    /// its material `material` (None before the first `usemtl`).
    pub fn push(&self, source: &mut Source, material: Option<usize>, parsed: &Parsed, corners: [usize; 3]) {
        match material.and_then(|m| self.per_material[m]) {
            Some(Placed { cutout, offset, scale }) => {
                let uv = corners.map(|c| {
                    let t = parsed.corner_texcoords[c];
                    debug_assert!(t != NO_TEXCOORD, "checked by `masks`");
                    let [u, v] = parsed.texcoords[t as usize];
                    [u * scale[0] + offset[0], 1.0 - (v * scale[1] + offset[1])]
                });
                source.push(cutout, uv);
            }
            None => source.push(SOLID, [[0.0; 2]; 3]),
        }
    }
}

/// The masks of `parsed`'s materials, None if no material its faces use has a `map_d`. `fetch`
/// reads a file named relative to the OBJ file; a library it cannot read is a note (`notes`).
pub fn masks(parsed: &Parsed, fetch: Fetch<'_>, notes: &mut Vec<String>) -> Result<Option<Masks>, String> {
    if parsed.material_runs.is_empty() || parsed.libraries.is_empty() {
        return Ok(None);
    }
    let mut bytes = Vec::new();
    // Every material defined, with the library that defines it first.
    let mut defined: Vec<(mtl::Material, String)> = Vec::new();
    let mut read = Vec::new();
    for (lib, line) in &parsed.libraries {
        if read.contains(lib) {
            continue;
        }
        read.push(lib.clone());
        let b = match fetch(lib) {
            Ok(b) => b,
            Err(e) => {
                notes.push(format!(
                    "material library '{lib}' (mtllib on line {line}): {e}; its materials render solid (no map_d \
                     cut-outs)"
                ));
                continue;
            }
        };
        let at = |e: String| format!("material library '{lib}' (mtllib on line {line}): {e}");
        let text = std::str::from_utf8(&b).map_err(|_| at("not UTF-8 text (is this an MTL file?)".into()))?;
        for m in mtl::parse(text).map_err(at)? {
            if !defined.iter().any(|(d, _)| d.name == m.name) {
                defined.push((m, lib.clone()));
            }
        }
        bytes.push(b);
    }
    let mut per_material = vec![None; parsed.materials.len()];
    let mut cutouts = Vec::new();
    let mut textures: Vec<(String, Decoded)> = Vec::new();
    let mut undefined = Vec::new();
    for (k, name) in parsed.materials.iter().enumerate() {
        let Some((m, lib)) = defined.iter().find(|(d, _)| &d.name == name) else {
            undefined.push(k);
            continue;
        };
        let Some(d) = &m.map_d else { continue };
        let at =
            |e: String| format!("material library '{lib}', line {}: map_d texture '{}': {e}", d.line, d.file);
        let path = beside(lib, &d.file);
        let decoded = match textures.iter().position(|t| t.0 == path) {
            Some(i) => &textures[i].1,
            None => {
                let b = fetch(&path).map_err(at)?;
                let image = alpha::decode(&b, d.channel, &d.file).map_err(at)?;
                bytes.push(b);
                textures.push((path, image));
                &textures.last().expect("pushed").1
            }
        };
        let (w, h, values) = decoded;
        let wrap = if d.clamp { Wrap::Clamp } else { Wrap::Repeat };
        // Opaque iff base + gain × value >= 0.5, that is gain × value >= 0.5 − base.
        cutouts.push(Cutout::new(*w, *h, values, d.gain, 0.5 - d.base, [wrap; 2]));
        per_material[k] = Some(Placed { cutout: cutouts.len() as u32 - 1, offset: d.offset, scale: d.scale });
    }
    if let Some(&first) = undefined.first()
        && !bytes.is_empty()
    {
        let line = parsed.material_runs.iter().find(|r| r.material as usize == first).map_or(0, |r| r.line);
        notes.push(format!(
            "{} material(s) used by `usemtl` are defined in no material library read (first: '{}', line \
             {line}); they render solid",
            undefined.len(),
            parsed.materials[first]
        ));
    }
    if cutouts.is_empty() {
        return Ok(None);
    }
    for run in &parsed.material_runs {
        if let (Some(line), Some(_)) = (run.untextured, per_material[run.material as usize]) {
            return Err(format!(
                "line {line}: a face of material '{}' has a corner without a texture coordinate, but the \
                 material is masked by a map_d texture, which needs them (`f v/vt …` at every corner)",
                parsed.materials[run.material as usize]
            ));
        }
    }
    Ok(Some(Masks { per_material, cutouts, bytes }))
}

/// A file named in a library, as a path relative to the OBJ file (the library's folder joined).
fn beside(library: &str, file: &str) -> String {
    let dir = std::path::Path::new(library).parent().unwrap_or(std::path::Path::new(""));
    dir.join(file).to_string_lossy().replace('\\', "/")
}
