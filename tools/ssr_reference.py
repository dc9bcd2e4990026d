#!/usr/bin/env python3
"""Mitsuba 3 references of screen-space reflections (issue 16, SSR part).

Run by hand, never in CI; an extension of tools/world_reference.py (whose
glTF loading, materials, camera, environment and lights it uses). For each
case of tools/ssr_cases.json — the plane with boxes on a polished metal
floor (`principled`, metallic 1, base colour 0.9, roughness 0.05 or 0.3:
Mitsuba's GGX with α = roughness², as Himmel's) — it renders with Mitsuba's
stock `path` integrator, max_depth 3 (the floor's reflection of the boxes
lit directly by the Sun and the sky: camera → floor → box → light), the
world lit by Himmel's own sky of the instant (disks removed) as the
environment and the Sun as a directional light (world_reference.py's
`himmel_env`, `remove_disks`, `lights_of`), and writes to --out
(tests/fixtures/ssr_ref):

* `<case>.exr` — RGB radiance, cd/m² (float32);
* `<case>_mask.exr` — R: the metal floor over the whole pixel (4 × 4
  sub-samples on one plane, y = 0, normal +y; eroded by one pixel);
  G: R and the mirror reflection of the pixel-centre ray meets geometry
  (eroded by one pixel); B: geometry over the whole pixel;
* `<case>.json` — spp, noise (two half images, relative RMS over G),
  Mitsuba version and variant, lights, time.

Usage (from the repository root; the worlds from
`cargo run -p himmel-world --example export_worlds -- tests/fixtures/worlds`;
`--himmel` makes the environment when it is not cached in --work):

    DRJIT_LIBLLVM_PATH=/usr/lib/x86_64-linux-gnu/libLLVM.so.19.1 \\
      /tmp/venv/bin/python tools/ssr_reference.py --out tests/fixtures/ssr_ref \\
        [--case glossy_floor_005] [--spp 2048] [--himmel target/debug/himmel]
"""

import argparse
import json
import os
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import world_reference as wr  # noqa: E402


def floor_masks(scene, case):
    """(floor (h, w), floor whose mirror ray meets geometry (h, w),
    geometry (h, w)), each eroded by one pixel."""
    mi = wr.mi
    cam = case["camera"]
    w, h = int(cam["width"]), int(cam["height"])
    hit_frac, _, pure = wr.classify(scene, cam, None)
    geometry = (hit_frac >= 1.0) & pure
    ys, xs = np.meshgrid(np.arange(h), np.arange(w), indexing="ij")
    u = ((xs + 0.5) / w).ravel()
    v = ((ys + 0.5) / h).ravel()
    n = u.size
    sensor = scene.sensors()[0]
    ray, _ = sensor.sample_ray(mi.Float(np.zeros(n)), mi.Float(np.full(n, 0.5)),
                               mi.Point2f(mi.Float(u), mi.Float(v)),
                               mi.Point2f(mi.Float(np.full(n, 0.5)), mi.Float(np.full(n, 0.5))))
    si = scene.ray_intersect(ray)
    p = wr.rows3(si.p)
    ng = wr.rows3(si.n)
    d = wr.rows3(ray.d)
    on_floor = np.array(si.is_valid(), dtype=bool) & (np.abs(p[:, 1]) < 1e-3) & \
        (np.abs(ng[:, 1]) > 0.999)
    r = d.copy()
    r[:, 1] = -r[:, 1]
    o = p + np.array([0.0, 1e-3, 0.0])
    refl = mi.Ray3f(mi.Point3f(*[mi.Float(o[:, c].astype(np.float32)) for c in range(3)]),
                    mi.Vector3f(*[mi.Float(r[:, c].astype(np.float32)) for c in range(3)]))
    meets = np.array(scene.ray_test(refl), dtype=bool)
    floor = geometry & on_floor.reshape(h, w)
    reflects = floor & (on_floor & meets).reshape(h, w)
    return wr.erode(floor), wr.erode(reflects), wr.erode(geometry)


def run_case(case, args):
    mi = wr.mi
    t0 = time.time()
    env_path, stats_path = wr.himmel_env(args.himmel, case, args.work)
    stats = json.load(open(stats_path))
    lights = wr.lights_of(stats)
    env, removed = wr.remove_disks(wr.read_exr_rgb(env_path), stats)
    world = wr.load_world(os.path.join(wr.ROOT, case["world"]))
    scene = wr.build_scene(case, world, env, lights, max_depth=int(case.get("max_depth", 3)))
    floor, reflects, geometry = floor_masks(scene, case)
    h, w = floor.shape
    acc = [np.zeros((h, w, 3)), np.zeros((h, w, 3))]
    batches = max(2, args.spp // args.batch_spp)
    for k in range(batches):
        acc[k % 2] += wr.render(scene, args.batch_spp, 1000 + k)
        print(f"  {case['name']}: {(k + 1) * args.batch_spp} spp, "
              f"{time.time() - t0:.0f} s", file=sys.stderr)
    a, b = acc[0] / (batches // 2), acc[1] / (batches - batches // 2)
    img = (acc[0] + acc[1]) / batches
    noise, noise_w, used = wr.noise_of(a, b, reflects)
    mask = np.stack([floor, reflects, geometry], axis=2).astype(np.float32)
    os.makedirs(args.out, exist_ok=True)
    name = case["name"]
    wr.write_exr(os.path.join(args.out, f"{name}.exr"), img)
    wr.write_exr(os.path.join(args.out, f"{name}_mask.exr"), mask)
    meta = {
        "case": name,
        "world": case["world"],
        "roughness": case.get("roughness"),
        "camera": case["camera"],
        "mitsuba": mi.__version__,
        "variant": mi.variant(),
        "integrator": {"type": "path", "max_depth": int(case.get("max_depth", 3)),
                       "hide_emitters": False},
        "spp": batches * args.batch_spp,
        "noise_rel_rms": round(noise, 5),
        "noise_weighted_rms": round(noise_w, 5),
        "noise_pixels_used": used,
        "mask_pixels": {"floor": int(floor.sum()), "floor_reflecting_geometry": int(reflects.sum()),
                        "geometry": int(geometry.sum())},
        "lights": lights,
        "env_disks_removed": {k: {"radius_deg": round(v["radius_deg"], 4), "pixels": v["pixels"]}
                              for k, v in removed.items()},
        "render_s": round(time.time() - t0, 1),
        "command": "tools/ssr_reference.py " + " ".join(sys.argv[1:]),
    }
    with open(os.path.join(args.out, f"{name}.json"), "w") as fh:
        json.dump(meta, fh, indent=1)
        fh.write("\n")
    return meta


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--cases", default=os.path.join(HERE, "ssr_cases.json"))
    ap.add_argument("--case", action="append", help="case name (repeatable; default all)")
    ap.add_argument("--out", default=os.path.join(wr.ROOT, "tests", "fixtures", "ssr_ref"))
    ap.add_argument("--work", default="/tmp/himmel-world-ref")
    ap.add_argument("--himmel", default=wr.default_himmel())
    ap.add_argument("--variant")
    ap.add_argument("--spp", type=int, default=2048)
    ap.add_argument("--batch-spp", type=int, default=128)
    args = ap.parse_args()
    variant = wr.setup_mitsuba(args.variant)
    print(f"Mitsuba {wr.mi.__version__}, variant {variant}", file=sys.stderr)
    cases = json.load(open(args.cases))["cases"]
    if args.case:
        cases = [c for c in cases if c["name"] in args.case]
    for case in cases:
        meta = run_case(case, args)
        print(json.dumps({k: meta[k] for k in ("case", "spp", "noise_rel_rms", "render_s")}))
    return 0


if __name__ == "__main__":
    sys.exit(main())
