//! Copies textures back to the CPU: row padding to wgpu's 256-byte alignment is added for the
//! copy and stripped again, so callers get tightly packed rows.

use super::Gpu;

/// Errors of a readback.
#[derive(Debug, thiserror::Error)]
pub enum ReadbackError {
    /// The texture's format has no fixed texel size (compressed or depth-stencil).
    #[error("cannot read back a texture of format {0:?}")]
    UnsupportedFormat(wgpu::TextureFormat),
    /// Mapping the staging buffer failed (usually a lost device).
    #[error("mapping the readback buffer failed: {0}")]
    Map(#[from] wgpu::BufferAsyncError),
    /// The device was lost or timed out while waiting.
    #[error("waiting for the GPU failed: {0}")]
    Poll(#[from] wgpu::PollError),
    /// The mapped range could not be accessed.
    #[error("reading the mapped readback buffer failed: {0}")]
    MapRange(#[from] wgpu::MapRangeError),
    /// The result channel closed before the map callback ran.
    #[error("the GPU never answered the readback")]
    NoAnswer,
}

/// Reads mip level 0 of a 2D texture (which needs `COPY_SRC` usage) into tightly packed rows.
pub fn read_texture_bytes(gpu: &Gpu, texture: &wgpu::Texture) -> Result<Vec<u8>, ReadbackError> {
    let format = texture.format();
    let texel_bytes = format
        .block_copy_size(None)
        .ok_or(ReadbackError::UnsupportedFormat(format))?;
    let (width, height) = (texture.width(), texture.height());
    let row_bytes = width * texel_bytes;
    let padded_row_bytes = row_bytes.next_multiple_of(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT);
    let buffer = gpu.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("readback"),
        size: u64::from(padded_row_bytes) * u64::from(height),
        usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
        mapped_at_creation: false,
    });
    let mut encoder = gpu
        .device
        .create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("readback"),
        });
    encoder.copy_texture_to_buffer(
        texture.as_image_copy(),
        wgpu::TexelCopyBufferInfo {
            buffer: &buffer,
            layout: wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(padded_row_bytes),
                rows_per_image: Some(height),
            },
        },
        texture.size(),
    );
    gpu.queue.submit([encoder.finish()]);
    let slice = buffer.slice(..);
    let (sender, receiver) = std::sync::mpsc::channel();
    slice.map_async(wgpu::MapMode::Read, move |result| {
        let _ = sender.send(result);
    });
    gpu.device.poll(wgpu::PollType::wait_indefinitely())?;
    receiver.recv().map_err(|_| ReadbackError::NoAnswer)??;
    let mapped = slice.get_mapped_range()?;
    let mut packed = Vec::with_capacity((row_bytes * height) as usize);
    for row in mapped.chunks_exact(padded_row_bytes as usize) {
        packed.extend_from_slice(&row[..row_bytes as usize]);
    }
    drop(mapped);
    buffer.unmap();
    Ok(packed)
}

/// Reads an RGBA8 texture (`Rgba8Unorm` or `Rgba8UnormSrgb`: the stored, encoded bytes) into an
/// image.
pub fn read_texture_rgba8(
    gpu: &Gpu,
    texture: &wgpu::Texture,
) -> Result<image::RgbaImage, ReadbackError> {
    match texture.format() {
        wgpu::TextureFormat::Rgba8Unorm | wgpu::TextureFormat::Rgba8UnormSrgb => {}
        other => return Err(ReadbackError::UnsupportedFormat(other)),
    }
    let bytes = read_texture_bytes(gpu, texture)?;
    image::RgbaImage::from_raw(texture.width(), texture.height(), bytes)
        .ok_or(ReadbackError::UnsupportedFormat(texture.format()))
}
