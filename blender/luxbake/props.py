"""LuxBake's properties: per material (photometric reflectance and emission), per object
(luminaire profile, probe, photometric light value), per scene (working plane, bake settings,
display of a bake) and the add-on's preferences (where `bake` is). They live under
`luxbake_settings` (`material.luxbake_settings` …): the name `luxbake` is the custom property
Blender's glTF importer makes of a bake's `extras.luxbake`.

Inputs: what the user sets in the panels (ui.py). Outputs: read by the export hooks
(export_hooks.py), the bake operator (operators.py) and the display switch (shading.py).
Units: SI and photometric (m, cd/m², lm, cd, lx); Blender's axes (+Z up) until export.
"""

import bpy
from bpy.props import (
    BoolProperty,
    EnumProperty,
    FloatProperty,
    FloatVectorProperty,
    PointerProperty,
    StringProperty,
)


class LuxbakeMaterial(bpy.types.PropertyGroup):
    reflectance_mode: EnumProperty(
        name="Reflectance",
        items=[
            ("BASE_COLOR", "From base colour",
             "luxbake's rule: base colour × mean of its texture × (1 − metallic), from the "
             "exported glTF material"),
            ("VALUE", "Value", "One diffuse reflectance for all three channels"),
            ("RGB", "Colour", "A linear RGB diffuse reflectance"),
        ],
        default="BASE_COLOR",
    )
    reflectance: FloatProperty(
        name="Reflectance", min=0.0, max=0.99, default=0.5,
        description="Linear diffuse reflectance, below 1")
    reflectance_rgb: FloatVectorProperty(
        name="Reflectance", subtype="COLOR", size=3, min=0.0, max=0.99,
        default=(0.5, 0.5, 0.5), description="Linear RGB diffuse reflectance, each below 1")
    emission_mode: EnumProperty(
        name="Emission",
        items=[
            ("NONE", "None", "The material emits no light (or what its glTF emission says)"),
            ("LUMINANCE", "Luminance", "Luminance of every emitting face, cd/m²"),
            ("FLUX", "Flux", "Luminous flux shared by all faces of the material by area, lm"),
        ],
        default="NONE",
    )
    luminance: FloatProperty(
        name="Luminance (cd/m²)", min=0.0, default=1000.0, soft_max=1e5,
        description="Luminance of each emitting face, cd/m²")
    flux: FloatProperty(
        name="Flux (lm)", min=0.0, default=1000.0, soft_max=1e5,
        description="Luminous flux of all faces using the material, lm")
    emission_color: FloatVectorProperty(
        name="Colour", subtype="COLOR", size=3, min=0.0, max=1.0, default=(1.0, 1.0, 1.0),
        description="Relative colour of the emitted light (normalised to luminance 1 by luxbake)")


class LuxbakeObject(bpy.types.PropertyGroup):
    node_name: StringProperty(
        name="glTF node name", default="",
        description="Name of the object's glTF node (empty: the object's name). Blender's names "
                    "are unique, glTF's need not be: two desks may both have a child `top`, "
                    "and luxbake names surfaces by node path (desk_dark/top)")
    # luminaire (on an Empty or a Light): a measured profile
    profile: StringProperty(
        name="Profile", subtype="FILE_PATH", options={"PATH_SUPPORTS_BLEND_RELATIVE"},
        description="IES LM-63 (.ies) or EULUMDAT (.ldt) file; its nadir points down the "
                    "object's local −Z, C0 along its local +X")
    multiplier: FloatProperty(name="Multiplier", min=0.0, default=1.0,
                              description="Scales the profile's intensities")
    color: FloatVectorProperty(name="Colour", subtype="COLOR", size=3, min=0.0, max=1.0,
                               default=(1.0, 1.0, 1.0), description="Light colour (tint)")
    maintenance_factor: FloatProperty(
        name="Maintenance factor", min=0.001, max=1.0, default=1.0,
        description="Light loss over the installation's life, in (0, 1]")
    use_opening: BoolProperty(
        name="Luminous opening", default=False,
        description="Give the luminous opening (else the profile's own dimensions are used)")
    opening: FloatVectorProperty(
        name="Opening", subtype="XYZ", size=3, min=0.0, default=(0.6, 0.6, 0.0), unit="LENGTH",
        description="Length along C0 (local X), width along C90 (local Y), height, m")
    # punctual lights: a photometric value instead of Blender's W
    use_photometric: BoolProperty(
        name="Photometric value", default=False,
        description="Give the light's intensity (cd) or a sun's illuminance (lx) directly "
                    "instead of converting Blender's W at 683 lm/W")
    intensity: FloatProperty(name="Intensity (cd)", min=0.0, default=100.0,
                             description="Luminous intensity of a point or spot light, cd")
    illuminance: FloatProperty(name="Illuminance (lx)", min=0.0, default=10000.0,
                               description="Illuminance of a sun light, lx")
    # probes (Empties)
    probe: BoolProperty(name="Probe", default=False,
                        description="Measure cubic illuminance at this Empty (extras.probe)")
    probe_aligned: BoolProperty(
        name="World aligned", default=False,
        description="Keep the probe's cube aligned with the world instead of the Empty")
    use_toward: BoolProperty(name="Toward", default=False,
                             description="Also report a semi-cylindrical value toward a direction")
    toward: FloatVectorProperty(name="Direction", subtype="DIRECTION", size=3,
                                default=(1.0, 0.0, 0.0),
                                description="Direction in world axes (Blender's, +Z up)")


def _display_update(self, context):
    from . import shading
    shading.apply_display(self.id_data)  # the scene these settings belong to


class LuxbakeScene(bpy.types.PropertyGroup):
    use_working_plane: BoolProperty(
        name="Working plane", default=False,
        description="Bake a working plane of probes (bake --working-plane)")
    working_plane_height: FloatProperty(
        name="Height", min=0.0, default=0.8, unit="LENGTH",
        description="Height of the working plane above the floor, m")
    working_plane_spacing: FloatProperty(
        name="Spacing", min=0.01, default=0.25, unit="LENGTH",
        description="Grid spacing of the working plane, m")
    quality: EnumProperty(
        name="Quality",
        items=[("draft", "Draft", ""), ("default", "Default", ""), ("high", "High", "")],
        default="default")
    lightmaps: BoolProperty(name="Lightmaps", default=False,
                            description="Also bake lightmaps (bake --lightmaps)")
    probe_glyphs: BoolProperty(name="Probe glyphs", default=True,
                               description="Draw each probe's illumination solid (--probe-glyphs)")
    output_dir: StringProperty(
        name="Output folder", subtype="DIR_PATH", default="//luxbake",
        options={"PATH_SUPPORTS_BLEND_RELATIVE"},
        description="Where the exported scene and the bake are written")
    extra_args: StringProperty(name="More options", default="",
                               description="Further bake options, as on the command line")
    # display of an imported bake
    display: EnumProperty(
        name="Show",
        items=[
            ("DISPLAY", "Display colours", "What an unlit glTF viewer shows: base colour × COLOR_0, "
                                           "or the lightmap's display texture"),
            ("ILLUMINANCE", "Illuminance (lx)", "False colour of _ILLUMINANCE"),
            ("LUMINANCE", "Luminance (cd/m²)", "False colour of _LUMINANCE"),
        ],
        default="DISPLAY", update=_display_update)
    range_min: FloatProperty(name="Min", default=0.0, update=_display_update,
                             description="Value shown at the bottom of the false-colour scale")
    range_max: FloatProperty(name="Max", default=1000.0, update=_display_update,
                             description="Value shown at the top of the false-colour scale")
    log_scale: BoolProperty(name="Logarithmic", default=False, update=_display_update,
                            description="Logarithmic false-colour scale (min must be above 0)")
    status: StringProperty(name="Status", default="")


class LuxbakePreferences(bpy.types.AddonPreferences):
    bl_idname = __package__

    bake_path: StringProperty(
        name="bake executable", subtype="FILE_PATH", default="",
        description="Path of luxbake's `bake` binary; empty: `bake` on PATH")

    def draw(self, context):
        self.layout.prop(self, "bake_path")


CLASSES = (LuxbakeMaterial, LuxbakeObject, LuxbakeScene, LuxbakePreferences)


def register():
    for cls in CLASSES:
        bpy.utils.register_class(cls)
    bpy.types.Material.luxbake_settings = PointerProperty(type=LuxbakeMaterial)
    bpy.types.Object.luxbake_settings = PointerProperty(type=LuxbakeObject)
    bpy.types.Scene.luxbake_settings = PointerProperty(type=LuxbakeScene)


def unregister():
    del bpy.types.Scene.luxbake_settings
    del bpy.types.Object.luxbake_settings
    del bpy.types.Material.luxbake_settings
    for cls in reversed(CLASSES):
        bpy.utils.unregister_class(cls)
