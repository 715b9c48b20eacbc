//! The temporal upscaler's settings: the typed choices (jitter phases, sample kernel, history
//! filter, rectification), the weights, the named presets, every parameter as data for the
//! CLI, viewer and sidecars (its [`Tunable`] implementation) and the override constants the
//! structural choices become.

pub use crate::aa::common::temporal::{HistoryFilter, Rectify};
use crate::aa::common::temporal::{
    MOTION_FALLOFF, SILHOUETTE_FALLOFF, parallax_falloff_param, silhouette_falloff_param,
    speed_falloff_param,
};
use crate::graph::hdr::TonemapOrder;
use crate::graph::params::{Named, Param, ParamValue, Tunable};

crate::named_enum! {
    /// Jitter phases per output pixel: the Halton(2,3) sequence has this many positions times
    /// the square of the upscale ratio (FSR 2's 8 x ratio^2), so every output pixel is sampled
    /// about this many times per cycle whatever the scale.
    pub enum PhasesPerPixel {
        /// Eight: converges faster.
        Eight => "8",
        /// Sixteen: resolves finer detail on a still image.
        Sixteen => "16",
    }
}

impl PhasesPerPixel {
    /// The number of phases at an upscale ratio (output / render per axis, at least 1).
    pub fn phases(self, ratio: f32) -> u32 {
        let base = match self {
            Self::Eight => 8.0,
            Self::Sixteen => 16.0,
        };
        (base * ratio.max(1.0).powi(2)).ceil() as u32
    }
}

crate::named_enum! {
    /// How a new sample is weighted by its distance from an output pixel's centre.
    pub enum Kernel {
        /// A Gaussian whose spread at width 1 is that of a one-pixel box (variance 1/12 per
        /// axis): converges to the pixel's area average.
        Gaussian => "gaussian",
        /// Radial Lanczos-2 (a negative lobe from one pixel out, scaled by the width): sharper;
        /// the current frame's estimate is clamped to its neighbourhood, so it cannot ring.
        Lanczos => "lanczos",
    }
}

/// Every setting of the temporal upscaler.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TaauSettings {
    /// Jitter phases per output pixel.
    pub phases: PhasesPerPixel,
    /// The new samples' kernel.
    pub kernel: Kernel,
    /// Kernel width in output pixels (1: the spread of one pixel) of the samples where the
    /// history is resampled (on a still camera the samples inside the pixel count alike).
    pub kernel_width: f32,
    /// How the history is read at the reprojected position.
    pub history_filter: HistoryFilter,
    /// How the history is made to agree with the current frame.
    pub rectify: Rectify,
    /// Variance clip: half-width of the box in standard deviations.
    pub gamma: f32,
    /// The most samples (kernel weight) the history keeps on a still camera.
    pub max_samples: f32,
    /// The most samples where reading the history between texels blurs it most.
    pub motion_samples: f32,
    /// Change of speed (output pixels per frame) at which rectification applies in full.
    pub velocity_tolerance: f32,
    /// Speed (output pixels per frame) over which the history's samples fall to 1/e (0: no
    /// falloff).
    pub speed_falloff: f32,
    /// Parallax (output pixels per frame: how differently the nearest and the farthest surface
    /// of the 3x3 move) over which the history's samples fall to 1/e, at native scale only
    /// (0: no falloff).
    pub parallax_falloff: f32,
    /// The parallax falloff's length where the farthest surface of the 3x3 is broad (a
    /// silhouette over a wide background), at native scale only (0: `parallax_falloff`
    /// everywhere).
    pub silhouette_falloff: f32,
    /// Relative depth difference beyond which the reprojected history shows another surface;
    /// at native scale also the spread of the 3x3's depths from which this frame's estimate
    /// in motion is wholly the kernel's (on one surface it shares the place with the pixel's
    /// own sample, so the texture stays sharp).
    pub depth_tolerance: f32,
    /// How far the reactive mask (surfaces moving on their own) leans on the current frame.
    pub reactive: f32,
    /// Texture mip bias added to the render scale's log2(render / output).
    pub mip_bias: f32,
    /// How far the renderer's mask of blended surfaces' coverage leans on the current frame;
    /// 0 reads no mask.
    pub reactive_mask: f32,
    /// In HDR frames, before the tonemapper (on radiance, through Karis' reversible tonemap,
    /// as engines run their temporal upscalers) or after it.
    pub tonemap_order: TonemapOrder,
}

impl Default for TaauSettings {
    fn default() -> Self {
        Self {
            phases: PhasesPerPixel::Eight,
            kernel: Kernel::Gaussian,
            kernel_width: 1.3,
            history_filter: HistoryFilter::CatmullRom,
            rectify: Rectify::Variance,
            gamma: 1.0,
            max_samples: 6.0,
            motion_samples: 1.5,
            velocity_tolerance: 1.0,
            speed_falloff: MOTION_FALLOFF,
            parallax_falloff: MOTION_FALLOFF,
            silhouette_falloff: SILHOUETTE_FALLOFF,
            depth_tolerance: 0.05,
            reactive: 0.0,
            mip_bias: -1.0,
            reactive_mask: 0.0,
            tonemap_order: TonemapOrder::Before,
        }
    }
}

crate::named_enum! {
    /// The named presets, in the order a UI offers them.
    pub enum Preset {
        /// The defaults.
        Default => "default",
        /// One bilinear history read and an RGB clamp: fewer reads, softer under motion.
        Fast => "fast",
        /// Sixteen phases per pixel and a longer history: finer detail on a still image,
        /// slower to settle.
        Quality => "quality",
        /// The Lanczos-2 kernel: sharper samples, a little more aliasing.
        Sharp => "sharp",
        /// No rectification: shows the ghosting that rectification exists to remove.
        Unrectified => "unrectified",
    }
}

impl Tunable for TaauSettings {
    type Preset = Preset;

    fn params(&self) -> Vec<Param> {
        let s = self;
        vec![
            Param::named(
                "phases",
                "Jitter phases per pixel",
                "Length of the Halton(2,3) jitter sequence per output pixel: the sequence has \
                 this many positions times the square of the upscale ratio (FSR 2 uses 8), so \
                 each output pixel is sampled about this many times per cycle.",
                s.phases,
            ),
            Param::named(
                "kernel",
                "Sample kernel",
                "How each new sample is weighted by its distance from the output pixel's centre \
                 before it joins the history: gaussian (the spread of one pixel at width 1) or \
                 lanczos (Lanczos-2, sharper; clamped to the neighbourhood so it cannot ring).",
                s.kernel,
            ),
            Param::float(
                "kernel_width",
                "Kernel width",
                "Width of the sample kernel in output pixels where the history is resampled \
                 (motion): wider takes in more samples per frame (less noise, softer), narrower \
                 fewer. On a still camera the samples inside the pixel count alike.",
                0.5,
                2.0,
                s.kernel_width,
            ),
            Param::named(
                "history_filter",
                "History filter",
                "How the output-resolution history is read at the reprojected position: \
                 bilinear (cheap, softens under motion) or catmull-rom (five bilinear taps, \
                 sharp).",
                s.history_filter,
            ),
            Param::named(
                "rectify",
                "History rectification",
                "How the history is made to agree with the current frame's samples around the \
                 pixel: none (ghost trails, for comparison), clamp (RGB min/max), clip (towards \
                 the YCoCg box centre) or variance (mean +/- gamma standard deviations).",
                s.rectify,
            ),
            Param::float(
                "gamma",
                "Variance gamma",
                "Variance clipping only: half-width of the colour box in standard deviations.",
                0.25,
                3.0,
                s.gamma,
            ),
            Param::float(
                "max_samples",
                "History samples",
                "The most samples the history accumulates (in kernel weight: a sample at the \
                 pixel's centre counts 1): more converges further on a still image and reacts \
                 slower.",
                1.0,
                64.0,
                s.max_samples,
            ),
            Param::float(
                "motion_samples",
                "History samples in motion",
                "The most samples the history keeps where reading it between texels blurs it \
                 most (half-pixel motion): fewer keeps moving detail sharp, more keeps it calm.",
                1.0,
                64.0,
                s.motion_samples,
            ),
            Param::float(
                "velocity_tolerance",
                "Velocity tolerance",
                "Change of speed in output pixels per frame between the history and the pixel \
                 at which rectification applies in full; where the content moves as it did, \
                 the history shows the same surface and rectification eases off, so thin \
                 features the current samples missed are kept. 0 always rectifies in full.",
                0.0,
                4.0,
                s.velocity_tolerance,
            ),
            speed_falloff_param(s.speed_falloff),
            parallax_falloff_param(s.parallax_falloff),
            silhouette_falloff_param(s.silhouette_falloff),
            Param::float(
                "depth_tolerance",
                "Disocclusion depth tolerance",
                "Relative depth difference between the surface now and the one the history \
                 held at the reprojected place beyond which the history is dropped there \
                 (disocclusion). 1 never drops it. At native scale it also tells one surface \
                 from several: in motion the kernel's estimate takes the pixel's place in full \
                 only as far as the 3x3's depths spread up to it (on one surface half of it), \
                 so a textured surface keeps much of its own sharp sample and edges are still \
                 averaged.",
                0.005,
                1.0,
                s.depth_tolerance,
            ),
            Param::float(
                "reactive",
                "Reactive mask",
                "How far surfaces that move on their own (their motion differs from what the \
                 camera explains) lean on the current frame: 0 treats them like the rest, 1 \
                 keeps almost no history there.",
                0.0,
                1.0,
                s.reactive,
            ),
            Param::float(
                "mip_bias",
                "Texture mip bias",
                "Texture level-of-detail bias added to the render scale's log2(render / \
                 output); -1 (FSR 2's recommendation) samples textures at twice the output's \
                 detail, whose aliasing the accumulation averages away.",
                -2.0,
                0.0,
                s.mip_bias,
            ),
            Param::float(
                "reactive_mask",
                "Transparency reactive mask",
                "Reactive mask of transparency (after AMD FidelityFX FSR 2's): where \
                 alpha-blended surfaces cover the pixel (the renderer's mask of their coverage), \
                 the history keeps this times the coverage fewer of its samples, so glass and \
                 particles follow the current frame instead of smearing. 0 (the default) reads \
                 no mask and renders none.",
                0.0,
                1.0,
                s.reactive_mask,
            ),
            s.tonemap_order.param(),
        ]
    }

    fn set(&mut self, key: &str, value: &ParamValue) -> bool {
        crate::set_fields!(
            self,
            key,
            value,
            [
                phases,
                kernel,
                kernel_width,
                history_filter,
                rectify,
                gamma,
                max_samples,
                motion_samples,
                velocity_tolerance,
                speed_falloff,
                parallax_falloff,
                silhouette_falloff,
                depth_tolerance,
                reactive,
                mip_bias,
                reactive_mask,
                tonemap_order,
            ]
        )
    }

    /// Replaces every setting with the preset's but the tonemap order, which no preset sets.
    fn apply_preset(&mut self, preset: Preset) {
        *self = Self {
            tonemap_order: self.tonemap_order,
            ..Self::preset(preset)
        };
    }
}

impl TaauSettings {
    /// The settings of a preset.
    pub fn preset(preset: Preset) -> Self {
        let default = Self::default();
        match preset {
            Preset::Default => default,
            Preset::Fast => Self {
                history_filter: HistoryFilter::Bilinear,
                rectify: Rectify::Clamp,
                ..default
            },
            Preset::Quality => Self {
                phases: PhasesPerPixel::Sixteen,
                max_samples: 12.0,
                ..default
            },
            Preset::Sharp => Self {
                kernel: Kernel::Lanczos,
                ..default
            },
            Preset::Unrectified => Self {
                rectify: Rectify::None,
                ..default
            },
        }
    }

    /// The override constants of the structural settings, `RADIANCE` (before the tonemapper
    /// of an HDR frame; `aa/common/radiance.wgsl`), `OWN_MOTION` (the derived reactive mask,
    /// read only where `reactive` is above 0) and `PARALLAX` (the parallax and
    /// silhouette falloffs, on at native scale only: below it the current estimate reaches past
    /// the output pixel's neighbours, and leaning on it where surfaces part spreads their
    /// colours).
    pub(super) fn constants(&self, radiance: bool, native: bool) -> [(&'static str, f64); 7] {
        [
            (
                "HISTORY_FILTER",
                f64::from(u8::from(self.history_filter == HistoryFilter::CatmullRom)),
            ),
            ("RECTIFY", self.rectify.index() as f64),
            ("KERNEL", self.kernel.index() as f64),
            ("RADIANCE", f64::from(u8::from(radiance))),
            (
                "REACTIVE_MASK",
                f64::from(u8::from(self.reactive_mask > 0.0)),
            ),
            ("OWN_MOTION", f64::from(u8::from(self.reactive > 0.0))),
            (
                "PARALLAX",
                f64::from(u8::from(
                    native && (self.parallax_falloff > 0.0 || self.silhouette_falloff > 0.0),
                )),
            ),
        ]
    }
}
