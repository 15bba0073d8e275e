//! Vertex attributes as numbers, whatever their component type: glTF 2.0 core stores positions and
//! texture coordinates as FLOAT (texture coordinates also as normalized UNSIGNED_BYTE/SHORT), and
//! `KHR_mesh_quantization` adds BYTE, UNSIGNED_BYTE, SHORT and UNSIGNED_SHORT, normalized or not,
//! for both (quantized meshes put the scale and offset back in the node transform or in
//! `KHR_texture_transform`). The `gltf` crate's readers take the bytes as f32 whatever the
//! accessor says, so each type is read as itself here and widened by the specification's rule for
//! normalized integers (glTF 2.0, section 3.11): a normalized signed value is
//! max(c / (2^(b-1) - 1), -1), an unsigned one c / (2^b - 1); a value that is not normalized is c.

use ::gltf::accessor::{DataType, Dimensions, Item, Iter};

/// The values of `accessor`, each element `N` numbers (`N` = 2 for VEC2, 3 for VEC3), or why not.
pub fn read<const N: usize>(accessor: &::gltf::Accessor, buffers: &[Vec<u8>]) -> Result<Vec<[f64; N]>, String>
where
    [f32; N]: Item,
    [i8; N]: Item,
    [u8; N]: Item,
    [i16; N]: Item,
    [u16; N]: Item,
    [u32; N]: Item,
{
    let want = match N {
        2 => Dimensions::Vec2,
        3 => Dimensions::Vec3,
        _ => unreachable!("positions and texture coordinates only"),
    };
    if accessor.dimensions() != want {
        return Err(format!("accessor {} is {:?}, not {want:?}", accessor.index(), accessor.dimensions()));
    }
    let norm = accessor.normalized();
    let got = match accessor.data_type() {
        DataType::F32 => items::<f32, N>(accessor, buffers, 1.0, false),
        DataType::I8 => items::<i8, N>(accessor, buffers, if norm { 127.0 } else { 1.0 }, norm),
        DataType::U8 => items::<u8, N>(accessor, buffers, if norm { 255.0 } else { 1.0 }, false),
        DataType::I16 => items::<i16, N>(accessor, buffers, if norm { 32767.0 } else { 1.0 }, norm),
        DataType::U16 => items::<u16, N>(accessor, buffers, if norm { 65535.0 } else { 1.0 }, false),
        DataType::U32 => items::<u32, N>(accessor, buffers, 1.0, false),
    };
    got.ok_or_else(|| format!("accessor {}: its data lies outside its buffer", accessor.index()))
}

/// Each element's components divided by `scale`, clamped at -1 if `clamp` (normalized signed).
fn items<T, const N: usize>(
    accessor: &::gltf::Accessor,
    buffers: &[Vec<u8>],
    scale: f64,
    clamp: bool,
) -> Option<Vec<[f64; N]>>
where
    T: Copy + Into<f64>,
    [T; N]: Item,
{
    let iter =
        Iter::<[T; N]>::new(accessor.clone(), |b: ::gltf::Buffer| buffers.get(b.index()).map(|d| &d[..]))?;
    Some(
        iter.map(|v| {
            v.map(|c| {
                let x = c.into() / scale;
                if clamp { x.max(-1.0) } else { x }
            })
        })
        .collect(),
    )
}
