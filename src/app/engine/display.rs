//! How the engine's images reach the screen ([`Display`]: the output textures themselves on
//! eframe's device, or read back and uploaded), and a published image with what it shows
//! ([`Published`]).

use super::*;

/// How finished images reach the screen (see the module docs).
#[derive(Clone)]
pub enum Display {
    /// The engine renders on a device of its own; every output is read back and uploaded to
    /// eframe's device (software adapters).
    Readback(egui_wgpu::RenderState),
    /// The engine renders on eframe's device and the output textures are drawn directly;
    /// pixels come back to the CPU only when something reads them (hardware adapters).
    Native(egui_wgpu::RenderState),
}

/// Which [`Display`] the viewer uses.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum DisplayPath {
    /// Native on hardware adapters, readback on software ones; the environment variable
    /// `AA_LAB_DISPLAY=native` or `readback` overrides the choice.
    #[default]
    Auto,
    /// Always [`Display::Native`].
    Native,
    /// Always [`Display::Readback`].
    Readback,
}

impl Display {
    /// The display for eframe's render state along `path`.
    pub fn choose(state: &egui_wgpu::RenderState, path: DisplayPath) -> Self {
        let native = match path {
            DisplayPath::Native => true,
            DisplayPath::Readback => false,
            DisplayPath::Auto => match std::env::var("AA_LAB_DISPLAY").as_deref() {
                Ok("native") => true,
                Ok("readback") => false,
                _ => state.adapter.get_info().device_type != wgpu::DeviceType::Cpu,
            },
        };
        // An output is drawn through its linear view of the sRGB texture.
        let viewable = state
            .adapter
            .get_downlevel_capabilities()
            .flags
            .contains(wgpu::DownlevelFlags::VIEW_FORMATS);
        let native = native && viewable;
        if native {
            Self::Native(state.clone())
        } else {
            Self::Readback(state.clone())
        }
    }

    pub(super) fn state(&self) -> &egui_wgpu::RenderState {
        match self {
            Self::Readback(state) | Self::Native(state) => state,
        }
    }

    pub(super) fn is_native(&self) -> bool {
        matches!(self, Self::Native(_))
    }
}

/// A finished image: the texture it is drawn from and, when read back, its pixels on the CPU.
#[derive(Clone)]
pub struct Published {
    /// The pixels (sRGB-encoded RGBA8) when they were read back: always on the readback path,
    /// on the native path only for frames that something wanted to read.
    pub pixels: Option<Arc<image::RgbaImage>>,
    /// What the image shows.
    pub stamp: ImageStamp,
    pub(super) texture: Arc<DisplayTexture>,
}

impl Published {
    /// An image whose pixels are on the CPU and on screen.
    pub fn new(image: RenderedImage, stamp: ImageStamp) -> Self {
        Self {
            pixels: Some(Arc::new(image.pixels)),
            stamp,
            texture: image.texture,
        }
    }

    /// What [`blit::paint`] draws.
    pub fn texture(&self) -> &Arc<DisplayTexture> {
        &self.texture
    }

    /// Size in pixels.
    pub fn size(&self) -> (u32, u32) {
        self.texture.size()
    }
}
