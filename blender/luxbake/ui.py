"""Panels: LuxBake in the Material, Object and Scene properties, and in the 3D view's sidebar
(bake, display switch with its legend range, the active probe's results)."""

import bpy


def draw_material(layout, material):
    s = material.luxbake_settings
    layout.prop(s, "reflectance_mode")
    if s.reflectance_mode == "VALUE":
        layout.prop(s, "reflectance")
    elif s.reflectance_mode == "RGB":
        layout.prop(s, "reflectance_rgb")
    layout.prop(s, "emission_mode")
    if s.emission_mode == "LUMINANCE":
        layout.prop(s, "luminance")
    elif s.emission_mode == "FLUX":
        layout.prop(s, "flux")
    if s.emission_mode != "NONE":
        layout.prop(s, "emission_color")


def draw_object(layout, obj):
    s = obj.luxbake_settings
    layout.prop(s, "node_name")
    if obj.type == "EMPTY":
        layout.prop(s, "probe")
        if s.probe:
            layout.prop(s, "probe_aligned")
            row = layout.row()
            row.prop(s, "use_toward")
            if s.use_toward:
                row.prop(s, "toward", text="")
    if obj.type in {"EMPTY", "LIGHT"}:
        layout.prop(s, "profile")
        if s.profile:
            layout.prop(s, "multiplier")
            layout.prop(s, "color")
            layout.prop(s, "maintenance_factor")
            layout.prop(s, "use_opening")
            if s.use_opening:
                layout.prop(s, "opening")
    if obj.type == "LIGHT" and not s.profile and obj.data.type in {"POINT", "SPOT", "SUN"}:
        layout.prop(s, "use_photometric")
        if s.use_photometric:
            layout.prop(s, "illuminance" if obj.data.type == "SUN" else "intensity")
        else:
            from . import units
            if obj.data.type == "SUN":
                value = f"{units.sun_illuminance_lx(obj.data.energy, obj.data.exposure):.4g} lx"
            else:
                value = f"{units.point_intensity_cd(obj.data.energy, obj.data.exposure):.4g} cd"
            layout.label(text=f"Exported as {value} (683 lm/W)")


def draw_results(layout, obj):
    keys = [k for k in obj.keys() if k.endswith("_lx") or k.endswith("_deg") or k == "vector_scalar_ratio"]
    if not keys:
        return
    col = layout.column(align=True)
    col.label(text=f"Probe {obj.name}")
    for key in keys:
        col.label(text=f"{key}: {obj[key]:.1f}")


def draw_scene(layout, context):
    s = context.scene.luxbake_settings
    layout.prop(s, "quality")
    row = layout.row()
    row.prop(s, "use_working_plane")
    sub = row.row()
    sub.enabled = s.use_working_plane
    sub.prop(s, "working_plane_height")
    sub.prop(s, "working_plane_spacing")
    layout.prop(s, "lightmaps")
    layout.prop(s, "probe_glyphs")
    layout.prop(s, "output_dir")
    layout.prop(s, "extra_args")
    layout.operator("luxbake.bake", icon="LIGHT")
    if s.status:
        layout.label(text=s.status)
    draw_display(layout, context)


def draw_display(layout, context):
    s = context.scene.luxbake_settings
    box = layout.box()
    box.prop(s, "display")
    if s.display != "DISPLAY":
        row = box.row(align=True)
        row.prop(s, "range_min")
        row.prop(s, "range_max")
        row = box.row()
        row.prop(s, "log_scale")
        row.operator("luxbake.fit_range")
        group = bpy.data.node_groups.get("LuxBake display")
        if group is not None and "palette" in group.nodes:
            box.template_color_ramp(group.nodes["palette"], "color_ramp")
            unit = "cd/m²" if s.display == "LUMINANCE" else "lx"
            box.label(text=f"{s.range_min:.4g} … {s.range_max:.4g} {unit}")


class LUXBAKE_PT_material(bpy.types.Panel):
    bl_label = "LuxBake"
    bl_space_type = "PROPERTIES"
    bl_region_type = "WINDOW"
    bl_context = "material"

    @classmethod
    def poll(cls, context):
        return context.material is not None

    def draw(self, context):
        draw_material(self.layout, context.material)


class LUXBAKE_PT_object(bpy.types.Panel):
    bl_label = "LuxBake"
    bl_space_type = "PROPERTIES"
    bl_region_type = "WINDOW"
    bl_context = "object"

    @classmethod
    def poll(cls, context):
        return context.object is not None

    def draw(self, context):
        draw_object(self.layout, context.object)
        draw_results(self.layout, context.object)


class LUXBAKE_PT_scene(bpy.types.Panel):
    bl_label = "LuxBake"
    bl_space_type = "PROPERTIES"
    bl_region_type = "WINDOW"
    bl_context = "scene"

    def draw(self, context):
        draw_scene(self.layout, context)


class LUXBAKE_PT_sidebar(bpy.types.Panel):
    bl_label = "LuxBake"
    bl_space_type = "VIEW_3D"
    bl_region_type = "UI"
    bl_category = "LuxBake"

    def draw(self, context):
        layout = self.layout
        layout.operator("luxbake.bake", icon="LIGHT")
        s = context.scene.luxbake_settings
        if s.status:
            layout.label(text=s.status)
        draw_display(layout, context)
        if context.object is not None:
            draw_results(layout, context.object)


CLASSES = (LUXBAKE_PT_material, LUXBAKE_PT_object, LUXBAKE_PT_scene, LUXBAKE_PT_sidebar)


# Blender's own helper: registers in order, unregisters in reverse.
register, unregister = bpy.utils.register_classes_factory(CLASSES)
