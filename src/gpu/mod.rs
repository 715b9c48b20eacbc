//! GPU access shared by every front end: device creation (headless, or adopted from the
//! viewer's eframe device), the capability report, texture readback and the small helpers
//! every pass uses (shader loading, fullscreen triangle).
//!
//! Headless creation ranks every adapter wgpu can see (discrete GPU first, software
//! rasterisers last) and asks for the optional features the frame graph can use: timestamp
//! queries (per-pass GPU time), pipeline-statistics queries (fragment invocations) and
//! adapter-specific format features (the real list of MSAA sample counts instead of WebGPU's
//! guaranteed {1, 4}).

pub mod capabilities;
pub mod fullscreen;
pub mod readback;
pub mod shader;

pub use capabilities::Capabilities;
pub use readback::{ReadbackBelt, read_texture_rgba8};

/// Colour format of every scene render and every technique output: 8-bit RGBA storing
/// sRGB-encoded values, so that blending, filtering and MSAA resolves happen in linear light.
pub const COLOR_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8UnormSrgb;
/// The same texels viewed without sRGB decoding (what FXAA/SMAA and egui read).
pub const COLOR_FORMAT_ENCODED_VIEW: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8Unorm;
/// The extra view formats of an image texture in [`COLOR_FORMAT`]: its encoded view where the
/// device can reinterpret formats, none on backends that cannot (wgpu's GL), where only the
/// techniques that never read encoded values can run (see `aa::registry`).
pub fn encoded_view_formats(caps: &Capabilities) -> &'static [wgpu::TextureFormat] {
    if caps.view_formats {
        &[COLOR_FORMAT_ENCODED_VIEW]
    } else {
        &[]
    }
}
/// Colour format of HDR scene renders and of the outputs of techniques that run before the
/// tonemapper: linear radiance in half floats (`graph::hdr`).
pub const HDR_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;
/// Depth format of scene renders.
pub const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;
/// Screen-space motion vectors, in pixels from the previous frame to this one.
pub const MOTION_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rg16Float;

/// How a 2D texture with one mip level is made: [`texture_2d`]'s parameters.
#[derive(Clone, Copy, Debug)]
pub struct Texture2d<'a> {
    /// Debug label.
    pub label: &'a str,
    /// Width and height in texels.
    pub size: (u32, u32),
    /// Texel format.
    pub format: wgpu::TextureFormat,
    /// Samples per texel (1 unless multisampled).
    pub sample_count: u32,
    /// What the texture is used for.
    pub usage: wgpu::TextureUsages,
    /// Other formats views of it may take.
    pub view_formats: &'a [wgpu::TextureFormat],
}

impl<'a> Texture2d<'a> {
    /// A single-sample texture with no other view formats.
    pub fn new(
        label: &'a str,
        size: (u32, u32),
        format: wgpu::TextureFormat,
        usage: wgpu::TextureUsages,
    ) -> Self {
        Self {
            label,
            size,
            format,
            sample_count: 1,
            usage,
            view_formats: &[],
        }
    }
}

impl<'a> Texture2d<'a> {
    /// The wgpu descriptor: one mip level, one layer.
    pub fn descriptor(&self) -> wgpu::TextureDescriptor<'a> {
        wgpu::TextureDescriptor {
            label: Some(self.label),
            size: wgpu::Extent3d {
                width: self.size.0,
                height: self.size.1,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: self.sample_count,
            dimension: wgpu::TextureDimension::D2,
            format: self.format,
            usage: self.usage,
            view_formats: self.view_formats,
        }
    }
}

/// Creates the 2D texture `desc` describes: the one place every render target, history buffer,
/// lookup table and output texture is made (uploads pass [`Texture2d::descriptor`] to wgpu's
/// `create_texture_with_data`).
pub fn texture_2d(device: &wgpu::Device, desc: &Texture2d<'_>) -> wgpu::Texture {
    device.create_texture(&desc.descriptor())
}

/// What installing a software Vulkan driver takes on Debian/Ubuntu, quoted in every
/// "no adapter" message.
pub const SOFTWARE_DRIVER_HINT: &str = "install a Vulkan driver; on a machine without a GPU, Mesa's software rasteriser \
     (Debian/Ubuntu: `apt-get install mesa-vulkan-drivers libvulkan1`)";

/// Errors of device creation.
#[derive(Debug, thiserror::Error)]
pub enum GpuError {
    /// No adapter on any backend.
    #[error("no GPU adapter found on any backend; {SOFTWARE_DRIVER_HINT}")]
    NoAdapter,
    /// The adapter refused the device.
    #[error("the adapter {adapter} refused to create a device: {source}")]
    RequestDevice {
        /// Adapter name.
        adapter: String,
        /// wgpu's reason.
        source: wgpu::RequestDeviceError,
    },
}

/// A device with its queue, the adapter it came from and what that adapter can do.
#[derive(Clone, Debug)]
pub struct Gpu {
    /// The adapter the device was created on.
    pub adapter: wgpu::Adapter,
    /// The device.
    pub device: wgpu::Device,
    /// Its queue.
    pub queue: wgpu::Queue,
    /// What the device was created with and supports.
    pub caps: Capabilities,
}

/// Optional features the engine uses when the adapter has them.
pub fn wanted_features() -> wgpu::Features {
    wgpu::Features::TIMESTAMP_QUERY
        | wgpu::Features::TIMESTAMP_QUERY_INSIDE_ENCODERS
        | wgpu::Features::TIMESTAMP_QUERY_INSIDE_PASSES
        | wgpu::Features::PIPELINE_STATISTICS_QUERY
        | wgpu::Features::TEXTURE_ADAPTER_SPECIFIC_FORMAT_FEATURES
}

/// The device descriptor the engine wants from `adapter`: every wanted feature it has, its
/// full limits (large supersampled targets need the real maximum texture size), and on a
/// software adapter, whose video memory is the process's own, wgpu's small memory blocks
/// rather than its 128 MB ones.
pub fn device_descriptor(adapter: &wgpu::Adapter) -> wgpu::DeviceDescriptor<'static> {
    wgpu::DeviceDescriptor {
        label: Some("aa-lab device"),
        required_features: adapter.features() & wanted_features(),
        required_limits: adapter.limits(),
        memory_hints: if adapter.get_info().device_type == wgpu::DeviceType::Cpu {
            wgpu::MemoryHints::MemoryUsage
        } else {
            wgpu::MemoryHints::Performance
        },
        ..Default::default()
    }
}

fn adapter_rank(info: &wgpu::AdapterInfo) -> u8 {
    let type_rank = match info.device_type {
        wgpu::DeviceType::DiscreteGpu => 0,
        wgpu::DeviceType::IntegratedGpu => 1,
        wgpu::DeviceType::VirtualGpu => 2,
        wgpu::DeviceType::Other => 3,
        wgpu::DeviceType::Cpu => 4,
    };
    // OpenGL reads multisampled textures as zeros on Mesa: prefer any other backend.
    let backend_rank = u8::from(info.backend == wgpu::Backend::Gl);
    backend_rank * 8 + type_rank
}

impl Gpu {
    /// Creates a device without a window on the best adapter (see module docs).
    /// `WGPU_BACKEND` (e.g. `vulkan`, `gl`) and `WGPU_ADAPTER_NAME` narrow the choice.
    pub fn headless() -> Result<Self, GpuError> {
        pollster::block_on(Self::headless_async())
    }

    async fn headless_async() -> Result<Self, GpuError> {
        // Vulkan/Metal/DX12 first; OpenGL (whose EGL probing also prints noise about missing
        // displays) only when none of those has an adapter, or when WGPU_BACKEND asks for it.
        let enumerate = |backends: wgpu::Backends| {
            let descriptor = wgpu::InstanceDescriptor {
                backends,
                ..wgpu::InstanceDescriptor::new_without_display_handle_from_env()
            };
            let instance = wgpu::Instance::new(descriptor);
            async move { instance.enumerate_adapters(backends).await }
        };
        let mut adapters = match wgpu::Backends::from_env() {
            Some(backends) => enumerate(backends).await,
            None => {
                let primary = enumerate(wgpu::Backends::PRIMARY).await;
                if primary.is_empty() {
                    enumerate(wgpu::Backends::GL).await
                } else {
                    primary
                }
            }
        };
        if let Ok(wanted) = std::env::var("WGPU_ADAPTER_NAME") {
            let wanted = wanted.to_lowercase();
            adapters.retain(|a| a.get_info().name.to_lowercase().contains(&wanted));
        }
        adapters.sort_by_key(|a| adapter_rank(&a.get_info()));
        let adapter = adapters.into_iter().next().ok_or(GpuError::NoAdapter)?;
        let (device, queue) = adapter
            .request_device(&device_descriptor(&adapter))
            .await
            .map_err(|source| GpuError::RequestDevice {
                adapter: adapter.get_info().name,
                source,
            })?;
        Ok(Self::from_parts(adapter, device, queue))
    }

    /// Wraps a device created elsewhere (the viewer's eframe device).
    pub fn from_parts(adapter: wgpu::Adapter, device: wgpu::Device, queue: wgpu::Queue) -> Self {
        let caps = Capabilities::query(&adapter, &device, &queue);
        Self {
            adapter,
            device,
            queue,
            caps,
        }
    }

    /// Blocks until all submitted work has finished.
    pub fn wait_idle(&self) {
        // A poll error means the device is lost; the next submission reports that properly.
        let _ = self.device.poll(wgpu::PollType::wait_indefinitely());
    }
}

/// Writes an RGBA8 image into mip level `level` of a texture of the same size (the texture
/// needs `COPY_DST`; its bytes are taken as they are, sRGB-encoded for sRGB formats).
pub fn write_rgba8_level(gpu: &Gpu, texture: &wgpu::Texture, level: u32, image: &image::RgbaImage) {
    let (width, height) = image.dimensions();
    gpu.queue.write_texture(
        wgpu::TexelCopyTextureInfo {
            texture,
            mip_level: level,
            origin: wgpu::Origin3d::ZERO,
            aspect: wgpu::TextureAspect::All,
        },
        image.as_raw(),
        wgpu::TexelCopyBufferLayout {
            offset: 0,
            bytes_per_row: Some(4 * width),
            rows_per_image: Some(height),
        },
        wgpu::Extent3d {
            width,
            height,
            depth_or_array_layers: 1,
        },
    );
}

/// [`write_rgba8_level`] into level 0.
pub fn write_rgba8(gpu: &Gpu, texture: &wgpu::Texture, image: &image::RgbaImage) {
    write_rgba8_level(gpu, texture, 0, image);
}

/// Bytes a texture occupies: every mip level times its sample count. Formats without a fixed
/// copy size (combined depth-stencil) are counted at 4 bytes a texel, what drivers allocate
/// for `Depth24PlusStencil8`.
pub fn texture_bytes(texture: &wgpu::Texture) -> u64 {
    let texel = u64::from(texture.format().block_copy_size(None).unwrap_or(4));
    let texels: u64 = (0..texture.mip_level_count())
        .map(|level| {
            let w = u64::from((texture.width() >> level).max(1));
            let h = u64::from((texture.height() >> level).max(1));
            w * h
        })
        .sum();
    texels * texel * u64::from(texture.sample_count())
}

/// A colour attachment cleared to zero and stored.
pub fn cleared_attachment(view: &wgpu::TextureView) -> wgpu::RenderPassColorAttachment<'_> {
    wgpu::RenderPassColorAttachment {
        view,
        depth_slice: None,
        resolve_target: None,
        ops: wgpu::Operations {
            load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
            store: wgpu::StoreOp::Store,
        },
    }
}
