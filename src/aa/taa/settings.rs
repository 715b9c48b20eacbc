//! TAA's settings: the typed choices (history filter, rectification, velocity source, colour
//! neighbourhood, current-frame filter, jitter length), the weights, the named presets, every
//! parameter as data for the CLI, viewer and sidecars (its [`Tunable`] implementation) and the
//! override constants the structural choices become.

pub use crate::aa::common::temporal::{HistoryFilter, Rectify};
use crate::aa::common::temporal::{
    MOTION_FALLOFF, SILHOUETTE_FALLOFF, parallax_falloff_param, silhouette_falloff_param,
    speed_falloff_param,
};
use crate::graph::hdr::TonemapOrder;
use crate::graph::params::{Named, Param, ParamValue, Tunable};

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
        /// The 3x3 block (nine colours from four loads, the rest shared within the 2x2 quad).
        Box => "3x3",
        /// The pixel and its four direct neighbours (five colours from three loads; a tighter
        /// box).
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
    /// Parallax (pixels per frame between the motions of the nearest and the farthest surface
    /// around the pixel) over which the history's share falls to 1/e (0: no falloff).
    pub parallax_falloff: f32,
    /// The parallax falloff's length where the farthest surface around the pixel is broad (a
    /// silhouette over a wide background; 0: `parallax_falloff` everywhere).
    pub silhouette_falloff: f32,
    /// Speed (pixels per frame) over which the history's share falls to 1/e (0: no falloff).
    pub speed_falloff: f32,
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
    /// In HDR frames, before the tonemapper (on radiance, as engines run TAA, through Karis'
    /// reversible tonemap) or after it.
    pub tonemap_order: TonemapOrder,
    /// Least share of the current frame where blended surfaces cover the pixel fully (the
    /// reactive mask's strength); 0 reads no mask.
    pub reactive_mask: f32,
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
            parallax_falloff: MOTION_FALLOFF,
            silhouette_falloff: SILHOUETTE_FALLOFF,
            speed_falloff: MOTION_FALLOFF,
            resample_feedback: true,
            trust_own_speed: false,
            trust_sharp_only: false,
            luma_weight: false,
            current_filter: CurrentFilter::Gaussian,
            velocity: VelocityTaps::Quads,
            neighbourhood: Neighbourhood::Cross,
            mip_bias: -1.0,
            tonemap_order: TonemapOrder::Before,
            reactive_mask: 0.0,
        }
    }
}

crate::named_enum! {
    /// The named presets, in the order a UI offers them.
    pub enum Preset {
        /// The defaults.
        Default => "default",
        /// The defaults with one bilinear history read instead of five (7 reads per pixel
        /// instead of 11): about 9.5x a full-screen copy at 1920x1080 on lavapipe against the
        /// defaults' 12.2-12.6x, SSIM still at MSAA 4x's on hairball and above it on atrium, but
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
        /// own motion (5 reads per pixel).
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

impl Tunable for TaaSettings {
    type Preset = Preset;

    fn params(&self) -> Vec<Param> {
        let mut params = self.history_params();
        params.extend(self.current_frame_params());
        params
    }

    fn set(&mut self, key: &str, value: &ParamValue) -> bool {
        crate::set_fields!(
            self,
            key,
            value,
            [
                samples,
                history_filter,
                rectify,
                gamma,
                current_weight,
                motion_weight,
                velocity_tolerance,
                parallax_falloff,
                silhouette_falloff,
                speed_falloff,
                luma_weight,
                current_filter,
                velocity,
                neighbourhood,
                trust_own_speed,
                resample_feedback,
                trust_sharp_only,
                mip_bias,
                tonemap_order,
                reactive_mask,
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

impl TaaSettings {
    /// The parameters of the history: its samples, filter, rectification, weights and falloff
    /// under motion.
    fn history_params(&self) -> Vec<Param> {
        let s = self;
        vec![
            Param::named(
                "samples",
                "Jitter samples",
                "Length of the Halton(2,3) jitter sequence: each pixel is sampled at this many \
                 places in turn. 8 converges faster; 16 resolves finer detail on a still image.",
                s.samples,
            ),
            Param::named(
                "history_filter",
                "History filter",
                "How the previous result is read at the reprojected position: bilinear is cheap \
                 but softens the image a little more every frame the camera moves; catmull-rom \
                 (five bilinear taps) keeps it sharp.",
                s.history_filter,
            ),
            Param::named(
                "rectify",
                "History rectification",
                "How the history is made to agree with the current frame, which removes ghosts of \
                 moved or uncovered content: none (ghost trails, for comparison); clamp to the RGB \
                 range of the 3x3 neighbourhood; clip towards the neighbourhood's YCoCg box (Karis); \
                 variance: clip to mean +/- gamma standard deviations (Salvi: tighter, less ghosting).",
                s.rectify,
            ),
            Param::float(
                "gamma",
                "Variance gamma",
                "Variance clipping only: half-width of the colour box in standard deviations. \
                 Smaller rejects more history (less ghosting, more flicker); about 1 is usual.",
                0.25,
                3.0,
                s.gamma,
            ),
            Param::float(
                "current_weight",
                "Current frame weight",
                "Share of the new frame in each blend: small values (0.04) accumulate more samples \
                 and look smoother but react slower; 1 turns the history off.",
                0.01,
                1.0,
                s.current_weight,
            ),
            Param::float(
                "motion_weight",
                "Current weight in motion",
                "Share of the new frame where the image moves by a pixel per frame or more (it \
                 rises from the current frame weight with the speed): every frame of motion \
                 resamples the history between pixels, which softens it a little; a larger share \
                 keeps thin lines sharp under motion at the cost of a little more aliasing.",
                0.01,
                1.0,
                s.motion_weight,
            ),
            Param::float(
                "velocity_tolerance",
                "Velocity tolerance",
                "Change of speed in pixels per frame between the history and the current pixel at \
                 which rectification applies in full. Where the content moves as it did, the \
                 history shows the same surface: rectification is eased off there, so thin lines \
                 that this frame's jitter missed are kept; an occluder sliding over its background \
                 changes the speed and brings it back. 0 always rectifies in full.",
                0.0,
                4.0,
                s.velocity_tolerance,
            ),
            parallax_falloff_param(s.parallax_falloff),
            silhouette_falloff_param(s.silhouette_falloff),
            speed_falloff_param(s.speed_falloff),
        ]
    }

    /// The parameters of the current frame's side: its filter, the velocity and
    /// neighbourhood it reads, the trust tests, the mip bias and the reactive mask.
    fn current_frame_params(&self) -> Vec<Param> {
        let s = self;
        vec![
            Param::named(
                "current_filter",
                "Current-frame filter",
                "What the new frame adds to the history: sample, the pixel's own jittered sample (a \
                 point of the scene); gaussian, under motion, the samples of the colour \
                 neighbourhood weighed by their distance from the pixel centre with the spread of \
                 the pixel's area, so the new frame estimates the pixel's average as a \
                 supersampled image does (less noise on sub-pixel geometry, a little softer; no \
                 extra reads). It takes over as far as resampling blurs the history: a still \
                 camera keeps the exact samples.",
                s.current_filter,
            ),
            Param::bool(
                "luma_weight",
                "Luminance weighting",
                "Weigh current frame and history by 1 / (1 + luminance) (Karis), so a single bright \
                 sample cannot make a pixel flicker.",
                s.luma_weight,
            ),
            Param::named(
                "velocity",
                "Velocity source",
                "Which motion vector reprojects the pixel: own (the pixel's, no depth reads); \
                 diagonals (the nearest surface among the pixel and its four diagonal neighbours, \
                 five depth reads); 3x3 (the nearest of the whole block, nine); quads (the \
                 nearest of the two 2x2 blocks that share the pixel along its main diagonal: \
                 seven pixels from two depth gathers, the default). The nearest \
                 surface makes antialiased silhouettes move with the foreground object; without it \
                 thin geometry smears.",
                s.velocity,
            ),
            Param::named(
                "neighbourhood",
                "Colour neighbourhood",
                "Which current-frame colours bound the history: 3x3 (nine reads) or cross (the \
                 pixel and its four direct neighbours: five reads, a tighter box that rejects a \
                 little more history).",
                s.neighbourhood,
            ),
            Param::bool(
                "resample_feedback",
                "Resampling-adaptive feedback",
                "What raises the current frame's share from the current frame weight towards the \
                 motion weight: on, the blur of reading the history between texels (none on a \
                 still camera or whole-pixel motion, most at half-pixel offsets); off, the speed \
                 (in full at one pixel per frame).",
                s.resample_feedback,
            ),
            Param::bool(
                "trust_sharp_only",
                "Trust sharp history only",
                "Ease the velocity tolerance's trust off as the read between texels blurs the \
                 history: a blurred history spreads a little into its neighbours every frame, and \
                 trusted, that spread is never rectified away (a dark veil creeping out of moving \
                 thin geometry, ghosts beside slow objects).",
                s.trust_sharp_only,
            ),
            Param::bool(
                "trust_own_speed",
                "Trust by own speed",
                "Velocity tolerance compares the history's speed with the speed of the pixel's own \
                 surface (one more motion read) instead of the nearest surface's: a background \
                 pixel next to a moving strand then does not inherit the strand's speed, and \
                 keeps no stale strand colour (the grey veil over fine geometry).",
                s.trust_own_speed,
            ),
            Param::float(
                "mip_bias",
                "Texture mip bias",
                "Texture level-of-detail bias of the jittered render: negative values pick sharper \
                 mip levels, whose extra aliasing the accumulation averages away.",
                -2.0,
                0.0,
                s.mip_bias,
            ),
            s.tonemap_order.param(),
            Param::float(
                "reactive_mask",
                "Reactive mask",
                "Reactive mask (after AMD FidelityFX FSR 2's): where alpha-blended surfaces cover \
                 the pixel (the renderer's mask of their coverage), the current frame's share \
                 rises to at least this times the coverage, and the history is rectified in full \
                 there: glass and particles, whose colour the background's motion vectors do not \
                 carry, then follow the current frame instead of smearing. 0 (the default) reads \
                 no mask and renders none.",
                0.0,
                1.0,
                s.reactive_mask,
            ),
        ]
    }

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

    /// The override constants of the structural settings, and `RADIANCE` (before the
    /// tonemapper of an HDR frame: the resolve works through Karis' reversible tonemap).
    pub(super) fn constants(&self, radiance: bool) -> [(&'static str, f64); 8] {
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
            ("RADIANCE", f64::from(u8::from(radiance))),
            (
                "REACTIVE_MASK",
                f64::from(u8::from(self.reactive_mask > 0.0)),
            ),
        ]
    }
}
