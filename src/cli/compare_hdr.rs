//! `aa-lab compare REFERENCE.exr TEST.exr`: two images of linear radiance (OpenEXR, as
//! `render --exr` writes them) scored with HDR-FLIP (`metrics::hdr_flip`), as text or JSON,
//! with the HDR-FLIP map as the heatmap. The LDR metrics would clip the radiance they are
//! about, so they are not computed; score the PNGs for those.

use std::path::Path;

use anyhow::{Context, bail};

use super::compare::{CompareArgs, MAX_COMPARE_PIXELS, heatmap_policy};
use super::heatmap_files::write_metric_heatmap;
use crate::export::radiance::read_radiance;
use crate::metrics::Metric;
use crate::metrics::hdr_flip::hdr_flip;

/// What `compare --json` prints for two HDR images.
#[derive(serde::Serialize)]
struct HdrCompareOutput<'a> {
    reference: &'a Path,
    test: &'a Path,
    width: u32,
    height: u32,
    /// Mean HDR-FLIP (0: indistinguishable at every exposure).
    hdr_flip: f64,
    /// First and last exposure compared, in stops.
    exposure_range: (f32, f32),
    /// Exposures compared.
    exposures: usize,
}

/// Runs `aa-lab compare` on two OpenEXR images.
pub fn run(args: &CompareArgs) -> anyhow::Result<()> {
    if args.heatmap.is_some() && args.metric != Metric::Flip {
        bail!(
            "two OpenEXR images are scored with HDR-FLIP only: use --metric flip for the heatmap"
        );
    }
    let policy = heatmap_policy(args, [args.reference.as_path(), args.test.as_path()])?;
    let read = |path: &Path| read_radiance(path, MAX_COMPARE_PIXELS, "compare");
    let (reference, test) = (read(&args.reference)?, read(&args.test)?);
    let scored = hdr_flip(&reference, &test).with_context(|| {
        format!(
            "cannot compare {} with {}",
            args.reference.display(),
            args.test.display()
        )
    })?;
    let output = HdrCompareOutput {
        reference: &args.reference,
        test: &args.test,
        width: reference.width(),
        height: reference.height(),
        hdr_flip: scored.mean,
        exposure_range: scored.exposure_range,
        exposures: scored.exposures,
    };
    if let Some(path) = &args.heatmap {
        let compare = serde_json::to_value(&output)?;
        write_metric_heatmap(path, Metric::Flip, &scored.map, compare, &policy)?;
    }
    if args.json {
        println!("{}", serde_json::to_string_pretty(&output)?);
        return Ok(());
    }
    println!(
        "{} vs reference {} ({}x{}, linear radiance)",
        args.test.display(),
        args.reference.display(),
        output.width,
        output.height
    );
    println!(
        "HDR-FLIP  {:.5}  mean of the largest FLIP over {} exposures from {:+.1} to {:+.1} EV",
        scored.mean, scored.exposures, scored.exposure_range.0, scored.exposure_range.1
    );
    Ok(())
}
