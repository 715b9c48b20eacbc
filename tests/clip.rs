//! `aa-lab clip` end to end on a tiny chart: the same command writes the same bytes, the APNG
//! loops forever with one frame control per frame and carries its record, a `.gif` path
//! writes a GIF, and bad input is a clear error. GPU tests fail (naming the driver package)
//! where no adapter exists.

mod common;

use common::{fails_with, stderr};
use std::path::Path;

fn clip(out: &Path, extra: &[&str]) -> std::process::Output {
    let mut args = vec![
        "clip",
        "--scene",
        "chart",
        "--size",
        "64x48",
        "--frames",
        "4",
        "--warmup",
        "2",
        "--technique",
        "none,fxaa,taa,msaa4",
        "--out",
        out.to_str().expect("utf-8"),
    ];
    args.extend_from_slice(extra);
    common::aa_lab(&args)
}

fn be32(bytes: &[u8]) -> u32 {
    u32::from_be_bytes(bytes[..4].try_into().expect("4 bytes"))
}

#[test]
fn clips_are_deterministic_apngs_with_their_record() {
    let _gpu = common::gpu();
    let dir = tempfile::tempdir().expect("temp dir");
    let a = dir.path().join("a.png");
    let b = dir.path().join("b.png");
    for path in [&a, &b] {
        let out = clip(path, &["--region", "8,8,32,24", "--zoom", "2"]);
        assert!(out.status.success(), "{}", stderr(&out));
    }
    let bytes = std::fs::read(&a).expect("clip written");
    assert!(
        bytes == std::fs::read(&b).expect("clip written"),
        "two runs of the same command wrote different animations"
    );
    assert_eq!(
        std::fs::read(dir.path().join("a.json")).expect("record"),
        std::fs::read(dir.path().join("b.json")).expect("record")
    );

    let chunks = aa_lab::export::animation::png_chunks(&bytes).expect("a PNG chunk stream");
    let actl = chunks
        .iter()
        .find(|(kind, _)| kind == b"acTL")
        .expect("an acTL chunk")
        .1;
    assert_eq!(be32(&actl[0..4]), 4, "num_frames");
    assert_eq!(be32(&actl[4..8]), 0, "num_plays = 0 loops forever");
    assert_eq!(
        chunks.iter().filter(|(kind, _)| kind == b"fcTL").count(),
        4,
        "one fcTL per frame"
    );
    let record = aa_lab::export::png::read_record(&a)
        .expect("readable")
        .expect("the APNG carries its record");
    let json: serde_json::Value = serde_json::from_str(&record).expect("JSON record");
    assert_eq!(json["motion"], "pan");
    assert_eq!(json["frames"], 4);
    assert_eq!(json["zoom"], 2);
    assert_eq!(json["region"]["width"], 32);
    assert_eq!(json["reference"]["id"], "ssaa");
    let techniques = json["techniques"].as_array().expect("techniques");
    assert_eq!(techniques.len(), 4);
    for t in techniques {
        let instability = t["temporal_instability"].as_f64().expect("a figure");
        assert!(instability.is_finite() && instability > 0.0, "{t}");
        assert!(t["ghosting"].as_f64().is_some(), "{t}");
    }
    // The file beside is the same record.
    let beside = std::fs::read_to_string(dir.path().join("a.json")).expect("record");
    assert_eq!(beside, record);

    // Never replaced without --force.
    let out = clip(&a, &["--region", "8,8,32,24", "--zoom", "2"]);
    assert!(!out.status.success());
    assert!(stderr(&out).contains("--force"), "{}", stderr(&out));
    assert!(std::fs::read(&a).expect("kept") == bytes);
}

#[test]
fn a_gif_path_writes_a_looping_gif_of_the_full_frame_grid() {
    let _gpu = common::gpu();
    let dir = tempfile::tempdir().expect("temp dir");
    let path = dir.path().join("clip.gif");
    let out = clip(&path, &["--motion", "still"]);
    assert!(out.status.success(), "{}", stderr(&out));
    let bytes = std::fs::read(&path).expect("gif written");
    assert!(bytes.starts_with(b"GIF89a"), "not a GIF");
    assert!(
        bytes.windows(11).any(|w| w == b"NETSCAPE2.0"),
        "no loop extension"
    );
    let decoder = image::codecs::gif::GifDecoder::new(std::io::Cursor::new(&bytes)).expect("gif");
    let frames = image::AnimationDecoder::into_frames(decoder)
        .collect_frames()
        .expect("frames");
    assert_eq!(frames.len(), 4);
    let json: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(dir.path().join("clip.json")).expect("record beside"),
    )
    .expect("JSON");
    assert_eq!(json["format"], "gif");
    assert_eq!(json["motion"], "still");
    assert!(json["region"].is_null());
}

#[test]
fn bad_clip_input_is_a_clear_error() {
    let dir = tempfile::tempdir().expect("temp dir");
    let out = dir.path().join("x.png");
    let out = out.to_str().expect("utf-8");
    let base = ["clip", "--scene", "chart", "--size", "64x48", "--out", out];
    let with = |extra: &[&'static str]| {
        let mut args = base.to_vec();
        args.extend_from_slice(extra);
        args
    };
    fails_with(&with(&["--frames", "0"]), &["--frames"]);
    fails_with(&with(&["--frames", "100000"]), &["--frames", "600"]);
    fails_with(&with(&["--zoom", "0"]), &["--zoom"]);
    fails_with(&with(&["--speed", "0"]), &["--speed"]);
    fails_with(&with(&["--motion", "spin"]), &["--motion"]);
    fails_with(
        &with(&["--region", "60,40,16,16"]),
        &["--region", "outside the 64x48 render"],
    );
    fails_with(&with(&["--region", "1,2,3"]), &["X,Y,W,H"]);
    let _gpu = common::gpu();
    fails_with(&with(&["--technique", "bogus"]), &["bogus"]);
    fails_with(&with(&["--camera-motion", "still"]), &["--motion"]);
    assert!(!Path::new(out).exists(), "nothing written on bad input");
}
