//! What the adapter and device can do, as the frame graph and the UI need to know it: MSAA
//! sample counts per format the engine renders to (queried, never assumed), timestamp and
//! pipeline-statistics support, and limits. `aa-lab info` prints this report.

use super::{COLOR_FORMAT, DEPTH_FORMAT, MOTION_FORMAT};

/// Sample counts supported for one texture format.
#[derive(Clone, Debug, PartialEq, Eq, serde::Serialize)]
pub struct FormatSampleCounts {
    /// The format, as wgpu names it.
    pub format: String,
    /// Supported sample counts, ascending, always including 1.
    pub sample_counts: Vec<u32>,
}

/// The capability report of one device.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Capabilities {
    /// Adapter name as the driver reports it.
    pub adapter_name: String,
    /// Backend (Vulkan, Metal, Dx12, Gl).
    pub backend: String,
    /// Device type (DiscreteGpu, IntegratedGpu, Cpu, ...).
    pub device_type: String,
    /// Driver name and version.
    pub driver: String,
    /// True for software rasterisers (lavapipe, llvmpipe, WARP, SwiftShader).
    pub software: bool,
    /// Sample counts per format the scene renderer writes.
    pub formats: Vec<FormatSampleCounts>,
    /// Sample counts usable for a whole scene render (colour, depth and motion together).
    pub scene_sample_counts: Vec<u32>,
    /// Timestamp queries can bracket passes (per-pass GPU time).
    pub timestamps: bool,
    /// Nanoseconds per timestamp tick.
    pub timestamp_period_ns: f32,
    /// Pipeline-statistics queries (fragment-shader invocations).
    pub pipeline_statistics: bool,
    /// Largest 2D texture side.
    pub max_texture_dimension_2d: u32,
    /// Largest buffer size in bytes.
    pub max_buffer_size: u64,
    /// A texture can be viewed in its sRGB and its linear format (wgpu's `VIEW_FORMATS`
    /// downlevel flag, which the OpenGL backend lacks): every technique reads its input's
    /// sRGB-encoded values through such a view.
    pub view_formats: bool,
    /// Fragment shaders can write storage textures (wgpu's `FRAGMENT_WRITABLE_STORAGE`
    /// downlevel flag; every Vulkan, Metal and DX12 device has it): TAA and TAAU store their
    /// history so.
    pub fragment_storage: bool,
}

impl Capabilities {
    /// Queries the adapter for everything the device was created with.
    pub fn query(adapter: &wgpu::Adapter, device: &wgpu::Device, queue: &wgpu::Queue) -> Self {
        let info = adapter.get_info();
        let features = device.features();
        let adapter_specific =
            features.contains(wgpu::Features::TEXTURE_ADAPTER_SPECIFIC_FORMAT_FEATURES);
        let formats: Vec<FormatSampleCounts> = [COLOR_FORMAT, DEPTH_FORMAT, MOTION_FORMAT]
            .into_iter()
            .map(|format| FormatSampleCounts {
                format: format!("{format:?}"),
                sample_counts: sample_counts(adapter, format, adapter_specific),
            })
            .collect();
        let scene_sample_counts = formats
            .iter()
            .map(|f| f.sample_counts.clone())
            .reduce(|acc, counts| acc.into_iter().filter(|c| counts.contains(c)).collect())
            .unwrap_or_else(|| vec![1]);
        let limits = device.limits();
        let downlevel = adapter.get_downlevel_capabilities().flags;
        let timestamps = features.contains(
            wgpu::Features::TIMESTAMP_QUERY | wgpu::Features::TIMESTAMP_QUERY_INSIDE_ENCODERS,
        );
        Self {
            software: info.device_type == wgpu::DeviceType::Cpu,
            adapter_name: info.name,
            backend: format!("{:?}", info.backend),
            device_type: format!("{:?}", info.device_type),
            driver: format!("{} {}", info.driver, info.driver_info)
                .trim()
                .to_owned(),
            formats,
            scene_sample_counts,
            timestamps,
            timestamp_period_ns: if timestamps {
                queue.get_timestamp_period()
            } else {
                0.0
            },
            pipeline_statistics: features.contains(wgpu::Features::PIPELINE_STATISTICS_QUERY),
            max_texture_dimension_2d: limits.max_texture_dimension_2d,
            max_buffer_size: limits.max_buffer_size,
            view_formats: downlevel.contains(wgpu::DownlevelFlags::VIEW_FORMATS),
            fragment_storage: downlevel.contains(wgpu::DownlevelFlags::FRAGMENT_WRITABLE_STORAGE),
        }
    }

    /// Whether the device runs on wgpu's OpenGL backend.
    pub fn is_gl(&self) -> bool {
        self.backend == format!("{:?}", wgpu::Backend::Gl)
    }

    /// Whether a whole scene render can use `count` samples.
    pub fn supports_sample_count(&self, count: u32) -> bool {
        self.scene_sample_counts.contains(&count)
    }

    /// Human-readable multi-line report (what `aa-lab info` prints).
    pub fn report(&self) -> String {
        let yes_no = |b: bool| if b { "yes" } else { "no" };
        let mut out = format!(
            "adapter:            {}\nbackend:            {}\ndevice type:        {}{}\ndriver:             {}\n",
            self.adapter_name,
            self.backend,
            self.device_type,
            if self.software {
                " (software rendering)"
            } else {
                ""
            },
            self.driver,
        );
        out += &format!(
            "MSAA sample counts: {:?} (usable for a scene render)\n",
            self.scene_sample_counts
        );
        for f in &self.formats {
            out += &format!("  {:<18}{:?}\n", f.format, f.sample_counts);
        }
        out += &format!(
            "timestamp queries:  {}{}\npipeline statistics: {}\nmax texture size:   {}\nmax buffer size:    {} MiB\nsRGB/linear views:  {}\nfragment storage:   {}\n",
            yes_no(self.timestamps),
            if self.timestamps {
                format!(" ({} ns per tick)", self.timestamp_period_ns)
            } else {
                String::new()
            },
            yes_no(self.pipeline_statistics),
            self.max_texture_dimension_2d,
            self.max_buffer_size >> 20,
            if self.view_formats {
                "yes"
            } else {
                "no (no technique can run: install a Vulkan driver)"
            },
            if self.fragment_storage {
                "yes"
            } else {
                "no (TAA and TAAU cannot run)"
            },
        );
        out
    }
}

fn sample_counts(
    adapter: &wgpu::Adapter,
    format: wgpu::TextureFormat,
    adapter_specific: bool,
) -> Vec<u32> {
    let flags = if adapter_specific {
        adapter.get_texture_format_features(format).flags
    } else {
        // Without the adapter-specific feature wgpu allows only WebGPU's guaranteed counts.
        format
            .guaranteed_format_features(wgpu::Features::empty())
            .flags
    };
    let mut counts = flags.supported_sample_counts();
    if !counts.contains(&1) {
        counts.push(1);
    }
    counts.sort_unstable();
    counts
}
