#!/usr/bin/env python3
"""Writes the Cornell box variants compared with Blender Cycles (issue 29):

  lambert   every material KHR_materials_specular specularFactor 0: F0 =
            F90 = 0, a Lambertian BRDF in gistream and Cycles' Diffuse BSDF
            (no BRDF model of the two renderers differs);
  near_2s   lambert, the lamp 1 cm under the ceiling and double-sided: the
            ceiling beside it lit at a centimetre (issue 29's near field);
  ior_1     lambert's walls written as an exporter writes a diffuse
            material: roughness 0.9, KHR_materials_ior 1 and
            KHR_materials_specular 0 (Lambertian whatever the roughness);
  gold      lambert with the tall block a gold metal, roughness 0.3
            (glTF's GGX against Cycles' Principled BSDF at metallic 1).

  variants.py SCENE.gltf OUT_DIR
"""
import copy
import json
import os
import sys

CEILING_Y = 0.5488  # the ceiling's plane in cornell_box.gltf


def add_extension(doc, name):
    used = doc.setdefault("extensionsUsed", [])
    if name not in used:
        used.append(name)


def lambert(doc):
    for m in doc["materials"]:
        m.setdefault("extensions", {})["KHR_materials_specular"] = {"specularFactor": 0.0}
    add_extension(doc, "KHR_materials_specular")
    return doc


def near_2s(doc):
    doc = lambert(doc)
    light = next(n for n in doc["nodes"] if n.get("name") == "light")
    light["translation"][1] = CEILING_Y - 0.01
    lamp = next(m for m in doc["materials"] if m.get("name") == "light")
    lamp["doubleSided"] = True
    return doc


def ior_1(doc):
    doc = lambert(doc)
    for m in doc["materials"]:
        m["pbrMetallicRoughness"]["roughnessFactor"] = 0.9
        m["extensions"]["KHR_materials_ior"] = {"ior": 1.0}
    add_extension(doc, "KHR_materials_ior")
    return doc


def gold(doc):
    doc = lambert(doc)
    doc["materials"].append({"name": "gold", "pbrMetallicRoughness": {
        "baseColorFactor": [1.0, 0.78, 0.34, 1.0], "metallicFactor": 1.0,
        "roughnessFactor": 0.3}})
    block = next(n for n in doc["nodes"] if n.get("name") == "tall_block")
    for primitive in doc["meshes"][block["mesh"]]["primitives"]:
        primitive["material"] = len(doc["materials"]) - 1
    return doc


def main():
    scene, out = sys.argv[1], sys.argv[2]
    os.makedirs(out, exist_ok=True)
    base = json.load(open(scene))
    for name, make in (("lambert", lambert), ("near_2s", near_2s), ("ior_1", ior_1),
                       ("gold", gold)):
        path = os.path.join(out, f"{name}.gltf")
        with open(path, "w") as f:
            json.dump(make(copy.deepcopy(base)), f)
        print(path)


if __name__ == "__main__":
    main()
