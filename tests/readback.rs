//! The readback belt (`gpu::readback`) on a real device: several copies of different kinds in
//! one encoder come back byte-exact, the staging buffer is reused across frames, the
//! non-blocking path delivers after polling, and misuse is an error rather than a panic.

mod common;

use aa_lab::gpu::Gpu;
use aa_lab::gpu::readback::{ReadbackBelt, ReadbackError, Region, read_texture_rgba8};
use wgpu::util::DeviceExt;

/// Deterministic test bytes.
fn pattern(len: usize, seed: u8) -> Vec<u8> {
    (0..len)
        .map(|i| (i as u8).wrapping_mul(31).wrapping_add(seed) ^ (i >> 8) as u8)
        .collect()
}

fn texture(gpu: &Gpu, size: (u32, u32), format: wgpu::TextureFormat, data: &[u8]) -> wgpu::Texture {
    gpu.device.create_texture_with_data(
        &gpu.queue,
        &aa_lab::gpu::Texture2d::new(
            "readback test",
            size,
            format,
            wgpu::TextureUsages::COPY_SRC | wgpu::TextureUsages::TEXTURE_BINDING,
        )
        .descriptor(),
        wgpu::util::TextureDataOrder::LayerMajor,
        data,
    )
}

fn source_buffer(gpu: &Gpu, data: &[u8]) -> wgpu::Buffer {
    gpu.device
        .create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("readback test buffer"),
            contents: data,
            usage: wgpu::BufferUsages::COPY_SRC,
        })
}

fn encoder(gpu: &Gpu) -> wgpu::CommandEncoder {
    gpu.device
        .create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("readback test"),
        })
}

/// Texel rows `region` of a tightly packed `width`-wide image of `texel` bytes per texel.
fn crop(data: &[u8], width: u32, texel: u32, region: Region) -> Vec<u8> {
    let mut out = Vec::new();
    for y in region.y..region.y + region.height {
        let start = ((y * width + region.x) * texel) as usize;
        out.extend_from_slice(&data[start..start + (region.width * texel) as usize]);
    }
    out
}

#[test]
fn one_encoder_many_copies_come_back_byte_exact() {
    let gpu = common::gpu();
    let rgba = wgpu::TextureFormat::Rgba8Unorm;
    // Odd widths: rows of 4, 28 and 260 bytes all need padding to 256 (or 512).
    let sizes = [(1, 1), (7, 5), (65, 3), (64, 64)];
    let datas: Vec<Vec<u8>> = sizes
        .iter()
        .enumerate()
        .map(|(i, (w, h))| pattern((w * h * 4) as usize, i as u8))
        .collect();
    let textures: Vec<_> = sizes
        .iter()
        .zip(&datas)
        .map(|(&size, data)| texture(&gpu, size, rgba, data))
        .collect();
    let float_data = pattern(5 * 3 * 4, 99);
    let float = texture(&gpu, (5, 3), wgpu::TextureFormat::R32Float, &float_data);
    let srgb_data = pattern(9 * 2 * 4, 7);
    let srgb = texture(
        &gpu,
        (9, 2),
        wgpu::TextureFormat::Rgba8UnormSrgb,
        &srgb_data,
    );
    let buffer_data = pattern(1000, 42);
    let buffer = source_buffer(&gpu, &buffer_data);

    let mut belt = ReadbackBelt::new(&gpu.device);
    let mut enc = encoder(&gpu);
    let whole: Vec<_> = textures
        .iter()
        .map(|t| belt.copy_texture(&mut enc, t, Region::whole(t)).unwrap())
        .collect();
    let region = Region {
        x: 3,
        y: 1,
        width: 61,
        height: 2,
    };
    let part = belt.copy_texture(&mut enc, &textures[2], region).unwrap();
    let float_ticket = belt
        .copy_texture(&mut enc, &float, Region::whole(&float))
        .unwrap();
    let srgb_ticket = belt
        .copy_texture(&mut enc, &srgb, Region::whole(&srgb))
        .unwrap();
    let buffer_ticket = belt.copy_buffer(&mut enc, &buffer, 12, 400).unwrap();
    assert_eq!(belt.pending_copies(), 8);
    let pending = belt.finish(&mut enc);
    gpu.queue.submit([enc.finish()]);
    let frame = pending.wait().unwrap();
    assert_eq!(frame.len(), 8);
    assert_eq!(
        belt.buffers_created(),
        1,
        "one staging buffer for the frame"
    );

    for ((ticket, data), size) in whole.iter().zip(&datas).zip(sizes) {
        let image = frame.rgba8(*ticket).unwrap();
        assert_eq!(image.dimensions(), size);
        assert_eq!(image.as_raw(), data, "{size:?} texture");
        assert_eq!(&frame.bytes(*ticket).unwrap(), data);
    }
    let cropped = frame.rgba8(part).unwrap();
    assert_eq!(cropped.dimensions(), (61, 2));
    assert_eq!(cropped.as_raw(), &crop(&datas[2], 65, 4, region));
    assert_eq!(frame.bytes(float_ticket).unwrap(), float_data);
    assert!(matches!(
        frame.rgba8(float_ticket),
        Err(ReadbackError::UnsupportedFormat(
            wgpu::TextureFormat::R32Float
        ))
    ));
    assert_eq!(frame.rgba8(srgb_ticket).unwrap().as_raw(), &srgb_data);
    assert_eq!(frame.bytes(buffer_ticket).unwrap(), &buffer_data[12..412]);
    assert!(frame.rgba8(buffer_ticket).is_err());
}

#[test]
fn staging_buffer_is_reused_across_frames() {
    let gpu = common::gpu();
    let data = pattern(33 * 17 * 4, 3);
    let tex = texture(&gpu, (33, 17), wgpu::TextureFormat::Rgba8Unorm, &data);
    let mut belt = ReadbackBelt::new(&gpu.device);
    let run = |belt: &mut ReadbackBelt| {
        let mut enc = encoder(&gpu);
        let a = belt
            .copy_texture(&mut enc, &tex, Region::whole(&tex))
            .unwrap();
        let b = belt
            .copy_texture(&mut enc, &tex, Region::whole(&tex))
            .unwrap();
        let pending = belt.finish(&mut enc);
        gpu.queue.submit([enc.finish()]);
        (pending, a, b)
    };
    for frame_number in 0..3 {
        let (pending, a, b) = run(&mut belt);
        let frame = pending.wait().unwrap();
        assert_eq!(frame.rgba8(a).unwrap().as_raw(), &data);
        assert_eq!(frame.rgba8(b).unwrap().as_raw(), &data);
        drop(frame);
        assert_eq!(
            belt.buffers_created(),
            1,
            "frame {frame_number} allocated a staging buffer"
        );
    }
    // One frame still mapped while the next records: a second buffer, then no more.
    let (first, _, _) = run(&mut belt);
    let held = first.wait().unwrap();
    let (second, a, _) = run(&mut belt);
    assert_eq!(belt.buffers_created(), 2);
    let second = second.wait().unwrap();
    assert_eq!(second.rgba8(a).unwrap().as_raw(), &data);
    drop((held, second));
    for _ in 0..3 {
        let (pending, _, _) = run(&mut belt);
        drop(pending.wait().unwrap());
    }
    assert_eq!(belt.buffers_created(), 2, "the pool serves later frames");
}

#[test]
fn a_frame_that_outgrows_the_belt_grows_it() {
    let gpu = common::gpu();
    // 300x300 RGBA: 1280-byte rows, 384000 bytes a copy, beyond the first staging buffer.
    let small = pattern(4 * 4 * 4, 1);
    let small_tex = texture(&gpu, (4, 4), wgpu::TextureFormat::Rgba8Unorm, &small);
    let big = pattern(300 * 300 * 4, 2);
    let big_tex = texture(&gpu, (300, 300), wgpu::TextureFormat::Rgba8Unorm, &big);
    let mut belt = ReadbackBelt::new(&gpu.device);
    let frame = |belt: &mut ReadbackBelt| {
        let mut enc = encoder(&gpu);
        let a = belt
            .copy_texture(&mut enc, &small_tex, Region::whole(&small_tex))
            .unwrap();
        let b = belt
            .copy_texture(&mut enc, &big_tex, Region::whole(&big_tex))
            .unwrap();
        let c = belt
            .copy_texture(&mut enc, &big_tex, Region::whole(&big_tex))
            .unwrap();
        let pending = belt.finish(&mut enc);
        gpu.queue.submit([enc.finish()]);
        let frame = pending.wait().unwrap();
        assert_eq!(frame.rgba8(a).unwrap().as_raw(), &small);
        assert_eq!(frame.rgba8(b).unwrap().as_raw(), &big);
        assert_eq!(frame.rgba8(c).unwrap().as_raw(), &big);
    };
    frame(&mut belt);
    let after_first = belt.buffers_created();
    assert!(belt.capacity() >= 2 * 384_000);
    frame(&mut belt);
    assert_eq!(
        belt.buffers_created(),
        after_first + 1,
        "the second frame gets one buffer of the grown size"
    );
    frame(&mut belt);
    frame(&mut belt);
    assert_eq!(belt.buffers_created(), after_first + 1);
}

#[test]
fn try_take_delivers_after_polling() {
    let gpu = common::gpu();
    let data = pattern(19 * 11 * 4, 5);
    let tex = texture(&gpu, (19, 11), wgpu::TextureFormat::Rgba8Unorm, &data);
    let buffer_data = pattern(64, 9);
    let buffer = source_buffer(&gpu, &buffer_data);
    let mut belt = ReadbackBelt::new(&gpu.device);
    let mut enc = encoder(&gpu);
    let image = belt
        .copy_texture(&mut enc, &tex, Region::whole(&tex))
        .unwrap();
    let bytes = belt.copy_buffer(&mut enc, &buffer, 0, 64).unwrap();
    let mut pending = belt.finish(&mut enc);
    gpu.queue.submit([enc.finish()]);
    let start = std::time::Instant::now();
    let frame = loop {
        if let Some(frame) = pending.try_take().unwrap() {
            break frame;
        }
        assert!(
            start.elapsed() < std::time::Duration::from_secs(60),
            "the readback never arrived"
        );
        std::thread::sleep(std::time::Duration::from_millis(1));
    };
    assert_eq!(frame.rgba8(image).unwrap().as_raw(), &data);
    assert_eq!(frame.bytes(bytes).unwrap(), buffer_data);
    assert!(matches!(
        pending.try_take(),
        Err(ReadbackError::AlreadyTaken)
    ));
}

#[test]
fn an_abandoned_readback_returns_its_buffer() {
    let gpu = common::gpu();
    let data = pattern(8 * 8 * 4, 11);
    let tex = texture(&gpu, (8, 8), wgpu::TextureFormat::Rgba8Unorm, &data);
    let mut belt = ReadbackBelt::new(&gpu.device);
    let mut enc = encoder(&gpu);
    belt.copy_texture(&mut enc, &tex, Region::whole(&tex))
        .unwrap();
    let pending = belt.finish(&mut enc);
    gpu.queue.submit([enc.finish()]);
    drop(pending);
    gpu.wait_idle();
    let mut enc = encoder(&gpu);
    let ticket = belt
        .copy_texture(&mut enc, &tex, Region::whole(&tex))
        .unwrap();
    let pending = belt.finish(&mut enc);
    gpu.queue.submit([enc.finish()]);
    assert_eq!(
        pending.wait().unwrap().rgba8(ticket).unwrap().as_raw(),
        &data
    );
    assert_eq!(belt.buffers_created(), 1);
}

#[test]
fn misuse_is_an_error_not_a_panic() {
    let gpu = common::gpu();
    let data = pattern(6 * 4 * 4, 0);
    let tex = texture(&gpu, (6, 4), wgpu::TextureFormat::Rgba8Unorm, &data);
    let no_copy = gpu.device.create_texture(
        &aa_lab::gpu::Texture2d::new(
            "no copy",
            (4, 4),
            wgpu::TextureFormat::Rgba8Unorm,
            wgpu::TextureUsages::TEXTURE_BINDING,
        )
        .descriptor(),
    );
    let buffer = source_buffer(&gpu, &pattern(32, 1));
    let mut belt = ReadbackBelt::new(&gpu.device);
    let mut enc = encoder(&gpu);
    let outside = Region {
        x: 4,
        y: 0,
        width: 3,
        height: 1,
    };
    assert!(matches!(
        belt.copy_texture(&mut enc, &tex, outside),
        Err(ReadbackError::Region { .. })
    ));
    let empty = Region {
        width: 0,
        ..Region::whole(&tex)
    };
    assert!(belt.copy_texture(&mut enc, &tex, empty).is_err());
    assert!(matches!(
        belt.copy_texture(&mut enc, &no_copy, Region::whole(&no_copy)),
        Err(ReadbackError::NotCopySource(_))
    ));
    for (offset, size) in [(2, 4), (0, 6), (0, 0), (16, 32)] {
        assert!(
            matches!(
                belt.copy_buffer(&mut enc, &buffer, offset, size),
                Err(ReadbackError::BufferRange { .. })
            ),
            "{offset}+{size}"
        );
    }
    assert_eq!(belt.pending_copies(), 0);
    // A ticket redeemed on another frame.
    let first = belt
        .copy_texture(&mut enc, &tex, Region::whole(&tex))
        .unwrap();
    let pending = belt.finish(&mut enc);
    gpu.queue.submit([enc.finish()]);
    drop(pending.wait().unwrap());
    let mut enc = encoder(&gpu);
    belt.copy_texture(&mut enc, &tex, Region::whole(&tex))
        .unwrap();
    let pending = belt.finish(&mut enc);
    gpu.queue.submit([enc.finish()]);
    let frame = pending.wait().unwrap();
    assert!(matches!(
        frame.bytes(first),
        Err(ReadbackError::ForeignTicket { .. })
    ));
    drop(frame);
    // An encoder that is never submitted: an error, no hang.
    let mut enc = encoder(&gpu);
    belt.copy_texture(&mut enc, &tex, Region::whole(&tex))
        .unwrap();
    let pending = belt.finish(&mut enc);
    drop(enc);
    assert!(matches!(pending.wait(), Err(ReadbackError::NoAnswer)));
}

#[test]
fn convenience_read_matches_the_belt() {
    let gpu = common::gpu();
    let data = pattern(13 * 7 * 4, 77);
    let tex = texture(&gpu, (13, 7), wgpu::TextureFormat::Rgba8UnormSrgb, &data);
    assert_eq!(read_texture_rgba8(&gpu, &tex).unwrap().as_raw(), &data);
    let float = texture(&gpu, (2, 2), wgpu::TextureFormat::R32Float, &pattern(16, 1));
    assert!(matches!(
        read_texture_rgba8(&gpu, &float),
        Err(ReadbackError::UnsupportedFormat(_))
    ));
}

/// The viewer's use: a frame renders several techniques, their outputs are copied in the
/// frame's own encoder (one submission), and the images arrive through `try_take`, equal to
/// what a separate blocking read of each output gives; the next frame allocates nothing.
#[test]
fn a_frame_graph_frame_reads_back_every_output_in_its_own_encoder() {
    use aa_lab::aa::{self, FrameInfo};
    use aa_lab::graph::{FrameGraph, FrameScope};
    use aa_lab::scene::camera::FrameCamera;
    use aa_lab::scene::procedural::{BUILTIN_SCENES, SceneOptions};
    use aa_lab::scene::source;

    let gpu = common::gpu();
    let scene = source::load(BUILTIN_SCENES[0], &SceneOptions::default()).expect("scene loads");
    let mut graph = FrameGraph::new(gpu.clone(), &scene);
    for id in ["none", "fxaa", "msaa4"] {
        graph.add(aa::create(&gpu, id).expect("technique"));
    }
    let mut belt = ReadbackBelt::new(&gpu.device);
    for frame_number in 0..2 {
        let size = (101, 37);
        let info = FrameInfo {
            camera: FrameCamera::from_rig(&scene.camera, frame_number, size),
            reset_history: true,
        };
        let (mut pending, tickets) = graph
            .render_with(&info, FrameScope::All, |encoder, slots| {
                let tickets: Vec<_> = slots
                    .iter()
                    .filter_map(|slot| slot.output())
                    .map(|texture| {
                        belt.copy_texture(encoder, texture, Region::whole(texture))
                            .expect("copy")
                    })
                    .collect();
                (belt.finish(encoder), tickets)
            })
            .expect("frame renders");
        assert_eq!(tickets.len(), 3);
        let frame = loop {
            if let Some(frame) = pending.try_take().expect("readback") {
                break frame;
            }
            std::thread::sleep(std::time::Duration::from_millis(1));
        };
        for (ticket, slot) in tickets.iter().zip(graph.slots()) {
            let image = frame.rgba8(*ticket).expect("image");
            let expected = read_texture_rgba8(&gpu, slot.output().expect("output")).expect("read");
            assert_eq!(image.dimensions(), size);
            assert!(image == expected, "{} differs", slot.technique.id());
        }
    }
    assert_eq!(belt.buffers_created(), 1);
}
