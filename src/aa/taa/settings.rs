//! TAA's settings: the typed choices (history filter, rectification, velocity source, colour
//! neighbourhood, current-frame filter, jitter length), the weights, the named presets and the
//! override constants the structural choices become.

use crate::graph::params::Named;

crate::named_enum! {
    /// Length of the Halton(2,3) jitter sequence.
    pub enum JitterSamples {
        /// Eight positions: converges faster.
        Eight => "8",
        /// Sixteen positions: resolves finer detail on a still image.
        Sixteen => "16",
    }
}

impl JitterSamples {
    /// The number of positions.
    pub fn count(self) -> u32 {
        match self {
            Self::Eight => 8,
            Self::Sixteen => 16,
        }
    }
}

crate::named_enum! {
    /// How the reprojected history is read.
    pub enum HistoryFilter {
        /// One bilinear tap (cheap, blurs a little more every frame the camera moves).
        Bilinear => "bilinear",
        /// Five-tap bilinear-optimised Catmull-Rom (keeps the history sharp under motion).
        CatmullRom => "catmull-rom",
    }
}

crate::named_enum! {
    /// How the history is made consistent with the current frame.
    pub enum Rectify {
        /// Not at all: moving content leaves ghost trails (for comparison).
        None => "none",
        /// Per-channel clamp to the 3x3 neighbourhood's RGB min/max.
        Clamp => "clamp",
        /// Clip towards the centre of the neighbourhood's YCoCg min/max box (Karis).
        Clip => "clip",
        /// Clip to the YCoCg variance box mean +/- gamma sigma, within min/max (Salvi).
        Variance => "variance",
    }
}

crate::named_enum! {
    /// Which neighbours are searched for the nearest surface, whose motion the pixel reprojects
    /// with.
    pub enum VelocityTaps {
        /// The pixel's own motion (no depth reads).
        Own => "own",
        /// The nearest of the pixel and its four diagonal neighbours (five depth reads): catches
        /// a silhouette on either axis at about half the reads of the full block.
        Diagonals => "diagonals",
        /// The nearest of the 3x3 neighbourhood (nine depth reads).
        Box => "3x3",
        /// The nearest of the two 2x2 quads that share the pixel along its main diagonal: the
        /// pixel, its four direct neighbours and two diagonal ones (seven depths from two
        /// gathers).
        Quads => "quads",
    }
}

crate::named_enum! {
    /// Which current-frame colours make the box the history is rectified against.
    pub enum Neighbourhood {
        /// The 3x3 block (nine colour reads).
        Box => "3x3",
        /// The pixel and its four direct neighbours (five reads; a tighter box).
        Cross => "cross",
    }
}

crate::named_enum! {
    /// What the current frame contributes to the blend.
    pub enum CurrentFilter {
        /// The pixel's own jittered sample (a point sample of the scene).
        Sample => "sample",
        /// The samples of the colour neighbourhood weighed by a Gaussian of their distance from
        /// the pixel centre (each sample sits at its pixel's centre minus the jitter), with the
        /// variance of the pixel's box (1/12 per axis, `exp(-6 d^2)`): the current frame then
        /// estimates the pixel's area average, as the supersampled reference does, instead of one
        /// point of it. Mixed in as far as resampling blurs the history (none on a still camera).
        /// No extra reads.
        Gaussian => "gaussian",
    }
}

impl CurrentFilter {
    /// Sharpness a of the Gaussian `exp(-a d^2)` (d in pixels): a = 1 / (2 sigma^2) with
    /// sigma^2 = 1/12, the variance of a one-pixel box.
    pub const GAUSSIAN_SHARPNESS: f32 = 6.0;
}

/// TAA settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TaaSettings {
    /// Length of the Halton jitter sequence.
    pub samples: JitterSamples,
    /// History filter.
    pub history_filter: HistoryFilter,
    /// History rectification.
    pub rectify: Rectify,
    /// Width of the variance box in standard deviations.
    pub gamma: f32,
    /// Share of the current frame in the blend (before luminance weighting).
    pub current_weight: f32,
    /// Share of the current frame where the content moves one pixel per frame or more (the
    /// weight rises from `current_weight` with the speed; never below `current_weight`).
    pub motion_weight: f32,
    /// Change of speed (pixels per frame) between the history and the current pixel at which
    /// rectification applies in full; smaller changes ease it off proportionally (0: always
    /// rectify in full).
    pub velocity_tolerance: f32,
    /// Raise the current frame's share with the blur of reading the history between texels
    /// (else with the speed).
    pub resample_feedback: bool,
    /// Ease the velocity trust off as the read between texels blurs the history.
    pub trust_sharp_only: bool,
    /// Compare the history's speed with the pixel's own surface's (else with the speed of the
    /// nearest surface it reprojects with).
    pub trust_own_speed: bool,
    /// Karis' 1 / (1 + luminance) weighting of the blend.
    pub luma_weight: bool,
    /// What the current frame contributes.
    pub current_filter: CurrentFilter,
    /// Where the motion vector comes from.
    pub velocity: VelocityTaps,
    /// The colour box's neighbourhood.
    pub neighbourhood: Neighbourhood,
    /// Texture mip bias of the jittered render.
    pub mip_bias: f32,
}

impl Default for TaaSettings {
    fn default() -> Self {
        Self {
            samples: JitterSamples::Eight,
            history_filter: HistoryFilter::CatmullRom,
            rectify: Rectify::Variance,
            gamma: 0.5,
            current_weight: 0.1,
            motion_weight: 0.3,
            velocity_tolerance: 1.0,
            resample_feedback: true,
            trust_own_speed: false,
            trust_sharp_only: false,
            luma_weight: false,
            current_filter: CurrentFilter::Gaussian,
            velocity: VelocityTaps::Quads,
            neighbourhood: Neighbourhood::Cross,
            mip_bias: -1.5,
        }
    }
}

crate::named_enum! {
    /// The named presets, in the order a UI offers them.
    pub enum Preset {
        /// The defaults.
        Default => "default",
        /// The defaults with one bilinear history read instead of five (9 reads per pixel
        /// instead of 13): about 10x a full-screen copy at 1920x1080 on lavapipe against the
        /// defaults' 14x, SSIM still at MSAA 4x's on hairball and above it on atrium, but
        /// textures come out softer in motion (atrium FLIP 0.053 against the defaults' 0.036)
        /// and a slowly spinning object leaves a faint trail (13/255).
        Lean => "lean",
        /// The current frame's share follows the speed instead of the blur of reading the history
        /// between texels, a little higher (0.35 at one pixel per frame and faster): flickers
        /// less (flicker ratio at 640x360, hairball / atrium: 1.76 / 0.93 against the defaults'
        /// 2.10 / 1.06) and is closer to the reference by SSIM where content moves faster
        /// (hairball at 1280x720: 0.898 against 0.889; atrium at 640x360: 0.943 against 0.939),
        /// at the price of a little more lag behind motion (the bench's ghosting 18.2 / 12.0
        /// against 16.6 / 10.9) and a slightly higher FLIP at 640x360 (0.042 / 0.039 against
        /// 0.041 / 0.036).
        Steady => "steady",
        /// The cheapest variant: bilinear history, RGB clamp to the 5-pixel cross, the pixel's
        /// own motion (7 reads per pixel).
        Fast => "fast",
        /// The most reads: nearest surface and colour box of the 3x3 block, 16 jitter positions
        /// and a mip bias of -2 to match them.
        Quality => "quality",
        /// Karis 2014: YCoCg clip, a small current weight with luminance weighting.
        Karis => "karis",
        /// Salvi 2016: variance clipping with gamma 1.
        Salvi => "salvi",
        /// No rectification: shows the ghosting that rectification exists to remove.
        Unrectified => "unrectified",
    }
}

impl TaaSettings {
    /// The settings of a preset.
    pub fn preset(preset: Preset) -> Self {
        let default = Self::default();
        match preset {
            Preset::Default => default,
            Preset::Lean => Self {
                history_filter: HistoryFilter::Bilinear,
                ..default
            },
            Preset::Steady => Self {
                resample_feedback: false,
                motion_weight: 0.35,
                ..default
            },
            Preset::Fast => Self {
                history_filter: HistoryFilter::Bilinear,
                rectify: Rectify::Clamp,
                velocity: VelocityTaps::Own,
                neighbourhood: Neighbourhood::Cross,
                ..default
            },
            Preset::Quality => Self {
                samples: JitterSamples::Sixteen,
                velocity: VelocityTaps::Box,
                neighbourhood: Neighbourhood::Box,
                mip_bias: -2.0,
                ..default
            },
            Preset::Karis => Self {
                rectify: Rectify::Clip,
                current_weight: 0.04,
                luma_weight: true,
                ..default
            },
            Preset::Salvi => Self {
                rectify: Rectify::Variance,
                gamma: 1.0,
                ..default
            },
            Preset::Unrectified => Self {
                rectify: Rectify::None,
                ..default
            },
        }
    }

    /// The override constants of the structural settings.
    pub(super) fn constants(&self) -> [(&'static str, f64); 6] {
        [
            (
                "HISTORY_FILTER",
                f64::from(u8::from(self.history_filter == HistoryFilter::CatmullRom)),
            ),
            ("RECTIFY", self.rectify.index() as f64),
            ("LUMA_WEIGHT", f64::from(u8::from(self.luma_weight))),
            ("VELOCITY_TAPS", self.velocity.index() as f64),
            (
                "NEIGHBOURHOOD",
                f64::from(u8::from(self.neighbourhood == Neighbourhood::Cross)),
            ),
            ("TRUST_OWN_SPEED", f64::from(u8::from(self.trust_own_speed))),
        ]
    }
}
