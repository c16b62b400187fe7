//! Loading glTF buffers and images into memory.
//!
//! Inputs: the validated document, the GLB binary chunk (if any) and the [`Ctx`] (for confined
//! URI reads). Outputs: one byte vector per buffer, cut to its `byteLength`; one
//! [`scene::Image`] per image holding the encoded bytes and their media type, whatever the source
//! (file, `data:` URI, bufferView).
//! Invariants: a buffer shorter than its `byteLength`, a missing file, a URI escaping the input
//! folder, a bufferView outside its buffer or an image that is not PNG/JPEG is an error naming
//! `/buffers/N`, `/bufferViews/N` or `/images/N`.

use crate::Result;
use crate::import::{context::Ctx, images::sniff_mime, resources::read_uri};
use crate::scene;

/// Read every buffer of `doc`.
pub(super) fn load_buffers(
    ctx: &mut Ctx,
    doc: &::gltf::Document,
    bin: Option<&[u8]>,
) -> Result<Vec<Vec<u8>>> {
    let mut buffers = Vec::new();
    for buffer in doc.buffers() {
        let at = format!("/buffers/{}", buffer.index());
        let mut bytes = match buffer.source() {
            ::gltf::buffer::Source::Uri(uri) => read_uri(ctx, uri, &at, "buffer")?,
            ::gltf::buffer::Source::Bin => match bin {
                Some(bin) if buffer.index() == 0 => bin.to_vec(),
                _ => {
                    return Err(ctx.err(
                        &at,
                        "buffer has no uri, and only buffer 0 of a .glb file may use the \
                         binary chunk",
                    ));
                }
            },
        };
        if bytes.len() < buffer.length() {
            return Err(ctx.err(
                &at,
                format!(
                    "buffer holds {} bytes but its byteLength is {} (truncated file?)",
                    bytes.len(),
                    buffer.length()
                ),
            ));
        }
        bytes.truncate(buffer.length());
        buffers.push(bytes);
    }
    Ok(buffers)
}

/// The bytes of a bufferView, or a message if it does not fit in its buffer.
pub(super) fn view_bytes<'b>(
    buffers: &'b [Vec<u8>],
    view: &::gltf::buffer::View,
) -> Result<&'b [u8], String> {
    let buffer = &buffers[view.buffer().index()];
    view.offset()
        .checked_add(view.length())
        .and_then(|end| buffer.get(view.offset()..end))
        .ok_or_else(|| {
            format!(
                "/bufferViews/{} (byteOffset {}, byteLength {}) does not fit in /buffers/{} \
                 ({} bytes)",
                view.index(),
                view.offset(),
                view.length(),
                view.buffer().index(),
                buffer.len()
            )
        })
}

/// Read every image of `doc` (encoded bytes, never decoded here).
pub(super) fn load_images(
    ctx: &mut Ctx,
    doc: &::gltf::Document,
    buffers: &[Vec<u8>],
) -> Result<Vec<scene::Image>> {
    let mut images = Vec::new();
    for image in doc.images() {
        let at = format!("/images/{}", image.index());
        let bytes = match image.source() {
            ::gltf::image::Source::View { view, .. } => view_bytes(buffers, &view)
                .map_err(|m| ctx.err(&at, m))?
                .to_vec(),
            ::gltf::image::Source::Uri { uri, .. } => read_uri(ctx, uri, &at, "image")?,
        };
        let mime_type = sniff_mime(&bytes)
            .ok_or_else(|| ctx.err(&at, "the image is neither PNG nor JPEG"))?
            .to_owned();
        images.push(scene::Image {
            name: image.name().map(str::to_owned),
            mime_type,
            bytes,
        });
    }
    Ok(images)
}
