//! The scene's materials on the GPU: each material's uniform block (colours, alpha mode,
//! normal detail, emission), its texture (a white texel where it has none) and its sampler in
//! one bind group, and the switches that pick its pipeline (face culling, the shader's
//! anisotropic filter, normal detail), so that a material without a feature gets a pipeline
//! compiled without it.

use std::collections::HashMap;

use glam::Vec3;
use wgpu::util::DeviceExt;

use super::textures::{create_sampler, filtered_anisotropically, upload_texture};
use crate::gpu::{self, Gpu};
use crate::scene::{AlphaMode, Material, Scene, TextureImage, TextureSampler};

/// A material's uniform block (`Material` in `shaders/scene.wgsl`).
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct MaterialUniform {
    base_color: [f32; 4],
    specular: [f32; 4],
    params: [f32; 4],
    detail: [f32; 4],
    emissive: [f32; 4],
}

pub(super) struct GpuMaterial {
    pub(super) bind_group: wgpu::BindGroup,
    pub(super) cull_back: bool,
    /// Its texture is filtered by the shader's anisotropic filter (a pipeline of its own).
    pub(super) anisotropic: bool,
    /// It has normal detail (a pipeline of its own).
    pub(super) detail: bool,
}

/// Every material of `scene` (a default one for a scene without) with its uniform, texture
/// (white when it has none) and sampler bound; returns them and the textures' bytes.
pub(super) fn upload_materials(
    gpu: &Gpu,
    scene: &Scene,
    layout: &wgpu::BindGroupLayout,
) -> (Vec<GpuMaterial>, u64) {
    let device = &gpu.device;
    let white = TextureImage {
        label: "white".to_owned(),
        image: image::RgbaImage::from_pixel(1, 1, image::Rgba([255; 4])),
    };
    let textures: Vec<wgpu::Texture> = scene
        .textures
        .iter()
        .chain(std::iter::once(&white))
        .map(|t| upload_texture(gpu, t))
        .collect();
    let bytes = textures.iter().map(gpu::texture_bytes).sum::<u64>();
    let views: Vec<wgpu::TextureView> = textures
        .iter()
        .map(|t| t.create_view(&Default::default()))
        .collect();
    let mut samplers: HashMap<TextureSampler, wgpu::Sampler> = HashMap::new();
    let default_material = Material::default();
    let materials = (0..scene.materials.len().max(1))
        .map(|i| {
            let m = scene.materials.get(i).unwrap_or(&default_material);
            let (masked, cutoff) = match m.alpha_mode {
                AlphaMode::Opaque | AlphaMode::Blend => (0.0, 0.0),
                AlphaMode::Mask { cutoff } => (1.0, cutoff),
            };
            let uniform = MaterialUniform {
                base_color: m.base_color.extend(m.opacity).to_array(),
                specular: m.specular.extend(m.shininess.max(1.0)).to_array(),
                params: [cutoff, f32::from(u8::from(m.unlit)), masked, 0.0],
                detail: m.normal_detail.map_or([0.0; 4], |d| {
                    [d.frequency, d.ripple.max(0.0), d.flakes.max(0.0), 0.0]
                }),
                emissive: m.emissive.max(Vec3::ZERO).extend(0.0).to_array(),
            };
            let buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(&format!("material {}", m.name)),
                contents: bytemuck::bytes_of(&uniform),
                usage: wgpu::BufferUsages::UNIFORM,
            });
            let view = m
                .base_color_texture
                .and_then(|t| views.get(t))
                .unwrap_or_else(|| &views[views.len() - 1]);
            let sampler = samplers
                .entry(m.sampler)
                .or_insert_with(|| create_sampler(gpu, &m.sampler));
            let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some(&format!("material {}", m.name)),
                layout,
                entries: &[
                    wgpu::BindGroupEntry {
                        binding: 0,
                        resource: buffer.as_entire_binding(),
                    },
                    wgpu::BindGroupEntry {
                        binding: 1,
                        resource: wgpu::BindingResource::TextureView(view),
                    },
                    wgpu::BindGroupEntry {
                        binding: 2,
                        resource: wgpu::BindingResource::Sampler(sampler),
                    },
                ],
            });
            GpuMaterial {
                bind_group,
                cull_back: !m.double_sided,
                anisotropic: m.base_color_texture.is_some() && filtered_anisotropically(&m.sampler),
                // Detail as the shader reads it: a ripple or flake slope above zero.
                detail: uniform.detail[1] > 0.0 || uniform.detail[2] > 0.0,
            }
        })
        .collect();
    (materials, bytes)
}
