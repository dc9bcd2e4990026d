#!/usr/bin/env python3
"""Mitsuba 3 references of the fog's light shafts (issue 15, item 4).

Run by hand, never in CI; an extension of tools/world_reference.py (whose
world loading, Himmel environment, disk removal, lights and masks it uses).
For each case of tools/godrays_cases.json it renders with Mitsuba's `volpath`

* the world with every surface black (`diffuse`, reflectance 0), so that a
  pixel showing geometry receives only the light the fog scatters towards
  the camera in front of it: the fog's *added radiance*, isolated without a
  difference of two noisy renders (Himmel's side: the render with the
  godrays pass minus the same render without it, same materials);
* the fog: a `homogeneous` medium (σ_t = σ_s + σ_a, albedo σ_s/σ_t, phase
  `hg`/`rayleigh`/`isotropic`) inside a `cube` with a `null` BSDF spanning
  x, z ∈ [−5 km, 5 km], y ∈ [−100 m, top_m] — the layer y ≤ top_m of
  world.md — the camera inside it;
* the Sun (directional, Himmel's `--stats` `direct_rgb`) and the sky
  (Himmel's equirect environment, disks removed), both attenuated through
  the medium to each point along their own paths;
* `max_depth` 2: single scattering (world.md: the fog's light is single
  scattering of Sun, Moon and sky light).

It writes `<case>.exr` (RGB cd/m², linear sRGB), `<case>_mask.exr` (B =
geometry over the whole pixel, one plane, eroded; R/G as world_reference)
and `<case>.json` (spp, noise, lights, time) to --out
(tests/fixtures/godrays_ref).

    /tmp/venv/bin/python tools/godrays_reference.py --himmel $CARGO_TARGET_DIR/debug/himmel \
        [--case NAME] [--spp 1024] [--out tests/fixtures/godrays_ref]
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

HERE = wr.HERE
ROOT = wr.ROOT


def phase_of(phase):
    if phase == "rayleigh":
        return {"type": "rayleigh"}
    if phase == "isotropic":
        return {"type": "isotropic"}
    return {"type": "hg", "g": float(phase["hg"])}


def fog_scene(case, world, env_rgb, lights, max_depth=2):
    mi = wr.mi
    fog = case["fog"]
    ss, sa = float(fog["scattering_per_m"]), float(fog.get("absorption_per_m", 0.0))
    st = ss + sa
    top = float(fog["top_m"])
    medium = {"type": "homogeneous", "sigma_t": {"type": "rgb", "value": [st] * 3},
              "albedo": {"type": "rgb", "value": [ss / st] * 3}, "scale": 1.0,
              "phase": phase_of(fog.get("phase", {"hg": 0.6}))}
    scene = {"type": "scene", "integrator": {"type": "volpath", "max_depth": max_depth,
                                             "hide_emitters": False}}
    scene["fog"] = medium
    sensor = wr.sensor_of(case["camera"])
    sensor["medium"] = {"type": "ref", "id": "fog"}
    scene["sensor"] = sensor
    black = {"name": "black", "base_color": [0.0, 0.0, 0.0], "metallic": 0.0,
             "roughness": 1.0, "emissive": [0.0, 0.0, 0.0]}
    for i, (mat, p, nrm, f) in enumerate(world):
        scene[f"mesh{i}"] = wr.mesh_of(f"mesh{i}_{mat['name']}", black, p, nrm, f)
    lo, half = -100.0, 5000.0
    scene["fog_box"] = {
        "type": "cube", "bsdf": {"type": "null"}, "interior": {"type": "ref", "id": "fog"},
        "to_world": mi.ScalarTransform4f().translate([0.0, 0.5 * (top + lo), 0.0]).scale(
            [half, 0.5 * (top - lo), half])}
    scene["sky"] = {"type": "envmap", "bitmap": mi.Bitmap(env_rgb.astype(np.float32)),
                    "scale": 1.0}
    for name, light in lights.items():
        scene[name] = {"type": "directional",
                       "direction": [float(-c) for c in light["towards"]],
                       "irradiance": {"type": "rgb", "value": [float(c) for c in light["rgb"]]}}
    return mi.load_dict(scene)


def phase_eval(phase, c):
    """The phase function at cos θ (numpy), 1/sr."""
    if phase == "rayleigh":
        return 3.0 / (16.0 * math.pi) * (1.0 + c * c)
    if phase == "isotropic":
        return np.full_like(c, 1.0 / (4.0 * math.pi))
    g = float(phase["hg"])
    d = 1.0 + g * g - 2.0 * g * c
    return (1.0 - g * g) / (4.0 * math.pi * d * np.sqrt(d))


BOX_HALF, BOX_LO = 5000.0, -100.0


def box_exit(p, d, top):
    """Distance from points p inside the fog box along unit directions d to its boundary."""
    lo = np.array([-BOX_HALF, BOX_LO, -BOX_HALF])
    hi = np.array([BOX_HALF, top, BOX_HALF])
    with np.errstate(divide="ignore", invalid="ignore"):
        t = np.where(d > 0, (hi - p) / d, np.where(d < 0, (lo - p) / d, np.inf))
    return np.clip(t.min(axis=1), 0.0, None)


def scatter_pass(plain, env, case, lights, rng, steps, sky_dirs):
    """One pass of the single-scattering estimator: one primary ray per pixel
    (uniform in the pixel) to the first surface, `steps` stratified points
    along its part inside the fog, at each the Sun and Moon (one shadow ray,
    the box's transmittance) and the sky (`sky_dirs` directions, uniform
    over the sphere or, where the case names a `sky_portal` — an opening
    every ray leaving the room crosses — towards uniform points on it:
    shadow ray, the box's transmittance along it, the environment). Returns (H, W, 3) cd/m²."""
    mi = wr.mi
    cam = case["camera"]
    w, h = int(cam["width"]), int(cam["height"])
    fog = case["fog"]
    ss = float(fog["scattering_per_m"])
    st = ss + float(fog.get("absorption_per_m", 0.0))
    top = float(fog["top_m"])
    phase = fog.get("phase", {"hg": 0.6})
    n = w * h
    ys, xs = np.meshgrid(np.arange(h), np.arange(w), indexing="ij")
    u = ((xs + rng.random((h, w))) / w).ravel()
    v = ((ys + rng.random((h, w))) / h).ravel()
    sensor = plain.sensors()[0]
    ray, _ = sensor.sample_ray(mi.Float(np.zeros(n)), mi.Float(np.full(n, 0.5)),
                               mi.Point2f(mi.Float(u), mi.Float(v)),
                               mi.Point2f(mi.Float(np.full(n, 0.5)), mi.Float(np.full(n, 0.5))))
    si = plain.ray_intersect(ray)
    hit = np.array(si.is_valid(), dtype=bool)
    o, d = wr.rows3(ray.o), wr.rows3(ray.d)
    t_hit = np.where(hit, np.array(si.t, dtype=np.float64), 0.0)
    # The ray's part inside y <= top.
    with np.errstate(divide="ignore", invalid="ignore"):
        t_top = (top - o[:, 1]) / d[:, 1]
    t0 = np.where((d[:, 1] < 0) & (o[:, 1] > top), t_top, 0.0)
    t1 = np.where(d[:, 1] > 0, np.minimum(t_hit, t_top), t_hit)
    t1 = np.where((d[:, 1] >= 0) & (o[:, 1] > top), 0.0, t1)
    length = np.clip(t1 - t0, 0.0, None)
    frac = (np.arange(steps)[None, :] + rng.random((n, steps))) / steps
    ts = t0[:, None] + frac * length[:, None]
    # Exact per-stratum weight of the view transmittance times the stratum length.
    wgt = np.exp(-st * (ts - t0[:, None])) * (length / steps)[:, None]
    pts = (o[:, None, :] + d[:, None, :] * ts[:, :, None]).reshape(-1, 3)
    dv = np.repeat(d, steps, axis=0)
    out = np.zeros((n * steps, 3))
    for light in lights.values():
        towards = np.asarray(light["towards"], dtype=np.float64)
        dirs = np.broadcast_to(towards, pts.shape)
        occ = np.array(plain.ray_test(mi.Ray3f(wr.vec3(pts), wr.vec3(dirs))), dtype=bool)
        tr = np.exp(-st * box_exit(pts, dirs, top))
        p = phase_eval(phase, dv @ towards)
        out += (ss * p * tr * ~occ)[:, None] * np.asarray(light["rgb"])[None, :]
    if env is not None and sky_dirs > 0:
        portal = case.get("sky_portal")
        for _ in range(sky_dirs):
            if portal:
                # A uniform point on the opening every escaping ray crosses:
                # 1/pdf(ω) = A |cos| / r².
                c0 = np.asarray(portal["corner_m"], dtype=np.float64)
                e1 = np.asarray(portal["edge1_m"], dtype=np.float64)
                e2 = np.asarray(portal["edge2_m"], dtype=np.float64)
                nrm = np.cross(e1, e2)
                area = np.linalg.norm(nrm)
                nrm /= area
                q = c0 + rng.random((len(pts), 1)) * e1 + rng.random((len(pts), 1)) * e2
                om = q - pts
                r2 = np.sum(om * om, axis=1)
                om /= np.sqrt(r2)[:, None]
                inv_pdf = area * np.abs(om @ nrm) / r2
            else:
                z = rng.uniform(-1.0, 1.0, len(pts))
                a = rng.uniform(0.0, 2.0 * math.pi, len(pts))
                r = np.sqrt(1.0 - z * z)
                om = np.stack([r * np.cos(a), z, r * np.sin(a)], axis=1)
                inv_pdf = np.full(len(pts), 4.0 * math.pi)
            occ = np.array(plain.ray_test(mi.Ray3f(wr.vec3(pts), wr.vec3(om))), dtype=bool)
            tr = np.exp(-st * box_exit(pts, om, top))
            le = wr.env_eval(env, om)
            p = phase_eval(phase, np.sum(dv * om, axis=1))
            out += (ss * p * tr * ~occ * inv_pdf / sky_dirs)[:, None] * le
    img = (out.reshape(n, steps, 3) * wgt[:, :, None]).sum(axis=1)
    return img.reshape(h, w, 3)


def run_case(case, args, env_path, stats_path):
    t0 = time.time()
    stats = json.load(open(stats_path))
    lights = wr.lights_of(stats)
    env, _ = wr.remove_disks(wr.read_exr_rgb(env_path), stats)
    world = wr.load_world(os.path.join(ROOT, case["world"]))
    # Masks from the plain world (no fog box).
    plain = wr.build_scene(case, world, None, lights, with_env=False)
    main = max(lights.items(), key=lambda kv: np.dot(kv[1]["rgb"], wr.Y_WEIGHTS))[0]
    hit, lit, pure = wr.classify(plain, case["camera"], lights[main]["towards"])
    m = wr.masks(hit, lit, pure)
    h, w = m.shape[:2]
    # The environment as Mitsuba's envmap (the same lookups as volpath's).
    env_scene = wr.mi.load_dict({"type": "scene", "sky": {
        "type": "envmap", "bitmap": wr.mi.Bitmap(env.astype(np.float32)), "scale": 1.0}})
    emitter = env_scene.environment()
    acc = [np.zeros((h, w, 3)), np.zeros((h, w, 3))]
    for k in range(args.passes):
        acc[k % 2] += scatter_pass(plain, emitter, case, lights, np.random.default_rng(4242 + k),
                                   args.steps, args.sky_dirs)
        print(f"  {case['name']}: pass {k + 1}/{args.passes}, {time.time() - t0:.0f} s",
              file=sys.stderr)
    done = args.passes
    img = (acc[0] + acc[1]) / done
    half = done / 2
    noise, noise_w, used = wr.noise_of(acc[0] / half, acc[1] / half, m[:, :, 2])
    validation = None
    if args.validate:
        # Mitsuba's stock volpath (max_depth 2) with the same medium and
        # lights: the mean added luminance over the mask, and its standard
        # error from two halves.
        scene = fog_scene(case, world, env, lights)
        a = wr.render(scene, args.validate // 2, 777)
        b = wr.render(scene, args.validate // 2, 778)
        sel = m[:, :, 2]
        ya, yb = wr.luminance(a)[sel].mean(), wr.luminance(b)[sel].mean()
        mine = float(wr.luminance(img)[sel].mean())
        validation = {"volpath_spp": args.validate, "volpath_mean": 0.5 * (ya + yb),
                      "volpath_std_err": abs(ya - yb) / 2.0, "estimator_mean": mine,
                      "relative_difference": mine / (0.5 * (ya + yb)) - 1.0}
        print(f"  {case['name']}: validation {validation}", file=sys.stderr)
    os.makedirs(args.out, exist_ok=True)
    wr.write_exr(os.path.join(args.out, case["name"] + ".exr"), img)
    wr.write_exr(os.path.join(args.out, case["name"] + "_mask.exr"), m.astype(np.float32))
    meta = {"case": case["name"], "mitsuba": wr.mi.__version__, "variant": wr.mi.variant(),
            "integrator": {"type": "single scattering (tools/godrays_reference.py "
                           "scatter_pass: Mitsuba ray tracing and envmap)",
                           "steps": args.steps, "sky_dirs": args.sky_dirs},
            "validation_vs_volpath": validation, "surfaces": "black",
            "fog": case["fog"], "fog_box_m": {"xz_half": 5000.0, "y": [-100.0, case["fog"]["top_m"]]},
            "passes": done, "noise_rel_rms": round(noise, 5), "noise_weighted_rms": round(noise_w, 5),
            "noise_pixels_used": used, "mask_pixels_B": int(m[:, :, 2].sum()),
            "lights": lights, "render_s": round(time.time() - t0, 1),
            "mean_added_luminance_B": float(wr.luminance(img)[m[:, :, 2]].mean())}
    with open(os.path.join(args.out, case["name"] + ".json"), "w") as fh:
        json.dump(meta, fh, indent=1)
        fh.write("\n")
    return meta


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--cases", default=os.path.join(HERE, "godrays_cases.json"))
    ap.add_argument("--case", action="append")
    ap.add_argument("--out", default=os.path.join(ROOT, "tests", "fixtures", "godrays_ref"))
    ap.add_argument("--work", default="/tmp/himmel-world-ref")
    ap.add_argument("--himmel", default=wr.default_himmel())
    ap.add_argument("--variant")
    ap.add_argument("--passes", type=int, default=64, help="primary rays per pixel")
    ap.add_argument("--steps", type=int, default=16, help="points per view ray and pass")
    ap.add_argument("--sky-dirs", type=int, default=8, help="sky directions per point")
    ap.add_argument("--validate", type=int, metavar="SPP",
                    help="also render Mitsuba's volpath at SPP and compare the masked means")
    args = ap.parse_args()
    variant = wr.setup_mitsuba(args.variant)
    print(f"Mitsuba {wr.mi.__version__}, variant {variant}", file=sys.stderr)
    cases = json.load(open(args.cases))["cases"]
    if args.case:
        cases = [c for c in cases if c["name"] in args.case]
    for case in cases:
        env, stats = wr.himmel_env(args.himmel, case, args.work)
        meta = run_case(case, args, env, stats)
        print(json.dumps({k: meta[k] for k in ("case", "passes", "noise_rel_rms", "render_s",
                                                "mean_added_luminance_B")}))


if __name__ == "__main__":
    main()
