#!/usr/bin/env python3
"""Authors daemon/assets/models/lumar_brushed_table.glb: the round table of the paper's
figure 1 (daemon/assets/scenes/paper_fig1_brushed_table.toml), built from parametric shapes: a
disc top 1 m across and 3 cm thick on a central column and a round foot, 0.45 m tall (low, so
the fake camera sees the top). The top's uvs are planar, u along +X and v along +Z (not mirrored: the swirl tangent-rotation
texture's circles then run round the table's centre, lafortune_material.h). Plain
metallic-roughness materials ("top", "stand"); the scene gives them the brushed_metal
preset. Standard library only; deterministic output.

usage: scripts/make-brushed-table.py [OUT.glb]
"""
import math
import struct
import sys

from glb_writer import GlbBuffer, pack_glb

# +Y up, metres.
TOP_RADIUS = 0.5
TOP_THICKNESS = 0.03
HEIGHT = 0.45
COLUMN_RADIUS = 0.04
FOOT_RADIUS = 0.22
FOOT_THICKNESS = 0.02
SEGMENTS = 96
RINGS = 4


class Mesh:
    def __init__(self):
        self.positions, self.normals, self.uvs, self.indices = [], [], [], []

    def vertex(self, p, n, uv):
        self.positions.append(p)
        self.normals.append(n)
        self.uvs.append(uv)
        return len(self.positions) - 1

    def disc(self, y, radius, up):
        """A flat disc at height y facing +Y (up) or -Y, planar uvs over the table's top."""
        ny = 1.0 if up else -1.0
        centre = self.vertex((0.0, y, 0.0), (0.0, ny, 0.0), (0.5, 0.5))
        rings = []
        for r in range(1, RINGS + 1):
            rr = radius * r / RINGS
            ring = []
            for s in range(SEGMENTS):
                a = 2.0 * math.pi * s / SEGMENTS
                x, z = rr * math.cos(a), rr * math.sin(a)
                ring.append(self.vertex((x, y, z), (0.0, ny, 0.0), (0.5 + x / (2 * TOP_RADIUS), 0.5 + z / (2 * TOP_RADIUS))))
            rings.append(ring)
        for s in range(SEGMENTS):
            t = (s + 1) % SEGMENTS
            self.triangle(centre, rings[0][t], rings[0][s], up)
        for r in range(RINGS - 1):
            inner, outer = rings[r], rings[r + 1]
            for s in range(SEGMENTS):
                t = (s + 1) % SEGMENTS
                self.triangle(inner[s], inner[t], outer[t], up)
                self.triangle(inner[s], outer[t], outer[s], up)

    def triangle(self, a, b, c, up):
        # Counter-clockwise seen from the side the normal points to: with x = r cos a and
        # z = r sin a, increasing a turns clockwise seen from +Y.
        self.indices += [a, b, c] if up else [a, c, b]

    def band(self, y0, y1, radius):
        """The side of a cylinder between heights y0 < y1, normals outwards, u round, v down."""
        base = len(self.positions)
        for s in range(SEGMENTS + 1):
            a = 2.0 * math.pi * s / SEGMENTS
            n = (math.cos(a), 0.0, math.sin(a))
            self.vertex((radius * n[0], y1, radius * n[2]), n, (s / SEGMENTS, 0.0))
            self.vertex((radius * n[0], y0, radius * n[2]), n, (s / SEGMENTS, 1.0))
        for s in range(SEGMENTS):
            top, bottom, next_top, next_bottom = base + 2 * s, base + 2 * s + 1, base + 2 * s + 2, base + 2 * s + 3
            self.indices += [top, next_top, bottom, bottom, next_top, next_bottom]


def build():
    top, stand = Mesh(), Mesh()
    top.disc(HEIGHT, TOP_RADIUS, True)
    top.disc(HEIGHT - TOP_THICKNESS, TOP_RADIUS, False)
    top.band(HEIGHT - TOP_THICKNESS, HEIGHT, TOP_RADIUS)
    stand.band(FOOT_THICKNESS, HEIGHT - TOP_THICKNESS, COLUMN_RADIUS)
    stand.disc(FOOT_THICKNESS, FOOT_RADIUS, True)
    stand.disc(0.0, FOOT_RADIUS, False)
    stand.band(0.0, FOOT_THICKNESS, FOOT_RADIUS)
    return [("top", top), ("stand", stand)]


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else "daemon/assets/models/lumar_brushed_table.glb"
    buffer = GlbBuffer()
    accessors, primitives, materials = [], [], []

    def add_accessor(values, kind, component, target):
        flat = [x for v in values for x in (v if isinstance(v, tuple) else (v,))]
        fmt = "<%d%s" % (len(flat), "f" if component == 5126 else "I")
        accessor = {"bufferView": buffer.add_view(struct.pack(fmt, *flat), target), "componentType": component,
                    "count": len(values), "type": kind}
        if kind == "VEC3" and component == 5126 and values is not None:
            accessor["min"] = [min(v[k] for v in values) for k in range(3)]
            accessor["max"] = [max(v[k] for v in values) for k in range(3)]
        accessors.append(accessor)
        return len(accessors) - 1

    for index, (name, mesh) in enumerate(build()):
        position = add_accessor([tuple(p) for p in mesh.positions], "VEC3", 5126, 34962)
        normal = add_accessor([tuple(n) for n in mesh.normals], "VEC3", 5126, 34962)
        uv = add_accessor([tuple(t) for t in mesh.uvs], "VEC2", 5126, 34962)
        indices = add_accessor(mesh.indices, "SCALAR", 5125, 34963)
        primitives.append({"attributes": {"POSITION": position, "NORMAL": normal, "TEXCOORD_0": uv},
                           "indices": indices, "material": index})
        materials.append({"name": name, "pbrMetallicRoughness": {"baseColorFactor": [0.86, 0.86, 0.87, 1.0],
                                                                  "metallicFactor": 1.0, "roughnessFactor": 0.35}})
    document = {
        "asset": {"version": "2.0", "generator": "lumar scripts/make-brushed-table.py",
                  "copyright": "lumar project; generated, no third-party content"},
        "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"name": "table", "mesh": 0}],
        "meshes": [{"name": "table", "primitives": primitives}], "materials": materials,
        "accessors": accessors, "bufferViews": buffer.views, "buffers": [{"byteLength": buffer.pad()}],
    }
    glb = pack_glb(document, buffer)
    with open(out, "wb") as f:
        f.write(glb)
    print("%s: %d triangles" % (out, sum(len(m.indices) for _, m in build()) // 3))


if __name__ == "__main__":
    main()
