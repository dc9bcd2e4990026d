#!/usr/bin/env python3
"""Mitsuba 3 path-traced references for Himmel's 3D worlds (issue 14, item 5).

Run by hand, never in CI. For each case of a case file (tools/world_cases.json)
it renders, with Mitsuba 3, the world (.glb) lit by

* the sky: an environment light made from Himmel's own equirect EXR of the
  instant with every sky pass (`himmel render --projection equirect --effects
  atmosphere,sun,moon,stars,planets,milkyway --width 1024 --height 512
  --output env.exr --stats stats.json …`: Himmel's moonlit sky is part of the
  atmosphere pass only when `moon` is among the effects) from which the Sun
  and Moon disks are then removed (`remove_disks`): every pixel whose centre
  lies within (angular radius × 1.5 + 1.5 pixel pitches) of the body's
  refracted apparent place (stats `alt_refracted_deg`, `az_deg`,
  `semidiameter_deg`; for an eclipsed Sun, stats `sun.visible_fraction` < 1,
  6 solar radii — the drawn corona's edge — instead of 1.5) takes, per
  channel, the solid-angle-weighted mean of the annulus from that radius to
  twice it. The aureole stays; the disks are the directional lights below;
* the Sun and the Moon: directional lights whose irradiance is Himmel's
  `--stats` `sun.direct_rgb` / `moon.direct_rgb` (lux at normal incidence after
  the atmosphere, linear sRGB) from the direction `alt_refracted_deg`/`az_deg`;

and writes, in absolute units (cd/m², linear sRGB, Y = 0.2126 R + 0.7152 G +
0.0722 B):

* `<case>.exr` — RGB radiance (float32, lossless PIZ compression);
* `<case>_mask.exr` — R = directly lit by the Sun (Moon at night), G = geometry
  present but not directly lit (lit by the sky alone), B = geometry present;
  each 0/1 and eroded by one pixel (see `masks()`);
* `<case>.json` — what was rendered: Mitsuba version and variant, spp, the
  measured noise, the directional lights used, render time.

Setup (Debian 12, 2 cores, no GPU; the LLVM variant is ~10x faster than scalar):

    python3 -m venv /tmp/venv && /tmp/venv/bin/pip install mitsuba numpy   # mitsuba 3.9.1
    apt-get install -y libllvm19      # optional: the llvm_ad_rgb variant
    export DRJIT_LIBLLVM_PATH=/usr/lib/x86_64-linux-gnu/libLLVM.so.19.1   # set by default here
    cargo build --release -p himmel-cli          # the `himmel` binary
    cargo run -p himmel-world --example export_worlds -- tests/fixtures/worlds

Usage (from the repository root):

    /tmp/venv/bin/python tools/world_reference.py --selftest
    /tmp/venv/bin/python tools/world_reference.py --cases tools/world_cases.json \
        --out tests/fixtures/world_ref [--case NAME …] [--himmel target/release/himmel]
        [--min-spp 32 --max-spp 32] [--target-noise 0.01] [--preview DIR]
        [--integrator direct|path] [--validate SPP]

By default the script calls `himmel` itself (`--himmel PATH`, default
`$CARGO_TARGET_DIR/release/himmel` or `target/release/himmel`) to make the
environment and the stats of each case's instant in one render (`--effects
atmosphere,sun,moon,stars,planets,milkyway`, 1024 × 512 equirect, `--stats`;
`direct_rgb` is 0 for a body not among the effects), cached per instant in
`--work` (default /tmp/himmel-world-ref, files `*_env_disks.exr`,
`*_env_disks_stats.json`). `--env EXR --stats JSON` use given files instead
(only with one `--case`); the disks are removed from those too.

Integrator (`--integrator`): `direct` (default) is the estimator of
`direct_pass()` — the same direct-lighting integral as Mitsuba's `path` with
max_depth 2, with Mitsuba's ray tracing, BSDFs and envmap, but exact
directional lights and many stratified, MIS-combined sky samples per hit
(cosine, portals, envmap importance sampling as the case's `sky_sampling`
says); `path` is Mitsuba's stock path tracer (max_depth 2, hide_emitters
false, box filter), ~10⁴× slower to 1 % here. `--validate SPP` also renders
with `path` and prints the masked means of both.

Noise: passes (one primary sample per pixel each; `spp` counts them) go
alternately into two half images A and B; on the sky-lit-only pixels (mask G)
the relative RMS of (Y_A − Y_B) / ((Y_A + Y_B)/2), over the pixels whose mean
is ≥ 1 % of the mask's median, divided by 2 is the noise of the written image
(A + B)/2 (÷ √2: of one half); also the luminance-weighted RMS. Passes
continue until the former is below `--target-noise`, at least `--min-spp`,
at most `--max-spp`.

Conventions checked by `--selftest` (assertions, in scene-free Mitsuba runs):
* Himmel's equirect (column = azimuth/360°·W, azimuth from North through East,
  row = (90° − altitude)/180°·H, North = −z, East = +x, Up = +y) is Mitsuba's
  `envmap` latitude–longitude layout with the *identity* `to_world`: Mitsuba
  maps a local direction d to u = atan2(d.x, −d.z)/2π, v = acos(d.y)/π, i.e.
  u = 0 is −z (North), u = ¼ is +x (East), v = 0 is +y (the zenith). Verified:
  an env with markers at (az 0°, alt 0°), (az 90°, alt 0°) and (az 30°, alt 20°)
  appears at the image centre of a camera looking North, resp. East, and at
  the predicted pixel right of and above the centre (so no mirror either).
* `look_at` cameras are not mirrored: looking North, East is on the right.
* a directional light of irradiance E from altitude h on a horizontal
  Lambertian plane of albedo ρ gives ρ E sin h / π, and a pole's shadow falls
  away from the light's azimuth.
* `remove_disks` replaces a synthetic bright disk by the surrounding sky, and
  the horizontal-illuminance quadrature gives π for L = 1;
* with `himmel` (`--himmel PATH`; skipped with a note without it): for the
  first day ("high") and the first night case of `--cases`, the environment's
  horizontal illuminance ∫ L sin(alt) dΩ over the upper hemisphere, computed
  from the equirect EXR with the disks removed, equals `--stats`
  `sky.horizontal_illuminance_lux` of the same render (Himmel's own sky-dome
  illuminance without the disks) within 1 %.

Mitsuba 3 is BSD-3-Clause (Wenzel Jakob et al.); the worlds are Himmel's own.
"""

import argparse
import json
import math
import os
import struct
import subprocess
import sys
import time

import numpy as np

dr = None  # drjit, once Mitsuba is set up

LLVM = "/usr/lib/x86_64-linux-gnu/libLLVM.so.19.1"
HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.normpath(os.path.join(HERE, ".."))
Y_WEIGHTS = np.array([0.2126, 0.7152, 0.0722])

mi = None  # the mitsuba module, once a variant is set


def setup_mitsuba(variant=None):
    """Imports Mitsuba and sets `variant` (default: llvm_ad_rgb, else scalar_rgb)."""
    global mi, dr
    if os.path.exists(LLVM):
        os.environ.setdefault("DRJIT_LIBLLVM_PATH", LLVM)
    import drjit
    import mitsuba

    mi, dr = mitsuba, drjit
    for v in [variant] if variant else ["llvm_ad_rgb", "scalar_rgb"]:
        try:
            mi.set_variant(v)
            if v.startswith("llvm"):
                # Fails here (not later) when libLLVM cannot be loaded.
                mi.load_dict({"type": "scene"})
            return v
        except Exception as e:  # noqa: BLE001 - report and fall back
            print(f"note: Mitsuba variant {v} unavailable ({e})", file=sys.stderr)
    sys.exit("error: no usable Mitsuba variant")


# --------------------------------------------------------------------------
# glTF 2.0 binary (.glb) reader: numpy only, node transforms applied.

COMPONENT = {5120: np.int8, 5121: np.uint8, 5122: np.int16, 5123: np.uint16,
             5125: np.uint32, 5126: np.float32}
WIDTH = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4, "MAT2": 4, "MAT3": 9, "MAT4": 16}


def read_glb(path):
    """(gltf JSON, BIN chunk bytes) of a .glb file."""
    data = open(path, "rb").read()
    magic, version, length = struct.unpack_from("<4sII", data, 0)
    if magic != b"glTF" or version != 2:
        raise ValueError(f"{path}: not a glTF 2.0 binary")
    off, gltf, binary = 12, None, b""
    while off < min(length, len(data)):
        clen, ctype = struct.unpack_from("<II", data, off)
        chunk = data[off + 8: off + 8 + clen]
        if ctype == 0x4E4F534A:
            gltf = json.loads(chunk.decode("utf-8"))
        elif ctype == 0x004E4942:
            binary = chunk
        off += 8 + clen
    if gltf is None:
        raise ValueError(f"{path}: no JSON chunk")
    return gltf, binary


def accessor(gltf, binary, index):
    """The accessor's data as an (count, width) numpy array."""
    acc = gltf["accessors"][index]
    if "sparse" in acc:
        raise ValueError(f"accessor {index}: sparse accessors are not supported")
    dtype = np.dtype(COMPONENT[acc["componentType"]])
    width, count = WIDTH[acc["type"]], acc["count"]
    view = gltf["bufferViews"][acc["bufferView"]]
    if view.get("buffer", 0) != 0:
        raise ValueError(f"accessor {index}: only the GLB's own buffer is supported")
    start = view.get("byteOffset", 0) + acc.get("byteOffset", 0)
    stride = view.get("byteStride") or dtype.itemsize * width
    rows = np.ndarray((count, width), dtype=dtype, buffer=binary, offset=start,
                      strides=(stride, dtype.itemsize))
    out = rows.astype(np.float64 if dtype == np.float32 else np.int64)
    if acc.get("normalized") and dtype != np.float32:
        out = out / np.iinfo(dtype).max
    return out


def node_matrix(node):
    if "matrix" in node:
        return np.array(node["matrix"], dtype=np.float64).reshape(4, 4).T  # column-major
    t = np.array(node.get("translation", [0, 0, 0]), dtype=np.float64)
    x, y, z, w = node.get("rotation", [0, 0, 0, 1])
    r = np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                  [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                  [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])
    s = np.array(node.get("scale", [1, 1, 1]), dtype=np.float64)
    m = np.eye(4)
    m[:3, :3] = r * s[None, :]
    m[:3, 3] = t
    return m


def material_of(gltf, index):
    """Our reading of a glTF material: the fields world.md names."""
    m = gltf.get("materials", [])[index] if index is not None else {}
    pbr = m.get("pbrMetallicRoughness", {})
    strength = m.get("extensions", {}).get("KHR_materials_emissive_strength", {})
    emissive = np.array(m.get("emissiveFactor", [0, 0, 0]), dtype=np.float64)
    emissive *= strength.get("emissiveStrength", 1.0)
    if "baseColorTexture" in pbr:
        print(f"warning: material {m.get('name', index)}: base-colour texture ignored "
              "(the factor alone is used)", file=sys.stderr)
    return {
        "name": m.get("name", f"material{index}"),
        "base_color": list(pbr.get("baseColorFactor", [1, 1, 1, 1]))[:3],
        "metallic": pbr.get("metallicFactor", 1.0),
        "roughness": pbr.get("roughnessFactor", 1.0),
        "emissive": emissive.tolist(),
    }


def load_world(path):
    """[(material, positions (n,3), normals (n,3) or None, faces (m,3))], one per material."""
    gltf, binary = read_glb(path)
    groups = {}
    scene = gltf["scenes"][gltf.get("scene", 0)] if "scenes" in gltf else {
        "nodes": list(range(len(gltf.get("nodes", []))))}

    def visit(n, parent):
        node = gltf["nodes"][n]
        m = parent @ node_matrix(node)
        if "mesh" in node:
            for prim in gltf["meshes"][node["mesh"]]["primitives"]:
                if prim.get("mode", 4) != 4:
                    print(f"warning: node {n}: non-triangle primitive ignored", file=sys.stderr)
                    continue
                p = accessor(gltf, binary, prim["attributes"]["POSITION"])
                p = p @ m[:3, :3].T + m[:3, 3]
                nrm = None
                if "NORMAL" in prim["attributes"]:
                    nrm = accessor(gltf, binary, prim["attributes"]["NORMAL"])
                    nrm = nrm @ np.linalg.inv(m[:3, :3])  # (M⁻¹)ᵀ applied to rows
                    nrm /= np.maximum(np.linalg.norm(nrm, axis=1, keepdims=True), 1e-30)
                if "indices" in prim:
                    f = accessor(gltf, binary, prim["indices"]).reshape(-1, 3)
                else:
                    f = np.arange(len(p)).reshape(-1, 3)
                if f.size and (f.max() >= len(p) or f.min() < 0):
                    raise ValueError(f"{path}: node {n}: index past the vertices")
                if np.linalg.det(m[:3, :3]) < 0:
                    f = f[:, ::-1]
                groups.setdefault(prim.get("material"), []).append((p, nrm, f))
        for c in node.get("children", []):
            visit(c, m)

    for n in scene["nodes"]:
        visit(n, np.eye(4))
    out = []
    for mat, parts in groups.items():
        base, ps, ns, fs = 0, [], [], []
        with_normals = all(nrm is not None for _, nrm, _ in parts)
        for p, nrm, f in parts:
            ps.append(p)
            ns.append(nrm)
            fs.append(f + base)
            base += len(p)
        out.append((material_of(gltf, mat), np.concatenate(ps),
                    np.concatenate(ns) if with_normals else None, np.concatenate(fs)))
    return out


# --------------------------------------------------------------------------
# Scene construction.

def unit_towards(alt_deg, az_deg):
    """World-frame unit vector towards (altitude, azimuth from North through East)."""
    a, z = math.radians(alt_deg), math.radians(az_deg)
    return np.array([math.cos(a) * math.sin(z), math.sin(a), -math.cos(a) * math.cos(z)])


def bsdf_of(mat):
    rgb = {"type": "rgb", "value": [float(c) for c in mat["base_color"]]}
    if mat["metallic"] <= 0.0 and mat["roughness"] >= 1.0:
        return {"type": "diffuse", "reflectance": rgb}
    return {"type": "principled", "base_color": rgb, "metallic": float(mat["metallic"]),
            "roughness": float(mat["roughness"])}


def mesh_of(name, mat, p, nrm, f):
    props = mi.Properties()
    props["bsdf"] = mi.load_dict(bsdf_of(mat))
    if max(mat["emissive"]) > 0:
        props["emitter"] = mi.load_dict({"type": "area", "radiance": {
            "type": "rgb", "value": [float(e) for e in mat["emissive"]]}})
    mesh = mi.Mesh(name, len(p), len(f), props=props, has_vertex_normals=nrm is not None)
    params = mi.traverse(mesh)
    params["vertex_positions"] = mi.Float(p.astype(np.float32).ravel())
    params["faces"] = mi.UInt32(f.astype(np.uint32).ravel())
    if nrm is not None:
        params["vertex_normals"] = mi.Float(nrm.astype(np.float32).ravel())
    params.update()
    return mesh


def sensor_of(cam, spp=1):
    return {
        "type": "perspective", "fov_axis": "y", "fov": float(cam.get("fov_deg", 60.0)),
        "near_clip": 0.01, "far_clip": 1.0e6,
        "to_world": mi.ScalarTransform4f().look_at(
            origin=[float(v) for v in cam["position_m"]],
            target=[float(v) for v in cam["look_at_m"]],
            up=[float(v) for v in cam.get("up", [0, 1, 0])]),
        "film": {"type": "hdrfilm", "width": int(cam.get("width", 320)),
                 "height": int(cam.get("height", 180)), "rfilter": {"type": "box"},
                 "pixel_format": "rgb", "component_format": "float32"},
        "sampler": {"type": "independent", "sample_count": spp},
    }


def build_scene(case, world, env_rgb, lights, *, with_env=True, with_lights=True, max_depth=2):
    """Mitsuba scene dict; `env_rgb` is Himmel's equirect (H, W, 3) radiance."""
    scene = {"type": "scene", "integrator": {
        "type": "path", "max_depth": max_depth, "hide_emitters": False}}
    scene["sensor"] = sensor_of(case["camera"])
    for i, (mat, p, nrm, f) in enumerate(world):
        scene[f"mesh{i}"] = mesh_of(f"mesh{i}_{mat['name']}", mat, p, nrm, f)
    if case.get("ground"):
        # world.md: an infinite Lambertian plane at y = 0 with atmosphere.ground_albedo
        # (here 20 km square); it coincides with floors at y = 0 (z-fighting).
        albedo = float(case.get("ground_albedo", 0.3))
        scene["ground"] = {"type": "rectangle", "to_world": mi.ScalarTransform4f().rotate(
            [1, 0, 0], -90).scale([1.0e4, 1.0e4, 1.0]),
            "bsdf": {"type": "diffuse", "reflectance": {"type": "rgb", "value": [albedo] * 3}}}
    if with_env and env_rgb is not None:
        # Identity to_world: see the module docstring (--selftest asserts it).
        scene["sky"] = {"type": "envmap", "bitmap": mi.Bitmap(env_rgb.astype(np.float32)),
                        "scale": 1.0}
    if with_lights:
        for name, light in lights.items():
            scene[name] = {"type": "directional",
                           "direction": [float(-c) for c in light["towards"]],
                           "irradiance": {"type": "rgb",
                                          "value": [float(c) for c in light["rgb"]]}}
    return mi.load_dict(scene)


def render(scene, spp, seed):
    img = mi.render(scene, spp=spp, seed=seed)
    return np.array(img, dtype=np.float64)[:, :, :3]


# --------------------------------------------------------------------------
# The direct-lighting estimator (the default integrator, "direct").
#
# Mitsuba's `path` integrator with max_depth 2 (emitter sampling of the
# envmap + BSDF sampling, MIS) converges far too slowly where the sky is seen
# through openings: measured at 128 spp, the sky-lit-only pixels had 65 %
# relative noise in the sun room, 28 % in the atrium, 9 % on the plane
# (1 % would need ~10⁵–10⁶ spp). This estimator computes the same integral,
# L = L_env(camera ray) on a miss, else
#     Σ_lights E · f(ωl)·cos · V(ωl)  +  ∫ L_env(ω) f(ω) cos V(ω) dω,
# with Mitsuba's own ray tracing (Embree), BSDFs (`bsdf.eval`) and envmap
# (`emitter.eval`), but
# * one primary ray per pixel and pass, uniform in the pixel (the box filter),
# * the directional lights evaluated exactly (one shadow ray each),
# * the sky by many stratified samples per primary hit: cosine-weighted
#   hemisphere strata, plus, where the case names them, *portals* (the
#   sun room's window: a rectangle every escaping ray must cross), combined
#   with the balance heuristic over sample counts (multi-sample MIS).
# `--validate` compares it with Mitsuba's stock `path` on the masks.

def frame_rows(si):
    return rows3(si.sh_frame.s), rows3(si.sh_frame.t), rows3(si.sh_frame.n)


def portal_geometry(portal):
    c = np.asarray(portal["corner_m"], dtype=np.float64)
    e1 = np.asarray(portal["edge1_m"], dtype=np.float64)
    e2 = np.asarray(portal["edge2_m"], dtype=np.float64)
    cr = np.cross(e1, e2)
    area = float(np.linalg.norm(cr))
    return c, e1, e2, cr / area, area


def vec3(a):
    a = np.ascontiguousarray(a, dtype=np.float32)
    return mi.Vector3f(mi.Float(a[:, 0]), mi.Float(a[:, 1]), mi.Float(a[:, 2]))


def env_eval(env, w):
    se = dr.zeros(mi.SurfaceInteraction3f, len(w))
    se.wi = -vec3(w)
    return rows3(env.eval(se))


def direct_pass(scene, cam, lights, sky, rng, max_lanes=3_000_000):
    """One pass: one primary sample per pixel. Returns (H, W, 3) radiance."""
    w, h = int(cam.get("width", 320)), int(cam.get("height", 180))
    n = w * h
    sensor, env = scene.sensors()[0], scene.environment()
    pix = np.arange(n)
    u = (pix % w + rng.random(n)) / w
    v = (pix // w + rng.random(n)) / h
    ray, _ = sensor.sample_ray(mi.Float(np.zeros(n)), mi.Float(np.full(n, 0.5)),
                               mi.Point2f(mi.Float(u), mi.Float(v)),
                               mi.Point2f(mi.Float(np.full(n, 0.5)), mi.Float(np.full(n, 0.5))))
    si = scene.ray_intersect(ray)
    hit = np.array(si.is_valid(), dtype=bool)
    img = np.zeros((n, 3))
    if env is not None and not hit.all():
        miss = ~hit
        img[miss] = env_eval(env, rows3(ray.d)[miss])
    hidx = np.nonzero(hit)[0]
    m = len(hidx)
    if m == 0:
        return img.reshape(h, w, 3)
    sih = dr.gather(mi.SurfaceInteraction3f, si, mi.UInt32(hidx))
    ctx = mi.BSDFContext()
    emitter = sih.emitter(scene)
    img[hidx] += rows3(emitter.eval(sih, emitter != None))  # noqa: E711 (Dr.Jit pointer test)
    bsdf = sih.bsdf()
    for light in lights.values():
        lw = vec3(np.tile(np.asarray(light["towards"], dtype=np.float64), (m, 1)))
        f = rows3(bsdf.eval(ctx, sih, sih.to_local(lw)))
        occluded = np.array(scene.ray_test(sih.spawn_ray(lw)), dtype=bool)
        img[hidx] += f * np.asarray(light["rgb"]) * (~occluded)[:, None]
    if env is None:
        return img.reshape(h, w, 3)
    # The sky, in Dr.Jit (one fused kernel per chunk of lanes): per hit,
    # k_cos cosine strata then k_por strata on each portal; each sample
    # weighted by 1 / Σ_s k_s p_s(ω) (balance heuristic over sample counts).
    k_cos = int(sky.get("cosine_samples", 256))
    portals = [portal_geometry(p) for p in sky.get("portals", [])]
    k_por = int(sky.get("portal_samples", 256)) if portals else 0
    k_env = int(sky.get("env_samples", 0))
    e0 = k_cos + k_por * len(portals)  # the first envmap sample of the plan
    total = e0 + k_env
    s_cos = int(round(math.sqrt(k_cos)))
    s_por = int(round(math.sqrt(k_por)))
    s_env = int(round(math.sqrt(k_env)))
    assert s_cos * s_cos == k_cos and s_por * s_por == k_por and s_env * s_env == k_env, \
        "sample counts must be squares"
    sky_sum = dr.zeros(mi.Color3f, m)
    chunk = max(1, min(total, max_lanes // m))
    seed = int(rng.integers(0, 2**31))
    for start in range(0, total, chunk):
        kc = min(chunk, total - start)
        lane = dr.arange(mi.UInt32, m * kc)
        hi = lane // kc
        jj = lane % kc + dr.opaque(mi.UInt32, start)
        pcg = mi.PCG32(size=m * kc, initstate=mi.UInt64(seed + start))
        r1, r2 = pcg.next_float32(), pcg.next_float32()
        sik = dr.gather(mi.SurfaceInteraction3f, sih, hi)
        x = sik.p
        # Cosine-weighted strata (local shading frame).
        jc = mi.Float(jj % s_cos)
        ic = mi.Float(jj // s_cos)
        local_cos = mi.warp.square_to_cosine_hemisphere(
            mi.Point2f((jc + r1) / s_cos, (ic + r2) / s_cos))
        wdir = sik.to_world(local_cos)
        for i, (c, e1, e2, _, _) in enumerate(portals):
            jl = jj - (k_cos + i * k_por)
            this = (jj >= k_cos + i * k_por) & (jj < k_cos + (i + 1) * k_por)
            a_ = (mi.Float(jl % s_por) + r1) / s_por
            b_ = (mi.Float(jl // s_por) + r2) / s_por
            y = mi.Point3f(*[float(c[q]) + a_ * float(e1[q]) + b_ * float(e2[q])
                             for q in range(3)])
            wdir = dr.select(this, dr.normalize(y - x), wdir)
        if k_env:
            # Envmap importance sampling (Mitsuba's luminance warp): the stars
            # and the Milky Way by night, the circumsolar sky by day.
            is_env = jj >= e0
            je = jj - e0
            ds, _ = env.sample_direction(
                sik, mi.Point2f((mi.Float(je % s_env) + r1) / s_env,
                                (mi.Float(je // s_env) + r2) / s_env), is_env)
            wdir = dr.select(is_env, ds.d, wdir)
        local = sik.to_local(wdir)
        denom = k_cos * dr.maximum(mi.Frame3f.cos_theta(local), 0.0) * dr.inv_pi
        for c, e1, e2, nrm, area in portals:
            n_ = mi.Vector3f(*[float(q) for q in nrm])
            dn = dr.dot(wdir, n_)
            ok = dr.abs(dn) > 1e-9
            safe = dr.select(ok, dn, 1.0)
            t = dr.dot(mi.Vector3f(*[float(q) for q in c]) - x, n_) / safe
            q3 = x + t * wdir - mi.Vector3f(*[float(q) for q in c])
            ua = dr.dot(q3, mi.Vector3f(*[float(q) for q in e1])) / float(e1 @ e1)
            vb = dr.dot(q3, mi.Vector3f(*[float(q) for q in e2])) / float(e2 @ e2)
            inside = ok & (t > 0) & (ua >= 0) & (ua <= 1) & (vb >= 0) & (vb <= 1)
            denom += dr.select(inside, k_por * t * t / (area * dr.abs(safe)), 0.0)
        if k_env:
            dq = dr.zeros(mi.DirectionSample3f, m * kc)
            dq.d = wdir
            denom += k_env * env.pdf_direction(sik, dq)
        useful = denom > 0
        f = sik.bsdf().eval(ctx, sik, local, useful)
        free = useful & ~scene.ray_test(sik.spawn_ray(wdir), useful)
        se = dr.zeros(mi.SurfaceInteraction3f, m * kc)
        se.wi = -wdir
        le = env.eval(se, free)
        contrib = dr.select(free, f * le / dr.select(useful, denom, 1.0), 0.0)
        dr.scatter_reduce(dr.ReduceOp.Add, sky_sum, contrib, hi)
        dr.eval(sky_sum)
    sky_sum = rows3(sky_sum)
    img[hidx] += sky_sum
    return img.reshape(h, w, 3)


# --------------------------------------------------------------------------
# Masks by ray casting (16 stratified samples per pixel through the same sensor).

def classify(scene, cam, towards, n_sub=4):
    """Per pixel, over n_sub² stratified sub-samples through the same sensor:
    the fraction hitting geometry, the fraction of them lit by a directional
    light from unit direction `towards` (None: no light), and whether all of
    them lie on one plane (no silhouette, crease or change of surface inside
    the pixel: same geometric normal within 2°, same plane offset within
    1 cm + 0.2 % of the distance)."""
    w, h = int(cam.get("width", 320)), int(cam.get("height", 180))
    sensor = scene.sensors()[0]
    ys, xs, sy, sx = np.meshgrid(np.arange(h), np.arange(w), np.arange(n_sub),
                                 np.arange(n_sub), indexing="ij")
    u = (xs + (sx + 0.5) / n_sub) / w
    v = (ys + (sy + 0.5) / n_sub) / h
    n = u.size
    ray, _ = sensor.sample_ray(mi.Float(np.zeros(n)), mi.Float(np.full(n, 0.5)),
                               mi.Point2f(mi.Float(u.ravel()), mi.Float(v.ravel())),
                               mi.Point2f(mi.Float(np.full(n, 0.5)), mi.Float(np.full(n, 0.5))))
    si = scene.ray_intersect(ray)
    hit = np.array(si.is_valid(), dtype=bool)
    ng = rows3(si.n)
    lit = np.zeros(n, dtype=bool)
    if towards is not None:
        facing_light = ng @ np.asarray(towards, dtype=np.float64) > 0
        facing_cam = np.sum(ng * -rows3(ray.d), axis=1) > 0
        d = mi.Vector3f(*[float(c) for c in towards])
        occluded = np.array(scene.ray_test(si.spawn_ray(d)), dtype=bool)
        # Lit: the camera sees the side facing the light (Mitsuba's BSDFs are
        # one-sided) and nothing blocks the light.
        lit = hit & facing_light & facing_cam & ~occluded
    shape = (h, w, n_sub * n_sub)
    pos = rows3(si.p)
    offset = np.where(hit, np.sum(ng * pos, axis=1), 0.0).reshape(shape)
    dist = np.where(hit, np.array(si.t, dtype=np.float64), 0.0).reshape(shape)
    ng = np.where(hit[:, None], ng, 0.0).reshape(h, w, n_sub * n_sub, 3)
    same_n = np.sum(ng * ng[:, :, :1, :], axis=3) > math.cos(math.radians(2.0))
    same_d = np.abs(offset - offset[:, :, :1]) < 0.01 + 0.002 * dist
    pure = (same_n & same_d).all(axis=2)
    # An edge may pass between the sub-samples of two neighbours: each pixel
    # must also lie on the plane of its 8 neighbours' first sub-samples.
    n0, d0, t0 = ng[:, :, 0, :], offset[:, :, 0], dist[:, :, 0]
    pn = np.pad(n0, ((1, 1), (1, 1), (0, 0)))
    pd = np.pad(d0, 1, constant_values=np.inf)
    for dy in range(3):
        for dx in range(3):
            nb_n, nb_d = pn[dy:dy + h, dx:dx + w], pd[dy:dy + h, dx:dx + w]
            pure &= (np.sum(nb_n * n0, axis=2) > math.cos(math.radians(2.0))) & \
                (np.abs(nb_d - d0) < 0.01 + 0.002 * t0)
    return hit.reshape(shape).mean(axis=2), lit.reshape(shape).mean(axis=2), pure


def rows3(v):
    """A Dr.Jit 3-vector array as numpy rows (n, 3)."""
    a = np.array(v, dtype=np.float64)
    return a.T if a.shape[0] == 3 and a.ndim == 2 and a.shape[1] != 3 else a.reshape(-1, 3)


def erode(mask):
    """True where the pixel and its 8 neighbours are all True (image borders count as False)."""
    p = np.pad(mask, 1, constant_values=False)
    out = np.ones_like(mask)
    h, w = mask.shape
    for dy in range(3):
        for dx in range(3):
            out &= p[dy:dy + h, dx:dx + w]
    return out


def masks(hit, lit, pure):
    """R = fully lit, G = geometry fully present and not lit at all, B = geometry
    fully present (every sub-sample, one plane across the pixel); each then
    eroded by one pixel, so that no pixel next to a silhouette, crease or
    shadow edge counts (aliasing and edge sampling differ between renderers)."""
    geometry = (hit >= 1.0) & pure
    sunlit = geometry & (lit >= 1.0)
    shadowed = geometry & (lit <= 0.0)
    return np.stack([erode(sunlit), erode(shadowed), erode(geometry)], axis=2)


# --------------------------------------------------------------------------
# Output.

def write_exr(path, rgb):
    bmp = mi.Bitmap(np.ascontiguousarray(rgb, dtype=np.float32),
                    pixel_format=mi.Bitmap.PixelFormat.RGB)
    tmp = path + ".tmp.exr"
    bmp.write(tmp)  # OpenEXR, lossless PIZ compression
    os.replace(tmp, path)


def read_exr_rgb(path):
    bmp = mi.Bitmap(path)
    bmp = bmp.convert(mi.Bitmap.PixelFormat.RGB, mi.Struct.Type.Float32, srgb_gamma=False)
    return np.array(bmp, dtype=np.float64)


def luminance(rgb):
    return rgb @ Y_WEIGHTS


# --------------------------------------------------------------------------
# Himmel.

def default_himmel():
    target = os.environ.get("CARGO_TARGET_DIR", os.path.join(ROOT, "target"))
    return os.path.join(target, "release", "himmel")


def himmel_env(himmel, case, work, effects=None, tag="disks"):
    """(env.exr path, stats path) of the case's instant, cached in `work`
    (`effects`: default ENV_EFFECTS; `tag` names the cache files)."""
    effects = effects or ENV_EFFECTS
    key = f"{case['time']}_{case['lat']}_{case['lon']}_{case.get('elevation_m', 0)}"
    key = "".join(c if c.isalnum() or c in "-_." else "_" for c in key)
    # "_disks": made with the Sun and Moon effects (older caches had neither).
    env = os.path.join(work, key + f"_env_{tag}.exr")
    stats = os.path.join(work, key + f"_env_{tag}_stats.json")
    if not (os.path.exists(env) and os.path.exists(stats)):
        os.makedirs(work, exist_ok=True)
        where = ["--time", case["time"], f"--lat={case['lat']}", f"--lon={case['lon']}",
                 f"--elevation={case.get('elevation_m', 0)}", "--projection", "equirect"]
        # The environment: every sky pass, the Sun and the Moon included —
        # Himmel's moonlit sky belongs to the atmosphere pass only when the
        # Moon is among the effects — with --stats of the same render (its
        # sun/moon direct_rgb are 0 unless `sun`/`moon` are among the
        # effects; `sky.horizontal_illuminance_lux` is this sky's own dome
        # illuminance without the disks). The disks are removed afterwards
        # (`remove_disks`). No fixed --exposure: passes invisible at the
        # exposure are skipped; the EXR is absolute either way.
        cmds = [[himmel, "render", *where, "--effects", effects,
                 "--width", "1024", "--height", "512", "--output", env, "--stats", stats]]
        for cmd in cmds:
            print("+", " ".join(cmd), file=sys.stderr)
            subprocess.run(cmd, check=True)
    return env, stats


ENV_EFFECTS = "atmosphere,sun,moon,stars,planets,milkyway"


def equirect_dirs(h, w):
    """Per pixel of a Himmel equirect (h, w): unit direction of its centre
    (world frame) and its solid angle (sr)."""
    az = np.radians(360.0 * (np.arange(w) + 0.5) / w)
    alt_edges = np.radians(90.0 - 180.0 * np.arange(h + 1) / h)
    alt = 0.5 * (alt_edges[:-1] + alt_edges[1:])
    ca, sa = np.cos(alt)[:, None], np.sin(alt)[:, None]
    d = np.stack([ca * np.sin(az)[None, :], np.broadcast_to(sa, (h, w)),
                  -ca * np.cos(az)[None, :]], axis=2)
    domega = (2.0 * math.pi / w) * (np.sin(alt_edges[:-1]) - np.sin(alt_edges[1:]))
    return d, np.broadcast_to(domega[:, None], (h, w)), alt_edges


def disk_regions(stats, h, w):
    """[(name, centre direction, radius rad)]: what `remove_disks` replaces —
    each body's refracted apparent place and angular radius × 1.5 + 1.5 pixel
    pitches; for the Sun during a solar eclipse (stats `sun.visible_fraction`
    < 1) the drawn inner corona's outer edge, 6 solar radii, instead of 1.5."""
    pitch = math.radians(max(360.0 / w, 180.0 / h))
    out = []
    for name in ("sun", "moon"):
        s = stats.get(name) or {}
        if "az_deg" not in s or "semidiameter_deg" not in s:
            continue
        alt = s.get("alt_refracted_deg", s.get("alt_deg"))
        k = 1.5
        if name == "sun" and float(s.get("visible_fraction", 1.0)) < 1.0:
            k = 6.0
        radius = math.radians(float(s["semidiameter_deg"])) * k + 1.5 * pitch
        out.append((name, unit_towards(alt, s["az_deg"]), radius))
    return out


def remove_disks(env, stats):
    """Himmel's equirect `env` (h, w, 3) without the Sun and Moon disks (and
    an eclipse's corona): each pixel whose centre lies within a region of
    `disk_regions` takes, per channel, the solid-angle-weighted mean of the
    annulus from that radius to twice it (the sky around the disk: the
    aureole stays, only the disk goes). Returns (new env, report)."""
    h, w = env.shape[:2]
    d, domega, _ = equirect_dirs(h, w)
    env = np.array(env, dtype=np.float64, copy=True)
    report = {}
    for name, c, r in disk_regions(stats, h, w):
        ang = np.arccos(np.clip(d @ c, -1.0, 1.0))
        inner = ang < r
        ring = (ang >= r) & (ang < 2.0 * r)
        if not inner.any():
            continue
        wr = domega[ring]
        mean = (env[ring] * wr[:, None]).sum(axis=0) / wr.sum()
        before = (env[inner] * domega[inner][:, None]).sum(axis=0)
        env[inner] = mean
        report[name] = {"radius_deg": math.degrees(r), "pixels": int(inner.sum()),
                        "ring_pixels": int(ring.sum()), "ring_mean_rgb": mean.tolist(),
                        "removed_intensity_rgb": (before - mean * domega[inner].sum()).tolist()}
    return env, report


def horizontal_illuminance(env):
    """∫ L sin(alt) dΩ over the upper hemisphere of a Himmel equirect (h, w, 3):
    (lux, linear sRGB triple). Each row's ∫ sin·cos d(alt) is exact."""
    h, w = env.shape[:2]
    _, _, edges = equirect_dirs(h, w)
    wrow = 0.5 * (np.sin(edges[:-1]) ** 2 - np.sin(edges[1:]) ** 2) * (2.0 * math.pi / w)
    up = edges[1:] >= 0.0  # rows wholly above the horizon (h even: exactly the upper half)
    rgb = (env[up] * wrow[up][:, None, None]).sum(axis=(0, 1))
    return float(rgb @ Y_WEIGHTS), rgb.tolist()


def lights_of(stats):
    """Directional lights from Himmel's --stats: name → {towards, rgb, alt, az}."""
    out = {}
    for name in ("sun", "moon"):
        s = stats.get(name) or {}
        rgb = s.get("direct_rgb")
        if rgb is None:
            print(f"warning: stats have no {name}.direct_rgb (is himmel older than "
                  "world.md's --stats additions?)", file=sys.stderr)
            continue
        if float(np.dot(rgb, Y_WEIGHTS)) <= 0.0:
            continue
        alt = s.get("alt_refracted_deg", s.get("alt_deg"))
        out[name] = {"towards": unit_towards(alt, s["az_deg"]).tolist(),
                     "rgb": [float(c) for c in rgb], "alt_refracted_deg": alt,
                     "az_deg": s["az_deg"]}
    return out


# --------------------------------------------------------------------------
# One case.

def noise_of(a, b, sel):
    """Noise of (A + B)/2 from two independent half images A, B on the pixels
    `sel`: (per-pixel relative RMS, luminance-weighted RMS, pixels used).
    The per-pixel measure is the RMS of (Y_A − Y_B)/((Y_A + Y_B)/2) over the
    pixels whose mean is at least 1 % of the selection's median (pixels the
    sky barely reaches — under arches, beside window reveals — have ~0
    radiance and an undefined relative error), divided by 2; the weighted one
    is RMS(Y_A − Y_B) / mean((Y_A + Y_B)/2) over all of `sel`, divided by 2
    (the noise that a luminance-weighted error like mean|ΔY| / mean Y sees)."""
    ya, yb = luminance(a)[sel], luminance(b)[sel]
    mean = 0.5 * (ya + yb)
    if mean.size == 0 or mean.max() <= 0:
        return float("nan"), float("nan"), 0
    ok = mean >= 0.01 * np.median(mean[mean > 0])
    d = (ya[ok] - yb[ok]) / mean[ok]
    rel = float(np.sqrt(np.mean(d * d))) / 2.0
    weighted = float(np.sqrt(np.mean((ya - yb) ** 2)) / mean.mean()) / 2.0
    return rel, weighted, int(ok.sum())


def run_case(case, args, env_path, stats_path):
    t0 = time.time()
    stats = json.load(open(stats_path))
    lights = lights_of(stats)
    env, removed = remove_disks(read_exr_rgb(env_path), stats)
    for name, r in removed.items():
        print(f"  {case['name']}: {name} disk removed from the environment: {r['pixels']} "
              f"pixels within {r['radius_deg']:.3f} deg", file=sys.stderr)
    world = load_world(os.path.join(ROOT, case["world"]))
    scene = build_scene(case, world, env, lights, max_depth=case.get("max_depth", 2))
    # The mask's light: the brightest directional light (the Sun by day, the Moon at night).
    main = max(lights.items(), key=lambda kv: np.dot(kv[1]["rgb"], Y_WEIGHTS))[0] \
        if lights else None
    hit, lit, pure = classify(scene, case["camera"], lights[main]["towards"] if main else None)
    m = masks(hit, lit, pure)
    if main:
        # Cross-check with a render lit by that light alone (value > 0 ⇔ lit).
        only = build_scene(case, world, None, {main: lights[main]}, with_env=False)
        y = luminance(render(only, 16, 12345))
        bad = (m[:, :, 0] & (y <= 0)) | (m[:, :, 1] & (y > 0))
        assert not bad.any(), f"{case['name']}: mask disagrees with the light-only render " \
                              f"at {int(bad.sum())} pixels"
    sel = m[:, :, 1] if m[:, :, 1].sum() >= 50 else m[:, :, 2]
    noise_pixels = "G (sky-lit only)" if sel is m[:, :, 1] else "B (all geometry)"
    h, w = m.shape[:2]
    acc = [np.zeros((h, w, 3)), np.zeros((h, w, 3))]
    sky = case.get("sky_sampling", {})
    if args.integrator == "path":
        step, check = args.batch_spp, 2  # spp per batch, batches per noise check
    else:
        step, check = 1, 8  # one primary sample per pass
    spp, k, noise, noise_w, n_noise = 0, 0, float("inf"), float("inf"), 0
    while True:
        if args.integrator == "path":
            acc[k % 2] += render(scene, step, 1000 + k)
        else:
            acc[k % 2] += direct_pass(scene, case["camera"], lights, sky,
                                      np.random.default_rng(1000 + k))
        spp += step
        k += 1
        if k % check == 0:
            noise, noise_w, n_noise = noise_of(acc[0], acc[1], sel)  # of (A + B)/2
            print(f"  {case['name']}: {spp} spp, noise {100 * noise:.2f} % "
                  f"(weighted {100 * noise_w:.2f} %), "
                  f"{time.time() - t0:.0f} s", file=sys.stderr)
            if spp >= args.max_spp or (spp >= args.min_spp and noise < args.target_noise):
                break
    img = (acc[0] + acc[1]) / k
    half_noise = noise * math.sqrt(2.0)
    validation = validate(case, scene, img, m, args.validate) if args.validate else None
    os.makedirs(args.out, exist_ok=True)
    write_exr(os.path.join(args.out, case["name"] + ".exr"), img)
    write_exr(os.path.join(args.out, case["name"] + "_mask.exr"), m.astype(np.float32))
    meta = {
        "case": case["name"], "mitsuba": mi.__version__, "variant": mi.variant(),
        "integrator": {"type": "path", "max_depth": case.get("max_depth", 2),
                       "hide_emitters": False} if args.integrator == "path" else
        {"type": "direct (tools/world_reference.py: Mitsuba ray tracing, BSDFs, envmap)",
         "sky_sampling": {"cosine_samples": int(sky.get("cosine_samples", 256)),
                          "portals": sky.get("portals", []),
                          "portal_samples": int(sky.get("portal_samples", 256))
                          if sky.get("portals") else 0,
                          "env_samples": int(sky.get("env_samples", 0))},
         "sky_samples_per_pixel": spp * (int(sky.get("cosine_samples", 256)) + len(
             sky.get("portals", [])) * int(sky.get("portal_samples", 256))
             + int(sky.get("env_samples", 0)))},
        "spp": spp, "noise_rel_rms": round(noise, 5),
        "noise_rel_rms_half": round(half_noise, 5), "noise_pixels": noise_pixels,
        "noise_pixels_used": n_noise, "noise_weighted_rms": round(noise_w, 5),
        "mask_pixels": {"R": int(m[:, :, 0].sum()), "G": int(m[:, :, 1].sum()),
                        "B": int(m[:, :, 2].sum())},
        "mask_light": main,
        "lights": lights,
        "sky_horizontal_illuminance_lux": (stats.get("sky") or {}).get(
            "horizontal_illuminance_lux"),
        "env_effects": ENV_EFFECTS if env_path.endswith("_env_disks.exr") else None,
        "env_horizontal_illuminance_lux": horizontal_illuminance(env)[0],
        "env_disks_removed": {k: {"radius_deg": round(v["radius_deg"], 4), "pixels": v["pixels"]}
                              for k, v in removed.items()},
        "render_s": round(time.time() - t0, 1),
        "validation_vs_path": validation,
        "himmel_time_utc": stats.get("time_utc"),
    }
    with open(os.path.join(args.out, case["name"] + ".json"), "w") as fh:
        json.dump(meta, fh, indent=1)
        fh.write("\n")
    if args.preview:
        write_preview(os.path.join(args.preview, case["name"] + ".png"), img, m)
    return meta


def validate(case, scene, img, m, spp):
    """Mean luminance over each mask: this image vs Mitsuba's stock `path`
    (max_depth 2, MIS) at `spp`; the relative difference and the path
    render's standard error of that mean (from two half renders)."""
    a = render(scene, spp // 2, 777)
    b = render(scene, spp // 2, 778)
    ref = 0.5 * (a + b)
    out = {"path_spp": spp}
    for ch, name in enumerate("RGB"):
        sel = m[:, :, ch]
        if sel.sum() == 0:
            continue
        mean_path, mean_here = luminance(ref)[sel].mean(), luminance(img)[sel].mean()
        # Standard error of the path render's masked mean: half the spread of the halves.
        se = abs(luminance(a)[sel].mean() - luminance(b)[sel].mean()) / 2.0
        diff = (mean_here - mean_path) / mean_path
        out[name] = {"pixels": int(sel.sum()), "mean_path": round(float(mean_path), 6),
                     "mean_direct": round(float(mean_here), 6), "rel_diff": round(float(diff), 5),
                     "path_rel_std_err_approx": round(float(se / mean_path), 5)}
        print(f"  validate {name}: direct {mean_here:.5g} vs path {mean_path:.5g} "
              f"({100 * diff:+.2f} %, path ±{100 * se / mean_path:.2f} %)", file=sys.stderr)
    return out


def write_preview(path, img, m):
    """A tone-mapped PNG beside the masks (for eyes only)."""
    os.makedirs(os.path.dirname(path), exist_ok=True)
    y = luminance(img)
    scale = 0.18 / max(np.median(y[y > 0]) if (y > 0).any() else 1.0, 1e-12)
    v = np.clip(img * scale, 0, 1)
    v = np.where(v <= 0.0031308, 12.92 * v, 1.055 * np.power(v, 1 / 2.4) - 0.055)
    both = np.concatenate([v, m.astype(np.float64)], axis=1)
    mi.Bitmap(np.ascontiguousarray((both * 255 + 0.5).astype(np.uint8)),
              pixel_format=mi.Bitmap.PixelFormat.RGB).write(path)


# --------------------------------------------------------------------------
# Self-test of the conventions (no Himmel needed).

def selftest_env(args):
    """The environment against Himmel's own figure: for the first day ("high")
    and night case of the case file, ∫ L sin(alt) dΩ over the upper hemisphere
    of the equirect, disks removed, must be `--stats`
    `sky.horizontal_illuminance_lux` of the same render (the sky dome without
    the disks, Sun-lit and Moon-lit) within 1 %. That figure leaves out the
    night passes (stars, planets, Milky Way, diffuse night-sky light: +1.7 %
    of it on the moonlit night of tools/world_cases.json), so the assertion
    is on the environment rendered with `atmosphere,sun,moon` alone (disks
    removed likewise); the full environment's figure and the night passes'
    share are printed beside it. Needs `himmel`."""
    # remove_disks on a synthetic map: a constant sky with a bright disk.
    h, w = 512, 1024
    stats = {"sun": {"alt_refracted_deg": 30.0, "az_deg": 120.0, "semidiameter_deg": 0.27},
             "moon": {"alt_refracted_deg": 60.0, "az_deg": 300.0, "semidiameter_deg": 0.25}}
    env = np.full((h, w, 3), [1.0, 2.0, 3.0])
    d, _, _ = equirect_dirs(h, w)
    for name in ("sun", "moon"):
        c = unit_towards(stats[name]["alt_refracted_deg"], stats[name]["az_deg"])
        env[np.arccos(np.clip(d @ c, -1, 1)) < math.radians(0.3)] = 1.0e6
    clean, rep = remove_disks(env, stats)
    assert np.allclose(clean, [1.0, 2.0, 3.0]), "remove_disks left disk pixels"
    assert all(r["pixels"] > 0 for r in rep.values()) and len(rep) == 2
    e, _ = horizontal_illuminance(np.ones((h, w, 3)))
    assert abs(e / math.pi - 1.0) < 1e-9, f"∫ sin dΩ of L = 1 gives {e}, not π"
    print("selftest: remove_disks and the horizontal-illuminance quadrature OK", file=sys.stderr)
    if not os.path.exists(args.himmel):
        print(f"selftest: SKIPPED the environment vs --stats check ({args.himmel} "
              "not found; --himmel PATH)", file=sys.stderr)
        return
    cases = json.load(open(args.cases))["cases"]
    picked = [next(c for c in cases if c.get("condition") == k) for k in ("high", "night")]
    failed = []
    for case in picked:
        env_path, stats_path = himmel_env(args.himmel, case, args.work)
        stats = json.load(open(stats_path))
        raw = read_exr_rgb(env_path)
        clean, rep = remove_disks(raw, stats)
        e_raw, _ = horizontal_illuminance(raw)
        e_env, _ = horizontal_illuminance(clean)
        # The same without the night passes (stars, planets, Milky Way and the
        # diffuse night-sky light): `sky.horizontal_illuminance_lux` is the
        # atmosphere's sky-view radiance alone (skymodel frame::lights::
        # sky_horizontal_rgb), so this is the like-for-like figure.
        atm_path, _ = himmel_env(args.himmel, case, args.work, "atmosphere,sun,moon", "atm")
        e_atm, _ = horizontal_illuminance(remove_disks(read_exr_rgb(atm_path), stats)[0])
        e_him = float(stats["sky"]["horizontal_illuminance_lux"])
        rel, rel_atm = e_env / e_him - 1.0, e_atm / e_him - 1.0
        regions = ", ".join(f"{k} {v['pixels']} px within {v['radius_deg']:.3f} deg"
                            for k, v in rep.items()) or "none above the horizon"
        print(f"selftest: {case['condition']} {case['time']}: stats "
              f"sky.horizontal_illuminance_lux {e_him:.6g}; environment "
              f"({ENV_EFFECTS}, disks removed) E_h {e_env:.6g} lux ({100 * rel:+.3f} %; "
              f"with the disks {e_raw:.6g}); without the night passes "
              f"(atmosphere,sun,moon) {e_atm:.6g} lux ({100 * rel_atm:+.3f} %); the night "
              f"passes add {e_env - e_atm:.4g} lux ({100 * (e_env - e_atm) / e_him:.3f} % of "
              f"the stats figure); removed: {regions}", file=sys.stderr)
        if not abs(rel_atm) < 0.01:
            failed.append(f"{case['condition']}: {100 * rel_atm:+.3f} %")
        if not abs(rel) < 0.01:
            print(f"selftest: NOTE {case['condition']}: the full environment differs from "
                  f"the stats figure by {100 * rel:+.3f} % — the night passes, which "
                  "Himmel's sky.horizontal_illuminance_lux leaves out", file=sys.stderr)
    assert not failed, "environment (atmosphere, Sun and Moon passes, disks removed) " \
        "horizontal illuminance off --stats by more than 1 %: " + "; ".join(failed)
    print("selftest: environment horizontal illuminance within 1 % of --stats OK",
          file=sys.stderr)


def selftest():
    w, h = 64, 32
    env = np.zeros((h, w, 3), dtype=np.float32)

    def mark(x, y, rgb):
        """Lights env pixel (x, y); returns its centre's (azimuth, altitude)."""
        env[y, x] = rgb
        return 360.0 * (x + 0.5) / w, 90.0 - 180.0 * (y + 0.5) / h

    n_az, n_alt = mark(0, 15, [1, 0, 0])   # North on the horizon: red
    e_az, e_alt = mark(16, 15, [0, 1, 0])  # East on the horizon: green
    b_az, b_alt = mark(5, 11, [0, 0, 1])   # NNE and up (31°, 25°): blue
    cam = {"width": 201, "height": 201, "fov_deg": 90.0, "position_m": [0, 0, 0], "up": [0, 1, 0]}

    def look(az, alt=0.0):
        c = dict(cam, look_at_m=unit_towards(alt, az).tolist())
        s = mi.load_dict({"type": "scene", "sensor": sensor_of(c),
                          "integrator": {"type": "path", "max_depth": 1},
                          "sky": {"type": "envmap", "bitmap": mi.Bitmap(env)}})
        return render(s, 4, 0)

    def centroid(img, ch):
        wgt = img[:, :, ch] * (img[:, :, ch] > 0.5 * img[:, :, ch].max())
        ys, xs = np.mgrid[0:img.shape[0], 0:img.shape[1]]
        return (xs * wgt).sum() / wgt.sum() + 0.5, (ys * wgt).sum() / wgt.sum() + 0.5

    def expect(img, ch, az, alt, cam_az, tol=3.0):
        """The marker's centroid is the pinhole projection of (az, alt) for a
        camera looking at (cam_az, 0) with up = +y, right = forward × up."""
        d = unit_towards(alt, az)
        f = unit_towards(0.0, cam_az)
        right = np.cross(f, [0, 1, 0])
        up = np.cross(right, f)
        k = (cam["height"] / 2) / math.tan(math.radians(cam["fov_deg"]) / 2)
        px = cam["width"] / 2 + k * np.dot(d, right) / np.dot(d, f)
        py = cam["height"] / 2 - k * np.dot(d, up) / np.dot(d, f)
        cx, cy = centroid(img, ch)
        assert abs(cx - px) < tol and abs(cy - py) < tol, \
            f"marker {ch}: at ({cx:.1f}, {cy:.1f}), expected ({px:.1f}, {py:.1f})"
        return cx, cy

    north = look(0.0)
    expect(north, 0, n_az, n_alt, 0.0)
    bx, by = expect(north, 2, b_az, b_alt, 0.0)
    assert bx > cam["width"] / 2 and by < cam["height"] / 2, "NNE marker must be right of and above the centre"
    assert north[:, :, 1].max() == 0, "East must be out of view looking North"
    east = look(90.0)
    expect(east, 1, e_az, e_alt, 90.0)
    print("selftest: envmap orientation and camera handedness OK", file=sys.stderr)

    # Directional light: a plane and a pole.
    alt, az, e, rho = 30.0, 90.0, 1000.0, 0.5
    towards = unit_towards(alt, az)
    case = {"name": "selftest", "camera": {"width": 64, "height": 64, "fov_deg": 40.0,
                                           "position_m": [0, 20, 0.001], "look_at_m": [0, 0, 0]}}
    plane = ({"name": "plane", "base_color": [rho] * 3, "metallic": 0.0, "roughness": 1.0,
              "emissive": [0, 0, 0]},
             np.array([[-50, 0, 50], [50, 0, 50], [50, 0, -50], [-50, 0, -50]], dtype=np.float64),
             None, np.array([[0, 1, 2], [0, 2, 3]]))
    pole_p = np.array([[-1, 0, -1], [1, 0, -1], [1, 0, 1], [-1, 0, 1],
                       [-1, 4, -1], [1, 4, -1], [1, 4, 1], [-1, 4, 1]], dtype=np.float64) * 0.6
    pole_f = np.array([[0, 4, 5], [0, 5, 1], [1, 5, 6], [1, 6, 2], [2, 6, 7], [2, 7, 3],
                       [3, 7, 4], [3, 4, 0], [4, 7, 6], [4, 6, 5]])
    pole = (dict(plane[0], name="pole"), pole_p, None, pole_f)
    lights = {"sun": {"towards": towards.tolist(), "rgb": [e, e, e]}}
    s = build_scene(case, [plane, pole], None, lights, with_env=False)
    img = render(s, 16, 0)
    expected = rho * e * math.sin(math.radians(alt)) / math.pi
    corner = img[2:10, 2:10, 0].mean()
    assert abs(corner / expected - 1) < 1e-3, f"plane radiance {corner}, expected {expected}"
    hit, lit, pure = classify(s, case["camera"], towards)
    m = masks(hit, lit, pure)
    # Looking down from above (image up = −z, North; right = +x, East) the shadow
    # of a pole lit from the East falls West: left of the centre.
    row = m[32, :, 1]
    west, east = row[:27].any(), row[38:].any()
    assert west and not east, f"shadow west {west}, east {east}"
    y = luminance(img)
    assert (y[m[:, :, 1]] == 0).all() and (y[m[:, :, 0]] > 0).all()
    print(f"selftest: directional light ({corner:.3f} vs {expected:.3f} cd/m²) and shadow OK",
          file=sys.stderr)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--cases", default=os.path.join(HERE, "world_cases.json"))
    ap.add_argument("--case", action="append", help="case name (repeatable; default all)")
    ap.add_argument("--out", default=os.path.join(ROOT, "tests", "fixtures", "world_ref"))
    ap.add_argument("--work", default="/tmp/himmel-world-ref")
    ap.add_argument("--himmel", default=default_himmel())
    ap.add_argument("--env", help="Himmel equirect EXR (with --stats; one --case)")
    ap.add_argument("--stats", help="Himmel --stats JSON (with --env)")
    ap.add_argument("--variant")
    ap.add_argument("--target-noise", type=float, default=0.007)
    ap.add_argument("--integrator", choices=["direct", "path"], default="direct",
                    help="direct: the estimator above (default); path: Mitsuba's stock path tracer")
    ap.add_argument("--min-spp", type=int, default=32, help="primary samples per pixel (direct) or spp")
    ap.add_argument("--max-spp", type=int, default=512)
    ap.add_argument("--batch-spp", type=int, default=64, help="spp per batch (path)")
    ap.add_argument("--validate", type=int, metavar="SPP",
                    help="also render with Mitsuba's path at SPP and compare the masked means")
    ap.add_argument("--preview", help="folder for tone-mapped PNG previews")
    ap.add_argument("--selftest", action="store_true")
    args = ap.parse_args()
    variant = setup_mitsuba(args.variant)
    print(f"Mitsuba {mi.__version__}, variant {variant}", file=sys.stderr)
    if args.selftest:
        selftest()
        selftest_env(args)
        return
    cases = json.load(open(args.cases))["cases"]
    if args.case:
        names = {c["name"] for c in cases}
        unknown = set(args.case) - names
        if unknown:
            sys.exit(f"error: --case: unknown {sorted(unknown)}; known {sorted(names)}")
        cases = [c for c in cases if c["name"] in args.case]
    if (args.env is None) != (args.stats is None) or (args.env and len(cases) != 1):
        sys.exit("error: --env and --stats go together, with exactly one --case")
    for case in cases:
        env, stats = (args.env, args.stats) if args.env else himmel_env(args.himmel, case, args.work)
        meta = run_case(case, args, env, stats)
        print(json.dumps({k: meta[k] for k in ("case", "spp", "noise_rel_rms", "render_s")}))


if __name__ == "__main__":
    main()
