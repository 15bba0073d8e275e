//! A small denoiser for `denoise_command`, as a user would write one: reads hemilab's input EXR
//! (channels in `hemilab::denoise_command`), averages each covered pixel over the covered pixels of
//! its 5 × 5 neighbourhood whose normal is within about 26° of its own (n · n' ≥ 0.9, so it does
//! not blur across a crease), and writes the result as an EXR with `Y` (and `A`, the coverage).
//! Background pixels are copied. The tests run it as the user's command; `examples/oidn_denoise.py`
//! plugs in Intel Open Image Denoise the same way.
//!
//! Usage: `denoise_box INPUT.exr OUTPUT.exr`

use hemilab::image::{Channel, Image};
use std::path::Path;
use std::process::ExitCode;

/// Half-side of the box: 2 gives 5 × 5.
const RADIUS: i64 = 2;
/// Least n · n' of a neighbour that is averaged in.
const NORMAL_COS: f32 = 0.9;

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().collect();
    if args.len() != 3 {
        eprintln!("usage: denoise_box INPUT.exr OUTPUT.exr");
        return ExitCode::from(2);
    }
    match denoise(Path::new(&args[1]), Path::new(&args[2])) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("denoise_box: {e}");
            ExitCode::from(1)
        }
    }
}

fn denoise(input: &Path, output: &Path) -> Result<(), String> {
    let channels = hemilab::io::read_exr(input).map_err(|e| e.to_string())?;
    let get = |name: &str| {
        channels
            .iter()
            .find(|(n, _)| n == name)
            .map(|(_, i)| i)
            .ok_or(format!("{}: no channel {name}", input.display()))
    };
    let (value, coverage) = (get("R")?, get("A")?);
    let normal = [get("N.X")?, get("N.Y")?, get("N.Z")?];
    let (w, h) = (value.width as i64, value.height as i64);
    let n_at = |i: usize| [normal[0].data[i], normal[1].data[i], normal[2].data[i]];
    let dot = |a: [f32; 3], b: [f32; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    let mut out = value.data.clone();
    for y in 0..h {
        for x in 0..w {
            let i = (y * w + x) as usize;
            if coverage.data[i] <= 0.5 {
                continue;
            }
            let (mut sum, mut count) = (0.0f64, 0u32);
            for qy in (y - RADIUS).max(0)..=(y + RADIUS).min(h - 1) {
                for qx in (x - RADIUS).max(0)..=(x + RADIUS).min(w - 1) {
                    let q = (qy * w + qx) as usize;
                    if coverage.data[q] > 0.5 && dot(n_at(i), n_at(q)) >= NORMAL_COS {
                        sum += value.data[q] as f64;
                        count += 1;
                    }
                }
            }
            if count > 0 {
                out[i] = (sum / count as f64) as f32;
            }
        }
    }
    let result = Image::from_vec(value.width, value.height, out);
    hemilab::io::write_exr(
        output,
        &[Channel { name: "Y", image: &result }, Channel { name: "A", image: coverage }],
    )
    .map_err(|e| e.to_string())
}
