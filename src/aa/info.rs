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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::aa::registry;

    /// A Vulkan adapter's report, with the two flags the availability checks read.
    fn caps(view_formats: bool, fragment_storage: bool) -> Capabilities {
        Capabilities {
            adapter_name: "test adapter".into(),
            backend: "Vulkan".into(),
            device_type: "Cpu".into(),
            driver: String::new(),
            software: true,
            formats: Vec::new(),
            scene_sample_counts: vec![1],
            timestamps: false,
            timestamp_period_ns: 0.0,
            pipeline_statistics: false,
            max_texture_dimension_2d: 8192,
            max_buffer_size: 1 << 28,
            view_formats,
            fragment_storage,
        }
    }

    fn available(id: &str, caps: &Capabilities) -> Result<(), String> {
        (registry::info(id).expect("registered").availability)(caps)
    }

    #[test]
    fn the_temporal_resolves_need_fragment_storage_writes_and_the_others_do_not() {
        let without_stores = caps(true, false);
        for id in ["taa", "taau"] {
            let reason = available(id, &without_stores).expect_err(id);
            assert!(
                reason.contains("FRAGMENT_WRITABLE_STORAGE"),
                "{id}: {reason}"
            );
            assert_eq!(available(id, &caps(true, true)), Ok(()), "{id}");
        }
        for id in ["fxaa", "smaa", "cmaa2", "mlaa"] {
            assert_eq!(available(id, &without_stores), Ok(()), "{id}");
        }
        // Without sRGB views the views are the reason given, stores or not.
        let reason = available("taau", &caps(false, true)).expect_err("taau without views");
        assert!(reason.contains("VIEW_FORMATS"), "{reason}");
    }
}
