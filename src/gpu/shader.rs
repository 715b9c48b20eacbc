//! Loading WGSL: the shared shaders of `shaders/` and each technique's own (in its folder under
//! `src/aa/`). The sources are compiled into the binary with `include_str!` ([`wgsl!`]), so an
//! installed `aa-lab` needs no files beside it; the naga validation test reads the same files
//! from disk.
//!
//! **Uniforms never steer control flow on their own.** Mesa's lavapipe (22.x, the driver of
//! CI and of machines without a GPU) specialises a shader on the uniforms that alone decide an
//! `if` condition or a loop bound ("inline uniforms"), compiles that variant at every draw and
//! never frees it, so the process grows every frame until LLVM runs out of section memory
//! (figures: `docs/gpu-figures.md`). So a condition made of uniforms only is written as a
//! `select`/`mix`, a loop runs to a constant bound and tests the uniform inside, a uniform
//! test is combined with `&`/`|` rather than `&&`/`||` (which naga lowers to an `if` on the
//! uniform operand alone), and a setting that changes which code runs is an `override`
//! constant. Conditions that also read a texture,
//! a varying or the pixel position are not affected. `tests/long_runs.rs` renders hundreds of
//! frames of every technique and fails on growth.
//!
//! **Per-pixel values are named, not kept in function-local arrays.** NVIDIA's compiler kept
//! TAA's small local arrays (the 3x3 colours, the Catmull-Rom taps and weights, the
//! nearest-surface candidates, each filled and read in a loop) in memory, which more than
//! doubled the resolve's cost; named values (structs, straight-line code) stay in registers.
//! lavapipe's LLVM keeps both forms in registers, so only a GPU shows the difference (figures:
//! `docs/techniques/taa.md`).
//!
//! **Work a pixel does not need is compiled out, not selected away.** On the GPUs this project
//! is measured on, fragment work runs on few of the chip's units and costs what its
//! instructions cost, so a feature that a material or setting may lack (the scene's
//! anisotropic filter and normal detail) is an override constant of its pipeline rather than
//! computed for every pixel and discarded by a `select`, and a bounds test is one unsigned
//! comparison per axis (figures: `docs/gpu-figures.md`).

/// A WGSL file compiled into the binary: its path from the repository root and its text.
/// Shared shaders are listed in [`SHADERS`]; a technique lists its own in its folder and
/// registry entry (`aa::TechniqueInfo::shaders`). The naga test walks `shaders/` and `src/`
/// and checks every file against those lists, so that none escapes validation.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Shader {
    /// Path from the repository root (`shaders/scene.wgsl`, `src/aa/fxaa/fxaa.wgsl`).
    pub path: &'static str,
    /// The WGSL text.
    pub source: &'static str,
    /// A shared file of functions compiled in front of this one (the tonemapping operators
    /// that the scene shader and the tonemap pass both use), so neither copies them.
    pub prelude: Option<&'static Shader>,
}

/// A [`Shader`] from its path relative to the repository root, its text included at compile
/// time (so the path written once is the path read).
#[macro_export]
macro_rules! wgsl {
    ($path:literal) => {
        $crate::gpu::shader::Shader {
            path: $path,
            source: include_str!(concat!(env!("CARGO_MANIFEST_DIR"), "/", $path)),
            prelude: None,
        }
    };
    ($path:literal, prelude = $prelude:expr) => {
        $crate::gpu::shader::Shader {
            prelude: Some(&$prelude),
            ..$crate::wgsl!($path)
        }
    };
}

impl Shader {
    /// The text the GPU compiles: the prelude's, if any (with its own prelude first), then this
    /// file's.
    pub fn composed_source(&self) -> std::borrow::Cow<'static, str> {
        match self.prelude {
            Some(prelude) => format!("{}\n{}", prelude.composed_source(), self.source).into(),
            None => self.source.into(),
        }
    }

    /// The file name (the module's label).
    pub fn name(&self) -> &'static str {
        self.path.rsplit('/').next().unwrap_or(self.path)
    }

    /// Creates the shader module.
    pub fn module(&self, device: &wgpu::Device) -> wgpu::ShaderModule {
        device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some(self.name()),
            source: wgpu::ShaderSource::Wgsl(self.composed_source()),
        })
    }
}

/// The shared WGSL files under `shaders/` (scene, full-screen vertex stage, metrics, viewer);
/// each technique's own shaders live in its folder under `src/aa/`.
pub const SHADERS: &[Shader] = &[
    crate::wgsl!("shaders/fullscreen.wgsl"),
    crate::wgsl!("shaders/scene.wgsl", prelude = TONEMAP_OPERATORS),
    crate::wgsl!("shaders/metrics_ssim.wgsl"),
    crate::wgsl!("shaders/metrics_copy.wgsl"),
    crate::wgsl!("shaders/viewer_blit.wgsl"),
    crate::wgsl!("shaders/viewer_fill.wgsl"),
    crate::wgsl!("shaders/overlay.wgsl"),
    crate::wgsl!("shaders/tonemap.wgsl", prelude = TONEMAP_OPERATORS),
    TONEMAP_OPERATORS,
];

/// The tonemapping operators (`tonemap_operator`), the prelude of the scene shader and of the
/// tonemap pass (see `graph::hdr`).
pub const TONEMAP_OPERATORS: Shader = crate::wgsl!("shaders/tonemap_operators.wgsl");

/// The shared shader `shaders/<name>`.
///
/// # Panics
/// Panics if `name` is not in [`SHADERS`]: shader names are compile-time constants of this
/// crate, so a miss is a programming error caught by the tests, never user input.
pub fn shared(name: &str) -> &'static Shader {
    SHADERS
        .iter()
        .find(|shader| shader.name() == name)
        .unwrap_or_else(|| panic!("shader {name} is not listed in gpu::shader::SHADERS"))
}

/// Creates a shader module from the shared shader `shaders/<name>`.
pub fn module(device: &wgpu::Device, name: &str) -> wgpu::ShaderModule {
    shared(name).module(device)
}
