//! What a technique's registry entry says about it ([`TechniqueInfo`]: stable id, display name,
//! trade-off paragraph, availability on an adapter, constructor and WGSL files), and the
//! availability checks several techniques share. Techniques build their entries from this
//! file; `registry.rs` lists the entries. Keeping the entry's type apart from the list keeps
//! the imports one-way: the registry imports the techniques, the techniques import only this.

use super::Technique;
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

/// The temporal resolves write their history as storage textures from the fragment shader,
/// so the adapter must allow that besides the views every technique needs.
pub fn needs_history_stores(caps: &Capabilities) -> Result<(), String> {
    needs_encoded_views(caps)?;
    if caps.fragment_storage {
        Ok(())
    } else {
        Err(format!(
            "the {} backend cannot write storage textures from a fragment shader (wgpu's \
             FRAGMENT_WRITABLE_STORAGE), where this technique keeps its history",
            caps.backend
        ))
    }
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
