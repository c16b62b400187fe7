"""The glTF exporter's user-extension hooks (io_scene_gltf2 finds `glTF2ExportUserExtension` in
every enabled add-on's module and calls its `gather_*_hook` methods during an export).

Inputs: the LuxBake properties of materials, objects and lights (props.py). Outputs, in the
exported glTF (+Y up, metres):
- materials: `LUXBAKE_material` {reflectance, emission {luminance | luminousFlux, color}}; a
  reflectance given as a value or colour is also the core `baseColorFactor` (no texture);
- luminaires (a profile on an Empty, or on a Light): `EXT_lights_ies` (IES files, listed at the
  root `EXT_lights_ies.lights`) or `LUXBAKE_luminaire` {profile} (EULUMDAT files, root
  `LUXBAKE_luminaire.profiles`), with multiplier, colour, maintenance factor and opening; each
  profile file is copied beside the glTF and referenced by a relative `uri`;
- punctual lights: `KHR_lights_punctual` intensity in cd (point, spot) or lx (sun), see units.py;
- probes: node `extras.probe` (`true` or `{"aligned": true}`) and `extras.toward`;
- node names: an object's `node_name` when set (glTF names need not be unique, Blender's are).
Invariants: every extension is in `extensionsUsed` only (never required); a profile file is
never overwritten: a different file of the same name already in the folder gets a new name.
The hooks are called with the exporter's `export_settings` as their last argument; an error in
one (a missing profile file) fails the export with a message naming the object, not silently.
"""

import contextlib
import filecmp
import math
import os
import shutil
from urllib.parse import quote

import bpy

from . import units

# glTF rotation [x, y, z, w] turning a child node's −Z onto its parent's −Y: an Empty's local −Z
# in Blender becomes its node's −Y when the exporter converts to +Y up (it turns only lights and
# cameras), so a luminaire on an Empty gets a child node with this rotation.
EMPTY_TO_PHOTOMETRIC = [-math.sqrt(0.5), 0.0, 0.0, math.sqrt(0.5)]

MIME = {".ies": "application/x-ies-lm-63", ".ldt": "application/x-eulumdat"}


def material_extension(settings):
    """The `LUXBAKE_material` object of a material's LuxBake settings, or None when it adds
    nothing to the core glTF material."""
    ext = {}
    if settings.reflectance_mode == "VALUE":
        ext["reflectance"] = round(float(settings.reflectance), 6)
    elif settings.reflectance_mode == "RGB":
        ext["reflectance"] = [round(float(c), 6) for c in settings.reflectance_rgb]
    if settings.emission_mode != "NONE":
        emission = {}
        if settings.emission_mode == "LUMINANCE":
            emission["luminance"] = float(settings.luminance)
        else:
            emission["luminousFlux"] = float(settings.flux)
        color = [round(float(c), 6) for c in settings.emission_color]
        if color != [1.0, 1.0, 1.0]:
            emission["color"] = color
        ext["emission"] = emission
    return ext or None


def show_reflectance(gltf2_material, reflectance):
    """A given reflectance becomes the core material's base colour too (when it has no base
    colour texture), so viewers — and the bake's display colours, base colour × COLOR_0 — show
    the surface as luxbake reflects light, not Blender's default grey 0.8."""
    pbr = gltf2_material.pbr_metallic_roughness
    if reflectance is None or pbr is None or pbr.base_color_texture is not None:
        return
    rgb = [reflectance] * 3 if isinstance(reflectance, float) else list(reflectance)
    alpha = pbr.base_color_factor[3] if pbr.base_color_factor else 1.0
    pbr.base_color_factor = [*rgb, alpha]


def luminaire_fields(settings):
    """Multiplier, colour, maintenance factor and opening of a luminaire, as glTF members."""
    fields = {"multiplier": float(settings.multiplier),
              "color": [round(float(c), 6) for c in settings.color]}
    extra = {}
    if settings.maintenance_factor != 1.0:
        extra["maintenanceFactor"] = round(float(settings.maintenance_factor), 6)
    if settings.use_opening:
        length, width, height = (round(float(c), 6) for c in settings.opening)
        extra["opening"] = {"length": length, "width": width, "height": height}
    return fields, extra


ERRORS = "luxbake_errors"


@contextlib.contextmanager
def collect_errors(export_settings, what):
    """The exporter logs and ignores a hook's exception; keep it so that
    `post_export_callback` can stop the export before any file is written."""
    try:
        yield
    except Exception as error:  # every failure of a hook, reported by post_export_callback
        export_settings.setdefault(ERRORS, []).append(f"LuxBake: {what}: {error}")


def post_export_callback(export_settings):
    """Module-level `glTF2_post_export_callback`: runs before the exporter writes its files,
    outside its try blocks, so raising here fails the export with LuxBake's messages."""
    errors = export_settings.get(ERRORS)
    if errors:
        raise RuntimeError("; ".join(errors))


class glTF2ExportUserExtension:
    def __init__(self):
        from io_scene_gltf2.io.com.gltf2_io_extensions import Extension

        self.Extension = Extension
        self.profiles = {".ies": [], ".ldt": []}  # absolute source paths, in order of first use

    def _ext(self, name, value):
        return self.Extension(name=name, extension=value, required=False)

    def _profile_index(self, path):
        kind = os.path.splitext(path)[1].lower()
        if kind not in MIME:
            raise ValueError(f"luminaire profile {path}: not an .ies or .ldt file")
        if not os.path.isfile(path):
            raise FileNotFoundError(f"luminaire profile {path}: no such file")
        paths = self.profiles[kind]
        if path not in paths:
            paths.append(path)
        return kind, paths.index(path)

    def pre_export_hook(self, export_settings):
        # The exporter drops Light objects unless Include › Punctual Lights is on: a luminaire
        # profile on a Light would vanish without a word.
        if export_settings.get("gltf_lights"):
            return
        for obj in bpy.context.scene.objects:
            if obj.type == "LIGHT" and obj.luxbake_settings.profile:
                export_settings.setdefault(ERRORS, []).append(
                    f"LuxBake: light {obj.name} carries a luminaire profile: enable the export's "
                    "Include › Punctual Lights (the Bake operator does)")

    def gather_material_hook(self, gltf2_material, blender_material, export_settings):
        with collect_errors(export_settings, f"material {getattr(blender_material, 'name', '?')}"):
            self._material(gltf2_material, blender_material)

    def gather_node_hook(self, gltf2_node, blender_object, export_settings):
        with collect_errors(export_settings, f"object {getattr(blender_object, 'name', '?')}"):
            self._node(export_settings, gltf2_node, blender_object)

    def gather_node_name_hook(self, gltf_hook_name, blender_object, export_settings):
        with collect_errors(export_settings, f"object {getattr(blender_object, 'name', '?')}"):
            if blender_object is not None and blender_object.luxbake_settings.node_name:
                gltf_hook_name.name = blender_object.luxbake_settings.node_name

    def gather_gltf_extensions_hook(self, gltf, export_settings):
        with collect_errors(export_settings, "profiles"):
            self._root(export_settings, gltf)

    def _material(self, gltf2_material, blender_material):
        if blender_material is None:
            return
        ext = material_extension(blender_material.luxbake_settings)
        if ext is None:
            return
        if gltf2_material.extensions is None:
            gltf2_material.extensions = {}
        gltf2_material.extensions["LUXBAKE_material"] = self._ext("LUXBAKE_material", ext)
        show_reflectance(gltf2_material, ext.get("reflectance"))

    def _node(self, export_settings, gltf2_node, blender_object):
        if blender_object is None:
            return
        settings = blender_object.luxbake_settings
        if (settings.probe or blender_object.get("probe")) and blender_object.type == "EMPTY":
            extras = dict(gltf2_node.extras or {})
            extras["probe"] = {"aligned": True} if settings.probe_aligned else True
            if settings.use_toward:
                extras["toward"] = [round(c, 6) for c in units.blender_to_gltf(settings.toward)]
            gltf2_node.extras = extras
        exts = gltf2_node.extensions if gltf2_node.extensions is not None else {}
        profile = bpy.path.abspath(settings.profile) if settings.profile else ""
        is_light = blender_object.type == "LIGHT"
        if profile:
            # A light's node already looks down the light's −Z (the exporter turns light nodes);
            # any other object gets a child node turned so.
            turned = is_light and export_settings.get("gltf_lights") and export_settings.get("gltf_yup")
            exts.pop("KHR_lights_punctual", None)
            target = self._luminaire_extensions(os.path.normpath(profile), settings)
            if turned:
                exts.update(target)
            else:
                self._add_child(export_settings, gltf2_node, blender_object.name, target)
        elif is_light and "KHR_lights_punctual" in exts:
            light = exts["KHR_lights_punctual"].extension["light"].extension
            light["intensity"] = self._light_value(blender_object.data, settings)
        gltf2_node.extensions = exts or None

    def _light_value(self, lamp, settings):
        if lamp.type == "SUN":
            if settings.use_photometric:
                return float(settings.illuminance)
            return units.sun_illuminance_lx(lamp.energy, lamp.exposure)
        if settings.use_photometric:
            return float(settings.intensity)
        return units.point_intensity_cd(lamp.energy, lamp.exposure)

    def _luminaire_extensions(self, profile, settings):
        kind, index = self._profile_index(profile)
        fields, extra = luminaire_fields(settings)
        if kind == ".ies":
            out = {"EXT_lights_ies": self._ext("EXT_lights_ies", {"light": index, **fields})}
            if extra:
                out["LUXBAKE_luminaire"] = self._ext("LUXBAKE_luminaire", extra)
            return out
        return {"LUXBAKE_luminaire": self._ext(
            "LUXBAKE_luminaire", {"profile": index, **fields, **extra})}

    def _add_child(self, export_settings, gltf2_node, name, extensions):
        from io_scene_gltf2.io.com import gltf2_io

        rotation = EMPTY_TO_PHOTOMETRIC if export_settings.get("gltf_yup", True) else None
        child = gltf2_io.Node(
            camera=None, children=[], extensions=extensions, extras=None, matrix=None,
            mesh=None, name=f"{name}.luminaire", rotation=rotation, scale=None, skin=None,
            translation=None, weights=None)
        if gltf2_node.children is None:
            gltf2_node.children = []
        gltf2_node.children.append(child)

    def _root(self, export_settings, gltf):
        if not any(self.profiles.values()):
            return
        folder = export_settings["gltf_filedirectory"]
        used = set()
        if gltf.extensions is None:
            gltf.extensions = {}
        for kind, root, key in ((".ies", "EXT_lights_ies", "lights"),
                                (".ldt", "LUXBAKE_luminaire", "profiles")):
            items = []
            for path in self.profiles[kind]:
                uri = copy_beside(path, folder, used)
                items.append({"uri": quote(uri), "name": os.path.splitext(os.path.basename(path))[0]})
            if items:
                gltf.extensions[root] = self._ext(root, {key: items})


def copy_beside(path, folder, used):
    """Copy the profile `path` into `folder` (unless it is already there) and return its file
    name there. A name in `used` or a different file already of that name gets a suffix."""
    base, ext = os.path.splitext(os.path.basename(path))
    n = 1
    while True:
        name = f"{base}{ext}" if n == 1 else f"{base}_{n}{ext}"
        target = os.path.join(folder, name)
        n += 1
        if name in used:
            continue
        if os.path.exists(target):
            same_file = os.path.samefile(path, target)
            if not same_file and not filecmp.cmp(path, target, shallow=False):
                continue
        else:
            shutil.copyfile(path, target)
        used.add(name)
        return name
