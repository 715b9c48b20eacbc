//! The list of every technique aa-lab knows: stable id, display name, the trade-off paragraph
//! (used for `aa-lab techniques`, tooltips and the README), whether this adapter can run it and
//! how to create it. Adding a technique is one entry here plus its module.

use super::Technique;
use super::fxaa::Fxaa;
use super::msaa::Msaa;
use super::none::NoAa;
use super::ssaa::Ssaa;
use super::taa::Taa;
use crate::gpu::{Capabilities, Gpu};

/// One registry entry.
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
}

/// What a Vulkan driver gives on a machine without a GPU, quoted where a technique cannot run.
const FULL_SET_HINT: &str = "a Vulkan driver runs every technique (without a GPU: Mesa's \
     software driver, `apt-get install mesa-vulkan-drivers libvulkan1`)";

/// Techniques that only draw and resolve in the output's own format run on every backend.
fn anywhere(_caps: &Capabilities) -> Result<(), String> {
    Ok(())
}

/// What the post-process techniques (and MSAA's resolve and debug views) need: sRGB and linear
/// views of one texture (see [`Capabilities::view_formats`]).
fn needs_encoded_views(caps: &Capabilities) -> Result<(), String> {
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

/// SMAA S2x reads depth with `textureLoad`, which wgpu cannot translate to GLSL.
fn smaa_s2x_availability(caps: &Capabilities) -> Result<(), String> {
    needs_encoded_views(caps)?;
    if caps.is_gl() {
        Err(format!(
            "SMAA S2x loads depth samples with textureLoad, which the OpenGL backend's GLSL \
             cannot do; {FULL_SET_HINT}"
        ))
    } else {
        Ok(())
    }
}

fn msaa_availability(caps: &Capabilities, samples: u32) -> Result<(), String> {
    needs_encoded_views(caps)?;
    if caps.supports_sample_count(samples) {
        Ok(())
    } else {
        Err(format!(
            "{samples}x MSAA is not supported by {} for the scene's colour, depth and motion formats \
             (supported sample counts: {:?})",
            caps.adapter_name, caps.scene_sample_counts
        ))
    }
}

const MSAA_SUMMARY: &str = "Multisampling: coverage and depth are tested at n sample positions per pixel but the \
     pixel shader runs once per pixel, and the samples are averaged at the end. Geometric edges get n+1 \
     coverage levels at a fraction of SSAA's shading cost, but colour and depth memory grow n times, and \
     aliasing inside triangles (textures, specular highlights, alpha-tested cut-outs) is left alone unless \
     alpha-to-coverage or sample-rate shading is switched on. Its cost grows with scene complexity.";

/// Every technique, in the order front ends list them.
pub fn registry() -> Vec<TechniqueInfo> {
    vec![
        TechniqueInfo {
            id: "none",
            name: "No AA",
            summary: "One sample per pixel at the pixel centre: the cheapest image and the baseline. Every \
                 edge is a staircase, sub-pixel geometry breaks up or vanishes, and anything thinner than a \
                 pixel flickers as the camera moves.",
            availability: anywhere,
            create: |_| Box::new(NoAa),
        },
        TechniqueInfo {
            id: "ssaa",
            name: "SSAA",
            summary: "Supersampling: every sample is fully shaded (k x k ordered grid, or N jittered samples \
                 with a chosen pattern and filter). It fixes every kind of aliasing - edges, textures, \
                 highlights, sub-pixel geometry - and is the reference the others are measured against, \
                 but it costs N times the shading, fill and memory bandwidth.",
            availability: anywhere,
            create: |gpu| Box::new(Ssaa::new(gpu)),
        },
        TechniqueInfo {
            id: "msaa2",
            name: "MSAA 2x",
            summary: MSAA_SUMMARY,
            availability: |caps| msaa_availability(caps, 2),
            create: |gpu| Box::new(Msaa::new(gpu, 2)),
        },
        TechniqueInfo {
            id: "msaa4",
            name: "MSAA 4x",
            summary: MSAA_SUMMARY,
            availability: |caps| msaa_availability(caps, 4),
            create: |gpu| Box::new(Msaa::new(gpu, 4)),
        },
        TechniqueInfo {
            id: "msaa8",
            name: "MSAA 8x",
            summary: MSAA_SUMMARY,
            availability: |caps| msaa_availability(caps, 8),
            create: |gpu| Box::new(Msaa::new(gpu, 8)),
        },
        TechniqueInfo {
            id: "msaa16",
            name: "MSAA 16x",
            summary: MSAA_SUMMARY,
            availability: |caps| msaa_availability(caps, 16),
            create: |gpu| Box::new(Msaa::new(gpu, 16)),
        },
        TechniqueInfo {
            id: "fxaa",
            name: "FXAA",
            summary: "Fast Approximate Antialiasing (Lottes, NVIDIA; the FXAA 3.11 quality path): one \
                 post pass over the finished image finds luma edges, follows each to its ends and \
                 blends across it. About the cost of a blur and independent of scene complexity, \
                 but it only sees the final pixels: it cannot recover sub-pixel geometry, it softens \
                 textures and text with contrast, and a still image's stair steps become a slight \
                 crawl in motion.",
            availability: needs_encoded_views,
            create: |gpu| Box::new(Fxaa::new(gpu)),
        },
        TechniqueInfo {
            id: "smaa",
            name: "SMAA 1x",
            summary: "Morphological antialiasing of the finished image: edges are found by luma (or colour or \
                 depth), the shape of each staircase is recognised (L, Z and U patterns, 45-degree diagonals, sharp corners) \
                 and every edge pixel is blended with its neighbour by the area the reconstructed edge line covers, read from \
                 precomputed tables. Smooth, sharp edges for about the cost of three fullscreen passes and no extra scene \
                 memory, but it cannot recover detail the single sample missed (sub-pixel geometry still breaks up and \
                 flickers) and it may soften text and fine texture.",
            availability: needs_encoded_views,
            create: |gpu| Box::new(super::smaa::Smaa::new(gpu, super::smaa::Mode::X1)),
        },
        TechniqueInfo {
            id: "smaa-t2x",
            name: "SMAA T2x",
            summary: "SMAA 1x on a render jittered by a quarter pixel, alternating between two offsets, mixed \
                 with the previous frame found through motion vectors (half weight, less where the pixel's speed \
                 changed). Two samples per pixel over two frames recover some sub-pixel detail and steady \
                 crawling edges for the cost of SMAA plus one resolve pass, but fast motion and disocclusions \
                 fall back to SMAA 1x and the jitter can shimmer where the history is rejected.",
            availability: needs_encoded_views,
            create: |gpu| Box::new(super::smaa::Smaa::new(gpu, super::smaa::Mode::T2x)),
        },
        TechniqueInfo {
            id: "smaa-s2x",
            name: "SMAA S2x",
            summary: "SMAA 1x on each sample of a two-sample render at the standard 2x MSAA positions, averaged: \
                 MSAA's real sub-pixel coverage plus SMAA's gradients, better than either alone on thin geometry, \
                 at the cost of a 2x render and two SMAA runs. Without 2x MSAA on the adapter it renders the scene \
                 twice at the two positions instead.",
            availability: smaa_s2x_availability,
            create: |gpu| Box::new(super::smaa::Smaa::new(gpu, super::smaa::Mode::S2x)),
        },
        TechniqueInfo {
            id: "taa",
            name: "TAA",
            summary: "Temporal antialiasing (after Karis 2014 and Salvi 2016): every frame renders one \
                 sample per pixel at a different sub-pixel jitter and blends it into a reprojected \
                 history, so a still image converges towards many samples per pixel for the cost of \
                 one post pass. It handles edges, textures and specular shimmer alike, but needs \
                 motion vectors, blurs slightly under motion, and can ghost or smear where the \
                 history cannot be matched (disocclusions, transparency, fast-changing shading).",
            availability: needs_encoded_views,
            create: |gpu| Box::new(Taa::new(gpu)),
        },
    ]
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
