//! UI test of the HDR path in the viewer: the real [`AaLabApp`] driven headless through
//! egui_kittest (see `tests/ui.rs`) on the `neon` scene. The View > Tonemap menu lists every
//! choice, and choosing one re-renders the techniques through it: `auto` shows the HDR scene
//! through AgX, `none` clamps it (the LDR path) and a lower exposure darkens it.

#[path = "common/viewer.rs"]
mod viewer;

use std::sync::Arc;

use aa_lab::app::AaLabApp;
use aa_lab::graph::hdr::TonemapChoice;
use egui_kittest::kittest::Queryable;
use viewer::{viewer, wait};

/// No AA's published pixels of a frame rendered after `old` (a new publication).
fn no_aa_after(
    harness: &mut egui_kittest::Harness<'static, AaLabApp>,
    old: &Arc<image::RgbaImage>,
) -> Arc<image::RgbaImage> {
    wait(harness, "a frame through the new tonemap", |app| {
        app.frame_ready()
            && app
                .output_pixels("none")
                .is_some_and(|p| !Arc::ptr_eq(&p, old))
    });
    harness
        .state()
        .output_pixels("none")
        .expect("No AA's pixels")
}

/// Pixels with a channel at 255 (clipped) and the mean of every channel.
fn clipped_and_mean(image: &image::RgbaImage) -> (usize, f64) {
    let clipped = image
        .pixels()
        .filter(|p| p[0].max(p[1]).max(p[2]) == 255)
        .count();
    let sum: f64 = image
        .pixels()
        .map(|p| f64::from(p[0]) + f64::from(p[1]) + f64::from(p[2]))
        .sum();
    (
        clipped,
        sum / (3.0 * f64::from(image.width() * image.height())),
    )
}

#[test]
fn the_tonemap_menu_re_renders_the_frame_through_the_choice() {
    let mut harness = viewer("neon");
    let first = harness
        .state()
        .output_pixels("none")
        .expect("No AA's pixels");
    harness.get_by_label("View").click();
    harness.run_steps(10);
    harness.get_by_label("Tonemap").hover();
    harness.run_steps(10);
    for choice in ["auto", "none", "reinhard", "aces", "agx", "neutral"] {
        assert!(
            harness.query_by_label(choice).is_some(),
            "{choice} missing from View > Tonemap"
        );
    }
    harness.get_by_label("none").click();
    harness.run_steps(10);
    assert_eq!(
        harness.state_mut().settings_mut().tonemap,
        TonemapChoice::None
    );

    let clamped = no_aa_after(&mut harness, &first);
    harness.state_mut().settings_mut().tonemap = TonemapChoice::Auto;
    harness.run_steps(10);
    let agx = no_aa_after(&mut harness, &clamped);
    harness.state_mut().settings_mut().exposure = -3.0;
    harness.run_steps(10);
    let darker = no_aa_after(&mut harness, &agx);
    let [agx, clamped, darker] = [&agx, &clamped, &darker].map(|i| clipped_and_mean(i));
    println!("clipped pixels and mean level: AgX {agx:?}, LDR {clamped:?}, AgX -3 EV {darker:?}");
    // Clamped, the tubes clip to 255; through AgX only the bulbs do.
    assert!(clamped.0 > agx.0 * 2, "{clamped:?} vs {agx:?}");
    assert!(darker.1 < agx.1 * 0.9, "{darker:?} vs {agx:?}");
}
