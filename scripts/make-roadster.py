#!/usr/bin/env python3
"""Authors daemon/assets/models/lumar_roadster.glb: lumar's demo car, built from
parametric shapes to the size of the paper's car (about 9.5k triangles, 7 materials), every
material given in full with the LUMAR_materials_lafortune extension (see
gles_renderer/LUMAR_materials_lafortune.md): red car paint, see-through glass
(KHR_materials_transmission), tyre rubber, chrome rims
and trim, a brushed-metal grille with a swirl tangent-rotation texture, black plastic
bumpers and emissive headlamps. Standard library only; deterministic output.

usage: scripts/make-roadster.py [OUT.glb]
"""
import math
import struct
import sys

from glb_writer import GlbBuffer, pack_glb, png_rgb

# The car faces +Z, +Y up, metres: 4.2 m long, 1.8 m wide.


class Mesh:
    def __init__(self):
        self.positions, self.uvs, self.indices = [], [], []

    def vertex(self, p, uv):
        self.positions.append(p)
        self.uvs.append(uv)
        return len(self.positions) - 1

    def grid(self, nu, nv, point, wrap_u=False):
        """Quads over (u, v) in [0,1]^2; point(u, v) -> (x, y, z); counter-clockwise from outside
        when point's u x v points outwards."""
        base = len(self.positions)
        for j in range(nv + 1):
            for i in range(nu + 1):
                u, v = i / nu, j / nv
                self.vertex(point(u, v), (u, v))
        row = nu + 1
        for j in range(nv):
            for i in range(nu):
                a = base + j * row + i
                b, c, d = a + 1, a + row + 1, a + row
                self.indices += [a, b, c, a, c, d]

    def normals(self):
        acc = [[0.0, 0.0, 0.0] for _ in self.positions]
        for t in range(0, len(self.indices), 3):
            ia, ib, ic = self.indices[t:t + 3]
            a, b, c = self.positions[ia], self.positions[ib], self.positions[ic]
            e1 = [b[k] - a[k] for k in range(3)]
            e2 = [c[k] - a[k] for k in range(3)]
            n = [e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]]
            for i in (ia, ib, ic):
                for k in range(3):
                    acc[i][k] += n[k]
        out = []
        for n in acc:
            length = math.sqrt(sum(x * x for x in n)) or 1.0
            out.append([x / length for x in n])
        return out


def spow(x, e):
    return math.copysign(abs(x) ** e, x)


def superellipsoid(mesh, centre, radii, e_vertical, e_horizontal, nu, nv, y_min=None):
    """A rounded box: exponents below 1 square it off. Optionally flattened below y_min."""
    def point(u, v):
        theta = (v - 0.5) * math.pi          # -pi/2 (bottom) .. pi/2 (top)
        phi = -u * 2.0 * math.pi             # round the vertical axis, outward-facing order
        cy, sy = math.cos(theta), math.sin(theta)
        x = radii[0] * spow(cy, e_vertical) * spow(math.cos(phi), e_horizontal)
        z = radii[2] * spow(cy, e_vertical) * spow(math.sin(phi), e_horizontal)
        y = radii[1] * spow(sy, e_vertical)
        if y_min is not None:
            y = max(y, y_min)
        return (centre[0] + x, centre[1] + y, centre[2] + z)
    mesh.grid(nu, nv, point)


def torus_x(mesh, centre, major, minor, nu, nv):
    """A tyre: a torus round the x axis."""
    def point(u, v):
        a = u * 2.0 * math.pi
        b = -v * 2.0 * math.pi
        r = major + minor * math.cos(b)
        return (centre[0] + minor * 1.6 * math.sin(b), centre[1] + r * math.cos(a), centre[2] + r * math.sin(a))
    mesh.grid(nu, nv, point)


def disc_x(mesh, centre, radius, segments, facing):
    """A wheel rim: a shallow cone facing +x or -x."""
    def point(u, v):
        a = u * 2.0 * math.pi * facing
        r = radius * v
        bulge = 0.03 * (1.0 - v * v)
        return (centre[0] + facing * bulge, centre[1] + r * math.cos(a), centre[2] + r * math.sin(a))
    mesh.grid(segments, 4, point)


def box(mesh, lo, hi):
    x0, y0, z0 = lo
    x1, y1, z1 = hi
    faces = [  # corners counter-clockwise seen from outside
        [(x1, y0, z0), (x1, y1, z0), (x1, y1, z1), (x1, y0, z1)],
        [(x0, y0, z1), (x0, y1, z1), (x0, y1, z0), (x0, y0, z0)],
        [(x0, y1, z0), (x0, y1, z1), (x1, y1, z1), (x1, y1, z0)],
        [(x0, y0, z0), (x1, y0, z0), (x1, y0, z1), (x0, y0, z1)],
        [(x0, y0, z1), (x1, y0, z1), (x1, y1, z1), (x0, y1, z1)],
        [(x1, y0, z0), (x0, y0, z0), (x0, y1, z0), (x1, y1, z0)],
    ]
    for quad in faces:
        # Each face its own vertices so the normals stay flat.
        ids = [mesh.vertex(p, uv) for p, uv in zip(quad, [(0, 0), (1, 0), (1, 1), (0, 1)])]
        mesh.indices += [ids[0], ids[1], ids[2], ids[0], ids[2], ids[3]]


def swirl_png(size):
    """Tangent angle / pi of concentric circles round the centre (gles_renderer's swirl)."""
    rows = []
    c = (size - 1) / 2.0
    for y in range(size):
        row = bytearray()
        for x in range(size):
            angle = math.atan2(c - y, x - c) + math.pi / 2.0
            a = (angle % math.pi) / math.pi
            g = int(round(a * 255))
            row += bytes([g, g, g])
        rows.append(bytes(row))
    return png_rgb(size, size, rows)


MATERIALS = [
    # name, LUMAR_materials_lafortune, glTF fallback (base colour, metallic, roughness), emissive
    ("paint", {"diffuseFactor": [0.45, 0.02, 0.02], "specularFactor": [0.05, 0.05, 0.05],
               "lobeFactor": [-1, -1, 1], "exponentFactor": 500.0, "fresnelPhi": 0.2}, [0.5, 0.02, 0.02, 1], 0, 0.2, None),
    ("glass", {"diffuseFactor": [0.0, 0.0, 0.0], "specularFactor": [0.04, 0.04, 0.04],
               "lobeFactor": [-1, -1, 1], "exponentFactor": 4096.0, "fresnelPhi": 0.17}, [0.85, 0.9, 0.95, 1], 0, 0.0, None),
    ("rubber", {"diffuseFactor": [0.035, 0.035, 0.035], "specularFactor": [0.02, 0.02, 0.02],
                "lobeFactor": [-1, -1, 1], "exponentFactor": 4.0, "fresnelPhi": 0.1}, [0.04, 0.04, 0.04, 1], 0, 0.9, None),
    ("chrome", {"diffuseFactor": [0.0, 0.0, 0.0], "specularFactor": [0.95, 0.95, 0.95],
                "lobeFactor": [-1, -1, 1], "exponentFactor": 4096.0, "fresnelPhi": 0.17}, [0.95, 0.95, 0.95, 1], 1, 0.0, None),
    ("brushed_grille", {"diffuseFactor": [0.02, 0.02, 0.02], "specularFactor": [0.8, 0.8, 0.8],
                        "lobeFactor": [-1.0, -0.8, 1.0], "exponentFactor": 200.0, "fresnelPhi": 0.17,
                        "tangentRotation": 1.0, "tangentRotationTexture": {"index": 0}}, [0.8, 0.8, 0.8, 1], 1, 0.3, None),
    ("bumper_plastic", {"diffuseFactor": [0.03, 0.03, 0.03], "specularFactor": [0.05, 0.05, 0.05],
                        "lobeFactor": [-1, -1, 1], "exponentFactor": 60.0, "fresnelPhi": 0.17}, [0.03, 0.03, 0.03, 1], 0, 0.4, None),
    ("headlamp", {"diffuseFactor": [0.1, 0.1, 0.1], "specularFactor": [0.04, 0.04, 0.04],
                  "lobeFactor": [-1, -1, 1], "exponentFactor": 4096.0, "fresnelPhi": 0.17}, [0.1, 0.1, 0.1, 1], 0, 0.0,
     [8.0, 7.5, 6.0]),
]


def build():
    parts = {name: Mesh() for name, *_ in MATERIALS}
    # Body: a long rounded box, flat underneath; the cabin: a smaller one on top, set back.
    superellipsoid(parts["paint"], (0.0, 0.62, 0.0), (0.9, 0.32, 2.1), 0.35, 0.3, 72, 32, y_min=-0.22)
    superellipsoid(parts["glass"], (0.0, 0.98, -0.25), (0.72, 0.3, 1.05), 0.5, 0.45, 40, 14, y_min=-0.05)
    for x in (-0.82, 0.82):
        for z in (-1.35, 1.3):
            torus_x(parts["rubber"], (x, 0.34, z), 0.26, 0.085, 32, 10)
            disc_x(parts["chrome"], (x + (0.1 if x > 0 else -0.1), 0.34, z), 0.25, 24, 1 if x > 0 else -1)
    box(parts["brushed_grille"], (-0.5, 0.42, 2.02), (0.5, 0.62, 2.12))
    box(parts["bumper_plastic"], (-0.85, 0.28, 2.0), (0.85, 0.38, 2.18))
    box(parts["bumper_plastic"], (-0.85, 0.28, -2.18), (0.85, 0.38, -2.0))
    box(parts["chrome"], (0.55, 0.22, -2.25), (0.65, 0.3, -1.9))  # exhaust
    for x in (-0.62, 0.62):
        superellipsoid(parts["headlamp"], (x, 0.66, 2.0), (0.16, 0.08, 0.1), 1.0, 1.0, 16, 8)
    return parts


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else "daemon/assets/models/lumar_roadster.glb"
    parts = build()
    buffer = GlbBuffer()
    add_view = buffer.add_view
    accessors, primitives, materials = [], [], []

    triangles = 0
    for index, (name, lafortune, base, metallic, roughness, emissive) in enumerate(MATERIALS):
        mesh = parts[name]
        normals = mesh.normals()
        pos = b"".join(struct.pack("<3f", *p) for p in mesh.positions)
        nor = b"".join(struct.pack("<3f", *n) for n in normals)
        uvs = b"".join(struct.pack("<2f", *t) for t in mesh.uvs)
        idx = b"".join(struct.pack("<I", i) for i in mesh.indices)
        lo = [min(p[k] for p in mesh.positions) for k in range(3)]
        hi = [max(p[k] for p in mesh.positions) for k in range(3)]
        count = len(mesh.positions)
        accessors.append({"bufferView": add_view(pos, 34962), "componentType": 5126, "count": count, "type": "VEC3",
                          "min": lo, "max": hi})
        accessors.append({"bufferView": add_view(nor, 34962), "componentType": 5126, "count": count, "type": "VEC3"})
        accessors.append({"bufferView": add_view(uvs, 34962), "componentType": 5126, "count": count, "type": "VEC2"})
        accessors.append({"bufferView": add_view(idx, 34963), "componentType": 5125, "count": len(mesh.indices),
                          "type": "SCALAR"})
        a = len(accessors) - 4
        primitives.append({"attributes": {"POSITION": a, "NORMAL": a + 1, "TEXCOORD_0": a + 2}, "indices": a + 3,
                           "material": index})
        triangles += len(mesh.indices) // 3
        material = {"name": name, "pbrMetallicRoughness": {"baseColorFactor": base, "metallicFactor": metallic,
                                                            "roughnessFactor": roughness},
                    "extensions": {"LUMAR_materials_lafortune": lafortune}}
        if name == "glass":
            # See-through (KHR_materials_transmission; the base colour tints the light through):
            # thin-walled, as a car's windows are, so the view goes straight through the cabin.
            material["extensions"]["KHR_materials_transmission"] = {"transmissionFactor": 1.0}
            material["extensions"]["KHR_materials_ior"] = {"ior": 1.5}
        if emissive:
            material["emissiveFactor"] = [1.0, 1.0, 1.0]
            material["extensions"]["KHR_materials_emissive_strength"] = {"emissiveStrength": max(emissive)}
            material["emissiveFactor"] = [e / max(emissive) for e in emissive]
        materials.append(material)

    image_view = add_view(swirl_png(128))
    byte_length = buffer.pad()
    gltf = {
        "asset": {"version": "2.0", "generator": "lumar scripts/make-roadster.py",
                  "copyright": "lumar project; generated, no third-party content"},
        "extensionsUsed": ["LUMAR_materials_lafortune", "KHR_materials_emissive_strength", "KHR_materials_transmission",
                           "KHR_materials_ior"],
        "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"name": "roadster", "mesh": 0}],
        "meshes": [{"name": "roadster", "primitives": primitives}],
        "materials": materials, "accessors": accessors, "bufferViews": buffer.views,
        "buffers": [{"byteLength": byte_length}],
        "images": [{"name": "swirl", "mimeType": "image/png", "bufferView": image_view}],
        "samplers": [{"magFilter": 9729, "minFilter": 9987, "wrapS": 33071, "wrapT": 33071}],
        "textures": [{"sampler": 0, "source": 0}],
    }
    glb = pack_glb(gltf, buffer)
    with open(out, "wb") as f:
        f.write(glb)
    print(f"{out}: {triangles} triangles, {len(MATERIALS)} materials, {len(glb)} bytes")


if __name__ == "__main__":
    main()
