"""Inside Blender (bpy): bake a luxbake lightmap's layout with Cycles, for bench/cycles_lightmap.py.

    python cycles_bake_bpy.py LIT.gltf JOB.json OUT.npy

LIT.gltf: a luxbake bake with `--lightmaps` (one atlas). JOB.json: {"samples": N, "seed": S,
"threads": T, "reflectance": {material: rho}, "emitters": {material: luminance cd/m2}}. Every
material becomes a Diffuse BSDF of its reflectance (grey), an emitter an Emission shader of its
luminance on its front face (its back is black, as luxbake's single-sided emitter). The lightmap
UVs (TEXCOORD_1) are the bake target; Cycles' DIFFUSE pass with direct, indirect and colour is
the luminance leaving each texel (cd/m2: an Emission of strength L is radiance L, and a
diffuse surface under it returns rho * E / pi in the same unit), the quantity in the EXR's R, G,
B. Writes OUT.npy (float32, H x W, rows top first as the EXR's) and prints one JSON line with
the bake's wall time (the bake call only, not the import).
"""

import json
import sys
import time

import bpy
import numpy as np


def main():
    lit, job_path, out = sys.argv[-3:]
    job = json.load(open(job_path))
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.ops.import_scene.gltf(filepath=lit)
    scene = bpy.context.scene
    scene.render.engine = "CYCLES"
    c = scene.cycles
    c.device = "CPU"
    c.samples = job["samples"]
    c.seed = job["seed"]
    c.use_adaptive_sampling = False
    c.use_denoising = False
    # Light is followed until it is gone: no bounce limit short of the room's, no clamping, no
    # light threshold (each would bias the reference).
    c.max_bounces = c.diffuse_bounces = 256
    c.glossy_bounces = c.transmission_bounces = c.volume_bounces = c.transparent_max_bounces = 0
    c.sample_clamp_direct = c.sample_clamp_indirect = 0.0
    c.light_sampling_threshold = 0.0
    c.caustics_reflective = c.caustics_refractive = False
    scene.render.threads_mode = "FIXED"
    scene.render.threads = job["threads"]
    scene.world = bpy.data.worlds.new("black")
    scene.world.use_nodes = True
    scene.world.node_tree.nodes["Background"].inputs["Strength"].default_value = 0.0

    width, height = job["width"], job["height"]
    image = bpy.data.images.new("lightmap", width, height, float_buffer=True, alpha=False)
    image.colorspace_settings.name = "Non-Color"
    materials = {}
    for name in set(job["reflectance"]) | set(job["emitters"]):
        materials[name] = shader(name, job["reflectance"].get(name, 0.0),
                                 job["emitters"].get(name), image)
    meshes = [o for o in scene.objects if o.type == "MESH"]
    for o in meshes:
        for slot in o.material_slots:
            base = slot.material.name.split(".")[0] if slot.material else None
            if base not in materials:
                raise SystemExit(f"material {slot.material.name!r} of {o.name} not in the job")
            slot.material = materials[base]
        uv = o.data.uv_layers
        if len(uv) == 0:
            raise SystemExit(f"{o.name} has no UVs: bake with --lightmaps")
        # TEXCOORD_1 (the lightmap's) when the importer made two layers.
        uv.active = uv[len(uv) - 1]
    bpy.ops.object.select_all(action="DESELECT")
    for o in meshes:
        o.select_set(True)
    bpy.context.view_layer.objects.active = meshes[0]
    t0 = time.perf_counter()
    bpy.ops.object.bake(type="DIFFUSE", pass_filter={"DIRECT", "INDIRECT", "COLOR"},
                        margin=0, use_clear=True, target="IMAGE_TEXTURES")
    seconds = time.perf_counter() - t0
    px = np.empty(width * height * 4, dtype=np.float32)
    image.pixels.foreach_get(px)
    # Blender's rows run bottom up, its v up: the EXR's row 0 is the top (glTF v down).
    lum = px.reshape(height, width, 4)[::-1, :, :3].mean(axis=2)
    np.save(out, lum.astype(np.float32))
    print(json.dumps({"bakeSeconds": seconds, "samples": job["samples"], "seed": job["seed"]}))


def shader(name, rho, luminance, image):
    """A material: grey Diffuse BSDF of reflectance rho, or (luminance given) an Emission of
    that luminance on the front face and black behind; with the bake target as its active
    image node."""
    m = bpy.data.materials.new("bench_" + name)
    m.use_nodes = True
    nt = m.node_tree
    nt.nodes.clear()
    out = nt.nodes.new("ShaderNodeOutputMaterial")
    diffuse = nt.nodes.new("ShaderNodeBsdfDiffuse")
    diffuse.inputs["Color"].default_value = (rho, rho, rho, 1.0)
    surface = diffuse.outputs["BSDF"]
    if luminance is not None:
        emit = nt.nodes.new("ShaderNodeEmission")
        emit.inputs["Color"].default_value = (1.0, 1.0, 1.0, 1.0)
        emit.inputs["Strength"].default_value = luminance
        geometry = nt.nodes.new("ShaderNodeNewGeometry")
        front = nt.nodes.new("ShaderNodeAddShader")
        nt.links.new(emit.outputs["Emission"], front.inputs[0])
        nt.links.new(diffuse.outputs["BSDF"], front.inputs[1])
        mix = nt.nodes.new("ShaderNodeMixShader")
        nt.links.new(geometry.outputs["Backfacing"], mix.inputs["Fac"])
        nt.links.new(front.outputs["Shader"], mix.inputs[1])
        nt.links.new(diffuse.outputs["BSDF"], mix.inputs[2])
        surface = mix.outputs["Shader"]
    nt.links.new(surface, out.inputs["Surface"])
    tex = nt.nodes.new("ShaderNodeTexImage")
    tex.image = image
    nt.nodes.active = tex
    return m


main()
