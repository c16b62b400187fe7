"""Blender's artist light units to the photometric units luxbake reads (no bpy here).

Blender gives point and spot lights a radiant power P in W (a spot as if it were a point light:
its cone cuts light, it does not concentrate it) and a sun an irradiance S in W/m². luxbake reads
KHR_lights_punctual intensities in cd (point, spot) and lx (directional). The add-on converts as
the glTF exporter's "Standard" lighting mode does (io_scene_gltf2 `lights.py`, its
PBR_WATTS_TO_LUMENS = 683 lm/W, the luminous efficacy of 555 nm light), whatever lighting mode the
export is run with:

    point, spot:  I = P · 683 / (4π) · 2^exposure   cd
    sun:          E = S · 683 · 2^exposure          lx

A light's LuxBake panel can instead give the photometric value directly (cd or lx); then that
value is written as is.
"""

import math

LUMENS_PER_WATT = 683.0


def point_intensity_cd(power_w, exposure=0.0):
    """Luminous intensity (cd) of a Blender point or spot light of power `power_w` (W)."""
    return power_w * LUMENS_PER_WATT / (4.0 * math.pi) * 2.0 ** exposure


def sun_illuminance_lx(strength_w_m2, exposure=0.0):
    """Illuminance (lx) of a Blender sun of strength `strength_w_m2` (W/m²)."""
    return strength_w_m2 * LUMENS_PER_WATT * 2.0 ** exposure


def blender_to_gltf(v):
    """A direction or point in Blender's axes (+Z up) in glTF's (+Y up): (x, y, z) → (x, z, −y)."""
    x, y, z = v
    return [x, z, -y]
