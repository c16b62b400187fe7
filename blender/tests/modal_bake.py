"""The Bake operator's interactive path (invoke → timer → modal), driven by hand: a script has
no event loop, so the timer events are sent by calling `modal` with a TIMER event, on a
stand-in for the operator instance (the class's own methods bound to it). Prints JSON.

Usage: PYTHON modal_bake.py --bake BAKE --out DIR
Stdout: {"statuses": [status texts while baking], "result": [...], "shown": scene name,
         "scenes": [...], "final_status": text, "reports": [[kind, text]]}
"""

import json
import os
import sys
import time
import types

HERE = os.path.dirname(os.path.abspath(__file__))


def main(bake, out):
    stdout_fd = os.dup(1)
    os.dup2(2, 1)
    sys.path.insert(0, os.path.dirname(HERE))
    import bpy
    import addon_utils

    bpy.ops.wm.read_factory_settings(use_empty=True)
    addon_utils.enable("luxbake", default_set=True, handle_error=None)
    from luxbake import operators

    bpy.context.preferences.addons["luxbake"].preferences.bake_path = bake
    mesh = bpy.data.meshes.new("floor")
    mesh.from_pydata([(0, 0, 0), (4, 0, 0), (4, 3, 0), (0, 3, 0)], [], [(0, 1, 2, 3)])
    bpy.context.scene.collection.objects.link(bpy.data.objects.new("floor", mesh))
    lamp = bpy.data.objects.new("bulb", bpy.data.lights.new("bulb", "POINT"))
    lamp.location = (2.0, 1.5, 2.0)
    bpy.context.scene.collection.objects.link(lamp)
    settings = bpy.context.scene.luxbake_settings
    settings.output_dir = out
    settings.quality = "draft"

    reports = []
    op = types.SimpleNamespace(report=lambda kind, text: reports.append([sorted(kind), text]))
    for name in ("_start", "_finish", "modal", "_end"):
        setattr(op, name, types.MethodType(getattr(operators.LUXBAKE_OT_bake, name), op))
    context = bpy.context
    # invoke, less modal_handler_add (it wants a real operator)
    op._start(context)
    op._timer = context.window_manager.event_timer_add(0.25, window=context.window)
    statuses = []
    timer = types.SimpleNamespace(type="TIMER")
    deadline = time.monotonic() + 60
    while time.monotonic() < deadline:
        result = op.modal(context, timer)
        if result != {"RUNNING_MODAL"}:
            break
        statuses.append(op._scene.luxbake_settings.status)
        time.sleep(0.05)
    report = {
        "statuses": statuses, "result": sorted(result), "shown": bpy.context.scene.name,
        "scenes": sorted(s.name for s in bpy.data.scenes),
        "final_status": op._scene.luxbake_settings.status, "reports": reports,
    }
    sys.stdout.flush()
    os.dup2(stdout_fd, 1)
    print(json.dumps(report))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[sys.argv.index("--bake") + 1], sys.argv[sys.argv.index("--out") + 1]))
