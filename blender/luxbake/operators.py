"""Operators: export the scene for luxbake, bake it with the `bake` binary, import a bake.

`luxbake.bake` exports the scene (glTF + profiles, through the export hooks) into the scene's
output folder as `<name>.gltf`, runs `bake <name>.gltf -o <name>-lit.gltf` with the scene's
settings, and imports the result (the import hooks set it up) into a scene of its own,
`<name>-lit`, which the window then shows (a later bake replaces that scene). Run from the UI (invoke) it works
in the background: a timer polls bake, the status bar and the scene's status show bake's latest
stderr line and the elapsed time, Esc cancels; a failed bake reports bake's error line. Run as
`bpy.ops.luxbake.bake()` from a script (exec) it waits for bake. The authoring scene is left as
it was (its objects, colour management and world).
"""

import os
import time

import bpy

from . import run

EXPORT_OPTIONS = dict(
    export_format="GLTF_SEPARATE",
    export_yup=True,               # glTF's +Y up, as luxbake reads it
    export_apply=True,             # modifiers applied
    export_lights=True,            # KHR_lights_punctual (intensity rewritten in cd / lx)
    export_cameras=True,
    export_extras=False,           # probes come from the LuxBake panel (or a `probe` property)
    export_import_convert_lighting_mode="SPEC",
    use_renderable=True,           # what renders: not helpers, not imported bakes
    use_active_scene=True,         # this scene alone, not the bakes' scenes
)


def bake_collections():
    """Collections holding imported bakes (tagged by import_bake) and their children."""
    found = []
    for collection in bpy.data.collections:
        if collection.get("luxbake_bake"):
            found.append(collection)
            found.extend(collection.children_recursive)
    return found


def export_scene(filepath, **options):
    """Export the current scene as glTF for luxbake (the hooks add the photometric data).
    Only what renders is exported (`use_renderable`): imported bakes are switched off for
    rendering meanwhile, so a second bake does not bake the first one's result."""
    kwargs = dict(EXPORT_OPTIONS)
    kwargs.update(options)
    hidden = [c for c in bake_collections() if not c.hide_render]
    for collection in hidden:
        collection.hide_render = True
    try:
        result = bpy.ops.export_scene.gltf(filepath=filepath, **kwargs)
    finally:
        for collection in hidden:
            collection.hide_render = False
    if "FINISHED" not in result:
        raise RuntimeError(f"glTF export to {filepath} failed: {result}")


def remove_collection(collection):
    """A collection, its objects and its child collections, gone."""
    for obj in list(collection.all_objects):
        bpy.data.objects.remove(obj)
    for child in list(collection.children_recursive):
        bpy.data.collections.remove(child)
    bpy.data.collections.remove(collection)


def import_bake(filepath, scene_name=None):
    """Import a bake into a collection of its own, named after the file and tagged
    `luxbake_bake` (the import hooks set up its display); a bake collection of that name from an
    earlier import is replaced. With `scene_name`, into that scene (made, or emptied and made
    anew), so the bake never lies over the objects it was baked from. Returns the collection."""
    name = os.path.splitext(os.path.basename(filepath))[0]
    if scene_name is not None:
        old_scene = bpy.data.scenes.get(scene_name)
        if old_scene is not None and old_scene.get("luxbake_bake"):
            for obj in list(old_scene.objects):
                bpy.data.objects.remove(obj)
            for child in list(old_scene.collection.children_recursive):
                bpy.data.collections.remove(child)
            bpy.data.scenes.remove(old_scene)
        scene = bpy.data.scenes.new(scene_name)
        scene["luxbake_bake"] = True
    else:
        scene = bpy.context.scene
    old = bpy.data.collections.get(name)
    if old is not None and old.get("luxbake_bake"):
        remove_collection(old)
    collection = bpy.data.collections.new(name)
    collection["luxbake_bake"] = True
    scene.collection.children.link(collection)
    view_layer = scene.view_layers[0] if scene_name is not None else bpy.context.view_layer
    view_layer.active_layer_collection = view_layer.layer_collection.children[collection.name]
    with bpy.context.temp_override(scene=scene, view_layer=view_layer):
        result = bpy.ops.import_scene.gltf(filepath=filepath)
    if "FINISHED" not in result:
        raise RuntimeError(f"glTF import of {filepath} failed: {result}")
    cameras = [o for o in collection.all_objects if o.type == "CAMERA"]
    if scene.camera is None and cameras:
        scene.camera = cameras[0]
    return collection


def bake_paths(context):
    s = context.scene.luxbake_settings
    folder = bpy.path.abspath(s.output_dir) if s.output_dir else ""
    if not folder or folder.startswith("//"):
        raise run.BakeError("set an output folder (save the .blend file first for a relative one)")
    os.makedirs(folder, exist_ok=True)
    stem = bpy.path.clean_name(bpy.path.display_name_from_filepath(bpy.data.filepath) or "scene")
    return os.path.join(folder, stem + ".gltf"), os.path.join(folder, stem + "-lit.gltf")


def bake_command(context, scene_path, output_path):
    s = context.scene.luxbake_settings
    prefs = context.preferences.addons[__package__].preferences
    return run.command(
        run.find_bake(prefs.bake_path), scene_path, output_path, quality=s.quality,
        working_plane=s.working_plane_height if s.use_working_plane else None,
        spacing=s.working_plane_spacing if s.use_working_plane else None,
        lightmaps=s.lightmaps, probe_glyphs=s.probe_glyphs, extra=s.extra_args)


def message(error):
    """One line for the user: an export failure arrives as Blender's whole Python traceback,
    whose last line is `RuntimeError: LuxBake: object …: …`."""
    lines = [line.strip() for line in str(error).strip().splitlines() if line.strip()]
    for line in reversed(lines):
        if line.startswith("RuntimeError: "):
            return line[len("RuntimeError: "):]
    return lines[0] if lines else repr(error)


class LUXBAKE_OT_bake(bpy.types.Operator):
    """Export the scene for luxbake, bake it and import the result"""

    bl_idname = "luxbake.bake"
    bl_label = "Bake with luxbake"
    bl_options = {"REGISTER"}

    _timer = None
    _run = None

    def _start(self, context):
        if context.scene.get("luxbake_bake"):
            raise run.BakeError(f"scene {context.scene.name} holds a bake: bake from the scene it "
                                "was made from")
        self._scene = context.scene  # the authoring scene, whatever the window shows meanwhile
        scene_path, self._output = bake_paths(context)
        args = bake_command(context, scene_path, self._output)  # finds bake before exporting
        context.scene.luxbake_settings.status = "exporting"
        export_scene(scene_path)
        context.scene.luxbake_settings.status = "baking"
        self._started = time.monotonic()
        self._run = run.Run(args)

    def _finish(self, context, code):
        s = self._scene.luxbake_settings
        if code != 0:
            s.status = self._run.error()
            self.report({"ERROR"}, s.status)
            return {"CANCELLED"}
        for line in self._run.lines:
            if line.startswith("warning"):
                self.report({"WARNING"}, line)
        scene_name = os.path.splitext(os.path.basename(self._output))[0]
        try:
            import_bake(self._output, scene_name=scene_name)
        except (RuntimeError, OSError) as error:
            s.status = message(error)
            self.report({"ERROR"}, s.status)
            return {"CANCELLED"}
        scene = bpy.data.scenes[scene_name]
        scene.luxbake_settings.status = f"bake of {self._scene.name}"
        if context.window is not None:
            context.window.scene = scene  # show the bake
        s.status = f"baked in {time.monotonic() - self._started:.1f} s: {self._output}"
        self.report({"INFO"}, s.status)
        return {"FINISHED"}

    def execute(self, context):
        try:
            self._start(context)
        except (run.BakeError, RuntimeError, OSError, ValueError) as error:
            context.scene.luxbake_settings.status = message(error)
            self.report({"ERROR"}, message(error))
            return {"CANCELLED"}
        return self._finish(context, self._run.wait())

    def invoke(self, context, event):
        try:
            self._start(context)
        except (run.BakeError, RuntimeError, OSError, ValueError) as error:
            context.scene.luxbake_settings.status = message(error)
            self.report({"ERROR"}, message(error))
            return {"CANCELLED"}
        self._timer = context.window_manager.event_timer_add(0.25, window=context.window)
        context.window_manager.modal_handler_add(self)
        return {"RUNNING_MODAL"}

    def modal(self, context, event):
        if event.type == "ESC":
            self._run.cancel()
            return self._end(context, {"CANCELLED"}, "bake cancelled")
        if event.type != "TIMER":
            return {"PASS_THROUGH"}
        code = self._run.poll()
        elapsed = time.monotonic() - self._started
        if code is None:
            last = self._run.lines[-1] if self._run.lines else ""
            text = f"luxbake: baking {elapsed:.0f} s  {last}"
            context.workspace.status_text_set(text)
            self._scene.luxbake_settings.status = text
            return {"RUNNING_MODAL"}
        context.workspace.status_text_set(None)
        context.window_manager.event_timer_remove(self._timer)
        return self._finish(context, code)

    def _end(self, context, result, text):
        context.workspace.status_text_set(None)
        context.window_manager.event_timer_remove(self._timer)
        self._scene.luxbake_settings.status = text
        self.report({"WARNING"}, text)
        return result


class LUXBAKE_OT_export(bpy.types.Operator):
    """Export the scene as glTF with luxbake's photometric extensions"""

    bl_idname = "luxbake.export"
    bl_label = "Export for luxbake"
    filepath: bpy.props.StringProperty(subtype="FILE_PATH")
    filter_glob: bpy.props.StringProperty(default="*.gltf;*.glb", options={"HIDDEN"})

    def execute(self, context):
        fmt = "GLB" if self.filepath.lower().endswith(".glb") else "GLTF_SEPARATE"
        try:
            export_scene(self.filepath, export_format=fmt)
        except (RuntimeError, OSError, ValueError) as error:
            self.report({"ERROR"}, message(error))
            return {"CANCELLED"}
        return {"FINISHED"}

    def invoke(self, context, event):
        if not self.filepath:
            self.filepath = bpy.path.ensure_ext(
                bpy.path.display_name_from_filepath(bpy.data.filepath) or "scene", ".gltf")
        context.window_manager.fileselect_add(self)
        return {"RUNNING_MODAL"}


class LUXBAKE_OT_import(bpy.types.Operator):
    """Import a luxbake bake (glTF) set up for display"""

    bl_idname = "luxbake.import_bake"
    bl_label = "Import a bake"
    filepath: bpy.props.StringProperty(subtype="FILE_PATH")
    filter_glob: bpy.props.StringProperty(default="*.gltf;*.glb", options={"HIDDEN"})

    def execute(self, context):
        try:
            import_bake(self.filepath)
        except (RuntimeError, OSError) as error:
            self.report({"ERROR"}, message(error))
            return {"CANCELLED"}
        return {"FINISHED"}

    def invoke(self, context, event):
        context.window_manager.fileselect_add(self)
        return {"RUNNING_MODAL"}


class LUXBAKE_OT_fit_range(bpy.types.Operator):
    """Set the false-colour range to the shown quantity's range over the visible meshes"""

    bl_idname = "luxbake.fit_range"
    bl_label = "Fit range"

    def execute(self, context):
        from . import import_hooks, shading

        s = context.scene.luxbake_settings
        name = "_LUMINANCE" if s.display == "LUMINANCE" else "_ILLUMINANCE"
        objects = [o for o in context.visible_objects if o.type == "MESH"]
        lo, hi = import_hooks.attribute_range(objects, name)
        if hi is None:
            self.report({"WARNING"}, f"no mesh with {name}")
            return {"CANCELLED"}
        s["range_min"] = max(lo, 1e-3 * hi) if s.log_scale else 0.0
        s["range_max"] = hi
        shading.apply_display(context.scene)
        return {"FINISHED"}


CLASSES = (LUXBAKE_OT_bake, LUXBAKE_OT_export, LUXBAKE_OT_import, LUXBAKE_OT_fit_range)


# Blender's own helper: registers in order, unregisters in reverse.
register, unregister = bpy.utils.register_classes_factory(CLASSES)
