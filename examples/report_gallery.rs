//! Writes one sample of every report figure from synthetic data, so the pictures can be looked at
//! without running an experiment: `cargo run --release --example report_gallery -- /tmp/gallery`.

use hemilab::image::Image;
use hemilab::report::figure_rows;
use hemilab::report::{self, Figure, Format, GridCell, Guide, Series, Table};
use hemilab::sampling::{Distribution, SeedMode, Sequence};
use std::path::PathBuf;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let dir = PathBuf::from(std::env::args().nth(1).unwrap_or_else(|| "/tmp/gallery".into()));
    let write = |name: &str, bytes: &[u8]| hemilab::io::write_atomic(&dir.join(name), bytes);

    let ds = [Distribution::Uniform, Distribution::Sine, Distribution::SineCosine];
    let rows = figure_rows(&ds, Sequence::Fibonacci, SeedMode::Static, &[500, 1000, 5000], 1)?;
    let title = "Table 1: Fibonacci lattice through the three distributions";
    write("table1.png", &report::point_panels(title, &rows, true, Format::Png)?)?;
    let fig2 = figure_rows(&ds[..1], Sequence::Random, SeedMode::Static, &[500, 1000, 5000], 1)?;
    write(
        "figure2.png",
        &report::point_panels("Figure 2: pseudo-random, uniform", &fig2, true, Format::Png)?,
    )?;
    write("table1.svg", &report::point_panels(title, &rows, false, Format::Svg)?)?;

    // A gradient "reference" with a masked-out hole; cells add noise shrinking with the ray count.
    let (w, h) = (64, 48);
    let reference = Image::from_vec(w, h, (0..w * h).map(|i| (i % w) as f32 / (w - 1) as f32).collect());
    let mask = Image::from_vec(
        w,
        h,
        (0..w * h)
            .map(|i| if (i % w).abs_diff(48) < 8 && (i / w).abs_diff(12) < 8 { 0.0 } else { 1.0 })
            .collect(),
    );
    let row_labels: Vec<String> = ["uniform", "sine", "sine-cosine"].map(String::from).to_vec();
    let col_labels: Vec<String> = ["8 rays", "16 rays", "32 rays"].map(String::from).to_vec();
    let mut images = Vec::new();
    for r in 0..3u32 {
        let mut row = Vec::new();
        for c in 0..3u32 {
            let amp = 0.3 / (1 << c) as f32 / (r + 1) as f32;
            let data = reference
                .data
                .iter()
                .enumerate()
                .map(|(i, v)| (v + amp * (noise(i as u64 * 9 + (r * 3 + c) as u64) - 0.5)).clamp(0.0, 1.0))
                .collect();
            row.push(Image::from_vec(w, h, data));
        }
        images.push(row);
    }
    let rmse = |img: &Image| {
        let s: f32 = img.data.iter().zip(&reference.data).map(|(a, b)| (a - b) * (a - b)).sum();
        (s / img.len() as f32).sqrt()
    };
    let cells: Vec<Vec<GridCell>> = images
        .iter()
        .map(|row| {
            row.iter()
                .map(|im| GridCell {
                    image: im,
                    mask: Some(&mask),
                    caption: format!("RMSE {:.4}  ρx 0.02", rmse(im)),
                })
                .collect()
        })
        .collect();
    let refcell = GridCell { image: &reference, mask: Some(&mask), caption: "4096 rays".into() };
    let t2 = "Table 2: pseudo-random sequence";
    write("table2.png", &report::image_grid(t2, &row_labels, &col_labels, &cells, Some(&refcell))?)?;
    let e2 = "Table 2: signed error against the reference";
    write("table2_error.png", &report::error_grid(e2, &row_labels, &col_labels, &cells, &refcell, None)?)?;

    let rays = [1.0, 2.0, 4.0, 8.0, 16.0, 32.0, 64.0, 128.0, 256.0, 512.0, 1024.0];
    let series: Vec<Series> = [
        (-0.5, "random / sine-cosine"),
        (-0.75, "fibonacci shift / sine-cosine"),
        (-1.0, "sobol / sine-cosine"),
    ]
    .iter()
    .enumerate()
    .map(|(k, (slope, label))| Series {
        note: Some(format!("slope {slope:+.2} [{:+.2}, {:+.2}]", slope - 0.02, slope + 0.02)),
        ..Series::new(
            label.to_string(),
            rays.iter()
                .map(|&n: &f64| {
                    let m =
                        0.3 * n.powf(*slope) * (1.0 + 0.05 * (noise(k as u64 * 100 + n as u64) as f64 - 0.5));
                    (n, m, 0.15 * m)
                })
                .collect(),
        )
    })
    .collect();
    for f in [Format::Png, Format::Svg] {
        let ext = if f == Format::Png { "png" } else { "svg" };
        let c = report::convergence_plot(
            "RMSE against rays per pixel",
            "rays per pixel",
            "RMSE",
            &series,
            &[Guide::Horizontal(4e-4, "reference noise floor".into())],
            f,
        )?;
        write(&format!("convergence_rays.{ext}"), &c)?;
        let bars = vec![
            ("random / sine-cosine".to_string(), 0.99, 0.07),
            ("fibonacci rotation / sine-cosine".to_string(), 1.02, 0.06),
            ("fibonacci static / sine-cosine".to_string(), 6.5, 0.7),
            ("random blue-noise / sine-cosine".to_string(), 0.56, 0.11),
        ];
        let marks = [(1.0, "white".to_string()), (1.5, "structured above".to_string())];
        let b = report::banding_plot("Structured error", "low-frequency ratio", &bars, &marks, f)?;
        write(&format!("banding.{ext}"), &b)?;
    }
    // Many series against run time: the legend must hold every row of Tables 2-3 and the variants.
    let many: Vec<Series> = (0..11)
        .map(|k| {
            let times = [0.05, 0.1, 0.2, 0.4, 0.8, 1.6].map(|t: f64| t * (1.0 + k as f64 * 0.1));
            Series {
                label: format!("configuration {k} / sine-cosine"),
                points: times.iter().map(|&t| (t, 0.01 * t.powf(-0.5 - 0.04 * k as f64), 0.001)).collect(),
                x_range: times.iter().map(|&t| (0.95 * t, 1.1 * t)).collect(),
                note: Some(format!("slope vs AO time {:+.2}", -0.5 - 0.04 * k as f64)),
            }
        })
        .collect();
    let guides = [
        Guide::Horizontal(2e-3, "reference noise floor".into()),
        Guide::Vertical(0.03, "image with no AO rays (overhead)".into()),
    ];
    let c = report::convergence_plot(
        "RMSE against render time",
        "render time (s)",
        "RMSE",
        &many,
        &guides,
        Format::Png,
    )?;
    write("convergence_time.png", &c)?;
    let table = Table {
        title: "RMSE".into(),
        header: vec!["configuration".into(), "8".into(), "16".into(), "32".into()],
        rows: vec![vec!["random / sine-cosine".into(), "0.05".into(), "0.035".into(), "0.025".into()]],
    };
    let figs: Vec<Figure> = ["table1", "table2", "table2_error", "convergence_rays", "banding"]
        .iter()
        .map(|n| Figure { path: format!("{n}.png"), caption: n.to_string(), links: vec![] })
        .collect();
    let tables = [table];
    let page = report::Page {
        title: "Gallery",
        lead: &[],
        intro: "Synthetic data.",
        interactive: "",
        tables: &tables,
        figures: &figs,
        collapsed: &[],
    };
    write("index.html", report::html_page(&page).as_bytes())?;
    println!("wrote the gallery to {}", dir.display());
    Ok(())
}

fn noise(i: u64) -> f32 {
    let mut z = i.wrapping_add(0x9E37_79B9_7F4A_7C15).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z ^= z >> 31;
    z = z.wrapping_mul(0x94D0_49BB_1331_11EB);
    (z >> 40) as f32 / (1u64 << 24) as f32
}
