#!/usr/bin/env python3
"""gltftex.py DIR IMAGE.png IMAGE.jpg - textured glTF models of the unit quad
(tests/cli/textured.sh), its texture's quadrants filling its quarters, as
tests/data/textured/quad-png.obj maps them:

    quad.gltf + quad.bin   the PNG as an external file beside it (copied in)
    quad.glb               the PNG embedded (a bufferView with a mimeType)
    quad-jpg.glb           the JPEG embedded
    quad-data.gltf         the PNG as a base64 data URI
    quad-nearest.glb       the PNG embedded, its sampler's magFilter NEAREST
    quad-missing.gltf      an external image that is not there
    quad-broken.glb        an embedded 'PNG' whose bytes are not one
    quad.dae               COLLADA, the PNG beside it (Assimp reads its textures too)

glTF's texture coordinates start at the image's top left (OBJ's at its
bottom left)."""
import base64
import json
import os
import shutil
import struct
import sys


def quad():
    pos = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0)]
    uv = [(0, 1), (1, 1), (1, 0), (0, 0)]
    idx = [0, 1, 2, 0, 2, 3]
    geo = b"".join(struct.pack("<3f", *p) for p in pos) + b"".join(struct.pack("<2f", *t) for t in uv)
    geo += b"".join(struct.pack("<I", i) for i in idx)
    return geo


def document(geo_len, image, sampler=None):
    doc = {
        "asset": {"version": "2.0", "generator": "lanray tests/tools/gltftex.py"},
        "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "TEXCOORD_0": 1}, "indices": 2, "material": 0}]}],
        "materials": [{"name": "tex", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}, "metallicFactor": 0}}],
        "textures": [{"source": 0}],
        "images": [image],
        "buffers": [{"byteLength": geo_len}],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": 48},
            {"buffer": 0, "byteOffset": 48, "byteLength": 32},
            {"buffer": 0, "byteOffset": 80, "byteLength": 24},
        ],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]},
            {"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC2"},
            {"bufferView": 2, "componentType": 5125, "count": 6, "type": "SCALAR"},
        ],
    }
    if sampler:
        doc["samplers"] = [sampler]
        doc["textures"][0]["sampler"] = 0
    return doc


def write_gltf(path, image, geo, bin_name):
    doc = document(len(geo), image)
    doc["buffers"][0]["uri"] = bin_name
    with open(os.path.join(os.path.dirname(path), bin_name), "wb") as out:
        out.write(geo)
    with open(path, "w") as out:
        json.dump(doc, out)


def write_glb(path, img_bytes, mime, sampler=None, maps=False, blend=False):
    """maps: the image is the material's normal map, emission texture (factor 0.3),
    metal-roughness texture (metallic factor 1, roughness factor 0.5) and occlusion texture too;
    blend: the material's alphaMode BLEND (the image's alpha a see-through blend)."""
    geo = quad()
    blob = geo + img_bytes
    doc = document(len(blob), {"bufferView": 3, "mimeType": mime}, sampler)
    if blend:
        doc["materials"][0]["alphaMode"] = "BLEND"
    if maps:
        m = doc["materials"][0]
        m["normalTexture"] = {"index": 0}
        m["emissiveTexture"] = {"index": 0}
        m["emissiveFactor"] = [0.3, 0.3, 0.3]
        m["occlusionTexture"] = {"index": 0, "strength": 0.8}
        m["pbrMetallicRoughness"].update(metallicFactor=1, roughnessFactor=0.5, metallicRoughnessTexture={"index": 0})
    doc["bufferViews"].append({"buffer": 0, "byteOffset": len(geo), "byteLength": len(img_bytes)})
    js = json.dumps(doc).encode()
    js += b" " * (-len(js) % 4)
    blob += b"\0" * (-len(blob) % 4)
    with open(path, "wb") as out:
        out.write(struct.pack("<4sII", b"glTF", 2, 12 + 8 + len(js) + 8 + len(blob)))
        out.write(struct.pack("<I4s", len(js), b"JSON") + js)
        out.write(struct.pack("<I4s", len(blob), b"BIN\0") + blob)


DAE = """<?xml version="1.0" encoding="utf-8"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
 <asset><unit name="meter" meter="1"/><up_axis>Y_UP</up_axis></asset>
 <library_images><image id="img"><init_from>quadrants.png</init_from></image></library_images>
 <library_effects><effect id="fx"><profile_COMMON>
  <newparam sid="surf"><surface type="2D"><init_from>img</init_from></surface></newparam>
  <newparam sid="samp"><sampler2D><source>surf</source></sampler2D></newparam>
  <technique sid="common"><lambert><diffuse><texture texture="samp" texcoord="UV0"/></diffuse></lambert></technique>
 </profile_COMMON></effect></library_effects>
 <library_materials><material id="tex" name="tex"><instance_effect url="#fx"/></material></library_materials>
 <library_geometries><geometry id="quad"><mesh>
  <source id="pos"><float_array id="pa" count="12">0 0 0 1 0 0 1 1 0 0 1 0</float_array>
   <technique_common><accessor source="#pa" count="4" stride="3"><param name="X" type="float"/><param name="Y" type="float"/><param name="Z" type="float"/></accessor></technique_common></source>
  <source id="uv"><float_array id="ua" count="8">0 0 1 0 1 1 0 1</float_array>
   <technique_common><accessor source="#ua" count="4" stride="2"><param name="S" type="float"/><param name="T" type="float"/></accessor></technique_common></source>
  <vertices id="v"><input semantic="POSITION" source="#pos"/></vertices>
  <triangles material="m" count="2"><input semantic="VERTEX" source="#v" offset="0"/><input semantic="TEXCOORD" source="#uv" offset="1" set="0"/>
   <p>0 0 1 1 2 2 0 0 2 2 3 3</p></triangles>
 </mesh></geometry></library_geometries>
 <library_visual_scenes><visual_scene id="s"><node id="n"><instance_geometry url="#quad">
  <bind_material><technique_common><instance_material symbol="m" target="#tex"><bind_vertex_input semantic="UV0" input_semantic="TEXCOORD" input_set="0"/></instance_material></technique_common></bind_material>
 </instance_geometry></node></visual_scene></library_visual_scenes>
 <scene><instance_visual_scene url="#s"/></scene>
</COLLADA>
"""


def main():
    d, png, jpg = sys.argv[1], sys.argv[2], sys.argv[3]
    os.makedirs(d, exist_ok=True)
    png_bytes = open(png, "rb").read()
    jpg_bytes = open(jpg, "rb").read()
    shutil.copy(png, os.path.join(d, "quadrants.png"))
    geo = quad()
    write_gltf(os.path.join(d, "quad.gltf"), {"uri": "quadrants.png"}, geo, "quad.bin")
    write_gltf(os.path.join(d, "quad-data.gltf"),
               {"uri": "data:image/png;base64," + base64.b64encode(png_bytes).decode()}, geo, "quad-data.bin")
    write_gltf(os.path.join(d, "quad-missing.gltf"), {"uri": "nothere.png"}, geo, "quad-missing.bin")
    write_glb(os.path.join(d, "quad.glb"), png_bytes, "image/png")
    write_glb(os.path.join(d, "quad-jpg.glb"), jpg_bytes, "image/jpeg")
    write_glb(os.path.join(d, "quad-nearest.glb"), png_bytes, "image/png", {"magFilter": 9728, "minFilter": 9729})
    write_glb(os.path.join(d, "quad-broken.glb"), b"\x89PNG\r\n\x1a\n" + b"\0" * 40, "image/png")
    with open(os.path.join(d, "quad.dae"), "w") as out:
        out.write(DAE)


if __name__ == "__main__":
    main()
