"""Luminous openings of a bake's luminaires, to draw them (no bpy here).

Input: a node's `EXT_lights_ies` / `LUXBAKE_luminaire` objects and its profile's bytes. Output:
(length along C0, width along C90) in metres — `LUXBAKE_luminaire.opening` when given, else the
profile's own: IES LM-63 width and length (TILT=NONE files; feet or metres), EULUMDAT luminous
area length/diameter and width (lines 16 and 17, mm; width 0 means round). None when unknown.
As `bake view` does, the opening is drawn at the node, facing its −Z (the nadir).
"""


def from_ies(data):
    lines = data.decode("latin-1").splitlines()
    tilt = next((i for i, line in enumerate(lines) if line.strip().upper().startswith("TILT=")), None)
    if tilt is None or lines[tilt].strip().upper() != "TILT=NONE":
        return None
    numbers = " ".join(lines[tilt + 1:]).replace(",", " ").split()
    if len(numbers) < 10:
        return None
    units, width, length = int(float(numbers[6])), abs(float(numbers[7])), abs(float(numbers[8]))
    scale = 0.3048 if units == 1 else 1.0
    return length * scale, width * scale


def from_ldt(data):
    lines = data.decode("latin-1").splitlines()
    if len(lines) < 17:
        return None
    length = float(lines[15].replace(",", ".")) / 1000.0
    width = float(lines[16].replace(",", ".")) / 1000.0
    return length, width


def opening(node_extensions, profile_bytes, mime):
    """(length, width) in m of a luminaire node's opening, or None."""
    lum = node_extensions.get("LUXBAKE_luminaire") or {}
    if "opening" in lum:
        return float(lum["opening"].get("length", 0.0)), float(lum["opening"].get("width", 0.0))
    if profile_bytes is None:
        return None
    try:
        return from_ldt(profile_bytes) if "eulumdat" in (mime or "") else from_ies(profile_bytes)
    except (ValueError, IndexError):
        return None
