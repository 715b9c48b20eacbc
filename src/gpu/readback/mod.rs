//! The one way pixels and buffer contents come back from the GPU: a readback belt, after
//! re_renderer's `GpuReadbackBelt`.
//!
//! This module owns every GPU-to-CPU copy of the crate: technique outputs for the viewer and
//! the CLI, the GPU metrics' totals and SSIM map, and the graph's pipeline-statistics results.
//!
//! # How the belt works
//! 1. While a frame is recorded, [`ReadbackBelt::copy_texture`] and
//!    [`ReadbackBelt::copy_buffer`] record copies into the caller's own command encoder (the
//!    frame's encoder, so a copy sees exactly what the passes before it wrote) and hand back a
//!    [`Ticket`]. Every copy of the frame is packed into one `MAP_READ` staging buffer, each at
//!    an offset aligned to [`COPY_OFFSET_ALIGNMENT`] (256 bytes: a multiple of every texel
//!    block size, of `MAP_ALIGNMENT` and of `COPY_BUFFER_ALIGNMENT`), texture rows padded to
//!    `COPY_BYTES_PER_ROW_ALIGNMENT`.
//! 2. [`ReadbackBelt::finish`], called last on that encoder before it is submitted, asks wgpu
//!    to map the staging buffer when the encoder's commands have run
//!    (`CommandEncoder::map_buffer_on_submit`) and returns a [`PendingReadback`].
//! 3. The caller submits, then either blocks ([`PendingReadback::wait`]: `device.poll(Wait)`)
//!    or polls each UI frame ([`PendingReadback::try_take`]: `Ok(None)` while the GPU works).
//!    Both give a [`ReadbackFrame`] handing out each ticket's bytes ([`ReadbackFrame::bytes`],
//!    row padding removed) or image ([`ReadbackFrame::rgba8`]).
//! 4. Dropping the [`ReadbackFrame`] (or an abandoned [`PendingReadback`]) unmaps the staging
//!    buffer and returns it to the belt's small pool, so the next frame records into it again
//!    while, if needed, another frame's buffer is still mapped.
//!
//! The staging buffer of a frame is sized from the largest frame seen so far. A frame that
//! outgrows it opens a second buffer (mapped separately, that frame only), and the belt then
//! grows: smaller buffers are dropped as they come back, and later frames get one buffer of
//! the new size. [`ReadbackBelt::buffers_created`] counts allocations, so tests can check that
//! a steady stream of frames allocates nothing.
//!
//! # Why one map per frame
//! Every `map_async` is a separate request the device must track and answer, and on Vulkan a
//! separate wait on the submission's fence; a buffer and an encoder per image (what the crate
//! did before) also allocate GPU memory every frame. Packing a frame's copies into one reused
//! buffer costs one allocation in steady state (none), one submission (the frame's own) and
//! one map, whatever the number of images.
//!
//! No call here panics on a GPU result: a failed map, a lost device, a ticket of another frame
//! or a copy wgpu would reject (missing `COPY_SRC`, a region outside the texture, unaligned
//! buffer ranges) are [`ReadbackError`]s.

mod belt;
mod frame;
mod pool;
mod types;

use super::Gpu;
pub use belt::ReadbackBelt;
pub use frame::{PendingReadback, ReadbackFrame};
pub use types::{COPY_OFFSET_ALIGNMENT, ReadbackError, Region, Ticket};

/// Records, submits and waits for one readback on its own encoder: `record` adds the copies to
/// `belt` and returns what `read` needs to redeem them.
fn read_now<T, R>(
    gpu: &Gpu,
    belt: &mut ReadbackBelt,
    record: impl FnOnce(&mut ReadbackBelt, &mut wgpu::CommandEncoder) -> Result<T, ReadbackError>,
    read: impl FnOnce(&ReadbackFrame, T) -> Result<R, ReadbackError>,
) -> Result<R, ReadbackError> {
    let mut encoder = gpu
        .device
        .create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("readback"),
        });
    let recorded = record(belt, &mut encoder);
    let pending = belt.finish(&mut encoder);
    let tickets = recorded?;
    gpu.queue.submit([encoder.finish()]);
    read(&pending.wait()?, tickets)
}

/// Reads mip level 0 of a 2D texture (which needs `COPY_SRC` usage) into tightly packed rows:
/// one encoder, one submission, a blocking wait (on a belt of its own).
pub fn read_texture_bytes(gpu: &Gpu, texture: &wgpu::Texture) -> Result<Vec<u8>, ReadbackError> {
    read_now(
        gpu,
        &mut ReadbackBelt::new(&gpu.device),
        |belt, encoder| belt.copy_texture(encoder, texture, Region::whole(texture)),
        |frame, ticket| frame.bytes(ticket),
    )
}

/// Reads a half-float RGBA texture (`Rgba16Float`: the radiance of a technique before the
/// tonemapper) into a linear RGB image (alpha dropped): one encoder, one submission, a
/// blocking wait.
pub fn read_texture_radiance(
    gpu: &Gpu,
    texture: &wgpu::Texture,
) -> Result<image::Rgb32FImage, ReadbackError> {
    if texture.format() != wgpu::TextureFormat::Rgba16Float {
        return Err(ReadbackError::UnsupportedFormat(texture.format()));
    }
    let bytes = read_texture_bytes(gpu, texture)?;
    from_half_floats((texture.width(), texture.height()), &bytes)
        .ok_or(ReadbackError::UnsupportedFormat(texture.format()))
}

/// The linear RGB image of half-float RGBA texels (`gpu::HDR_FORMAT`, tightly packed rows),
/// or `None` when the byte count does not match the size.
fn from_half_floats(size: (u32, u32), bytes: &[u8]) -> Option<image::Rgb32FImage> {
    let texels = bytes.len() / 8;
    if texels != (size.0 as usize) * (size.1 as usize) || !bytes.len().is_multiple_of(8) {
        return None;
    }
    let values: Vec<f32> = bytes
        .chunks_exact(8)
        .flat_map(|texel| {
            (0..3).map(move |c| half::f16::from_le_bytes([texel[2 * c], texel[2 * c + 1]]).to_f32())
        })
        .collect();
    image::Rgb32FImage::from_raw(size.0, size.1, values)
}

/// Reads an RGBA8 texture (`Rgba8Unorm` or `Rgba8UnormSrgb`: the stored, encoded bytes) into an
/// image: one encoder, one submission, a blocking wait (on a belt of its own).
pub fn read_texture_rgba8(
    gpu: &Gpu,
    texture: &wgpu::Texture,
) -> Result<image::RgbaImage, ReadbackError> {
    match texture.format() {
        wgpu::TextureFormat::Rgba8Unorm | wgpu::TextureFormat::Rgba8UnormSrgb => {}
        other => return Err(ReadbackError::UnsupportedFormat(other)),
    }
    read_now(
        gpu,
        &mut ReadbackBelt::new(&gpu.device),
        |belt, encoder| belt.copy_texture(encoder, texture, Region::whole(texture)),
        |frame, ticket| frame.rgba8(ticket),
    )
}

/// [`read_texture_bytes`] on a belt the caller keeps, so repeated reads reuse its staging
/// buffer.
pub fn read_texture_bytes_with(
    gpu: &Gpu,
    belt: &mut ReadbackBelt,
    texture: &wgpu::Texture,
) -> Result<Vec<u8>, ReadbackError> {
    read_now(
        gpu,
        belt,
        |belt, encoder| belt.copy_texture(encoder, texture, Region::whole(texture)),
        |frame, ticket| frame.bytes(ticket),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn handles_move_between_threads() {
        // The viewer records on its render thread and polls from the UI thread.
        fn send<T: Send>() {}
        send::<ReadbackBelt>();
        send::<PendingReadback>();
        send::<ReadbackFrame>();
        send::<Ticket>();
    }

    #[test]
    fn half_float_texels_decode_to_linear_rgb() {
        let texel = |v: f32| {
            let h = half::f16::from_f32(v).to_le_bytes();
            [h[0], h[1], h[0], h[1], h[0], h[1], 0, 0x3c]
        };
        let bytes: Vec<u8> = [0.5f32, 40.0].iter().flat_map(|&v| texel(v)).collect();
        let image = from_half_floats((2, 1), &bytes).expect("two texels");
        assert_eq!(image.get_pixel(1, 0).0, [40.0; 3]);
        assert!(from_half_floats((3, 1), &bytes).is_none());
    }
}
