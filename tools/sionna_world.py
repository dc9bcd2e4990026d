#!/usr/bin/env python3
"""Convert a city scene of the PyPI package `sionna-rt` (OpenStreetMap-derived
meshes, Apache-2.0; map data (c) OpenStreetMap contributors, ODbL) into a
binary glTF 2.0 world that `himmel render --world` loads.

    pip download sionna-rt==2.2.0 --no-deps -d /tmp/sionna
    python3 tools/sionna_world.py /tmp/sionna/sionna_rt-2.2.0-py3-none-any.whl \
        --scene munich --radius 110 --out tests/fixtures/worlds/munich_marienplatz.glb

The wheel is read as a zip: no sionna (nor TensorFlow, Mitsuba) needed.

* Frame: sionna's scenes are z up with x east and y north, metres; Himmel's
  world frame is x East, y Up, z South (shared/spec/world.md), so
  (x, y, z) -> (x, z, -y).
* `--radius` keeps the triangles whose centroid lies within that many metres
  (horizontally) of `--centre` (default 0, 0: the scene's origin, which for
  `munich` is Marienplatz); the ground plane ("Plane") is cut to the same
  square instead, so the world still has a floor.
* Materials: sionna's are ITU radio materials (permittivity, no colours).
  Each becomes a glTF metallic-roughness material with a base colour typical
  of that building material in daylight (our choice, listed in MATERIALS;
  diffuse albedos 0.1-0.6 as measured for such surfaces), so the world is lit
  plausibly, not measured.
* Every triangle keeps its own three vertices and its face normal (the scenes
  ask for face normals; shared vertices at a building's corners would be
  smoothed by a loader that computes vertex normals).
"""

import argparse
import json
import re
import struct
import sys
import zipfile

import numpy as np

# ITU material -> (base colour, linear sRGB; metallic; roughness).
MATERIALS = {
    "marble": ((0.62, 0.58, 0.52), 0.0, 0.6),  # light facade stone/plaster
    "concrete": ((0.45, 0.45, 0.43), 0.0, 0.9),
    "brick": ((0.40, 0.18, 0.12), 0.0, 0.9),
    "wood": ((0.30, 0.19, 0.10), 0.0, 0.8),
    "metal": ((0.35, 0.30, 0.28), 0.0, 0.7),  # roofs: weathered tiles/copper read as dull
    "glass": ((0.05, 0.05, 0.06), 0.0, 0.1),
    "medium_dry_ground": ((0.18, 0.17, 0.16), 0.0, 0.95),  # paved square
    "ground": ((0.18, 0.17, 0.16), 0.0, 0.95),
}


def read_ply(data):
    """Vertices (N, 3) and triangles (M, 3) of a binary little-endian PLY whose
    vertices have float properties, x, y, z among them, and whose faces are
    `list uchar int vertex_indices` polygons (fanned into triangles)."""
    end = data.index(b"end_header\n") + len(b"end_header\n")
    header = data[:end].decode("ascii")
    if "binary_little_endian" not in header:
        raise ValueError("not a binary little-endian PLY")
    nv = int(re.search(r"element vertex (\d+)", header).group(1))
    nf = int(re.search(r"element face (\d+)", header).group(1))
    vertex_part = header.split("element vertex")[1].split("element face")[0]
    props = re.findall(r"property (\w+) (\w+)", vertex_part)
    if any(t != "float" for t, _ in props):
        raise ValueError(f"vertex properties not all float: {props}")
    names = [n for _, n in props]
    v = np.frombuffer(data, dtype="<f4", count=nv * len(names), offset=end).reshape(nv, len(names))
    xyz = v[:, [names.index("x"), names.index("y"), names.index("z")]].astype(np.float64)
    pos = end + nv * len(names) * 4
    tris = []
    for _ in range(nf):
        k = data[pos]
        idx = struct.unpack_from(f"<{k}i", data, pos + 1)
        pos += 1 + 4 * k
        for j in range(1, k - 1):
            tris.append((idx[0], idx[j], idx[j + 1]))
    return xyz, np.array(tris, dtype=np.int64).reshape(-1, 3)


def scene_shapes(z, scene):
    """(PLY path in the wheel, material type) for each shape of the scene."""
    base = f"sionna/rt/scenes/{scene}/"
    xml = z.read(base + f"{scene}.xml").decode()
    types = dict(
        re.findall(r'<bsdf type="itu-radio-material" id="([^"]+)">\s*<string name="type" value="([^"]+)"', xml)
    )
    shapes = []
    for body in re.findall(r'<shape type="ply"[^>]*>(.*?)</shape>', xml, re.S):
        f = re.search(r'name="filename" value="([^"]+)"', body).group(1)
        m = re.search(r'<ref id="([^"]+)" name="bsdf"', body).group(1)
        shapes.append((base + f, types.get(m, m)))
    return shapes


def to_himmel(xyz):
    return np.stack([xyz[:, 0], xyz[:, 2], -xyz[:, 1]], axis=1)


def convert(wheel, scene, centre, radius):
    """Per material type: (positions (K, 3), normals (K, 3)) of flat triangles."""
    out = {}
    with zipfile.ZipFile(wheel) as z:
        for path, mat in scene_shapes(z, scene):
            xyz, tris = read_ply(z.read(path))
            if len(tris) == 0:
                continue
            p = to_himmel(xyz - np.array([centre[0], centre[1], 0.0]))
            tri = p[tris]  # (M, 3, 3)
            c = tri.mean(axis=1)
            if path.endswith(("/Plane.ply", "/ground.ply")):
                tri = np.clip(tri, [-radius, -1e9, -radius], [radius, 1e9, radius])
                keep = np.ones(len(tri), bool)
            else:
                keep = np.hypot(c[:, 0], c[:, 2]) <= radius
            tri = tri[keep]
            n = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
            area = np.linalg.norm(n, axis=1)
            ok = area > 1e-9
            tri, n = tri[ok], n[ok] / area[ok, None]
            if len(tri) == 0:
                continue
            pos, nor = out.setdefault(mat, ([], []))
            pos.append(tri.reshape(-1, 3))
            nor.append(np.repeat(n, 3, axis=0))
    return {m: (np.concatenate(p), np.concatenate(q)) for m, (p, q) in out.items()}


def write_glb(meshes, path, credit):
    bin_parts, views, accessors, materials, prims = [], [], [], [], []
    offset = 0

    def add(arr, target):
        nonlocal offset
        b = arr.astype("<f4").tobytes()
        views.append({"buffer": 0, "byteOffset": offset, "byteLength": len(b), "target": target})
        bin_parts.append(b)
        offset += len(b)
        return len(views) - 1

    for mat, (pos, nor) in sorted(meshes.items()):
        colour, metallic, rough = MATERIALS.get(mat, MATERIALS["concrete"])
        materials.append(
            {
                "name": mat,
                "pbrMetallicRoughness": {
                    "baseColorFactor": [*colour, 1.0],
                    "metallicFactor": metallic,
                    "roughnessFactor": rough,
                },
                "doubleSided": True,
            }
        )
        pos_acc = len(accessors)
        pv = add(pos, 34962)
        accessors.append(
            {
                "bufferView": pv,
                "componentType": 5126,
                "count": len(pos),
                "type": "VEC3",
                "min": pos.min(axis=0).tolist(),
                "max": pos.max(axis=0).tolist(),
            }
        )
        nv = add(nor, 34962)
        accessors.append({"bufferView": nv, "componentType": 5126, "count": len(nor), "type": "VEC3"})
        prims.append({"attributes": {"POSITION": pos_acc, "NORMAL": pos_acc + 1}, "material": len(materials) - 1})
    doc = {
        "asset": {"version": "2.0", "generator": "himmel tools/sionna_world.py", "copyright": credit},
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0, "name": "city"}],
        "meshes": [{"primitives": prims}],
        "materials": materials,
        "buffers": [{"byteLength": offset}],
        "bufferViews": views,
        "accessors": accessors,
    }
    js = json.dumps(doc, separators=(",", ":")).encode()
    js += b" " * (-len(js) % 4)
    binary = b"".join(bin_parts)
    binary += b"\0" * (-len(binary) % 4)
    total = 12 + 8 + len(js) + 8 + len(binary)
    with open(path, "wb") as f:
        f.write(struct.pack("<III", 0x46546C67, 2, total))
        f.write(struct.pack("<II", len(js), 0x4E4F534A))
        f.write(js)
        f.write(struct.pack("<II", len(binary), 0x004E4942))
        f.write(binary)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("wheel", help="the sionna-rt wheel (a zip)")
    ap.add_argument("--scene", default="munich")
    ap.add_argument("--centre", type=float, nargs=2, default=[0.0, 0.0], metavar=("X", "Y"),
                    help="sionna x (east) and y (north), metres")
    ap.add_argument("--radius", type=float, default=110.0, help="metres kept about the centre")
    ap.add_argument("--out", required=True)
    a = ap.parse_args()
    meshes = convert(a.wheel, a.scene, a.centre, a.radius)
    if not meshes:
        sys.exit("no triangles within the radius")
    credit = (f"sionna-rt scene '{a.scene}' (Apache-2.0), map data (c) OpenStreetMap contributors (ODbL); "
              f"cut to {a.radius:g} m about ({a.centre[0]:g}, {a.centre[1]:g})")
    write_glb(meshes, a.out, credit)
    n = sum(len(p) // 3 for p, _ in meshes.values())
    print(f"{a.out}: {n} triangles, materials {sorted(meshes)}")


if __name__ == "__main__":
    main()
