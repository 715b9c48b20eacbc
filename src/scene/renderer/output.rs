//! What a scene render writes into its colour target: display values clamped to [0, 1] (the
//! LDR path every scene had before HDR), linear radiance into a floating-point target (an HDR
//! render, tonemapped later by `graph::hdr`), or radiance tonemapped in the fragment shader
//! (an HDR scene rendered for a technique that runs after the tonemapper). The operators are
//! `shaders/tonemap_operators.wgsl`; their names, the command-line choices and the tonemap pass
//! live in `graph::hdr`.

use glam::{Mat3, Vec3};

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

    /// `radiance` through the exposure and the operator, on the CPU: the clear colour of a
    /// tonemapped render, which no fragment shader sees. The same curves as
    /// `shaders/tonemap_operators.wgsl` (a test holds them together).
    pub fn apply(&self, radiance: Vec3) -> Vec3 {
        let x = (radiance * self.scale()).max(Vec3::ZERO);
        let y = match self.operator {
            Tonemapper::Reinhard => x / (Vec3::ONE + x),
            Tonemapper::Aces => (x * (2.51 * x + 0.03)) / (x * (2.43 * x + 0.59) + 0.14),
            Tonemapper::Agx => agx(x),
            Tonemapper::Neutral => pbr_neutral(x),
        };
        y.clamp(Vec3::ZERO, Vec3::ONE)
    }
}

/// AgX as in `tonemap_operators.wgsl`.
fn agx(x: Vec3) -> Vec3 {
    let inset = Mat3::from_cols(
        Vec3::new(0.842_479_06, 0.042_328_24, 0.042_375_655),
        Vec3::new(0.078_433_6, 0.878_468_6, 0.078_433_6),
        Vec3::new(0.079_223_745, 0.079_166_13, 0.879_143),
    );
    let outset = Mat3::from_cols(
        Vec3::new(1.196_879, -0.052_896_85, -0.052_971_64),
        Vec3::new(-0.098_020_88, 1.151_903_1, -0.098_043_45),
        Vec3::new(-0.099_029_74, -0.098_961_18, 1.151_073_7),
    );
    let (min_ev, max_ev) = (-12.47393_f32, 4.026069_f32);
    let encoded = (inset * x)
        .max(Vec3::splat(1e-10))
        .to_array()
        .map(|v| (v.log2().clamp(min_ev, max_ev) - min_ev) / (max_ev - min_ev));
    let curve = |v: f32| {
        let (v2, v4) = (v * v, v * v * v * v);
        15.5 * v4 * v2 - 40.14 * v4 * v + 31.96 * v4 - 6.868 * v2 * v + 0.4298 * v2 + 0.1191 * v
            - 0.00232
    };
    let curved = Vec3::from_array(encoded.map(curve));
    (outset * curved).clamp(Vec3::ZERO, Vec3::ONE).powf(2.2)
}

/// Khronos PBR Neutral as in `tonemap_operators.wgsl`.
fn pbr_neutral(color: Vec3) -> Vec3 {
    let (start_compression, desaturation) = (0.8 - 0.04, 0.15);
    let lowest = color.min_element();
    let offset = if lowest < 0.08 {
        lowest - 6.25 * lowest * lowest
    } else {
        0.04
    };
    let color = color - Vec3::splat(offset);
    let peak = color.max_element();
    if peak < start_compression {
        return color;
    }
    let d = 1.0 - start_compression;
    let new_peak = 1.0 - d * d / (peak + d - start_compression);
    let color = color * (new_peak / peak);
    let g = 1.0 - 1.0 / (desaturation * (peak - new_peak) + 1.0);
    color.lerp(Vec3::splat(new_peak), g)
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
