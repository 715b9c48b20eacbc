//! The `compare` and `bench` subcommands end to end, through the built binary: scores and
//! error messages of `compare`, and a tiny `bench` on the chart whose report, charts and
//! sidecars are checked, and whose scored images `render --from` reproduces bit-exactly.

mod common;

use std::path::Path;

fn fixture(name: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/fixtures/metrics")
        .join(name)
        .display()
        .to_string()
}

#[test]
fn compare_prints_json_writes_heatmaps_and_explains_errors() {
    let dir = tempfile::tempdir().unwrap();
    let heatmap = dir.path().join("ssim.png");
    let out = common::aa_lab(&[
        "compare",
        &fixture("atrium_ssaa.png"),
        &fixture("atrium_msaa4.png"),
        "--json",
        "--heatmap",
        heatmap.to_str().unwrap(),
        "--metric",
        "ssim",
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    // The scikit-image values of this pair (see tests/metrics_fixtures.rs).
    assert!((json["ssim"].as_f64().unwrap() - 0.969670396).abs() < 1e-4);
    assert!((json["psnr"].as_f64().unwrap() - 39.666737990).abs() < 1e-6);
    assert!(json["flip"].as_f64().unwrap() > 0.0);
    let record = aa_lab::export::png::read_record(&heatmap).unwrap().unwrap();
    assert!(record.contains("\"metric\": \"ssim\""), "{record}");
    let image = image::open(&heatmap).unwrap();
    assert!(image.height() > 72, "the heatmap has a legend strip");

    let mismatch = common::aa_lab(&[
        "compare",
        &fixture("atrium_ssaa.png"),
        &fixture("noise_clean.png"),
    ]);
    assert!(!mismatch.status.success());
    let message = String::from_utf8_lossy(&mismatch.stderr);
    assert!(
        message.contains("96x72")
            && message.contains("61x37")
            && message.contains("noise_clean.png"),
        "{message}"
    );
    let missing = common::aa_lab(&["compare", "/nonexistent/a.png", &fixture("noise_clean.png")]);
    assert!(!missing.status.success());
    assert!(String::from_utf8_lossy(&missing.stderr).contains("/nonexistent/a.png"));
}

#[test]
fn bench_writes_a_report_whose_images_reproduce() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("report");
    let run = common::aa_lab(&[
        "bench",
        "--scene",
        "chart",
        "--technique",
        "none,ssaa",
        "--size",
        "160x90",
        "--frames",
        "3",
        "--warmup",
        "1",
        "--flicker-frames",
        "2",
        "--quality-frame",
        "0",
        "--images",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("report.json")).unwrap()).unwrap();
    assert_eq!(report["schema"], "aa-lab-bench/1");
    let run = &report["runs"][0];
    assert_eq!(run["scene"], "chart");
    assert_eq!(run["techniques"].as_array().unwrap().len(), 2);
    let none = &run["techniques"][0];
    assert_eq!(none["id"], "none");
    assert_eq!(none["own_ms"]["count"], 3);
    assert_eq!(none["relative_to_none"], 1.0);
    assert!(none["quality"]["ssim"].as_f64().unwrap() < 1.0);
    assert!(none["truth"]["ssim"].as_f64().unwrap() > 0.0);
    assert!(none["flicker_ratio"].as_f64().is_some());
    assert!(run["floor_ms"]["median"].as_f64().unwrap() > 0.0);
    assert!(run["spec"]["adapter"].is_string() && run["spec"]["build"].is_string());
    let md = std::fs::read_to_string(out.join("report.md")).unwrap();
    assert!(md.contains("## SSIM against the 64-sample SSAA reference"));
    for file in [
        "time-chart-160x90.png",
        "ssim-chart.png",
        "chart-160x90.spec.json",
    ] {
        assert!(out.join(file).is_file(), "{file} missing");
    }
    // The scored image reproduces bit-exactly from its sidecar.
    let again = dir.path().join("again");
    let render = common::aa_lab(&[
        "render",
        "--from",
        out.join("chart-160x90.spec.json").to_str().unwrap(),
        "--out",
        again.to_str().unwrap(),
    ]);
    assert!(
        render.status.success(),
        "{}",
        String::from_utf8_lossy(&render.stderr)
    );
    for id in ["none", "ssaa"] {
        let scored = image::open(out.join(format!("chart-160x90-{id}.png"))).unwrap();
        let reproduced = image::open(again.join(format!("chart-{id}.png"))).unwrap();
        assert!(scored == reproduced, "{id} does not reproduce");
    }
}
