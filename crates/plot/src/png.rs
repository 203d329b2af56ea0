//! PNG encoding of RGB8 buffers (the `image` crate's pure-Rust encoder),
//! for figures drawn in memory and for CT previews.

/// PNG-encodes an RGB8 buffer of `w × h` pixels (PNG, ISO/IEC 15948).
pub fn encode_png(rgb: &[u8], w: u32, h: u32) -> Result<Vec<u8>, image::ImageError> {
    use image::ImageEncoder;
    let mut out = Vec::new();
    image::codecs::png::PngEncoder::new(&mut out).write_image(rgb, w, h, image::ColorType::Rgb8)?;
    Ok(out)
}
