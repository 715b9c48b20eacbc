//! What several techniques share, kept once: the colour maths the shaders mirror ([`color`]),
//! sample patterns and reconstruction filters ([`sampling`]), what the temporal techniques
//! share (jitter sequence, camera continuity, ping-pong history: [`temporal`]), and the GPU
//! pieces of post-process passes: the bilinear sampler, encoded (`Rgba8Unorm`) views of the
//! sRGB colour targets, debug-view textures and a cache of full-screen pipelines keyed by what they are
//! specialised on ([`PipelineCache`]); for techniques before the tonemapper of an HDR frame,
//! Karis' reversible tonemap ([`RADIANCE_WGSL`]) and the perceptual copy of radiance that
//! morphological edge detection reads ([`perceptual`]). The full-screen vertex stage and pipeline builder itself
//! is `crate::gpu::fullscreen` (the frame graph hands it to every pass). And
//! two macros that write `Technique` methods once: `shared_1x_post_process!`, the ones every
//! post-process of the shared one-sample render spells the same way, and `tunable_settings!`,
//! the parameter methods of a technique whose settings are `Tunable`.

pub mod color;
pub mod morphology;
pub mod pass;
pub mod perceptual;
pub mod sampling;
pub mod temporal;

/// Writes, inside an `impl Technique` block, the methods that every post-process of the shared
/// one-sample render spells the same way: `id` and `label` (the id and name of the technique's
/// registry entry, the argument), `color_only` (true: it reads colour alone) and `scene_input`
/// (the shared 1x render, every frame).
macro_rules! shared_1x_post_process {
    ($info:path) => {
        fn id(&self) -> &'static str {
            $info.id
        }

        fn label(&self) -> String {
            $info.name.to_owned()
        }

        fn color_only(&self) -> bool {
            true
        }

        fn scene_input(&self, _frame: &$crate::aa::FrameInfo) -> Option<$crate::aa::SceneInput> {
            Some($crate::aa::SceneInput::Shared1x)
        }
    };
}
pub(crate) use shared_1x_post_process;

/// Writes, inside an `impl Technique` block, the parameter methods of a technique whose
/// settings (the field named by the argument) are [`Tunable`](crate::graph::params::Tunable):
/// `params`, `set_param`, `presets` and `apply_preset` forward to them under the technique's id.
/// A change is made on a copy of the settings, so a rejected one changes nothing; the copy
/// replaces the field, or with `then METHOD` is handed to `self.METHOD(settings)` (TAA's
/// `set_settings`, which also restarts the history).
macro_rules! tunable_settings {
    ($field:ident) => {
        $crate::aa::common::tunable_settings!(@methods $field, |this, settings| this.$field = settings);
    };
    ($field:ident, then $apply:ident) => {
        $crate::aa::common::tunable_settings!(@methods $field, |this, settings| this.$apply(settings));
    };
    (@methods $field:ident, |$this:ident, $settings:ident| $store:expr) => {
        fn params(&self) -> Vec<$crate::aa::Param> {
            $crate::graph::params::Tunable::params(&self.$field)
        }

        fn presets(&self) -> &'static [&'static str] {
            $crate::graph::params::Tunable::preset_names(&self.$field)
        }

        fn set_param(
            &mut self,
            key: &str,
            value: &$crate::aa::ParamValue,
        ) -> Result<(), $crate::aa::ParamError> {
            let (id, mut $settings) = (self.id(), self.$field.clone());
            $crate::graph::params::Tunable::set_param(&mut $settings, id, key, value)?;
            let $this = self;
            $store;
            Ok(())
        }

        fn apply_preset(&mut self, name: &str) -> Result<(), $crate::aa::ParamError> {
            let (id, mut $settings) = (self.id(), self.$field.clone());
            $crate::graph::params::Tunable::apply_preset_named(&mut $settings, id, name)?;
            let $this = self;
            $store;
            Ok(())
        }
    };
}
pub(crate) use tunable_settings;

use std::collections::{HashMap, HashSet};
use std::hash::Hash;
use std::sync::{Mutex, PoisonError};

use crate::gpu::{COLOR_FORMAT, COLOR_FORMAT_ENCODED_VIEW, HDR_FORMAT, Texture2d, texture_2d};

/// A clamp-to-edge bilinear sampler (post passes read neighbours past the image border as the
/// border pixel).
pub fn bilinear_clamp_sampler(device: &wgpu::Device, label: &str) -> wgpu::Sampler {
    device.create_sampler(&wgpu::SamplerDescriptor {
        label: Some(label),
        address_mode_u: wgpu::AddressMode::ClampToEdge,
        address_mode_v: wgpu::AddressMode::ClampToEdge,
        mag_filter: wgpu::FilterMode::Linear,
        min_filter: wgpu::FilterMode::Linear,
        ..Default::default()
    })
}

/// A view of a texture in another (compatible) format.
pub fn view_as(texture: &wgpu::Texture, format: wgpu::TextureFormat) -> wgpu::TextureView {
    texture.create_view(&wgpu::TextureViewDescriptor {
        format: Some(format),
        ..Default::default()
    })
}

/// A view of an RGBA8 sRGB texture that reads and writes the encoded values.
pub fn encoded_view(texture: &wgpu::Texture) -> wgpu::TextureView {
    view_as(texture, COLOR_FORMAT_ENCODED_VIEW)
}

/// Karis' reversible tonemap (`compressed`, `to_output`) for the techniques before the
/// tonemapper: the prelude of [`TEMPORAL_WGSL`] (so of `taa.wgsl` and `taau.wgsl`), of SMAA's
/// resolves (`smaa_modes.wgsl`) and of the perceptual copy ([`perceptual`]).
pub const RADIANCE_WGSL: crate::gpu::shader::Shader = crate::wgsl!("src/aa/common/radiance.wgsl");

/// What the temporal resolves share (the depths on the farthest surface and the parallax
/// falloff's rate, `temporal.wgsl`, after [`RADIANCE_WGSL`]): the prelude of `taa.wgsl` and
/// `taau.wgsl`.
pub const TEMPORAL_WGSL: crate::gpu::shader::Shader =
    crate::wgsl!("src/aa/common/temporal.wgsl", prelude = RADIANCE_WGSL);

/// Whether a colour texture holds radiance: the input or output of a technique running before
/// the tonemapper of an HDR frame (`graph::hdr`).
pub fn holds_radiance(texture: &wgpu::Texture) -> bool {
    texture.format() == HDR_FORMAT
}

/// The format of a technique's output: half-float radiance before the tonemapper, display
/// values otherwise.
pub fn output_format(radiance: bool) -> wgpu::TextureFormat {
    if radiance { HDR_FORMAT } else { COLOR_FORMAT }
}

/// The view a pass that works on display-encoded values reads or writes: the encoded view of
/// an RGBA8 sRGB texture, or the plain view of a radiance texture (which has no encoding: the
/// pass then works on radiance, as an engine's post pass before its tonemapper does).
pub fn encoded_or_radiance_view(texture: &wgpu::Texture) -> wgpu::TextureView {
    if holds_radiance(texture) {
        texture.create_view(&Default::default())
    } else {
        encoded_view(texture)
    }
}

/// A debug-view texture: RGBA8 sRGB at the output size, readable back and viewable by egui,
/// with an encoded view for passes that write encoded values.
pub fn debug_texture(device: &wgpu::Device, label: &str, size: (u32, u32)) -> wgpu::Texture {
    texture_2d(
        device,
        &Texture2d {
            view_formats: &[COLOR_FORMAT_ENCODED_VIEW],
            ..Texture2d::new(
                label,
                size,
                COLOR_FORMAT,
                wgpu::TextureUsages::RENDER_ATTACHMENT
                    | wgpu::TextureUsages::TEXTURE_BINDING
                    | wgpu::TextureUsages::COPY_SRC,
            )
        },
    )
}

/// Full-screen pipelines built on first use and kept by the key they are specialised on
/// (a technique's structural settings: override constants, entry point, debug targets), so
/// switching a setting back and forth builds each variant once.
pub struct PipelineCache<K> {
    pipelines: HashMap<K, wgpu::RenderPipeline>,
}

impl<K> Default for PipelineCache<K> {
    fn default() -> Self {
        Self {
            pipelines: HashMap::new(),
        }
    }
}

impl<K: Eq + Hash> PipelineCache<K> {
    /// The pipeline of `key`, built by `build` the first time it is asked for.
    pub fn get_or_build(
        &mut self,
        key: K,
        build: impl FnOnce(&K) -> wgpu::RenderPipeline,
    ) -> wgpu::RenderPipeline {
        self.pipelines
            .entry(key)
            .or_insert_with_key(|key| build(key))
            .clone()
    }
}

/// Keeps one copy of each distinct string for the life of the process: technique ids made at
/// run time (user techniques, combinations at a render scale) and a user technique's parameter
/// names become the `&'static str`s the `Technique` trait hands out, each leaked once.
pub fn intern(text: &str) -> &'static str {
    static STRINGS: Mutex<Option<HashSet<&'static str>>> = Mutex::new(None);
    let mut strings = STRINGS.lock().unwrap_or_else(PoisonError::into_inner);
    let set = strings.get_or_insert_with(HashSet::new);
    if let Some(&kept) = set.get(text) {
        return kept;
    }
    let kept: &'static str = Box::leak(text.to_owned().into_boxed_str());
    set.insert(kept);
    kept
}
