//! `aa-lab clip --html` in a real browser: headless Chromium (Debian's `chromium`, which
//! `.ci/run` installs) opens a small page offline with `#selftest`, where the page steps,
//! zooms, moves the wipe and plays by itself and logs what its wipe view shows to the console
//! (Chromium's log on stderr), then closes; the test checks those pixels against the frames
//! embedded in the page. It runs in real time: Chromium's virtual time (`--virtual-time-budget`
//! with `--dump-dom`) does not wait for image decoding and left the report empty on a CI
//! machine. The test fails with a clear message where Chromium is missing, like the GPU tests
//! without an adapter.

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

/// How long the browser may take to open the page, decode its frames and play them.
const BROWSER_DEADLINE: std::time::Duration = std::time::Duration::from_secs(120);

/// The results the page's self-test logs between its markers, from a line of Chromium's log.
fn selftest_line(line: &str) -> Option<&str> {
    let start = line.find("aa-lab-selftest<<<")? + "aa-lab-selftest<<<".len();
    let end = start + line[start..].rfind(">>>")?;
    Some(&line[start..end])
}

/// Opens `page` with `#selftest` in headless Chromium, in real time (no virtual time: the
/// frames' decoding and the playback timer run as in a user's browser), and returns what the
/// self-test reports. The page closes itself once it has reported, which ends the browser;
/// one that has not reported by [`BROWSER_DEADLINE`] is killed and the test fails with the
/// browser's log.
fn selftest_results(page: &std::path::Path) -> serde_json::Value {
    use std::io::BufRead;
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
            "--enable-logging=stderr",
            "--v=0",
        ])
        .arg(format!("--user-data-dir={}", profile.path().display()))
        .arg(format!("file://{}#selftest", page.display()))
        .stdin(std::process::Stdio::null())
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::piped())
        .spawn();
    let mut browser = match browser {
        Ok(child) => child,
        Err(err) => panic!(
            "cannot run chromium ({err}): the HTML test needs headless Chromium (Debian: apt-get install chromium; .ci/run installs it)"
        ),
    };
    let log = browser.stderr.take().expect("piped stderr");
    let (lines, received) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        for line in std::io::BufReader::new(log).lines().map_while(Result::ok) {
            if lines.send(line).is_err() {
                break;
            }
        }
    });
    let deadline = std::time::Instant::now() + BROWSER_DEADLINE;
    let mut seen = Vec::new();
    let report = loop {
        let left = deadline.saturating_duration_since(std::time::Instant::now());
        match received.recv_timeout(left) {
            Ok(line) => match selftest_line(&line) {
                Some(report) => break Some(report.to_owned()),
                None => seen.push(line),
            },
            // The browser exited, or the deadline passed, without a report.
            Err(_) => break None,
        }
    };
    // The page closed itself after reporting; a browser still running is ended either way.
    let _ = browser.kill();
    let _ = browser.wait();
    let Some(report) = report else {
        let tail: Vec<&str> = seen
            .iter()
            .skip(seen.len().saturating_sub(40))
            .map(|line| &line[..line.floor_char_boundary(400)])
            .collect();
        panic!(
            "headless Chromium exited or ran past {BROWSER_DEADLINE:?} without a self-test report; the end of its log:\n{}",
            tail.join("\n")
        )
    };
    serde_json::from_str(&report).unwrap_or_else(|e| panic!("self-test output {report:?}: {e}"))
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

    let results = selftest_results(&page);
    assert!(
        results.get("error").is_none(),
        "the page decodes its frames: {results}"
    );
    assert_eq!(results["stepped_to"], 2, "two steps from the first frame");
    let played = results["played_frames"].as_u64().expect("frames played");
    assert!(
        played >= 3,
        "playing moves on: {played} frames in up to five seconds"
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
