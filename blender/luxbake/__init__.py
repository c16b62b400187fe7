"""LuxBake for Blender: author photometric scenes for luxbake's radiosity baker, bake them, and
bring the bakes back.

An extension (Blender 4.2+, `blender_manifest.toml`) built on the glTF exporter's and importer's
user-extension hooks: io_scene_gltf2 looks up `glTF2ExportUserExtension` and
`glTF2ImportUserExtension` in the module of every enabled add-on, so both are exposed here.
Modules: props (properties), units (W → cd/lx), export_hooks, import_hooks (a bake made
readable: shading, probes), shading (display and false-colour materials), run (the `bake`
command line), operators, ui.
"""

from . import export_hooks, import_hooks, operators, props, ui

glTF2ExportUserExtension = export_hooks.glTF2ExportUserExtension
glTF2ImportUserExtension = import_hooks.glTF2ImportUserExtension
glTF2_post_export_callback = export_hooks.post_export_callback

_MODULES = (props, operators, ui)


def register():
    for module in _MODULES:
        module.register()


def unregister():
    for module in reversed(_MODULES):
        module.unregister()
