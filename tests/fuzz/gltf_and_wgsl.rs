//! The glTF/GLB and WGSL targets (issue 29, item 4), run in a confined child (see the parent
//! module's docs). The child prints the number of each case before running it, so a case that
//! aborts under the address-space limit or hangs is named by the parent.

use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::Path;
use std::time::Duration;

use serde_json::{Value, json};

use super::confined::{self, Ended};
use super::{Gen, judge_load, mutate};

/// glTF cases; most take well under a millisecond (the rare node fan up to a few seconds).
const GLTF_CASES: u64 = 500;
/// WGSL cases; each is one naga parse and validation.
const WGSL_CASES: u64 = 300;
/// Wall-clock limit of each target's child.
const CHILD_TIMEOUT: Duration = Duration::from_secs(240);
/// Prefix of the line a child prints before each case.
const CASE_PREFIX: &str = "fuzz case ";

/// Runs `test` (this target's own test function) in a confined child and fails with the case
/// that was running when the child died or hung.
fn run_in_child(test: &str) {
    let (what, output) =
        match confined::run(test, "all", confined::ADDRESS_SPACE_LIMIT, CHILD_TIMEOUT) {
            Ended::Reported(summary) => return eprintln!("{test}: {summary}"),
            Ended::Failed(output) => ("failed", output),
            Ended::TimedOut(output) => ("was still running after the time limit", output),
        };
    let last = output
        .lines()
        .rev()
        .find_map(|l| l.split_once(CASE_PREFIX).map(|(_, case)| case))
        .unwrap_or("none");
    panic!(
        "the child running {test} {what} in case {last} (address-space limit {} bytes, time \
         limit {CHILD_TIMEOUT:?}):\n{}",
        confined::ADDRESS_SPACE_LIMIT,
        output.lines().rev().take(40).collect::<Vec<_>>().join("\n")
    );
}

/// Announces a case on stdout (the parent names the last one when the child dies).
fn announce(case: u64) {
    use std::io::Write;
    let mut out = std::io::stdout().lock();
    let _ = writeln!(out, "{CASE_PREFIX}{case}");
    let _ = out.flush();
}

const FLOAT: u64 = 5126;

/// Hostile and ordinary values for counts, offsets, lengths and strides.
fn hostile_number(g: &mut Gen) -> Value {
    match g.below(16) {
        0 => json!(0),
        1 => json!(1),
        2 => json!(3),
        3 => json!(4),
        4 => json!(7),
        5 => json!(255),
        6 => json!(1 << 20),
        7 => json!(1u64 << 31),
        8 => json!(u32::MAX),
        9 => json!(1u64 << 32),
        10 => json!(1u64 << 53),
        11 => json!(u64::MAX),
        12 => json!(-1),
        13 => json!(1e300),
        14 => json!("x"),
        _ => json!(null),
    }
}

/// URIs a hostile file names.
const URIS: &[&str] = &[
    "/dev/zero",
    "pipe",
    "folder",
    "../../../../etc/passwd",
    "sub/../../model.bin",
    "missing.bin",
    "long.bin",
    "model.bin",
    "tex.png",
    "bad.png",
    "data:application/octet-stream;base64,AAAA",
    "data:application/octet-stream;base64,@@",
    "data:,%00%zz",
    "http://example.com/a.bin",
    "",
];

/// A valid quad model: positions, normals, UVs and indices in one buffer, a textured material
/// whose image is a file, two nodes and a camera.
fn base_model() -> (Value, Vec<u8>) {
    let positions = [
        -1.0f32, -1.0, 0.0, 1.0, -1.0, 0.0, 1.0, 1.0, 0.0, -1.0, 1.0, 0.0,
    ];
    let normals = [0.0f32, 0.0, 1.0].repeat(4);
    let uvs = [0.0f32, 1.0, 1.0, 1.0, 1.0, 0.0, 0.0, 0.0];
    let mut bin: Vec<u8> = positions
        .iter()
        .chain(&normals)
        .chain(&uvs)
        .flat_map(|v| v.to_le_bytes())
        .collect();
    bin.extend([0u16, 1, 2, 0, 2, 3].iter().flat_map(|i| i.to_le_bytes()));
    let json = json!({
        "asset": {"version": "2.0"},
        "buffers": [{"uri": "model.bin", "byteLength": bin.len()}],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": 48},
            {"buffer": 0, "byteOffset": 48, "byteLength": 48},
            {"buffer": 0, "byteOffset": 96, "byteLength": 32},
            {"buffer": 0, "byteOffset": 128, "byteLength": 12},
        ],
        "accessors": [
            {"bufferView": 0, "componentType": FLOAT, "count": 4, "type": "VEC3",
             "min": [-1, -1, 0], "max": [1, 1, 0]},
            {"bufferView": 1, "componentType": FLOAT, "count": 4, "type": "VEC3"},
            {"bufferView": 2, "componentType": FLOAT, "count": 4, "type": "VEC2"},
            {"bufferView": 3, "componentType": 5123, "count": 6, "type": "SCALAR"},
        ],
        "images": [{"uri": "tex.png"}],
        "textures": [{"source": 0}],
        "materials": [{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}],
        "meshes": [{"primitives": [{
            "attributes": {"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2},
            "indices": 3, "material": 0,
        }]}],
        "cameras": [{"type": "perspective", "perspective": {"yfov": 0.8, "znear": 0.1}}],
        "nodes": [
            {"mesh": 0, "children": [1]},
            {"camera": 0, "translation": [0, 0, 5]},
        ],
        "scenes": [{"nodes": [0]}],
        "scene": 0,
    });
    (json, bin)
}

/// One hostile edit of the model's JSON.
fn edit_model(g: &mut Gen, json: &mut Value) {
    let accessor = g.below(4);
    let view = g.below(4);
    match g.below(14) {
        0 => json["accessors"][accessor]["count"] = hostile_number(g),
        1 => json["accessors"][accessor]["byteOffset"] = hostile_number(g),
        2 => {
            json["accessors"][accessor]["componentType"] = json!(
                g.pick(&["5120", "5121", "5122", "5123", "5125", "5126", "0"])
                    .parse::<u64>()
                    .unwrap_or(0)
            );
        }
        3 => {
            json["accessors"][accessor]["type"] =
                json!(g.pick(&["SCALAR", "VEC2", "VEC3", "VEC4", "MAT4", "X"]));
        }
        4 => {
            if let Some(a) = json["accessors"][accessor].as_object_mut() {
                a.remove("bufferView");
            }
        }
        5 => {
            json["accessors"][accessor]["sparse"] = json!({
                "count": hostile_number(g),
                "indices": {"bufferView": 3, "componentType": 5123},
                "values": {"bufferView": 0},
            });
        }
        6 => json["bufferViews"][view]["byteOffset"] = hostile_number(g),
        7 => json["bufferViews"][view]["byteLength"] = hostile_number(g),
        8 => json["bufferViews"][view]["byteStride"] = hostile_number(g),
        9 => json["buffers"][0]["byteLength"] = hostile_number(g),
        10 => json["buffers"][0]["uri"] = json!(g.pick(URIS)),
        11 => json["images"][0]["uri"] = json!(g.pick(URIS)),
        12 => {
            // A hierarchy: a cycle, a node listed twice, or (rarely) a fan of shared nodes.
            let nodes = json["nodes"].as_array_mut().expect("nodes");
            match g.below(20) {
                0 => {
                    let mut below = 0;
                    for _ in 0..24 {
                        nodes.push(json!({"children": [below, below]}));
                        below = nodes.len() - 1;
                    }
                    json["scenes"][0]["nodes"] = json!([below]);
                }
                1..=9 => nodes[1]["children"] = json!([0]),
                _ => nodes[0]["children"] = json!([1, 1, 0]),
            }
        }
        _ => {
            json["meshes"][0]["primitives"][0]["mode"] = json!(g.below(8));
            json["nodes"][0]["matrix"] = json!([1e39, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]);
            if g.chance(50) {
                json["nodes"][0]
                    .as_object_mut()
                    .expect("node")
                    .remove("matrix");
            }
        }
    }
}

/// A GLB of `json` and `bin`, its container damaged now and then: chunk lengths too short or
/// too long, a cut, trailing bytes.
fn glb(g: &mut Gen, json: &Value, bin: &[u8]) -> Vec<u8> {
    let mut text = serde_json::to_vec(json).expect("json");
    while !text.len().is_multiple_of(4) {
        text.push(b' ');
    }
    let mut bin = bin.to_vec();
    while !bin.len().is_multiple_of(4) {
        bin.push(0);
    }
    let mut json_length = text.len() as u32;
    let mut bin_length = bin.len() as u32;
    let mut total = (12 + 8 + text.len() + 8 + bin.len()) as u32;
    if g.chance(40) {
        let hostile = [0, 1, 3, u32::MAX, u32::MAX - 7, 1 << 31, 12];
        match g.below(3) {
            0 => json_length = hostile[g.below(hostile.len())],
            1 => bin_length = hostile[g.below(hostile.len())],
            _ => total = hostile[g.below(hostile.len())],
        }
    }
    let mut out = Vec::new();
    out.extend_from_slice(b"glTF");
    out.extend_from_slice(&2u32.to_le_bytes());
    out.extend_from_slice(&total.to_le_bytes());
    out.extend_from_slice(&json_length.to_le_bytes());
    out.extend_from_slice(b"JSON");
    out.extend_from_slice(&text);
    out.extend_from_slice(&bin_length.to_le_bytes());
    out.extend_from_slice(b"BIN\0");
    out.extend_from_slice(&bin);
    match g.below(10) {
        0 => out.truncate(g.below(out.len())),
        1 => out.extend(std::iter::repeat_n(0xAB, g.below(64))),
        _ => {}
    }
    out
}

/// The files every glTF case may name: a texture, a damaged PNG, a FIFO, a folder, and a
/// 3 GiB sparse file whose first bytes are the model's buffer.
fn gltf_fixtures(dir: &Path, bin: &[u8]) {
    image::RgbaImage::from_pixel(4, 4, image::Rgba([200, 100, 50, 255]))
        .save(dir.join("tex.png"))
        .expect("texture");
    std::fs::write(dir.join("bad.png"), b"\x89PNG\r\n\x1a\nnot really").expect("bad");
    nix::unistd::mkfifo(&dir.join("pipe"), nix::sys::stat::Mode::S_IRWXU).expect("mkfifo");
    std::fs::create_dir_all(dir.join("folder")).expect("folder");
    std::fs::create_dir_all(dir.join("sub")).expect("sub");
    std::fs::write(dir.join("long.bin"), bin).expect("long");
    std::fs::OpenOptions::new()
        .append(true)
        .open(dir.join("long.bin"))
        .and_then(|f| f.set_len(3 << 30))
        .expect("a sparse file");
}

/// The child's side of [`gltf_and_glb_loading_stays_bounded`].
fn fuzz_gltf() {
    let dir = tempfile::tempdir().expect("temp dir");
    let (base, bin) = base_model();
    gltf_fixtures(dir.path(), &bin);
    std::fs::write(dir.path().join("model.bin"), &bin).expect("bin");
    let (mut loaded, mut refused) = (0, 0);
    for case in 0..GLTF_CASES {
        announce(case);
        let mut g = Gen::new(case ^ 0x6C7F);
        let mut json = base.clone();
        for _ in 0..1 + g.below(3) {
            edit_model(&mut g, &mut json);
        }
        let (name, mut bytes) = match g.below(10) {
            0..=4 => ("model.gltf", serde_json::to_vec(&json).expect("json")),
            _ => {
                // The GLB's buffer is its binary chunk unless an edit named a URI.
                if json["buffers"][0]["uri"] == "model.bin" {
                    json["buffers"][0]
                        .as_object_mut()
                        .expect("buffer")
                        .remove("uri");
                }
                let bytes = glb(&mut g, &json, &bin);
                ("model.glb", bytes)
            }
        };
        if g.chance(15) {
            bytes = mutate(&mut g, bytes);
        }
        let path = dir.path().join(name);
        std::fs::write(&path, &bytes).expect("case");
        let result = catch_unwind(AssertUnwindSafe(|| aa_lab::scene::gltf::load_gltf(&path)));
        let describe = || format!("case {case} ({name}):\n{}", String::from_utf8_lossy(&bytes));
        if judge_load("load_gltf", result, describe) {
            loaded += 1;
        } else {
            refused += 1;
        }
    }
    // The edits must reach both outcomes, or the harness tests nothing.
    assert!(
        loaded > 20 && refused > 20,
        "{loaded} loaded, {refused} refused"
    );
    confined::report(&format!(
        "glTF fuzz: {loaded} loaded, {refused} refused, no panic"
    ));
}

#[test]
fn gltf_and_glb_loading_stays_bounded() {
    if confined::case().is_some() {
        return fuzz_gltf();
    }
    run_in_child("gltf_and_wgsl::gltf_and_glb_loading_stays_bounded");
}

/// Pieces a WGSL edit inserts: hostile sizes, recursion, deep nesting, odd tokens.
const WGSL_PIECES: &[&str] = &[
    "var<private> big: array<f32, 65536>;",
    "fn huge() -> f32 { var a: array<f32, 65536>; return a[0]; }",
    "fn again(x: f32) -> f32 { return again(x); }",
    "override n: u32 = 4294967295u; // [0, 4294967295]",
    "override k: f32 = 1e39; // [-1e39, 1e39]",
    "override b: bool = true; // [1, 0]",
    "let x = 0x7fffffffi;",
    "const c = 1.0 / 0.0;",
    "@group(0) @binding(0) var t: texture_2d<f32>;",
    "fn aa_main(pixel: vec2<u32>, uv: vec2<f32>) -> vec4<f32> { return vec4<f32>(); }",
    "loop { }",
    "return aa_load(vec2<i32>(-2147483647 - 1, 0));",
    "}",
    "{",
    "\u{feff}",
    "/*",
];

/// One random edit of WGSL text: a line dropped, doubled or swapped, a piece inserted, a
/// number replaced, deep nesting, or bytes damaged.
fn edit_wgsl(g: &mut Gen, text: &str) -> Vec<u8> {
    let mut lines: Vec<String> = text.lines().map(str::to_owned).collect();
    let at = g.below(lines.len().max(1));
    match g.below(8) {
        0 if !lines.is_empty() => {
            lines.remove(at);
        }
        1 if !lines.is_empty() => {
            let line = lines[at].clone();
            lines.insert(at, line);
        }
        2 if lines.len() > 1 => {
            let other = g.below(lines.len());
            lines.swap(at, other);
        }
        3 | 4 => lines.insert(at, g.pick(WGSL_PIECES).to_owned()),
        5 if !lines.is_empty() => {
            let numbers = [
                "0",
                "-1",
                "65536",
                "4294967296",
                "1e39",
                "0.0",
                "nan",
                "2147483648",
            ];
            let line = &mut lines[at];
            if let Some(start) = line.find(|c: char| c.is_ascii_digit()) {
                let end = line[start..]
                    .find(|c: char| !c.is_ascii_digit() && c != '.')
                    .map_or(line.len(), |e| start + e);
                line.replace_range(start..end, g.pick(&numbers));
            }
        }
        6 => {
            let depth = [10, 100, 1_000, 20_000][g.below(4)];
            lines.insert(
                at,
                format!(
                    "const deep = {}1.0{};",
                    "(".repeat(depth),
                    ")".repeat(depth)
                ),
            );
        }
        _ => return mutate(g, text.as_bytes().to_vec()),
    }
    lines.join("\n").into_bytes()
}

/// The child's side of [`user_wgsl_compiling_stays_bounded`].
fn fuzz_wgsl() {
    let examples: Vec<String> = ["passthrough.wgsl", "edge_blur.wgsl"]
        .iter()
        .map(|name| {
            let path = Path::new(env!("CARGO_MANIFEST_DIR"))
                .join("assets/user_techniques")
                .join(name);
            std::fs::read_to_string(path).expect("example technique")
        })
        .collect();
    let path = Path::new("fuzz.wgsl");
    let (mut compiled, mut refused) = (0, 0);
    for case in 0..WGSL_CASES {
        announce(case);
        let mut g = Gen::new(case ^ 0x3E5);
        let mut bytes = examples[g.below(examples.len())].clone().into_bytes();
        for _ in 0..1 + g.below(3) {
            bytes = edit_wgsl(&mut g, &String::from_utf8_lossy(&bytes));
        }
        let result = catch_unwind(AssertUnwindSafe(|| {
            aa_lab::aa::user::program::compile(path, &bytes)
        }));
        let describe = || format!("case {case}:\n{}", String::from_utf8_lossy(&bytes));
        match result {
            Err(_) => panic!("compile panicked on {}", describe()),
            Ok(Ok(_)) => compiled += 1,
            Ok(Err(err)) => {
                refused += 1;
                let lines = bytes.split(|&b| b == b'\n').count() as u32;
                if let Some((line, _)) = err.location {
                    assert!(
                        (1..=lines).contains(&line),
                        "line {line} of {lines} for {}: {err}",
                        describe()
                    );
                }
                assert_eq!(err.path, path, "{}", describe());
            }
        }
    }
    assert!(
        compiled > 20 && refused > 20,
        "{compiled} compiled, {refused} refused"
    );
    confined::report(&format!(
        "WGSL fuzz: {compiled} compiled, {refused} refused, no panic"
    ));
}

#[test]
fn user_wgsl_compiling_stays_bounded() {
    if confined::case().is_some() {
        return fuzz_wgsl();
    }
    run_in_child("gltf_and_wgsl::user_wgsl_compiling_stays_bounded");
}
