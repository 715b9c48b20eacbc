//! The `compare` and `bench` subcommands end to end, through the built binary: scores and
//! error messages of `compare`, and a tiny `bench` on the chart whose report, charts and
//! sidecars are checked, and whose scored images `render --from` reproduces bit-exactly; `bench
//! --jod`, which adds every technique's JOD over the flicker frames.

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
fn compare_edge_gain_is_zero_for_no_aa_one_for_the_reference_and_checks_sizes() {
    let (reference, no_aa) = (fixture("hairball_ssaa.png"), fixture("hairball_none.png"));
    let gain = |test: &str| {
        let out = common::aa_lab(&["compare", &reference, test, "--edge-gain", &no_aa, "--json"]);
        assert!(out.status.success(), "{}", common::stderr(&out));
        let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
        json["edge_gain"].as_f64().expect("edge_gain in the JSON")
    };
    assert_eq!(gain(&no_aa), 0.0);
    assert_eq!(gain(&reference), 1.0);
    let text = common::aa_lab(&["compare", &reference, &no_aa, "--edge-gain", &no_aa]);
    assert!(
        common::stdout(&text).contains("edge gain 0.0000"),
        "{}",
        common::stdout(&text)
    );
    common::fails_with(
        &[
            "compare",
            &reference,
            &no_aa,
            "--edge-gain",
            &fixture("noise_clean.png"),
        ],
        &["--edge-gain", "61x37", "noise_clean.png"],
    );
}

/// The `report.json` a bench wrote into `out`.
fn read_report(out: &Path) -> serde_json::Value {
    let text = std::fs::read_to_string(out.join("report.json")).expect("report.json");
    serde_json::from_str(&text).expect("report.json is JSON")
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
    let report = read_report(&out);
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

/// Checks the `metric` front a bench run lists in `quality_fronts` against every technique of
/// the run and returns its ids: cheapest first; no technique is as good or better at the same
/// or lower cost than a front technique (and strictly better in one); every technique off the
/// front is matched by a front technique at no more cost. `better(a, b)`: quality `a` is
/// better than `b`.
fn assert_pareto_optimal(
    run: &serde_json::Value,
    metric: &str,
    better: fn(f64, f64) -> bool,
) -> Vec<String> {
    let points: Vec<(String, f64, f64)> = run["techniques"]
        .as_array()
        .expect("techniques")
        .iter()
        .map(|t| {
            (
                t["id"].as_str().expect("an id").to_owned(),
                t["total_ms"]["median"].as_f64().expect("a median"),
                t["quality"][metric].as_f64().expect("a score"),
            )
        })
        .collect();
    let front: Vec<String> = run["quality_fronts"][metric]
        .as_array()
        .unwrap_or_else(|| panic!("no {metric} front"))
        .iter()
        .map(|id| id.as_str().expect("an id").to_owned())
        .collect();
    assert!(!front.is_empty(), "empty {metric} front");
    let point = |id: &str| {
        points
            .iter()
            .find(|p| p.0 == id)
            .unwrap_or_else(|| panic!("{id} of the {metric} front is not a technique"))
            .clone()
    };
    let costs: Vec<f64> = front.iter().map(|id| point(id).1).collect();
    assert!(
        costs.windows(2).all(|w| w[0] <= w[1]),
        "{metric} front not cheapest first: {front:?} {costs:?}"
    );
    for (id, cost, quality) in &points {
        let matched_by = |other: &&(String, f64, f64)| {
            other.0 != *id && other.1 <= *cost && !better(*quality, other.2)
        };
        if front.contains(id) {
            let dominating = points
                .iter()
                .filter(matched_by)
                .find(|o| o.1 < *cost || better(o.2, *quality));
            assert!(
                dominating.is_none(),
                "{id} is on the {metric} front but {dominating:?} beats it"
            );
        } else {
            assert!(
                points
                    .iter()
                    .filter(|o| front.contains(&o.0))
                    .any(|o| matched_by(&o)),
                "{id} ({cost} ms, {metric} {quality}) is off the {metric} front {front:?} but nothing on it matches it"
            );
        }
    }
    front
}

#[test]
fn a_scale_sweep_puts_native_and_upscaled_techniques_on_one_pareto_front() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("report");
    let mut args = vec![
        "bench",
        "--scene",
        "chart",
        "--technique",
        "none,fxaa",
        "--sweep",
        "scale",
        "--scales",
        "native,0.5",
        "--size",
        "128x72",
        "--frames",
        "2",
        "--warmup",
        "1",
        "--flicker-frames",
        "2",
        "--quality-frame",
        "1",
        "--out",
    ];
    // Bad scales are refused before anything runs, and --scales needs the sweep.
    for (scales, needles) in [
        (
            "native,0.1",
            &["--scales", "`0.1`", "out of range", "0.25 to 1"][..],
        ),
        (
            "quality,fast",
            &["`fast`", "neither a number nor a preset", "performance"],
        ),
    ] {
        let mut bad = args.clone();
        bad[8] = scales;
        bad.push(out.to_str().unwrap());
        let refused = common::aa_lab(&bad);
        assert!(!refused.status.success(), "{scales} accepted");
        let message = String::from_utf8_lossy(&refused.stderr);
        for needle in needles {
            assert!(
                message.contains(needle),
                "{scales}: `{needle}` not in {message}"
            );
        }
    }
    let refused = common::aa_lab(&["bench", "--scales", "0.5", "--out", out.to_str().unwrap()]);
    assert!(!refused.status.success());
    assert!(String::from_utf8_lossy(&refused.stderr).contains("--sweep scale"));
    assert!(!out.exists(), "a refused bench wrote nothing");

    args.push(out.to_str().unwrap());
    let run = common::aa_lab(&args);
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let report = read_report(&out);
    let settings = &report["settings"];
    assert_eq!(settings["sweep"], "scale");
    assert_eq!(settings["scales"], serde_json::json!([1.0, 0.5]));
    assert_eq!(settings["quality"], true);
    let ids = [
        "none",
        "none@performance:easu",
        "fxaa",
        "fxaa@performance:easu",
    ];
    assert_eq!(settings["techniques"], serde_json::json!(ids));
    assert_eq!(
        report["runs"].as_array().unwrap().len(),
        1,
        "one run per scene and size"
    );
    let run = &report["runs"][0];
    let techniques = run["techniques"].as_array().unwrap();
    assert_eq!(techniques.len(), ids.len());
    for (technique, id) in techniques.iter().zip(ids) {
        assert_eq!(technique["id"], id);
        let scale = if id.contains('@') { 0.5 } else { 1.0 };
        assert_eq!(technique["render_scale"], scale, "{id}");
        assert!(
            technique["quality"]["ssim"].as_f64().is_some(),
            "{id} unscored"
        );
        assert!(technique["total_ms"]["median"].as_f64().unwrap() > 0.0);
    }
    // Upscaled techniques' own passes include the upscale.
    let upscaled = &techniques[1]["passes"];
    assert!(
        upscaled
            .as_array()
            .unwrap()
            .iter()
            .any(|p| p["label"].as_str().unwrap().ends_with("/upscale")),
        "{upscaled}"
    );
    let ssim_front = assert_pareto_optimal(run, "ssim", |a, b| a > b);
    let flip_front = assert_pareto_optimal(run, "flip", |a, b| a < b);

    let md = std::fs::read_to_string(out.join("report.md")).unwrap();
    let section = md
        .split("## Which technique at which scale for my budget")
        .nth(1)
        .expect("the budget section");
    let section = section.split("\n## ").next().unwrap();
    let rows = section
        .lines()
        .filter(|l| l.starts_with("| ") && !l.contains("---"))
        .count();
    let mut on_a_front: Vec<&String> = ssim_front.iter().chain(&flip_front).collect();
    on_a_front.sort();
    on_a_front.dedup();
    // The header, a row per technique on either front, and the charts' two rows.
    assert_eq!(rows, 1 + on_a_front.len() + 2, "{section}");
    for file in [
        "quality-cost-chart-128x72.png",
        "flip-cost-chart-128x72.png",
        "time-chart-128x72.png",
    ] {
        assert!(
            section.contains(file) || file.starts_with("time"),
            "{file} not linked"
        );
        assert_eq!(image::open(out.join(file)).unwrap().width(), 960, "{file}");
    }
}

#[test]
fn bench_jod_scores_every_technique_over_the_flicker_frames() {
    let _gpu = common::gpu();
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("report");
    let args = [
        "bench",
        "--scene",
        "chart",
        "--technique",
        "none,taa",
        "--size",
        "64x48",
        "--frames",
        "4",
        "--warmup",
        "1",
        "--flicker-frames",
        "4",
        "--quality-frame",
        "0",
        "--jod",
        "--jod-display",
        "standard_4k",
        "--jod-ppd",
        "45.5",
        "--out",
        out.to_str().unwrap(),
    ];
    let run = common::aa_lab(&args);
    assert!(run.status.success(), "{}", common::stderr(&run));
    let report = read_report(&out);
    let jod = &report["settings"]["jod"];
    assert_eq!(jod["display"], "standard_4k");
    assert_eq!(jod["fps"], 30.0);
    assert_eq!(
        jod["pixels_per_degree"], 45.5,
        "the viewing distance is recorded"
    );
    let techniques = report["runs"][0]["techniques"].as_array().unwrap();
    let jods: Vec<f64> = techniques
        .iter()
        .map(|t| t["jod"].as_f64().unwrap_or_else(|| panic!("no JOD: {t}")))
        .collect();
    assert_eq!(jods.len(), 2);
    for value in &jods {
        assert!(*value > 0.0 && *value < 10.0, "{jods:?}");
    }
    let md = std::fs::read_to_string(out.join("report.md")).unwrap();
    assert!(
        md.contains("## ColorVideoVDP: JOD of the flicker frames"),
        "{md}"
    );
    // Without flicker frames there is nothing to score.
    let mut no_quality = args.to_vec();
    no_quality.push("--no-quality");
    no_quality.push("--force");
    common::fails_with(&no_quality, &["--jod scores the flicker frames"]);
}
