//! Bounded fuzzing of the readers of untrusted files (issues 10 and 29): the OBJ/MTL loader,
//! the render-record reader (the `aa-lab` chunk of a PNG, then its JSON), the glTF/GLB loader
//! and the user technique compiler. Inputs come from a grammar of the records these formats
//! have (with hostile numbers, indices, names and paths) plus byte-level mutations; a fixed
//! seed and case count keep the run to seconds and reproducible. Properties: nothing panics,
//! every scene that loads is drawable (indices in range, finite positions), every record that
//! parses serialises back, and every compiler error points into the user's file.
//!
//! glTF (JSON and GLB: hostile counts, offsets, strides, component types, node hierarchies,
//! URIs naming `/dev/zero`, a FIFO, a directory, a path out of the folder or a file far longer
//! than its buffer, truncated and oversized chunks) and WGSL (random edits of the example
//! techniques) run in a child process under an address-space and a time limit
//! (`common/confined.rs`): a case that allocates without bound or never ends fails the test
//! with the number of the case, instead of taking the machine.

use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::Path;

use aa_lab::export::png::{RECORD_KEYWORD, read_record};
use aa_lab::spec::{RenderSpec, TechniqueSpec};

#[cfg(unix)]
#[path = "common/confined.rs"]
mod confined;
#[cfg(unix)]
#[path = "fuzz/gltf_and_wgsl.rs"]
mod gltf_and_wgsl;

/// Cases per target; each takes well under a millisecond.
const OBJ_CASES: u64 = 800;
const RECORD_CASES: u64 = 800;

/// xorshift64* (Vigna 2016): the fuzzer's own small generator, seeded per case.
pub(crate) struct Gen(u64);

impl Gen {
    pub(crate) fn new(case: u64) -> Self {
        Self(case.wrapping_mul(0x2545_F491_4F6C_DD1D) | 1)
    }

    pub(crate) fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }

    pub(crate) fn below(&mut self, n: usize) -> usize {
        (self.next() % n.max(1) as u64) as usize
    }

    pub(crate) fn pick<'a>(&mut self, items: &[&'a str]) -> &'a str {
        items[self.below(items.len())]
    }

    pub(crate) fn chance(&mut self, percent: u64) -> bool {
        self.next() % 100 < percent
    }

    /// From `usual` nineteen times in twenty, else from `hostile`.
    pub(crate) fn mostly<'a>(&mut self, usual: &[&'a str], hostile: &[&'a str]) -> &'a str {
        if self.chance(95) {
            self.pick(usual)
        } else {
            self.pick(hostile)
        }
    }
}

/// Ordinary numbers, drawn most of the time so that many files load.
const NUMBERS: &[&str] = &["0", "1", "-1", "0.5", "-2.25", "1e3", "-0", "+3"];
/// Hostile numbers.
const BAD_NUMBERS: &[&str] = &[
    "1e38",
    "3.4e39",
    "-1e-45",
    "nan",
    "inf",
    "-inf",
    "NaN",
    "1e",
    "abc",
    "",
    "0x10",
    "1,5",
    "99999999999999999999",
];

/// Indices that exist after the preamble.
const INDICES: &[&str] = &["1", "2", "3", "-1", "-2"];
/// Indices out of range or not indices at all.
const BAD_INDICES: &[&str] = &[
    "4",
    "-4",
    "0",
    "9",
    "2147483648",
    "-9223372036854775808",
    "18446744073709551616",
    "a",
    "",
    "1.5",
];

const NAMES: &[&str] = &[
    "a", "b c", "ünï", "m0", "m1", "m2", "", "\\", "..", "CON", "x\ty",
];

/// `usual` numbers nineteen times in twenty, else 0 to 5 of them.
fn numbers(g: &mut Gen, usual: usize) -> String {
    let count = if g.chance(95) { usual } else { g.below(6) };
    (0..count)
        .map(|_| g.mostly(NUMBERS, BAD_NUMBERS))
        .collect::<Vec<_>>()
        .join(" ")
}

fn corner(g: &mut Gen) -> String {
    match g.below(20) {
        0..=9 => g.mostly(INDICES, BAD_INDICES).to_owned(),
        10..=12 => format!(
            "{}/{}",
            g.mostly(INDICES, BAD_INDICES),
            g.mostly(INDICES, BAD_INDICES)
        ),
        13..=15 => format!(
            "{}//{}",
            g.mostly(INDICES, BAD_INDICES),
            g.mostly(INDICES, BAD_INDICES)
        ),
        16..=18 => format!(
            "{}/{}/{}",
            g.mostly(INDICES, BAD_INDICES),
            g.mostly(INDICES, BAD_INDICES),
            g.mostly(INDICES, BAD_INDICES)
        ),
        _ if g.chance(20) => format!("{}/1/1/1", g.mostly(INDICES, BAD_INDICES)),
        _ => g.pick(INDICES).to_owned(),
    }
}

/// Three of each element, so that the faces the grammar draws often refer to existing ones.
const PREAMBLE: &str = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\n\
                        vn 0 0 1\nvn 0 0 1\nvn 0 0 1\nf 1 2 3\n";

fn obj_line(g: &mut Gen) -> String {
    match g.below(16) {
        0..=3 => format!("v {}", numbers(g, 3)),
        4 => format!("vt {}", numbers(g, 2)),
        5 => format!("vn {}", numbers(g, 3)),
        6..=8 => {
            let corners: Vec<String> = (0..g.below(6)).map(|_| corner(g)).collect();
            format!("f {}", corners.join(" "))
        }
        9 => format!("l {} {} {}", corner(g), corner(g), corner(g)),
        10 => format!(
            "{} {}",
            g.pick(&["o", "g", "s", "usemtl", "p"]),
            g.pick(NAMES)
        ),
        11 => format!(
            "mtllib {}",
            g.pick(&[
                "lib.mtl",
                "lib.mtl other.mtl",
                "missing.mtl",
                "/dev/zero",
                ".",
                "sub\\lib.mtl",
                ""
            ])
        ),
        12 => "# comment".to_owned(),
        13 => "\u{feff}v 0 0 0".to_owned(),
        14 => String::new(),
        _ => (0..g.below(12))
            .map(|_| char::from(b' ' + (g.next() % 95) as u8))
            .collect(),
    }
}

fn mtl_line(g: &mut Gen) -> String {
    match g.below(10) {
        0 | 1 => format!("newmtl {}", g.pick(NAMES)),
        2 | 3 => format!("{} {}", g.pick(&["Kd", "Ks", "Ka", "Ke"]), numbers(g, 3)),
        4 => format!(
            "{} {}",
            g.pick(&["Ns", "d", "Tr", "Ni", "illum"]),
            numbers(g, 1)
        ),
        5..=7 => {
            let options = g.pick(&[
                "",
                "-imfchan r ",
                "-imfchan m ",
                "-s 1 1 1 ",
                "-o 0.5 ",
                "-bm ",
                "-clamp on ",
            ]);
            let file = g.pick(&["tex.png", "bad.png", "missing.png", "/dev/zero", ".", ""]);
            format!("{} {options}{file}", g.pick(&["map_Kd", "map_d", "bump"]))
        }
        8 => "# comment".to_owned(),
        _ => String::new(),
    }
}

/// Byte-level damage on top of the grammar: a replaced byte, a NUL, a cut.
pub(crate) fn mutate(g: &mut Gen, mut bytes: Vec<u8>) -> Vec<u8> {
    for _ in 0..g.below(4) {
        if bytes.is_empty() {
            break;
        }
        let at = g.below(bytes.len());
        match g.below(4) {
            0 => bytes[at] = g.next() as u8,
            1 => bytes.insert(at, 0),
            2 => bytes.truncate(at),
            _ => {
                let end = (at + g.below(16)).min(bytes.len());
                bytes.drain(at..end);
            }
        }
    }
    bytes
}

/// `least` to `least + spread - 1` lines of the grammar, damaged now and then.
fn text(g: &mut Gen, least: usize, spread: usize, line: fn(&mut Gen) -> String) -> Vec<u8> {
    let lines = least + g.below(spread);
    let mut out = String::new();
    for _ in 0..lines {
        out += &line(g);
        out.push(if g.chance(5) { '\r' } else { '\n' });
    }
    let bytes = out.into_bytes();
    if g.chance(25) {
        mutate(g, bytes)
    } else {
        bytes
    }
}

/// Judges one load of a fuzz case: a panic, an undrawable scene or an empty error fails the
/// test (naming the case through `describe`); returns whether the scene loaded.
pub(crate) fn judge_load<E: std::fmt::Display>(
    loader: &str,
    result: std::thread::Result<Result<aa_lab::scene::Scene, E>>,
    describe: impl Fn() -> String,
) -> bool {
    match result {
        Err(_) => panic!("{loader} panicked on {}", describe()),
        Ok(Ok(scene)) => {
            if let Err(problem) = check_scene(&scene) {
                panic!("{problem} after loading {}", describe());
            }
            true
        }
        Ok(Err(err)) => {
            assert!(
                !err.to_string().is_empty(),
                "empty error for {}",
                describe()
            );
            false
        }
    }
}

/// A loaded scene is drawable: every index in range, every position finite.
fn check_scene(scene: &aa_lab::scene::Scene) -> Result<(), String> {
    for mesh in &scene.meshes {
        if let Some(bad) = mesh
            .indices
            .iter()
            .find(|&&i| i as usize >= mesh.vertices.len())
        {
            return Err(format!(
                "mesh {} has index {bad} of {} vertices",
                mesh.name,
                mesh.vertices.len()
            ));
        }
        if mesh
            .vertices
            .iter()
            .any(|v| v.position.iter().chain(&v.normal).any(|c| !c.is_finite()))
        {
            return Err(format!("mesh {} has a non-finite position", mesh.name));
        }
        if mesh.material >= scene.materials.len().max(1) {
            return Err(format!("mesh {} has material {}", mesh.name, mesh.material));
        }
    }
    Ok(())
}

#[test]
fn obj_and_mtl_loading_never_panics() {
    let dir = tempfile::tempdir().expect("temp dir");
    let png = image::RgbaImage::from_pixel(4, 4, image::Rgba([200, 100, 50, 128]));
    png.save(dir.path().join("tex.png")).expect("texture");
    std::fs::write(dir.path().join("bad.png"), b"\x89PNG\r\n\x1a\nnot really").expect("bad");
    std::fs::create_dir_all(dir.path().join("sub")).expect("sub");
    let obj = dir.path().join("model.obj");
    let (mut loaded, mut refused) = (0, 0);
    for case in 0..OBJ_CASES {
        let mut g = Gen::new(case);
        let mut obj_text = if g.chance(60) {
            PREAMBLE.as_bytes().to_vec()
        } else {
            Vec::new()
        };
        obj_text.extend(text(&mut g, 2, 12, obj_line));
        let mtl_text = text(&mut g, 0, 14, mtl_line);
        std::fs::write(&obj, &obj_text).expect("obj");
        std::fs::write(dir.path().join("lib.mtl"), &mtl_text).expect("mtl");
        std::fs::write(dir.path().join("sub").join("lib.mtl"), &mtl_text).expect("mtl");
        let result = catch_unwind(AssertUnwindSafe(|| aa_lab::scene::obj::load_obj(&obj)));
        let describe = || {
            format!(
                "case {case}\n--- model.obj ---\n{}\n--- lib.mtl ---\n{}",
                String::from_utf8_lossy(&obj_text),
                String::from_utf8_lossy(&mtl_text)
            )
        };
        if judge_load("load_obj", result, describe) {
            loaded += 1;
        } else {
            refused += 1;
        }
    }
    eprintln!("OBJ/MTL fuzz: {loaded} loaded, {refused} refused, no panic");
    // The grammar must reach both outcomes, or the harness tests nothing.
    assert!(
        loaded > 20 && refused > 20,
        "{loaded} loaded, {refused} refused"
    );
}

fn sample_spec() -> RenderSpec {
    RenderSpec {
        scene: "chart".to_owned(),
        density: 1.0,
        seed: 7,
        specular_aa: false,
        tonemap: aa_lab::graph::hdr::TonemapChoice::Auto,
        exposure: 0.0,
        width: 160,
        height: 90,
        frame: 3,
        camera: None,
        rig: None,
        image: None,
        techniques: vec![TechniqueSpec {
            id: "msaa4".to_owned(),
            settings: Default::default(),
            source_hash: None,
        }],
        overlay: Some(aa_lab::graph::overlay::OverlayOrder::Before),
        adapter: Some("fuzz".to_owned()),
        build: None,
    }
}

const JSON_TOKENS: &[&str] = &[
    "null",
    "-1",
    "1e400",
    "18446744073709551616",
    "4294967296",
    "\"\"",
    "[]",
    "{}",
    "\"\\ud800\"",
    "true",
    "0.5",
    "\"none,none\"",
];

fn mutate_json(g: &mut Gen, json: &str) -> String {
    let mut text = json.to_owned();
    for _ in 0..1 + g.below(3) {
        match g.below(3) {
            0 => {
                // Replace a value after a colon.
                let colons: Vec<usize> = text.match_indices(": ").map(|(i, _)| i + 2).collect();
                if let Some(&at) = colons.get(g.below(colons.len())) {
                    let end = text[at..]
                        .find([',', '\n', '}'])
                        .map_or(text.len(), |e| at + e);
                    text.replace_range(at..end, g.pick(JSON_TOKENS));
                }
            }
            _ => {
                let bytes = mutate(g, text.into_bytes());
                text = String::from_utf8_lossy(&bytes).into_owned();
            }
        }
    }
    text
}

#[test]
fn render_record_reading_never_panics() {
    let dir = tempfile::tempdir().expect("temp dir");
    let json = serde_json::to_string_pretty(&sample_spec()).expect("json");
    let valid = dir.path().join("valid.png");
    aa_lab::export::write_png(
        &valid,
        &image::RgbaImage::new(2, 2),
        Some(&json),
        &aa_lab::files::Overwrite::default(),
    )
    .expect("write");
    let png = std::fs::read(&valid).expect("read");
    let path = dir.path().join("case.png");
    let (mut parsed, mut refused) = (0, 0);
    for case in 0..RECORD_CASES {
        let mut g = Gen::new(case ^ 0xA5A5);
        let text = mutate_json(&mut g, &json);
        // Half the cases go through a PNG (the record chunk itself damaged now and then).
        let result = catch_unwind(AssertUnwindSafe(|| {
            let text = if g.chance(50) {
                let bytes = if g.chance(30) {
                    mutate(&mut g, png.clone())
                } else {
                    encoded_with_record(&text)
                };
                std::fs::write(&path, &bytes).expect("write case");
                match read_record(Path::new(&path)) {
                    Ok(Some(text)) => text,
                    Ok(None) | Err(_) => return None,
                }
            } else {
                text.clone()
            };
            let spec = aa_lab::spec::parse_record(&text).ok()?;
            Some(serde_json::to_string(&spec).is_ok())
        }));
        match result {
            Err(_) => panic!("case {case} panicked on record:\n{text}"),
            Ok(Some(round_trips)) => {
                parsed += 1;
                assert!(round_trips, "case {case}: parsed but does not serialise");
            }
            Ok(None) => refused += 1,
        }
    }
    eprintln!("record fuzz: {parsed} parsed, {refused} refused, no panic");
    assert!(
        parsed > 20 && refused > 20,
        "{parsed} parsed, {refused} refused"
    );
}

/// A small PNG whose `aa-lab` chunk holds `text`.
fn encoded_with_record(text: &str) -> Vec<u8> {
    let mut bytes = Vec::new();
    let mut encoder = png::Encoder::new(&mut bytes, 1, 1);
    encoder.set_color(png::ColorType::Rgba);
    encoder
        .add_itxt_chunk(RECORD_KEYWORD.to_owned(), text.to_owned())
        .expect("chunk");
    let mut writer = encoder.write_header().expect("header");
    writer.write_image_data(&[0; 4]).expect("pixels");
    writer.finish().expect("finish");
    bytes
}
