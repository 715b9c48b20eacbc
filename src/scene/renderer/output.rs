//! What a scene render writes into its colour target: display values clamped to [0, 1] (the
//! LDR path every scene had before HDR), linear radiance into a floating-point target (an HDR
//! render, tonemapped later by `graph::hdr`), or radiance tonemapped in the fragment shader
//! (an HDR scene rendered for a technique that runs after the tonemapper). The operators are
//! `shaders/tonemap_operators.wgsl`; their names, the command-line choices and the tonemap pass
//! live in `graph::hdr`.

use crate::gpu::HDR_FORMAT;

/// A tonemapping operator: exposed linear radiance to linear display values in [0, 1].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Tonemapper {
    /// Reinhard, x / (1 + x) per channel.
    Reinhard,
    /// Krzysztof Narkowicz's fit of the ACES reference and sRGB output transforms.
    Aces,
    /// AgX (Blender 4's view transform), Benjamin Wrensch's compact form.
    Agx,
    /// Khronos PBR Neutral (2024).
    Neutral,
}

impl Tonemapper {
    /// The value of the shaders' `OPERATOR` override constant.
    pub fn shader_index(self) -> u32 {
        match self {
            Self::Reinhard => 0,
            Self::Aces => 1,
            Self::Agx => 2,
            Self::Neutral => 3,
        }
    }
}

/// How HDR radiance becomes a displayed image: an exposure and an operator.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Tonemap {
    /// The operator.
    pub operator: Tonemapper,
    /// Exposure in stops (EV): radiance is scaled by 2^exposure before the operator.
    pub exposure: f32,
}

impl Tonemap {
    /// The linear scale of the exposure.
    pub fn scale(&self) -> f32 {
        self.exposure.exp2()
    }
}

/// What a render's colour target receives (the scene shader's `OUTPUT` constant).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum SceneOutput {
    /// Display values clamped to [0, 1]: the LDR path.
    Display,
    /// Linear radiance, unclamped (a floating-point target).
    Radiance,
    /// Radiance after exposure and the operator.
    Tonemapped(Tonemapper),
}

impl SceneOutput {
    /// The output of a render into a colour target of `format` while the renderer's tonemap
    /// is `tonemap`: radiance into an HDR target, tonemapped display values into an 8-bit
    /// one when the scene is rendered in HDR, display values otherwise.
    pub fn of(format: wgpu::TextureFormat, tonemap: Option<&Tonemap>) -> Self {
        match tonemap {
            _ if format == HDR_FORMAT => Self::Radiance,
            Some(tonemap) => Self::Tonemapped(tonemap.operator),
            None => Self::Display,
        }
    }

    /// The override constants `OUTPUT` and `OPERATOR`.
    pub(super) fn constants(self) -> [(&'static str, f64); 2] {
        let (output, operator) = match self {
            Self::Display => (0, 0),
            Self::Radiance => (1, 0),
            Self::Tonemapped(operator) => (2, operator.shader_index()),
        };
        [
            ("OUTPUT", f64::from(output)),
            ("OPERATOR", f64::from(operator)),
        ]
    }
}
