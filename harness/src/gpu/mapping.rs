//! Waiting for the device and reading a mapped buffer: the two device operations the frame's
//! read-backs (textures, timestamps, pipeline statistics) share.

/// Blocks until all work submitted to `device` is done.
pub fn wait(device: &wgpu::Device) -> Result<(), String> {
    device
        .poll(wgpu::PollType::wait_indefinitely())
        .map(|_| ())
        .map_err(|e| format!("device poll failed: {e}"))
}

/// Waits for the device, maps a MAP_READ buffer and returns a copy of its bytes (unmapped again).
pub fn read_buffer(device: &wgpu::Device, buffer: &wgpu::Buffer) -> Result<Vec<u8>, String> {
    let slice = buffer.slice(..);
    let (tx, rx) = std::sync::mpsc::channel();
    slice.map_async(wgpu::MapMode::Read, move |r| {
        let _ = tx.send(r);
    });
    wait(device)?;
    rx.recv()
        .map_err(|_| "map callback never ran".to_string())?
        .map_err(|e| format!("buffer map failed: {e}"))?;
    let bytes = slice
        .get_mapped_range()
        .map_err(|e| format!("buffer map range: {e}"))?
        .to_vec();
    buffer.unmap();
    Ok(bytes)
}
