//! The scene's textures on the GPU: full mip chains made on the CPU with sRGB-correct
//! averaging (what a game's texture pipeline bakes), textures larger than the adapter allows
//! reduced to fit, and samplers with the material's filters and wrapping. The samplers never
//! filter anisotropically: the scene shader does (`anisotropic_footprint` in
//! `shaders/scene.wgsl`), the same way on every adapter, for the materials that
//! [`filtered_anisotropically`] picks.

use super::*;

/// Number of mip levels of a full chain for a size.
pub fn mip_level_count(width: u32, height: u32) -> u32 {
    32 - width.max(height).max(1).leading_zeros()
}

/// The next mip level of an sRGB-encoded RGBA8 image: a 2x2 box filter in linear light,
/// colour weighted by alpha so that transparent texels do not bleed their colour.
pub fn downsample_srgb(image: &image::RgbaImage) -> image::RgbaImage {
    let (w, h) = image.dimensions();
    let (nw, nh) = ((w / 2).max(1), (h / 2).max(1));
    image::RgbaImage::from_fn(nw, nh, |x, y| {
        let mut sum = Vec4::ZERO;
        for (dx, dy) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
            let p = image
                .get_pixel((2 * x + dx).min(w - 1), (2 * y + dy).min(h - 1))
                .0;
            let a = f32::from(p[3]) / 255.0;
            sum += Vec4::new(
                srgb::decode_byte(p[0]) * a,
                srgb::decode_byte(p[1]) * a,
                srgb::decode_byte(p[2]) * a,
                a,
            );
        }
        let alpha = sum.w / 4.0;
        let rgb = if sum.w > 0.0 {
            sum.truncate() / sum.w
        } else {
            Vec3::ZERO
        };
        image::Rgba([
            srgb::encode_byte(rgb.x),
            srgb::encode_byte(rgb.y),
            srgb::encode_byte(rgb.z),
            (alpha * 255.0 + 0.5) as u8,
        ])
    })
}

/// `image` shrunk (keeping its aspect ratio) to fit within `limit` texels a side, with a
/// warning naming the texture; borrowed unchanged when it fits.
fn fit_texture<'a>(
    image: &'a image::RgbaImage,
    label: &str,
    limit: u32,
) -> std::borrow::Cow<'a, image::RgbaImage> {
    let (width, height) = image.dimensions();
    if width <= limit && height <= limit {
        return std::borrow::Cow::Borrowed(image);
    }
    let scale = f64::from(limit) / f64::from(width.max(height));
    let fit = |side: u32| ((f64::from(side) * scale).round() as u32).clamp(1, limit);
    let (new_width, new_height) = (fit(width), fit(height));
    log::warn!(
        "texture {label} is {width}x{height}, larger than this adapter's largest texture side \
         ({limit}): downscaled to {new_width}x{new_height}"
    );
    std::borrow::Cow::Owned(image::imageops::resize(
        image,
        new_width,
        new_height,
        image::imageops::FilterType::Triangle,
    ))
}

pub(super) fn upload_texture(gpu: &Gpu, texture: &TextureImage) -> wgpu::Texture {
    let image = fit_texture(
        &texture.image,
        &texture.label,
        gpu.caps.max_texture_dimension_2d,
    );
    let (width, height) = image.dimensions();
    let levels = mip_level_count(width, height);
    let gpu_texture = gpu.device.create_texture(&wgpu::TextureDescriptor {
        label: Some(&texture.label),
        size: wgpu::Extent3d {
            width,
            height,
            depth_or_array_layers: 1,
        },
        mip_level_count: levels,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: wgpu::TextureFormat::Rgba8UnormSrgb,
        usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
        view_formats: &[],
    });
    let mut level_image = image.into_owned();
    for level in 0..levels {
        gpu::write_rgba8_level(gpu, &gpu_texture, level, &level_image);
        if level + 1 < levels {
            level_image = downsample_srgb(&level_image);
        }
    }
    gpu_texture
}

/// Whether the scene shader filters a material's texture anisotropically: only where every
/// filter is linear and mipmapped (trilinear probes need both); nearest-filtered and
/// unmipmapped samplers are sampled once, as they say.
pub fn filtered_anisotropically(sampler: &TextureSampler) -> bool {
    sampler.mag_filter == Filter::Linear
        && sampler.min_filter == Filter::Linear
        && sampler.mipmap_filter == Some(Filter::Linear)
}

/// The wgpu sampler of a material's [`TextureSampler`], without hardware anisotropy.
pub(super) fn create_sampler(gpu: &Gpu, sampler: &TextureSampler) -> wgpu::Sampler {
    let filter = |f: Filter| match f {
        Filter::Nearest => wgpu::FilterMode::Nearest,
        Filter::Linear => wgpu::FilterMode::Linear,
    };
    let wrap = |w: Wrap| match w {
        Wrap::Repeat => wgpu::AddressMode::Repeat,
        Wrap::MirroredRepeat => wgpu::AddressMode::MirrorRepeat,
        Wrap::ClampToEdge => wgpu::AddressMode::ClampToEdge,
    };
    let defaults = wgpu::SamplerDescriptor::default();
    gpu.device.create_sampler(&wgpu::SamplerDescriptor {
        label: Some("scene material sampler"),
        address_mode_u: wrap(sampler.wrap_u),
        address_mode_v: wrap(sampler.wrap_v),
        mag_filter: filter(sampler.mag_filter),
        min_filter: filter(sampler.min_filter),
        mipmap_filter: match sampler.mipmap_filter {
            Some(Filter::Linear) => wgpu::MipmapFilterMode::Linear,
            Some(Filter::Nearest) | None => wgpu::MipmapFilterMode::Nearest,
        },
        // Without mipmapping only the full-size level is read.
        lod_max_clamp: if sampler.mipmap_filter.is_some() {
            defaults.lod_max_clamp
        } else {
            0.0
        },
        ..defaults
    })
}
