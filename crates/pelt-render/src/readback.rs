//! Copying a render target back to the CPU, with rows padded to wgpu's 256-byte copy alignment.

use rayon::prelude::*;

use pelt_core::error::{PeltError, Result};
use pelt_core::threads::pool;

/// Reads an RGBA8 2D texture into tightly packed rows (`height × width × 4` bytes).
pub(super) fn read_rgba8(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    texture: &wgpu::Texture,
) -> Result<Vec<u8>> {
    read_texels(device, queue, texture, 4)
}

/// Reads a 2D texture of `texel_bytes` bytes per texel into tightly packed rows.
pub(super) fn read_texels(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    texture: &wgpu::Texture,
    texel_bytes: u32,
) -> Result<Vec<u8>> {
    read_texels_with(device, queue, texture, texel_bytes, texel_bytes, |row, out| {
        out.copy_from_slice(row);
    })
}

/// Reads a 2D texture of `texel_bytes` bytes per texel, each row turned by `convert` into a row
/// of `out_bytes` bytes per texel straight from the mapped buffer, rows in parallel on Pelt's
/// threads.
pub(super) fn read_texels_with(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    texture: &wgpu::Texture,
    texel_bytes: u32,
    out_bytes: u32,
    convert: impl Fn(&[u8], &mut [u8]) + Sync,
) -> Result<Vec<u8>> {
    let (width, height) = (texture.width(), texture.height());
    let row_bytes = width * texel_bytes;
    let padded = row_bytes.div_ceil(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT) * wgpu::COPY_BYTES_PER_ROW_ALIGNMENT;
    let buffer = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("readback"),
        size: u64::from(padded) * u64::from(height),
        usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
        mapped_at_creation: false,
    });
    let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
        label: Some("readback"),
    });
    encoder.copy_texture_to_buffer(
        texture.as_image_copy(),
        wgpu::TexelCopyBufferInfo {
            buffer: &buffer,
            layout: wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(padded),
                rows_per_image: Some(height),
            },
        },
        texture.size(),
    );
    queue.submit([encoder.finish()]);
    let out_row = (width * out_bytes) as usize;
    mapped(device, &buffer, |bytes| {
        let mut pixels = vec![0u8; out_row * height as usize];
        pool().install(|| {
            pixels
                .par_chunks_mut(out_row.max(1))
                .zip(bytes.par_chunks(padded as usize))
                .for_each(|(out, row)| convert(&row[..row_bytes as usize], out));
        });
        pixels
    })
}

/// Waits for the GPU, maps `buffer` (`MAP_READ`, copies submitted) and hands its bytes to `read`.
fn mapped<T>(device: &wgpu::Device, buffer: &wgpu::Buffer, read: impl FnOnce(&[u8]) -> T) -> Result<T> {
    let (sender, receiver) = std::sync::mpsc::channel();
    buffer.map_async(wgpu::MapMode::Read, .., move |r| {
        // the receiver outlives the poll below; a send error cannot happen
        let _ = sender.send(r);
    });
    device
        .poll(wgpu::PollType::wait_indefinitely())
        .map_err(|e| PeltError::Render(format!("waiting for the GPU failed: {e}")))?;
    receiver
        .recv()
        .map_err(|e| PeltError::Render(format!("readback never completed: {e}")))?
        .map_err(|e| PeltError::Render(format!("mapping the readback buffer failed: {e}")))?;
    let view = buffer
        .get_mapped_range(..)
        .map_err(|e| PeltError::Render(format!("reading the readback buffer failed: {e}")))?;
    let value = read(&view);
    drop(view);
    buffer.unmap();
    Ok(value)
}

/// Reads a whole buffer (which needs `COPY_SRC`) back to the CPU.
#[cfg(test)]
pub(super) fn read_buffer(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    source: &wgpu::Buffer,
) -> Result<Vec<u8>> {
    let buffer = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("readback"),
        size: source.size(),
        usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
        mapped_at_creation: false,
    });
    let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
        label: Some("readback"),
    });
    encoder.copy_buffer_to_buffer(source, 0, &buffer, 0, source.size());
    queue.submit([encoder.finish()]);
    mapped(device, &buffer, <[u8]>::to_vec)
}
