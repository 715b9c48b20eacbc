//! GPU tests of the UI overlay (`graph::overlay`): drawn after the antialiasing it comes out
//! exact in every technique; drawn before it, the post pass blurs it and the temporal pass
//! smears it under motion, while No AA and MSAA (every sample gets the overlay) keep it; the
//! reference always shows it exact; and the render record carries it.

mod common;

use aa_lab::graph::overlay::{OverlayOrder, hud};
use aa_lab::scene::source::load;
use image::RgbaImage;

/// Small, and an odd size, so the HUD's lines fall anywhere in the pixel grid.
const SIZE: (u32, u32) = (411, 233);

/// The HUD's fully covered pixels: where a technique's output should equal the HUD exactly.
fn opaque_pixels(hud: &RgbaImage) -> Vec<(u32, u32)> {
    hud.enumerate_pixels()
        .filter(|(_, _, p)| p[3] == 255)
        .map(|(x, y, _)| (x, y))
        .collect()
}

/// How many of `pixels` differ from the HUD's colour by more than 2/255 in `image`, and the
/// mean difference over them.
fn off_hud(image: &RgbaImage, hud: &RgbaImage, pixels: &[(u32, u32)]) -> (usize, f64) {
    let mut off = 0;
    let mut total = 0u64;
    for &(x, y) in pixels {
        let d = common::largest_channel_difference(image.get_pixel(x, y), hud.get_pixel(x, y));
        total += u64::from(d);
        if d > 2 {
            off += 1;
        }
    }
    (off, total as f64 / pixels.len() as f64)
}

/// No AA, FXAA, TAA, MSAA 4x and the 64-sample reference on atrium's orbit (geometry, and so
/// motion, behind every HUD pixel) with the overlay drawn `order`, after `frames` frames.
fn render(order: OverlayOrder, frames: u64) -> Vec<RgbaImage> {
    let gpu = common::gpu();
    let scene = load("atrium", &Default::default()).unwrap_or_else(|e| panic!("{e}"));
    let techniques = vec![
        common::technique(&gpu, "none", &[]),
        common::technique(&gpu, "fxaa", &[]),
        common::technique(&gpu, "taa", &[]),
        common::technique(&gpu, "msaa4", &[]),
        common::reference(&gpu),
    ];
    let mut graph = common::graph(&gpu, &scene, techniques);
    graph.set_overlay(Some(order));
    common::render_frames(&mut graph, &scene, SIZE, 0..=frames)
}

#[test]
fn after_the_antialiasing_the_overlay_is_exact_in_every_technique() {
    let hud = hud(SIZE);
    let opaque = opaque_pixels(&hud);
    assert!(opaque.len() > 300, "{} opaque HUD pixels", opaque.len());
    let images = render(OverlayOrder::After, 8);
    for (name, image) in ["none", "fxaa", "taa", "msaa4", "reference"]
        .iter()
        .zip(&images)
    {
        let (off, mean) = off_hud(image, &hud, &opaque);
        assert_eq!(off, 0, "{name}: {off} HUD pixels off (mean {mean:.2})");
    }
}

#[test]
fn before_the_antialiasing_fxaa_blurs_and_taa_smears_the_overlay_but_no_aa_and_msaa_keep_it() {
    let hud = hud(SIZE);
    let opaque = opaque_pixels(&hud);
    let before = render(OverlayOrder::Before, 8);
    let after = render(OverlayOrder::After, 8);
    let [none, fxaa, taa, msaa, reference] =
        [0, 1, 2, 3, 4].map(|i| off_hud(&before[i], &hud, &opaque));
    println!(
        "HUD pixels off (mean difference) with the overlay before: No AA {none:?}, FXAA \
         {fxaa:?}, TAA {taa:?}, MSAA 4x {msaa:?}, reference {reference:?} of {}",
        opaque.len()
    );
    // No AA and MSAA 4x (every sample gets the overlay) show it as drawn; so does the
    // reference, which renders its own scene and gets the overlay after its resolve.
    for (name, (off, _)) in [("No AA", none), ("MSAA 4x", msaa), ("reference", reference)] {
        assert_eq!(off, 0, "{name}: {off} HUD pixels off");
    }
    assert_eq!(before[0], after[0], "No AA depends on the order");
    // FXAA softens the one-pixel lines and glyph stems; TAA, whose history follows the
    // scene's motion, drags them along the orbit.
    assert!(
        fxaa.0 > opaque.len() / 20,
        "FXAA changed only {} HUD pixels",
        fxaa.0
    );
    assert!(
        taa.1 > fxaa.1,
        "TAA's smear {:.2} vs FXAA's blur {:.2}",
        taa.1,
        fxaa.1
    );
    // Against the reference, the overlay drawn before costs FXAA and TAA error on the HUD.
    let hud_error = |image: &RgbaImage| {
        opaque
            .iter()
            .map(|&(x, y)| {
                f64::from(common::largest_channel_difference(
                    image.get_pixel(x, y),
                    before[4].get_pixel(x, y),
                ))
            })
            .sum::<f64>()
    };
    for (name, slot) in [("FXAA", 1), ("TAA", 2)] {
        assert!(
            hud_error(&before[slot]) > hud_error(&after[slot]),
            "{name}: the overlay before is no further from the reference than after"
        );
    }
}

#[test]
fn the_render_record_carries_the_overlay_and_reproduces_it() {
    let dir = tempfile::tempdir().expect("temp dir");
    let out = dir.path().join("shot.png");
    let args = [
        "render",
        "--scene",
        "chart",
        "--size",
        "160x90",
        "--technique",
        "fxaa",
        "--ui-overlay",
        "before",
        "--out",
        out.to_str().expect("utf-8 path"),
    ];
    let rendered = common::aa_lab(&args);
    assert!(rendered.status.success(), "{}", common::stderr(&rendered));
    let record = aa_lab::export::png::read_record(&out)
        .expect("a PNG")
        .expect("its render record");
    let json: serde_json::Value = serde_json::from_str(&record).expect("JSON");
    assert_eq!(json["overlay"], "before", "{record}");
    common::assert_from_reproduces(&out);
    common::fails_with(
        &["render", "--scene", "chart", "--ui-overlay", "sideways"],
        &["before", "after"],
    );
}
