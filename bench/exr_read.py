"""Read the single-part, scan-line, uncompressed OpenEXR files luxbake writes (lightmap atlases,
view images): every channel as a list of rows, float. Python standard library only; refuses any
other layout (compressed, tiled, multi-part) with a message instead of guessing."""

import struct

_TYPES = {0: ("I", 4), 1: ("e", 2), 2: ("f", 4)}


def read(path):
    """{"width", "height", "channels": {name: [[value] * width] * height}, "attributes": {...}}
    with row 0 the top of the image (the file's first scan line)."""
    data = open(path, "rb").read()
    if data[:4] != b"\x76\x2f\x31\x01":
        raise ValueError(f"{path}: not an OpenEXR file")
    if struct.unpack_from("<I", data, 4)[0] & 0x1600:
        raise ValueError(f"{path}: tiled, deep or multi-part: not read here")
    pos, header = 8, {}
    while data[pos] != 0:
        name, pos = _string(data, pos)
        kind, pos = _string(data, pos)
        size = struct.unpack_from("<i", data, pos)[0]
        header[name] = (kind, data[pos + 4:pos + 4 + size])
        pos += 4 + size
    pos += 1
    if header["compression"][1] != b"\x00":
        raise ValueError(f"{path}: compressed: not read here")
    x0, y0, x1, y1 = struct.unpack("<4i", header["dataWindow"][1])
    width, height = x1 - x0 + 1, y1 - y0 + 1
    channels, raw, p = [], header["channels"][1], 0
    while raw[p] != 0:
        name, p = _string(raw, p)
        ptype = struct.unpack_from("<i", raw, p)[0]
        channels.append((name, ptype))
        p += 16
    pos += 8 * height  # the offset table: scan lines follow in order
    out = {name: [] for name, _ in channels}
    for _ in range(height):
        pos += 8  # y, byte count
        for name, ptype in channels:
            code, size = _TYPES[ptype]
            out[name].append(list(struct.unpack_from(f"<{width}{code}", data, pos)))
            pos += size * width
    attributes = {k: v[1].decode("latin-1") for k, v in header.items() if v[0] == "string"}
    return {"width": width, "height": height, "channels": out, "attributes": attributes}


def _string(data, pos):
    end = data.index(b"\x00", pos)
    return data[pos:end].decode("latin-1"), end + 1
