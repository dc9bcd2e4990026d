#!/usr/bin/env python3
"""Mitsuba 3 ambient-occlusion references (issue 16, item 5).

Run by hand, never in CI; an extension of tools/world_reference.py (whose
glTF loading, meshes, camera and masks it uses). For each named case of
tools/world_cases.json it traces, with Mitsuba's ray tracing:

* for every pixel, the primary ray through the pixel's centre (Mitsuba's
  `perspective` sensor of the case's camera, as world_reference.py builds it:
  Himmel's G-buffer rasterises pixel centres with the same camera);
* at its hit, the shading normal n (turned towards the camera, as Himmel's
  G-buffer stores it), and `--rays` cosine-weighted directions over n's
  hemisphere (stratified over a √rays × √rays grid per pixel, each cell
  jittered), each tested for a blocker closer than `--radius` metres
  (`ray_test` with maxt = radius, the origin moved off the surface along the
  geometric normal by 1e-4 × (1 + |p|) m);
* AO = the unoccluded fraction = (1/π) ∫ V_R(ω) (n·ω) dω, the quantity
  Himmel's `lighting.ao` passes estimate.

Writes to --out (tests/fixtures/ao_ref):

* `<case>_ao.exr` — AO in R, G and B (0 where there is no geometry);
* `<case>_ao_mask.exr` — world_reference.py's masks (B: geometry over the
  whole pixel on one plane, eroded by one pixel);
* `<case>_ao.json` — radius, rays, the noise (binomial standard error,
  mean and max over the masked pixels), Mitsuba version and variant, time.

Usage (from the repository root; the worlds exported by
`cargo run -p himmel-world --example export_worlds -- tests/fixtures/worlds`):

    /tmp/venv/bin/python tools/ao_reference.py --out tests/fixtures/ao_ref \
        [--case atrium_high --case plane_and_boxes_high] [--radius 1.0] [--rays 4096]
"""

import argparse
import json
import math
import os
import sys
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import world_reference as wr  # noqa: E402

DEFAULT_CASES = ["atrium_high", "plane_and_boxes_high"]


def primary_hits(scene, cam):
    """(hit (n,), p (n,3), shading normal towards the camera (n,3), geometric
    normal on the same side (n,3)) of the pixel-centre rays, row-major."""
    mi = wr.mi
    w, h = int(cam["width"]), int(cam["height"])
    ys, xs = np.meshgrid(np.arange(h), np.arange(w), indexing="ij")
    u = ((xs + 0.5) / w).ravel()
    v = ((ys + 0.5) / h).ravel()
    n = u.size
    sensor = scene.sensors()[0]
    ray, _ = sensor.sample_ray(mi.Float(np.zeros(n)), mi.Float(np.full(n, 0.5)),
                               mi.Point2f(mi.Float(u), mi.Float(v)),
                               mi.Point2f(mi.Float(np.full(n, 0.5)), mi.Float(np.full(n, 0.5))))
    si = scene.ray_intersect(ray)
    hit = np.array(si.is_valid(), dtype=bool)
    d = wr.rows3(ray.d)
    p = wr.rows3(si.p)
    ns = wr.rows3(si.sh_frame.n)
    ng = wr.rows3(si.n)
    flip = np.sum(ns * d, axis=1) > 0
    ns[flip] *= -1
    ng[np.sum(ng * d, axis=1) > 0] *= -1
    ns /= np.maximum(np.linalg.norm(ns, axis=1, keepdims=True), 1e-30)
    return hit, p, ns, ng


def tangent_frame(n):
    """Two unit tangents (n,3) completing each normal (Duff et al. 2017)."""
    s = np.where(n[:, 2] >= 0, 1.0, -1.0)
    a = -1.0 / (s + n[:, 2])
    b = n[:, 0] * n[:, 1] * a
    t = np.stack([1 + s * n[:, 0] ** 2 * a, s * b, -s * n[:, 0]], axis=1)
    bt = np.stack([b, s + n[:, 1] ** 2 * a, -n[:, 1]], axis=1)
    return t, bt


def ao_estimate(scene, p, ns, ng, radius, rays, rng, batch=32):
    """Unoccluded fraction within `radius` over `rays` cosine-weighted
    directions per point (stratified), and its binomial standard error."""
    mi = wr.mi
    side = int(round(math.sqrt(rays)))
    total = side * side
    t, bt = tangent_frame(ns)
    off = p + ng * (1e-4 * (1.0 + np.linalg.norm(p, axis=1)))[:, None]
    m = len(p)
    open_count = np.zeros(m)
    cells = np.arange(total)
    for start in range(0, total, batch):
        idx = cells[start:start + batch]
        k = len(idx)
        cu = (idx % side)[None, :] + rng.random((m, k))
        cv = (idx // side)[None, :] + rng.random((m, k))
        r = np.sqrt(cu / side)
        phi = 2 * math.pi * cv / side
        x, y = r * np.cos(phi), r * np.sin(phi)
        z = np.sqrt(np.maximum(0.0, 1.0 - x * x - y * y))
        d = (x[..., None] * t[:, None, :] + y[..., None] * bt[:, None, :]
             + z[..., None] * ns[:, None, :]).reshape(-1, 3)
        o = np.repeat(off, k, axis=0)
        ray = mi.Ray3f(mi.Point3f(*[mi.Float(o[:, c].astype(np.float32)) for c in range(3)]),
                       mi.Vector3f(*[mi.Float(d[:, c].astype(np.float32)) for c in range(3)]))
        ray.maxt = mi.Float(np.full(len(d), radius, dtype=np.float32))
        blocked = np.array(scene.ray_test(ray), dtype=bool).reshape(m, k)
        open_count += k - blocked.sum(axis=1)
    ao = open_count / total
    # Stratification only lowers the variance: the binomial error bounds it.
    err = np.sqrt(np.maximum(ao * (1 - ao), 0.0) / total)
    return ao, err


def run_case(case, radius, rays, out, seed):
    mi = wr.mi
    t0 = time.time()
    world = wr.load_world(os.path.join(wr.ROOT, case["world"]))
    scene = wr.build_scene(case, world, None, {}, with_env=False, with_lights=False)
    cam = case["camera"]
    w, h = int(cam["width"]), int(cam["height"])
    hit, p, ns, ng = primary_hits(scene, cam)
    rng = np.random.default_rng(seed)
    ao = np.zeros(w * h)
    err = np.zeros(w * h)
    a, e = ao_estimate(scene, p[hit], ns[hit], ng[hit], radius, rays, rng)
    ao[hit], err[hit] = a, e
    hit_frac, lit, pure = wr.classify(scene, cam, None)
    mask = wr.masks(hit_frac, lit, pure)
    name = case["name"]
    img = np.repeat(ao.reshape(h, w, 1), 3, axis=2)
    wr.write_exr(os.path.join(out, f"{name}_ao.exr"), img)
    wr.write_exr(os.path.join(out, f"{name}_ao_mask.exr"), mask.astype(np.float32))
    geo = mask[:, :, 2].ravel()
    info = {
        "case": name,
        "world": case["world"],
        "camera": cam,
        "radius_m": radius,
        "rays_per_pixel": int(round(math.sqrt(rays))) ** 2,
        "noise_mean": float(err[geo].mean()) if geo.any() else 0.0,
        "noise_max": float(err[geo].max()) if geo.any() else 0.0,
        "mean_ao": float(ao[geo].mean()) if geo.any() else 0.0,
        "geometry_pixels": int(geo.sum()),
        "mitsuba": mi.__version__,
        "variant": mi.variant(),
        "seconds": round(time.time() - t0, 1),
        "command": " ".join(["tools/ao_reference.py"] + sys.argv[1:]),
    }
    with open(os.path.join(out, f"{name}_ao.json"), "w") as f:
        json.dump(info, f, indent=1)
        f.write("\n")
    print(json.dumps(info))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--cases", default=os.path.join(wr.HERE, "world_cases.json"))
    ap.add_argument("--case", action="append", help="a case name (repeatable)")
    ap.add_argument("--radius", type=float, default=1.0, help="AO radius, metres")
    ap.add_argument("--rays", type=int, default=4096, help="rays per pixel (a square)")
    ap.add_argument("--out", default=os.path.join(wr.ROOT, "tests/fixtures/ao_ref"))
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--variant", default=None)
    a = ap.parse_args()
    wr.setup_mitsuba(a.variant)
    os.makedirs(a.out, exist_ok=True)
    with open(a.cases) as f:
        cases = {c["name"]: c for c in json.load(f)["cases"]}
    for name in a.case or DEFAULT_CASES:
        run_case(cases[name], a.radius, a.rays, a.out, a.seed)


if __name__ == "__main__":
    main()
