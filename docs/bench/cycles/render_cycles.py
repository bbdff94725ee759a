"""Renders a glTF file with Blender Cycles as gistream's pathtrace does
(issue 29: an independent renderer to check the reference against):
the file's camera, a box pixel filter one pixel wide, no denoising, no
clamping, 64 bounces, a black world, linear EXR.

Materials are rebuilt from the glTF document, not taken from Blender's
importer (Blender 3.4's does not read every extension): a material whose
specular layer is off (KHR_materials_specular specularFactor 0, metallic 0)
is Cycles' Diffuse BSDF, i.e. Lambert; a metal (metallic 1) is Principled's
GGX with F0 = base colour, as glTF's; any other is refused, since
Principled's diffuse (Burley) is not glTF's. Emission is emissiveFactor x
KHR_materials_emissive_strength, from the front face only unless the
material is double-sided.

  blender -b --factory-startup --python render_cycles.py -- IN.gltf OUT.exr SPP SEED SIZE
"""
import json
import sys

import bpy
import numpy

# Debian 12's Blender 3.4 glTF importer uses numpy.bool, which its numpy
# (1.24) no longer has.
if not hasattr(numpy, "bool") or numpy.bool is not bool:
    numpy.bool = bool


def material_node_tree(mat, m):
    ext = m.get("extensions", {})
    pbr = m.get("pbrMetallicRoughness", {})
    specular = ext.get("KHR_materials_specular", {}).get("specularFactor", 1.0)
    metallic = pbr.get("metallicFactor", 1.0)
    color = pbr.get("baseColorFactor", [1, 1, 1, 1])
    mat.use_nodes = True
    nt = mat.node_tree
    nt.nodes.clear()
    out = nt.nodes.new("ShaderNodeOutputMaterial")
    if metallic == 0.0 and specular == 0.0:
        diffuse = nt.nodes.new("ShaderNodeBsdfDiffuse")
        diffuse.inputs["Color"].default_value = color
        diffuse.inputs["Roughness"].default_value = 0.0  # Oren-Nayar at 0: Lambert
        shader = diffuse.outputs["BSDF"]
    elif metallic == 1.0:
        metal = nt.nodes.new("ShaderNodeBsdfPrincipled")
        metal.distribution = "GGX"
        metal.inputs["Base Color"].default_value = color
        metal.inputs["Metallic"].default_value = 1.0
        metal.inputs["Roughness"].default_value = pbr.get("roughnessFactor", 1.0)
        shader = metal.outputs["BSDF"]
    else:
        sys.exit(f"material '{m.get('name')}': only Lambertian materials (metallic 0, "
                 "KHR_materials_specular specularFactor 0) and metals are compared")
    emissive = m.get("emissiveFactor", [0, 0, 0])
    strength = ext.get("KHR_materials_emissive_strength", {}).get("emissiveStrength", 1.0)
    if max(emissive) > 0.0:
        emission = nt.nodes.new("ShaderNodeEmission")
        emission.inputs["Color"].default_value = list(emissive) + [1.0]
        emission.inputs["Strength"].default_value = strength
        emitted = emission.outputs["Emission"]
        if not m.get("doubleSided", False):
            # glTF: a single-sided material's back face does not emit.
            dark = nt.nodes.new("ShaderNodeEmission")
            dark.inputs["Strength"].default_value = 0.0
            geometry = nt.nodes.new("ShaderNodeNewGeometry")
            mix = nt.nodes.new("ShaderNodeMixShader")
            nt.links.new(geometry.outputs["Backfacing"], mix.inputs["Fac"])
            nt.links.new(emitted, mix.inputs[1])
            nt.links.new(dark.outputs["Emission"], mix.inputs[2])
            emitted = mix.outputs["Shader"]
        add = nt.nodes.new("ShaderNodeAddShader")
        nt.links.new(shader, add.inputs[0])
        nt.links.new(emitted, add.inputs[1])
        shader = add.outputs["Shader"]
    nt.links.new(shader, out.inputs["Surface"])


def main():
    argv = sys.argv[sys.argv.index("--") + 1:]
    gltf, out, spp, seed, size = argv[0], argv[1], int(argv[2]), int(argv[3]), int(argv[4])
    doc = json.load(open(gltf))
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.ops.import_scene.gltf(filepath=gltf)
    scene = bpy.context.scene
    by_name = {m.get("name"): m for m in doc.get("materials", [])}
    for mat in bpy.data.materials:
        if mat.name in by_name:
            material_node_tree(mat, by_name[mat.name])
    cameras = [o for o in scene.objects if o.type == "CAMERA"]
    if not cameras:
        sys.exit("the file has no camera")
    scene.camera = cameras[0]
    world = bpy.data.worlds.new("black")
    world.use_nodes = True
    world.node_tree.nodes["Background"].inputs["Strength"].default_value = 0.0
    scene.world = world
    scene.render.engine = "CYCLES"
    c = scene.cycles
    c.device = "CPU"
    c.samples = spp
    c.use_adaptive_sampling = False
    c.use_denoising = False
    c.seed = seed
    c.max_bounces = c.diffuse_bounces = c.glossy_bounces = 64
    c.transmission_bounces = c.volume_bounces = 0
    c.transparent_max_bounces = 8
    c.sample_clamp_direct = c.sample_clamp_indirect = 0.0
    c.caustics_reflective = c.caustics_refractive = True
    c.blur_glossy = 0.0
    c.pixel_filter_type = "BOX"
    c.filter_width = 1.0
    scene.render.resolution_x = scene.render.resolution_y = size
    scene.render.resolution_percentage = 100
    scene.render.film_transparent = False
    scene.view_settings.view_transform = "Standard"
    scene.view_settings.look = "None"
    scene.view_settings.exposure = 0.0
    scene.view_settings.gamma = 1.0
    scene.render.image_settings.file_format = "OPEN_EXR"
    scene.render.image_settings.color_depth = "32"
    scene.render.image_settings.color_mode = "RGB"
    scene.render.filepath = out
    bpy.ops.render.render(write_still=True)


main()
