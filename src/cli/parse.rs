//! Parsers of the option values several commands share (sizes, the UI overlay, the tonemap and
//! the exposure), each with an error message that says what a good value looks like.

use crate::graph::hdr::TonemapChoice;
use crate::graph::overlay::OverlayOrder;
use crate::graph::params::Named;

/// Parses `--tonemap`: a [`TonemapChoice`] by name.
pub fn parse_tonemap(text: &str) -> Result<TonemapChoice, String> {
    TonemapChoice::from_name(text)
        .ok_or_else(|| format!("expected one of {}", TonemapChoice::NAMES.join(", ")))
}

/// Parses `--exposure` in stops; beyond +-20 stops (a factor of a million) is a mistake, not a
/// look.
pub fn parse_exposure(text: &str) -> Result<f32, String> {
    match text.trim().parse::<f32>() {
        Ok(ev) if ev.is_finite() && ev.abs() <= 20.0 => Ok(ev),
        _ => Err(format!(
            "`{text}` is not an exposure: a number of stops between -20 and 20"
        )),
    }
}

/// Parses `--ui-overlay`.
pub fn parse_overlay(text: &str) -> Result<OverlayOrder, String> {
    OverlayOrder::from_name(text)
        .ok_or_else(|| format!("expected one of {}", OverlayOrder::NAMES.join(", ")))
}

/// Parses `WIDTHxHEIGHT`, both whole numbers of at least 1.
pub fn parse_size(text: &str) -> Result<(u32, u32), String> {
    let expected =
        "a size is WIDTHxHEIGHT in pixels, both whole numbers of at least 1 (e.g. 1280x720)";
    let (w, h) = text
        .split_once(['x', 'X'])
        .ok_or_else(|| format!("`{text}`: {expected}"))?;
    let parse = |s: &str| match s.trim().parse::<u32>() {
        Ok(0) | Err(_) => Err(format!("`{s}` in `{text}` is not a size; {expected}")),
        Ok(v) => Ok(v),
    };
    Ok((parse(w)?, parse(h)?))
}
