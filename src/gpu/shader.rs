//! Loading WGSL from `shaders/` and from the technique folders `src/aa/<name>/`. The sources
//! are compiled into the binary with `include_str!`, so an installed `aa-lab` needs no files
//! beside it; the naga validation test reads the same files from disk.
//!
//! **Uniforms never steer control flow on their own.** Mesa's lavapipe (22.x, the driver of
//! CI and of machines without a GPU) specialises a shader on the uniforms that alone decide an
//! `if` condition or a loop bound ("inline uniforms"), compiles that variant at every draw and
//! never frees it: TAA's `if params.trust.x > 0.0 { .. }` grew the process by 1.1 MB per frame
//! until LLVM ran out of section memory. So a condition made of uniforms only is written as a
//! `select`/`mix`, a loop runs to a constant bound and tests the uniform inside, a uniform
//! test is combined with `&`/`|` rather than `&&`/`||` (which naga lowers to an `if` on the
//! uniform operand alone), and a setting that changes which code runs is an `override`
//! constant. Conditions that also read a texture,
//! a varying or the pixel position are not affected. `tests/long_runs.rs` renders hundreds of
//! frames of every technique and fails on growth.

/// Every WGSL file under `shaders/` and `src/aa/<name>/`, by file name. The naga test checks
/// this list against the directories so that no shader escapes validation.
pub const SHADERS: &[(&str, &str)] = &[
    (
        "fullscreen.wgsl",
        include_str!("../../shaders/fullscreen.wgsl"),
    ),
    ("scene.wgsl", include_str!("../../shaders/scene.wgsl")),
    (
        "msaa_resolve.wgsl",
        include_str!("../../shaders/msaa_resolve.wgsl"),
    ),
    (
        "msaa_debug.wgsl",
        include_str!("../../shaders/msaa_debug.wgsl"),
    ),
    ("ssaa.wgsl", include_str!("../../shaders/ssaa.wgsl")),
    ("fxaa.wgsl", include_str!("../../shaders/fxaa.wgsl")),
    ("taa.wgsl", include_str!("../../shaders/taa.wgsl")),
    (
        "taa_debug.wgsl",
        include_str!("../../shaders/taa_debug.wgsl"),
    ),
    ("smaa.wgsl", include_str!("../../shaders/smaa.wgsl")),
    (
        "smaa_modes.wgsl",
        include_str!("../../shaders/smaa_modes.wgsl"),
    ),
    ("mlaa.wgsl", include_str!("../aa/mlaa/mlaa.wgsl")),
    ("smaa_4x.wgsl", include_str!("../aa/smaa_4x/smaa_4x.wgsl")),
    (
        "metrics_ssim.wgsl",
        include_str!("../../shaders/metrics_ssim.wgsl"),
    ),
    (
        "metrics_copy.wgsl",
        include_str!("../../shaders/metrics_copy.wgsl"),
    ),
    (
        "viewer_blit.wgsl",
        include_str!("../../shaders/viewer_blit.wgsl"),
    ),
    (
        "viewer_fill.wgsl",
        include_str!("../../shaders/viewer_fill.wgsl"),
    ),
];

/// The source of the shader file `name`.
///
/// # Panics
/// Panics if `name` is not in [`SHADERS`]: shader names are compile-time constants of this
/// crate, so a miss is a programming error caught by the tests, never user input.
pub fn source(name: &str) -> &'static str {
    SHADERS
        .iter()
        .find(|(file, _)| *file == name)
        .map(|(_, src)| *src)
        .unwrap_or_else(|| panic!("shader {name} is not listed in gpu::shader::SHADERS"))
}

/// Creates a shader module from the shader file `name`.
pub fn module(device: &wgpu::Device, name: &str) -> wgpu::ShaderModule {
    device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some(name),
        source: wgpu::ShaderSource::Wgsl(source(name).into()),
    })
}
