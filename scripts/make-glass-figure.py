#!/usr/bin/env python3
"""Authors the two glass balls of the paper's figure 3 (a transparent object with its normal
map disabled and enabled; daemon/assets/scenes/paper_fig3_glass_*.toml):
daemon/assets/models/lumar_glass_ball.glb, a smooth sphere of clear glass, and
daemon/assets/models/lumar_glass_ball_hammered.glb, the same sphere with a normal map of
hammered dimples. Glass is glTF's own: KHR_materials_transmission (1), KHR_materials_ior
(1.5) and KHR_materials_volume (solid: it bends the view). A UV sphere of diameter 1 (+Y up,
64 x 32 quads); standard library only; deterministic output.

usage: scripts/make-glass-figure.py [OUT_DIR]
"""
import math
import os
import struct
import sys

from glb_writer import GlbBuffer, pack_glb, png_rgb

SEGMENTS, RINGS = 64, 32
# Dimples of the hammered ball: around the sphere and from pole to pole, and how far the
# normal tilts at most (tan of ~19 degrees).
DIMPLES_AROUND, DIMPLES_DOWN, TILT = 24, 12, 0.35


def sphere():
    positions, normals, uvs, indices = [], [], [], []
    for j in range(RINGS + 1):
        v = j / RINGS
        theta = math.pi * v
        for i in range(SEGMENTS + 1):
            u = i / SEGMENTS
            phi = 2.0 * math.pi * u
            n = (math.sin(theta) * math.cos(phi), math.cos(theta), math.sin(theta) * math.sin(phi))
            positions.append(tuple(0.5 * c for c in n))
            normals.append(n)
            uvs.append((u, v))
    row = SEGMENTS + 1
    for j in range(RINGS):
        for i in range(SEGMENTS):
            a = j * row + i
            b, c, d = a + 1, a + row + 1, a + row
            # Counter-clockwise from outside (d/du x d/dv points out).
            indices += [a, b, c, a, c, d]
    return positions, normals, uvs, indices


def png(width, height, pixel):
    return png_rgb(width, height, (b"".join(bytes(pixel(x, y)) for x in range(width)) for y in range(height)))


def hammered_normal_png(width=256, height=128):
    """Tangent-space normals of a bumpy surface h = sin(a u) sin(b v), tilted up to TILT."""
    def pixel(x, y):
        u, v = (x + 0.5) / width, (y + 0.5) / height
        a, b = 2.0 * math.pi * DIMPLES_AROUND, 2.0 * math.pi * DIMPLES_DOWN
        nx = -TILT * math.cos(a * u) * math.sin(b * v)
        ny = -TILT * math.sin(a * u) * math.cos(b * v)
        length = math.sqrt(nx * nx + ny * ny + 1.0)
        return [int(round((c / length * 0.5 + 0.5) * 255)) for c in (nx, ny, 1.0)]
    return png(width, height, pixel)


def glb(normal_map):
    positions, normals, uvs, indices = sphere()
    buffer = GlbBuffer()
    add_view = buffer.add_view

    count = len(positions)
    accessors = [
        {"bufferView": add_view(b"".join(struct.pack("<3f", *p) for p in positions), 34962), "componentType": 5126,
         "count": count, "type": "VEC3", "min": [-0.5, -0.5, -0.5], "max": [0.5, 0.5, 0.5]},
        {"bufferView": add_view(b"".join(struct.pack("<3f", *n) for n in normals), 34962), "componentType": 5126,
         "count": count, "type": "VEC3"},
        {"bufferView": add_view(b"".join(struct.pack("<2f", *t) for t in uvs), 34962), "componentType": 5126,
         "count": count, "type": "VEC2"},
        {"bufferView": add_view(b"".join(struct.pack("<I", i) for i in indices), 34963), "componentType": 5125,
         "count": len(indices), "type": "SCALAR"},
    ]
    material = {
        "name": "glass",
        "pbrMetallicRoughness": {"baseColorFactor": [1.0, 1.0, 1.0, 1.0], "metallicFactor": 0.0,
                                 "roughnessFactor": 0.0},
        "extensions": {
            "KHR_materials_transmission": {"transmissionFactor": 1.0},
            "KHR_materials_ior": {"ior": 1.5},
            # Solid glass, the ball's diameter thick; a faint green over that path, as
            # window glass shows at its edge.
            "KHR_materials_volume": {"thicknessFactor": 1.0, "attenuationDistance": 8.0,
                                     "attenuationColor": [0.85, 0.95, 0.9]},
        },
    }
    gltf = {
        "asset": {"version": "2.0", "generator": "lumar scripts/make-glass-figure.py",
                  "copyright": "lumar project; generated, no third-party content"},
        "extensionsUsed": ["KHR_materials_transmission", "KHR_materials_ior", "KHR_materials_volume"],
        "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"name": "glass_ball", "mesh": 0}],
        "meshes": [{"name": "glass_ball", "primitives": [
            {"attributes": {"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2}, "indices": 3, "material": 0}]}],
        "materials": [material], "accessors": accessors, "bufferViews": buffer.views,
    }
    if normal_map:
        image_view = add_view(hammered_normal_png())
        material["normalTexture"] = {"index": 0, "scale": 1.0}
        gltf["images"] = [{"name": "hammered", "mimeType": "image/png", "bufferView": image_view}]
        gltf["samplers"] = [{"magFilter": 9729, "minFilter": 9987, "wrapS": 10497, "wrapT": 33071}]
        gltf["textures"] = [{"sampler": 0, "source": 0}]
    gltf["buffers"] = [{"byteLength": buffer.pad()}]
    return pack_glb(gltf, buffer)


def main():
    out_dir = sys.argv[1] if len(sys.argv) > 1 else "daemon/assets/models"
    for name, normal_map in (("lumar_glass_ball.glb", False), ("lumar_glass_ball_hammered.glb", True)):
        data = glb(normal_map)
        path = os.path.join(out_dir, name)
        with open(path, "wb") as f:
            f.write(data)
        print(f"{path}: {len(data)} bytes")


if __name__ == "__main__":
    main()
