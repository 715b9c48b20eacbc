//! Non-blocking readback of RGBA8 texture regions: the copy is recorded and submitted at once,
//! the buffer is mapped asynchronously, and the UI polls each frame until the bytes are there.
//! Nothing waits for the GPU, so a long frame on a software rasteriser never stalls input.

use std::sync::mpsc;

/// A rectangle of texels.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Region {
    /// Left edge.
    pub x: u32,
    /// Top edge.
    pub y: u32,
    /// Width (at least 1).
    pub width: u32,
    /// Height (at least 1).
    pub height: u32,
}

impl Region {
    /// The whole of a texture.
    pub fn whole(texture: &wgpu::Texture) -> Self {
        Self {
            x: 0,
            y: 0,
            width: texture.width(),
            height: texture.height(),
        }
    }

    /// The part of `self` inside a `size` image, `None` when nothing is left.
    pub fn clipped(self, size: (u32, u32)) -> Option<Self> {
        let x1 = (self.x + self.width).min(size.0);
        let y1 = (self.y + self.height).min(size.1);
        (x1 > self.x && y1 > self.y).then_some(Self {
            width: x1 - self.x,
            height: y1 - self.y,
            ..self
        })
    }
}

/// A readback in flight.
pub struct PendingImage {
    buffer: wgpu::Buffer,
    region: Region,
    padded_row: u32,
    answer: mpsc::Receiver<Result<(), wgpu::BufferAsyncError>>,
}

/// Errors of a readback.
#[derive(Debug, thiserror::Error)]
pub enum ReadbackError {
    /// Mapping failed (device lost).
    #[error("reading pixels back from the GPU failed: {0}")]
    Map(String),
}

impl PendingImage {
    /// Starts reading `region` (clipped by the caller to the texture) of an RGBA8 texture with
    /// `COPY_SRC` usage.
    pub fn start(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        texture: &wgpu::Texture,
        region: Region,
    ) -> Self {
        let padded_row = (region.width * 4).next_multiple_of(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT);
        let buffer = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("viewer readback"),
            size: u64::from(padded_row) * u64::from(region.height),
            usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
            mapped_at_creation: false,
        });
        let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("viewer readback"),
        });
        encoder.copy_texture_to_buffer(
            wgpu::TexelCopyTextureInfo {
                texture,
                mip_level: 0,
                origin: wgpu::Origin3d {
                    x: region.x,
                    y: region.y,
                    z: 0,
                },
                aspect: wgpu::TextureAspect::All,
            },
            wgpu::TexelCopyBufferInfo {
                buffer: &buffer,
                layout: wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(padded_row),
                    rows_per_image: Some(region.height),
                },
            },
            wgpu::Extent3d {
                width: region.width,
                height: region.height,
                depth_or_array_layers: 1,
            },
        );
        queue.submit([encoder.finish()]);
        let (sender, answer) = mpsc::channel();
        buffer
            .slice(..)
            .map_async(wgpu::MapMode::Read, move |result| {
                let _ = sender.send(result);
            });
        Self {
            buffer,
            region,
            padded_row,
            answer,
        }
    }

    /// The pixels once the GPU has delivered them (the caller polls the device), `Ok(None)`
    /// while still in flight.
    pub fn try_take(&self) -> Result<Option<image::RgbaImage>, ReadbackError> {
        match self.answer.try_recv() {
            Err(mpsc::TryRecvError::Empty) => Ok(None),
            Err(mpsc::TryRecvError::Disconnected) => Err(ReadbackError::Map(
                "the map callback was dropped".to_owned(),
            )),
            Ok(Err(err)) => Err(ReadbackError::Map(err.to_string())),
            Ok(Ok(())) => {
                let mapped = self
                    .buffer
                    .slice(..)
                    .get_mapped_range()
                    .map_err(|e| ReadbackError::Map(e.to_string()))?;
                let row = (self.region.width * 4) as usize;
                let mut packed = Vec::with_capacity(row * self.region.height as usize);
                for line in mapped.chunks_exact(self.padded_row as usize) {
                    packed.extend_from_slice(&line[..row]);
                }
                drop(mapped);
                self.buffer.unmap();
                Ok(image::RgbaImage::from_raw(
                    self.region.width,
                    self.region.height,
                    packed,
                ))
            }
        }
    }
}
