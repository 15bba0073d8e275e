//! Seeded mutations for the fuzz tests (`tests/stages/fuzz_inputs.rs`, `fuzz_files.rs`): a fixed,
//! portable random stream per case, so a failure names a case that reproduces, and the text and
//! byte mutations a person, a bad editor or a hostile file makes.

/// Tokens a person (or a bad editor) puts where they do not belong.
pub const TOKENS: &[&str] = &[
    "=",
    "[",
    "]",
    "[[",
    "]]",
    "{",
    "}",
    "\"",
    "'",
    "\"\"\"",
    "#",
    ",",
    ".",
    "-",
    "+",
    "-0",
    "0",
    "1",
    "1e400",
    "-1e30",
    "1e30",
    "nan",
    "inf",
    "-inf",
    "2147483648",
    "4294967296",
    "18446744073709551616",
    "0.0",
    "1e-320",
    "é",
    "é = [256, 256]",
    "ü",
    "𝄞",
    "\u{feff}",
    "\n",
    " ",
    "\t",
    "\r\n",
    "\r",
    "\0",
    "\\",
    "\\u00e9",
    "true",
    "[camera]",
    "[camera.perspective]",
    "[[table]]",
    "[reference]",
    "up",
    "eye",
    "target",
    "rays",
    "scenes",
    "resolution",
    "ao_distance",
    "infinite",
    "f",
    "v",
    "l",
    "p",
    "vt",
    "vn",
    "o",
    "g",
    "s",
    "/",
    "//",
    "1/2/3",
    "-1",
    "-2",
    "999999",
    "mtllib",
    "usemtl",
    "curv",
    "surf",
    "# comment",
];

/// xorshift64*: a fixed, portable stream per case.
pub struct Rng(pub u64);

impl Rng {
    pub fn new(seed: u64) -> Self {
        Rng(seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1)
    }
    pub fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }
    pub fn below(&mut self, n: usize) -> usize {
        (self.next() % n.max(1) as u64) as usize
    }
}

/// A character boundary of `s` at or before byte `i`.
pub fn boundary(s: &str, mut i: usize) -> usize {
    i = i.min(s.len());
    while !s.is_char_boundary(i) {
        i -= 1;
    }
    i
}

/// One to three mutations of `text`.
pub fn mutate(text: &str, rng: &mut Rng) -> String {
    let mut s = text.to_string();
    for _ in 0..1 + rng.below(3) {
        let at = boundary(&s, rng.below(s.len() + 1));
        let token = TOKENS[rng.below(TOKENS.len())];
        match rng.below(8) {
            0 | 1 => s.insert_str(at, token),
            2 => {
                let end = boundary(&s, at + 1 + rng.below(8)).max(at);
                s.replace_range(at..end, token);
            }
            3 => {
                let end = boundary(&s, at + 1 + rng.below(16)).max(at);
                s.replace_range(at..end, "");
            }
            4 => s.truncate(at),
            _ => {
                let mut lines: Vec<&str> = s.split('\n').collect();
                let (i, j) = (rng.below(lines.len()), rng.below(lines.len()));
                match rng.below(3) {
                    0 => lines.swap(i, j),
                    1 => drop(lines.remove(i)),
                    _ => lines.insert(i, lines[j]),
                }
                s = lines.join("\n");
            }
        }
    }
    s
}

/// Sizes a hostile header claims: zero, one, the edges of 8, 16, 31, 32 and 63 bits.
pub const SIZES: &[u64] = &[
    0,
    1,
    2,
    3,
    4,
    7,
    255,
    256,
    65_535,
    65_536,
    (1 << 31) - 1,
    1 << 31,
    u32::MAX as u64,
    1 << 32,
    1 << 62,
    u64::MAX,
];

/// One to three mutations of binary `bytes`: a byte flipped or set, a 4-byte little-endian field
/// overwritten with one of `SIZES`, a run deleted, duplicated or inserted, or the file cut short.
pub fn mutate_bytes(bytes: &[u8], rng: &mut Rng) -> Vec<u8> {
    let mut b = bytes.to_vec();
    for _ in 0..1 + rng.below(3) {
        let at = rng.below(b.len() + 1);
        match rng.below(7) {
            0 if at < b.len() => b[at] ^= 1 << rng.below(8),
            1 if at < b.len() => b[at] = [0u8, 0x7F, 0x80, 0xFF][rng.below(4)],
            2 | 3 => {
                let at = at & !3;
                let v = SIZES[rng.below(SIZES.len())].to_le_bytes();
                for (k, &x) in v[..4].iter().enumerate() {
                    if let Some(c) = b.get_mut(at + k) {
                        *c = x;
                    }
                }
            }
            4 => {
                let end = (at + 1 + rng.below(32)).min(b.len());
                b.drain(at.min(end)..end);
            }
            5 => {
                let end = (at + 1 + rng.below(32)).min(b.len());
                let run = b[at.min(end)..end].to_vec();
                b.splice(at.min(end)..at.min(end), run);
            }
            _ => b.truncate(at),
        }
    }
    b
}

/// One to three mutations of a JSON document: a value (at any depth) replaced by another kind or
/// an edge value (sizes, indices out of range, negative, fractional), a key removed, or an array
/// element repeated.
pub fn mutate_json(doc: &serde_json::Value, rng: &mut Rng) -> serde_json::Value {
    use serde_json::{Value, json};
    let mut doc = doc.clone();
    for _ in 0..1 + rng.below(3) {
        // Every place in the document, as a path of keys and indices.
        let mut places: Vec<Vec<Value>> = Vec::new();
        fn walk(v: &Value, path: &mut Vec<Value>, out: &mut Vec<Vec<Value>>) {
            out.push(path.clone());
            match v {
                Value::Object(m) => m.iter().for_each(|(k, c)| {
                    path.push(json!(k));
                    walk(c, path, out);
                    path.pop();
                }),
                Value::Array(a) => a.iter().enumerate().for_each(|(i, c)| {
                    path.push(json!(i));
                    walk(c, path, out);
                    path.pop();
                }),
                _ => {}
            }
        }
        walk(&doc, &mut Vec::new(), &mut places);
        let path = places[rng.below(places.len())].clone();
        let Some((last, parent)) = path.split_last() else { continue };
        let mut holder = &mut doc;
        for step in parent {
            holder = match step {
                Value::String(k) => &mut holder[k.as_str()],
                _ => &mut holder[step.as_u64().unwrap() as usize],
            };
        }
        let pick = rng.below(14);
        let value = match pick {
            0 => json!(SIZES[rng.below(SIZES.len())]),
            1 => json!(-1),
            2 => json!(0.5),
            3 => json!(null),
            4 => json!([]),
            5 => json!({}),
            6 => json!("x"),
            7 => json!([0, 0]),
            8 => json!(5126),
            9 => json!(rng.below(8)),
            10 => json!(1e300),
            _ => Value::Null, // 11..: remove or repeat
        };
        match (holder, last) {
            (Value::Object(m), Value::String(k)) if pick >= 11 => {
                m.remove(k);
            }
            (Value::Array(a), Value::Number(i)) if pick >= 11 => {
                let i = i.as_u64().unwrap() as usize;
                let v = a[i].clone();
                a.insert(i, v);
            }
            (Value::Object(m), Value::String(k)) => {
                m.insert(k.clone(), value);
            }
            (Value::Array(a), Value::Number(i)) => a[i.as_u64().unwrap() as usize] = value,
            _ => {}
        }
    }
    doc
}
