//! The list of every technique aa-lab knows. Each technique's folder provides its own entry
//! ([`TechniqueInfo`]: stable id (the folder's `ID` constant), display name, the trade-off
//! paragraph used for `aa-lab techniques` and tooltips, whether this adapter can
//! run it, how to create it and its WGSL files); [`registry`] lists the entries, one line per
//! technique. The availability checks several techniques share live here too.

use super::{Technique, cmaa2, fxaa, mlaa, msaa, none, smaa, smaa_4x, ssaa, taa};
use crate::gpu::shader::Shader;
use crate::gpu::{Capabilities, Gpu};

/// One registry entry.
#[derive(Clone, Copy)]
pub struct TechniqueInfo {
    /// Stable id, as on the command line.
    pub id: &'static str,
    /// Display name.
    pub name: &'static str,
    /// One paragraph: what it does, what it costs, where it fails.
    pub summary: &'static str,
    /// `Ok` when this adapter can run it, otherwise the reason it cannot.
    pub availability: fn(&Capabilities) -> Result<(), String>,
    /// Creates the technique with default settings (only called when available).
    pub create: fn(&Gpu) -> Box<dyn Technique>,
    /// The technique's own WGSL files (in its folder), which the naga test validates.
    pub shaders: &'static [Shader],
}

/// What a Vulkan driver gives on a machine without a GPU, quoted where a technique cannot run.
pub const FULL_SET_HINT: &str = "a Vulkan driver runs every technique (without a GPU: Mesa's \
     software driver, `apt-get install mesa-vulkan-drivers libvulkan1`)";

/// Techniques that only draw and resolve in the output's own format run on every backend.
pub fn anywhere(_caps: &Capabilities) -> Result<(), String> {
    Ok(())
}

/// What the post-process techniques (and MSAA's resolve and debug views) need: sRGB and linear
/// views of one texture (see [`Capabilities::view_formats`]).
pub fn needs_encoded_views(caps: &Capabilities) -> Result<(), String> {
    if caps.view_formats {
        Ok(())
    } else {
        Err(format!(
            "the {} backend cannot view a texture both as sRGB and as linear values (wgpu's \
             VIEW_FORMATS), which this technique needs; {FULL_SET_HINT}",
            caps.backend
        ))
    }
}

/// Every technique, in the order front ends list them: each technique folder provides its
/// entries (`INFO`, or `INFOS` for a family of fixed variants), and adding a technique is one
/// line here.
pub fn registry() -> Vec<TechniqueInfo> {
    [
        &[none::INFO][..],
        &[ssaa::INFO],
        &msaa::INFOS,
        &[fxaa::INFO],
        &[mlaa::INFO],
        &smaa::INFOS,
        &[smaa_4x::INFO],
        &[taa::INFO],
        &[cmaa2::INFO],
    ]
    .concat()
}

/// The registry entry of an id.
pub fn info(id: &str) -> Option<TechniqueInfo> {
    registry().into_iter().find(|t| t.id == id)
}

/// The display name of a registered technique or a user technique (`user:PATH`; any other
/// id as it is): the label of techniques whose settings do not change what they are.
pub fn display_name(id: &str) -> String {
    match info(id) {
        Some(info) => info.name.to_owned(),
        None if super::user::is_user_id(id) => super::user::display_name(id),
        None => id.to_owned(),
    }
}
