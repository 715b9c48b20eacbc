//! `aa-lab clip --html` in a real browser: headless Chromium (Debian's `chromium`, which
//! `.ci/run` installs) opens a small page offline with `#selftest`, where the page steps,
//! zooms, moves the wipe and plays by itself and writes what its wipe view shows into the DOM;
//! the test checks those pixels against the frames embedded in the page. The test fails with a
//! clear message where Chromium is missing, like the GPU tests without an adapter.

mod common;

use base64::Engine;
use common::stderr;

/// The frames embedded in the page: one sprite of the panes side by side per frame.
fn sprites(html: &str) -> Vec<image::RgbaImage> {
    let marker = "F.push(\"data:image/png;base64,";
    html.split(marker)
        .skip(1)
        .map(|rest| {
            let data = &rest[..rest.find('"').expect("end of the data URI")];
            let png = base64::engine::general_purpose::STANDARD
                .decode(data)
                .expect("base64");
            image::load_from_memory(&png).expect("a PNG").to_rgba8()
        })
        .collect()
}

/// What the page's self-test wrote into `<pre id="selftest">` (empty before it has run).
fn selftest_text(dom: &str) -> String {
    let start = dom.find("id=\"selftest\"").expect("the self-test element");
    let text = &dom[start..];
    let text = &text[text.find('>').expect("its text") + 1..];
    let text = &text[..text.find("</pre>").expect("its end")];
    text.replace("&quot;", "\"").replace("&amp;", "&")
}

/// The self-test's results.
fn selftest_results(dom: &str) -> serde_json::Value {
    let text = selftest_text(dom);
    serde_json::from_str(&text).unwrap_or_else(|e| panic!("self-test output {text:?}: {e}"))
}

/// The DOM of `page` opened with `#selftest` in headless Chromium, once its virtual time is
/// spent.
fn selftest_dom(page: &std::path::Path) -> String {
    let profile = tempfile::tempdir().expect("profile dir");
    let browser = std::process::Command::new("chromium")
        .args([
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--disable-background-networking",
            "--disable-component-update",
            "--disable-sync",
            "--no-first-run",
            "--virtual-time-budget=10000",
            "--dump-dom",
        ])
        .arg(format!("--user-data-dir={}", profile.path().display()))
        .arg(format!("file://{}#selftest", page.display()))
        .output();
    let browser = match browser {
        Ok(output) => output,
        Err(err) => panic!(
            "cannot run chromium ({err}): the HTML test needs headless Chromium (Debian: apt-get install chromium; .ci/run installs it)"
        ),
    };
    String::from_utf8_lossy(&browser.stdout).into_owned()
}

#[test]
fn the_html_page_plays_steps_zooms_and_wipes_in_chromium() {
    let _gpu = common::gpu();
    let dir = tempfile::tempdir().expect("temp dir");
    let out = dir.path().join("clip.png");
    let run = common::clip(&out, &["--region", "20,14,16,12", "--zoom", "4", "--html"]);
    assert!(run.status.success(), "{}", stderr(&run));
    let page = dir.path().join("clip.html");
    let html = std::fs::read_to_string(&page).expect("page written");
    assert!(
        !html.contains("http://") && !html.contains("https://"),
        "the page must work offline"
    );
    let sprites = sprites(&html);
    assert_eq!(sprites.len(), 4, "every frame embedded");
    assert_eq!(
        sprites[0].dimensions(),
        (5 * 16, 12),
        "five panes of the region"
    );

    // Chromium's virtual time can run out while the page's images are still decoding on a
    // loaded machine (the self-test then has written nothing yet): such a run is tried again.
    let mut attempts = 0;
    let results = loop {
        attempts += 1;
        let dom = selftest_dom(&page);
        if attempts == 3 || !selftest_text(&dom).is_empty() {
            break selftest_results(&dom);
        }
    };
    assert_eq!(results["stepped_to"], 2, "two steps from the first frame");
    let played = results["played_frames"].as_u64().expect("frames played");
    assert!(
        played >= 3,
        "playing moves on: {played} frames in 10 frames' time"
    );
    let samples = results["samples"].as_array().expect("samples");
    let panes: Vec<u64> = samples
        .iter()
        .map(|s| s["pane"].as_u64().expect("pane"))
        .collect();
    assert!(
        panes.contains(&0) && panes.contains(&4),
        "both sides of the wipe: {panes:?}"
    );
    let distinct: std::collections::HashSet<String> =
        samples.iter().map(|s| s["rgba"].to_string()).collect();
    assert!(
        distinct.len() > 1,
        "the samples show detail, not a flat area: {distinct:?}"
    );
    for sample in samples {
        let at = |key: &str| sample[key].as_u64().expect("a number") as u32;
        let expected = sprites[at("frame") as usize].get_pixel(at("pane") * 16 + at("x"), at("y"));
        let shown: Vec<u8> = sample["rgba"]
            .as_array()
            .expect("rgba")
            .iter()
            .map(|v| v.as_u64().expect("a channel") as u8)
            .collect();
        assert_eq!(shown, expected.0.to_vec(), "pixel shown for {sample}");
    }
}
