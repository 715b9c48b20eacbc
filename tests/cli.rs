//! The `aa-lab` binary on good and bad input: it writes what it says, and every user error is a
//! clear message and a non-zero exit, never a panic.

mod common;

use common::{fails_with, stderr};
use std::path::Path;

#[test]
fn render_writes_a_png_with_its_record_and_reproduces_it() {
    let dir = tempfile::tempdir().expect("temp dir");
    let first = dir.path().join("chart.png");
    let out = common::aa_lab(&[
        "render",
        "--scene",
        "chart",
        "--size",
        "160x90",
        "--technique",
        "msaa4",
        "--out",
        first.to_str().expect("utf-8"),
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    let record = aa_lab::export::png::read_record(&first)
        .expect("readable")
        .expect("has a record");
    assert!(
        record.contains("\"scene\": \"chart\"") && record.contains("msaa4"),
        "{record}"
    );
    common::assert_from_reproduces(&first);
}

#[test]
fn several_techniques_go_to_one_directory() {
    let dir = tempfile::tempdir().expect("temp dir");
    let out = common::aa_lab(&[
        "render",
        "--scene",
        "chart",
        "--size",
        "96x54",
        "--technique",
        "none,ssaa",
        "--out",
        dir.path().to_str().expect("utf-8"),
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    for id in ["none", "ssaa"] {
        assert!(
            dir.path().join(format!("chart-{id}.png")).is_file(),
            "chart-{id}.png missing"
        );
    }
}

#[test]
fn bad_input_gets_clear_errors() {
    let tmp = tempfile::tempdir().expect("temp dir");
    let out = tmp.path().join("x.png");
    let out = out.to_str().expect("utf-8");
    fails_with(
        &["render", "--scene", "sponza", "--out", out],
        &["unknown scene `sponza`", "hairball, atrium, chart"],
    );
    fails_with(
        &[
            "render",
            "--scene",
            "chart",
            "--technique",
            "fxaa9",
            "--out",
            out,
        ],
        &["unknown technique `fxaa9`", "none"],
    );
    fails_with(
        &["render", "--scene", "chart", "--size", "0x10", "--out", out],
        &["at least 1"],
    );
    fails_with(
        &[
            "render", "--scene", "chart", "--size", "99999x10", "--out", out,
        ],
        &["largest texture side"],
    );
    fails_with(
        &["render", "--scene", "chart", "--size", "12", "--out", out],
        &["WIDTHxHEIGHT"],
    );
    fails_with(
        &[
            "render",
            "--scene",
            "chart",
            "--size",
            "32x18",
            "--out",
            "/proc/nope/x.png",
        ],
        &["/proc/nope"],
    );
    fails_with(
        &[
            "render",
            "--scene",
            "chart",
            "--technique",
            "none,msaa4",
            "--size",
            "32x18",
            "--out",
            out,
        ],
        &["give a directory"],
    );
    fails_with(
        &[
            "render",
            "--scene",
            "chart",
            "--technique",
            "ssaa",
            "--ssaa-pattern",
            "spiral",
            "--out",
            out,
        ],
        &["spiral", "rgss"],
    );
    fails_with(
        &[
            "render",
            "--scene",
            "chart",
            "--technique",
            "none",
            "--ssaa-factor",
            "4",
            "--out",
            out,
        ],
        &["ssaa technique"],
    );
    let fixtures = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/obj");
    for (file, needle) in [
        ("garbage.obj", "garbage.obj"),
        ("empty.obj", "empty.obj"),
        ("nan_vertex.obj", "nan_vertex.obj"),
        ("missing_mtl.obj", ".mtl"),
    ] {
        let path = fixtures.join(file);
        fails_with(
            &[
                "render",
                "--scene",
                path.to_str().expect("utf-8"),
                "--size",
                "32x18",
                "--out",
                out,
            ],
            &[needle],
        );
    }
    let gpu = aa_lab::gpu::Gpu::headless()
        .expect("GPU tests need a Vulkan driver: apt-get install mesa-vulkan-drivers libvulkan1");
    for samples in [2u32, 8, 16] {
        if !gpu.caps.supports_sample_count(samples) {
            let id = format!("msaa{samples}");
            fails_with(
                &[
                    "render",
                    "--scene",
                    "chart",
                    "--technique",
                    &id,
                    "--size",
                    "32x18",
                    "--out",
                    out,
                ],
                &["supported sample counts"],
            );
        }
    }
}

#[test]
fn a_missing_texture_warns_and_strict_refuses() {
    let tmp = tempfile::tempdir().expect("temp dir");
    let out = tmp.path().join("x.png");
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/obj/missing_texture.obj");
    let path = path.to_str().expect("utf-8");
    let run = common::aa_lab(&[
        "render",
        "--scene",
        path,
        "--size",
        "32x18",
        "--out",
        out.to_str().expect("utf-8"),
    ]);
    assert!(run.status.success(), "{}", stderr(&run));
    assert!(
        stderr(&run).contains("warning:"),
        "no warning: {}",
        stderr(&run)
    );
    fails_with(
        &[
            "render",
            "--scene",
            path,
            "--size",
            "32x18",
            "--strict",
            "--out",
            out.to_str().expect("utf-8"),
        ],
        &["--strict"],
    );
}
