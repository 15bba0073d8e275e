use super::*;

/// `text` read in batches of `batch` bytes (cut after line ends) and parts of `part` bytes.
fn read(text: &str, batch: usize, part: usize) -> Result<Parsed, String> {
    let mut r = Reader::with_parts(part);
    let b = text.as_bytes();
    let mut start = 0;
    while start < b.len() {
        let cut = (start + batch).min(b.len());
        let end = b[cut..].iter().position(|&c| c == b'\n').map_or(b.len(), |k| cut + k + 1);
        r.feed_bytes(&b[start..end]);
        start = end;
    }
    r.finish()
}

fn same(a: &Parsed, b: &Parsed) {
    assert_eq!(a.positions, b.positions);
    assert_eq!((&a.corners, &a.face_ends, &a.skipped), (&b.corners, &b.face_ends, &b.skipped));
    assert_eq!((&a.texcoords, &a.corner_texcoords), (&b.texcoords, &b.corner_texcoords));
    assert_eq!(
        (&a.libraries, &a.materials, &a.material_runs),
        (&b.libraries, &b.materials, &b.material_runs)
    );
}

#[test]
fn comments_weights_colours_and_skipped_elements() {
    let text = "v 0 0 0 # origin\nv 2 0 0 2\nv 0 1 0 0.5 0.5 0.5\nl 1 2 3\np 1\nl 2 3\nf 1 2 3\n";
    let p = parse(text).unwrap();
    assert_eq!(p.positions[1], DVec3::new(1.0, 0.0, 0.0), "w divides");
    assert_eq!((p.corners.len(), p.face_ends.len()), (3, 1));
    assert_eq!(p.skipped, vec![("l", 2, 4), ("p", 1, 5)]);
    assert!(p.corner_texcoords.is_empty() && p.texcoords.is_empty() && p.material_runs.is_empty());
}

/// A grid with relative indices, texture coordinates on some faces, materials switched, skipped
/// elements and a forward reference.
fn grid() -> String {
    let mut text = String::from("# a grid\r\nmtllib a.mtl b.mtl\nf 1 2 3\n");
    for i in 0..40 {
        text += &format!("v {i} 0 0\nv {i} 1 0\nvt {i} 0\nvt {i} 1\n");
        if i > 0 {
            if i % 3 == 0 {
                text += "f -4/-4 -3/-3 -1/-1 -2/-2\n";
            } else {
                text += "f -4 -3 -1//1 -2\n";
            }
        }
        if i % 7 == 0 {
            text += &format!("l {} {}\np 1\nusemtl mat {}\n", 2 * i + 1, 2 * i + 2, i % 2);
        }
    }
    text += "f 1/1 2/2 3/80"; // no line end
    text
}

#[test]
fn batches_and_parts_read_as_one_file() {
    let text = grid();
    let whole = read(&text, usize::MAX, usize::MAX).unwrap();
    assert_eq!(whole.materials, ["mat 0", "mat 1"]);
    assert_eq!(whole.libraries, [("a.mtl".to_string(), 2), ("b.mtl".to_string(), 2)]);
    assert_eq!(whole.material_runs[0], Run { first_face: 1, material: 0, line: 10, untextured: Some(15) });
    assert_eq!(whole.corner_texcoords.len(), whole.corners.len());
    assert_eq!(&whole.corner_texcoords[..3], [NO_TEXCOORD; 3], "the first face has none");
    assert_eq!(*whole.corner_texcoords.last().unwrap(), 79);
    for (batch, part) in [(usize::MAX, 1), (usize::MAX, 5), (1, usize::MAX), (13, 3), (64, 17), (200, 64)] {
        same(&read(&text, batch, part).unwrap(), &whole);
    }
}

#[test]
fn a_fault_reads_as_in_one_pass_in_any_batch_and_part() {
    let text = grid();
    // A fault's line and counts are the whole file's, wherever it is; the first in file order wins.
    for bad in
        ["f 1 2 999", "f -100 1 2", "v 1 x 2", "f 1 2", "f 1/300 2 3", "f 1/-300 2 3", "vt x", "usemtl"]
    {
        let lines: Vec<&str> = text.lines().collect();
        for at in [3, 50, lines.len() - 1] {
            let mut l = lines.clone();
            l.insert(at, bad);
            let t = l.join("\n");
            let want = read(&t, usize::MAX, usize::MAX).err().unwrap();
            assert!(want.starts_with(&format!("line {}:", at + 1)), "{want}");
            for (batch, part) in [(usize::MAX, 1), (9, 100), (100, 9), (1, 1)] {
                assert_eq!(read(&t, batch, part).err().unwrap(), want, "{bad} at {at}");
            }
            // A later fault does not hide it; an earlier one does.
            let later = format!("{t}\nf 0 1 2\n");
            assert_eq!(read(&later, 7, 5).err().unwrap(), want);
            let mut l = l.clone();
            l.insert(1, "v 1 2");
            assert!(read(&l.join("\n"), 7, 5).err().unwrap().starts_with("line 2:"));
        }
    }
    // A forward reference beyond the file's end is reported before a later fault of another kind.
    let e = read("v 0 0 0\nf 1 2 7\nv 1 0 0\nv 0 1 0\nv 1 1\n", 8, 4).err().unwrap();
    assert!(e.starts_with("line 2: face index 7 out of range (the file has 4 vertices, 1 before"), "{e}");
    // Not UTF-8, in a later batch: its line.
    let mut b = b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n".to_vec();
    b.extend(b"# \xff\n");
    let mut r = Reader::with_parts(3);
    r.feed_bytes(&b[..16]);
    r.feed_bytes(&b[16..]);
    assert_eq!(r.finish().err().unwrap(), "line 5: not UTF-8 text (is this an OBJ file?)");
}

#[test]
fn faults_name_their_line() {
    for (text, want) in [
        ("v 0 0 0\nv 1e30 0 0\n", "line 2: vertex coordinate 1e30 is beyond ±1e18"),
        ("v 0 0 inf\n", "line 1: vertex coordinate 'inf' is not a finite number"),
        ("v 0 0 1e999\n", "line 1: vertex coordinate '1e999' is not a finite number"),
        ("v 0 0 nan\n", "line 1: vertex coordinate 'nan' is not a finite number"),
        ("v 1 1 1 0\n", "line 1: vertex weight w is 0"),
        ("v 1 1 1 1e-300\n", "line 1: vertex coordinate 1 / 1e-300 is beyond"),
        ("v 1 1 1 1 1\n", "line 1: a vertex is `v x y z`"),
        ("v 1 1 1 a b c\n", "line 1: vertex colour 'a'"),
        ("v 0 0 0\nf 1 1/x 1\n", "line 2: face vertex '1/x' is not an index"),
        ("v 0 0 0\nf 1 1/2/3/4 1\n", "line 2: face vertex '1/2/3/4' is not an index"),
        ("v 0 0 0\nf 1 1 -2\n", "line 2: face index -2 out of range"),
        (
            "v 0 0 0\nvt 0 0\nf 1/1 1/2 1/1\n",
            "line 3: face texture index 2 out of range (the file has 1 texture",
        ),
        ("vt 0 1 2 3\n", "line 1: a texture coordinate is `vt u [v [w]]`"),
        ("vt 0 inf\n", "line 1: a texture coordinate is"),
        ("mtllib\n", "line 1: `mtllib` needs a file name"),
        ("usemtl # none\n", "line 1: `usemtl` needs a material name"),
    ] {
        let e = parse(text).err().unwrap_or_default();
        assert!(e.starts_with(want), "{text:?}: want '{want}', got '{e}'");
    }
}
