//! ColorVideoVDP in aa-lab agrees with the authors' implementation: three aa-lab clips
//! (committed as frames in `tests/fixtures/jod/`, with how they were made) scored by
//! `metrics::jod` come within 0.1 JOD of the values the PyTorch `cvvdp` 0.5.7 gave for them.

use std::path::Path;

use aa_lab::metrics::jod::JodScorer;

fn frames(folder: &Path) -> Vec<image::RgbaImage> {
    let mut paths: Vec<_> = std::fs::read_dir(folder)
        .expect("fixture frames")
        .map(|entry| entry.expect("entry").path())
        .filter(|p| p.extension().is_some_and(|e| e == "png"))
        .collect();
    paths.sort();
    paths
        .iter()
        .map(|p| image::open(p).expect("a PNG frame").to_rgba8())
        .collect()
}

#[test]
fn jod_agrees_with_the_reference_implementation_on_three_clips() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/jod");
    let expected: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(root.join("cvvdp.json")).expect("reference values"),
    )
    .expect("JSON");
    let display = expected["display"].as_str().expect("display");
    let fps = expected["fps"].as_f64().expect("fps") as f32;
    let scorer = JodScorer::new(display).expect("display model");
    let reference = frames(&root.join("frames/reference"));
    let clips = expected["jod"].as_object().expect("scores");
    assert!(clips.len() >= 3, "three clips at least");
    for (clip, value) in clips {
        let want = value.as_f64().expect("a JOD");
        let got = scorer
            .score(&frames(&root.join("frames").join(clip)), &reference, fps)
            .expect("scored");
        assert!(
            (got - want).abs() <= 0.1,
            "{clip}: aa-lab {got:.4} JOD, cvvdp {want:.4}"
        );
    }
}
