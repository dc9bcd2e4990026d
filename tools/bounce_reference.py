#!/usr/bin/env python3
"""Mitsuba 3 one-bounce reference for near-field indirect light (issue 16,
item 2: `lighting.ao.bounce`).

Run by hand, never in CI; an extension of tools/world_reference.py (whose
glTF loading, sky environment from Himmel, Sun and Moon as directional
lights, camera and scene building it uses). For one case of
tools/world_cases.json (default plane_and_boxes_high, whose camera looks at
the boxes' east faces: in the Sun's shadow, beside the sunlit floor) it
renders with Mitsuba's `path` integrator

* at max_depth 3 (direct light + one bounce) and
* at max_depth 2 (direct light only),

with the same seeds and spp, each in two independent halves. The one-bounce
light is their difference, B = L₃ − L₂: the light that the Sun, the Moon
and the sky put on the world's surfaces, reflected once more into the
camera — what Himmel's bounce pass adds (Himmel's side: the render with
`lighting.ao.bounce` minus the render without).

Writes to --out (tests/fixtures/bounce_ref):

* `<case>_bounce.exr` — B, linear RGB, cd/m²;
* `<case>_bounce_mask.exr` — R: the masked pixels: geometry over the whole
  pixel on one plane (world_reference.py's B mask, eroded by one pixel), in
  the main light's shadow (its G mask: sky-lit only), on a vertical surface
  (|n_y| < 0.3: the walls, whose bounce comes from the floor in front of
  them, which the camera sees), and with B at least 2 % of the masked
  pixels' median (where there is a bounce to measure); G and B: the sky-lit
  and geometry masks as they are;
* `<case>_bounce_onscreen.exr` — on the masked pixels, the part of B that
  comes from surfaces the camera sees (what a screen-space pass can
  gather): `--rays` cosine-distributed rays from the pixel centre's hit;
  where the first surface hit lies inside the image and is seen by the
  camera, its radiance is the max_depth-2 image at its pixel; times the
  pixel's diffuse albedo (Mitsuba's `eval_diffuse_reflectance`);
* `<case>_bounce.json` — the command, spp, the noise of B (relative RMS of
  the two halves' luminance difference over the mask, luminance-weighted,
  as the test's error measures it), Mitsuba version and variant, time.

Usage (from the repository root; the environment from a Himmel binary,
cached in --work as world_reference.py does):

    /tmp/venv/bin/python tools/bounce_reference.py --out tests/fixtures/bounce_ref \
        --himmel $CARGO_TARGET_DIR/debug/himmel [--case plane_and_boxes_high] [--spp 1024]
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


def camera_basis(cam):
    """(eye, forward, right, up, tan(fov_y / 2)) of the case's camera."""
    eye = np.asarray(cam["position_m"], dtype=np.float64)
    f = np.asarray(cam["look_at_m"], dtype=np.float64) - eye
    f /= np.linalg.norm(f)
    r = np.cross(f, np.asarray(cam.get("up", [0, 1, 0]), dtype=np.float64))
    r /= np.linalg.norm(r)
    u = np.cross(r, f)
    return eye, f, r, u, math.tan(math.radians(float(cam.get("fov_deg", 60.0))) / 2)


def onscreen_bounce(scene, cam, direct, sel, rays, rng):
    """The one-bounce light of the pixels `sel` from the surfaces the camera
    sees: per pixel centre hit p (normal n towards the camera, diffuse
    albedo ρ from Mitsuba's BSDF), `rays` cosine-distributed directions ω;
    where the first hit q lies inside the image and the camera sees it
    (unblocked, the same side), L_o(q) = the max_depth-2 image `direct` at
    q's pixel; B = ρ · mean(L_o), 0 for the other rays."""
    mi = wr.mi
    w, h = int(cam["width"]), int(cam["height"])
    eye, fwd, right, up, tan_half = camera_basis(cam)
    out = np.zeros((h, w, 3))
    ys, xs = np.nonzero(sel)
    npx = len(ys)
    sensor = scene.sensors()[0]
    ray, _ = sensor.sample_ray(mi.Float(np.zeros(npx)), mi.Float(np.full(npx, 0.5)),
                               mi.Point2f(mi.Float((xs + 0.5) / w), mi.Float((ys + 0.5) / h)),
                               mi.Point2f(mi.Float(np.full(npx, 0.5)), mi.Float(np.full(npx, 0.5))))
    si = scene.ray_intersect(ray)
    p = wr.rows3(si.p)
    d = wr.rows3(ray.d)
    n = wr.rows3(si.sh_frame.n)
    n[np.sum(n * d, axis=1) > 0] *= -1
    rho = wr.rows3(si.bsdf().eval_diffuse_reflectance(si))
    # Cosine-distributed directions about n, stratified over √rays².
    k = int(math.isqrt(rays))
    a, b = np.meshgrid(np.arange(k), np.arange(k), indexing="ij")
    u1 = (a.ravel()[None, :] + rng.random((npx, k * k))) / k
    u2 = (b.ravel()[None, :] + rng.random((npx, k * k))) / k
    helper = np.where(np.abs(n[:, 1:2]) < 0.9, [[0.0, 1.0, 0.0]], [[1.0, 0.0, 0.0]])
    t1 = np.cross(n, helper)
    t1 /= np.linalg.norm(t1, axis=1, keepdims=True)
    t2 = np.cross(n, t1)
    rad, phi = np.sqrt(u1), 2 * math.pi * u2
    dirs = (t1[:, None] * (rad * np.cos(phi))[..., None]
            + t2[:, None] * (rad * np.sin(phi))[..., None]
            + n[:, None] * np.sqrt(np.maximum(1 - u1, 0))[..., None]).reshape(-1, 3)
    origin = np.repeat(p + n * 1e-4 * (1 + np.linalg.norm(p, axis=1, keepdims=True)), k * k, 0)
    m = len(dirs)
    s2 = scene.ray_intersect(mi.Ray3f(wr.vec3(origin), wr.vec3(dirs)))
    hit = np.array(s2.is_valid(), dtype=bool)
    q = wr.rows3(s2.p)
    nq = wr.rows3(s2.n)
    v = q - eye
    z = v @ fwd
    kx = 0.5 * h / (np.maximum(z, 1e-9) * tan_half)
    px = v @ right * kx + 0.5 * w
    py = -(v @ up) * kx + 0.5 * h
    inside = hit & (z > 0) & (px >= 0) & (px < w) & (py >= 0) & (py < h)
    # The camera sees the side of q that the ray arrives at, unblocked.
    same_side = np.sign(np.sum(nq * -dirs, axis=1)) == np.sign(np.sum(nq * (eye - q), axis=1))
    # From q towards the eye (spawned off q): blocked if anything lies between.
    to_eye = s2.spawn_ray_to(mi.Point3f(*[float(c) for c in eye]))
    blocked = np.array(scene.ray_test(to_eye), dtype=bool)
    seen = inside & same_side & ~blocked
    print(f"  on-screen bounce: {npx} pixels x {k * k} rays: hit {hit.mean():.3f}, "
          f"inside {inside.mean():.3f}, same side {(inside & same_side).mean():.3f}, "
          f"seen {seen.mean():.3f}", file=sys.stderr)
    ix = np.clip(px.astype(int), 0, w - 1)
    iy = np.clip(py.astype(int), 0, h - 1)
    lo = np.where(seen[:, None], direct[iy, ix], 0.0).reshape(npx, k * k, 3)
    out[ys, xs] = rho * lo.mean(axis=1)
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--cases", default=os.path.join(wr.HERE, "world_cases.json"))
    ap.add_argument("--case", default="plane_and_boxes_high")
    ap.add_argument("--out", default=os.path.join(wr.ROOT, "tests", "fixtures", "bounce_ref"))
    ap.add_argument("--work", default="/tmp/himmel-world-ref")
    ap.add_argument("--himmel", default=wr.default_himmel())
    ap.add_argument("--variant")
    ap.add_argument("--spp", type=int, default=1024, help="spp per half (two halves)")
    ap.add_argument("--batch", type=int, default=128, help="spp per Mitsuba render call")
    ap.add_argument("--rays", type=int, default=4096,
                    help="rays per masked pixel of the on-screen bounce")
    args = ap.parse_args()
    t0 = time.time()
    variant = wr.setup_mitsuba(args.variant)
    mi = wr.mi
    cases = json.load(open(args.cases))["cases"]
    case = next(c for c in cases if c["name"] == args.case)
    env_path, stats_path = wr.himmel_env(args.himmel, case, args.work)
    stats = json.load(open(stats_path))
    lights = wr.lights_of(stats)
    env, _ = wr.remove_disks(wr.read_exr_rgb(env_path), stats)
    world = wr.load_world(os.path.join(wr.ROOT, case["world"]))
    scenes = {d: wr.build_scene(case, world, env, lights, max_depth=d) for d in (2, 3)}
    main_light = max(lights.items(), key=lambda kv: np.dot(kv[1]["rgb"], wr.Y_WEIGHTS))[0]
    hit, lit, pure = wr.classify(scenes[2], case["camera"], lights[main_light]["towards"])
    m = wr.masks(hit, lit, pure)
    cam = case["camera"]
    w, h = int(cam["width"]), int(cam["height"])
    # The shading normal at each pixel centre (for the walls' mask).
    ys, xs = np.meshgrid(np.arange(h), np.arange(w), indexing="ij")
    n = w * h
    sensor = scenes[2].sensors()[0]
    ray, _ = sensor.sample_ray(mi.Float(np.zeros(n)), mi.Float(np.full(n, 0.5)),
                               mi.Point2f(mi.Float(((xs + 0.5) / w).ravel()),
                                          mi.Float(((ys + 0.5) / h).ravel())),
                               mi.Point2f(mi.Float(np.full(n, 0.5)), mi.Float(np.full(n, 0.5))))
    si = scenes[2].ray_intersect(ray)
    ny = wr.rows3(si.sh_frame.n)[:, 1].reshape(h, w)
    halves, direct = [], np.zeros((h, w, 3))
    for half in range(2):
        acc = {2: np.zeros((h, w, 3)), 3: np.zeros((h, w, 3))}
        done = 0
        while done < args.spp:
            k = min(args.batch, args.spp - done)
            seed = 100_000 * (half + 1) + done
            for d in (2, 3):
                acc[d] += wr.render(scenes[d], k, seed) * k
            done += k
            print(f"  half {half}: {done} spp, {time.time() - t0:.0f} s", file=sys.stderr)
        halves.append((acc[3] - acc[2]) / args.spp)
        direct += acc[2] / (2 * args.spp)
    bounce = 0.5 * (halves[0] + halves[1])
    y = wr.luminance(bounce)
    walls = m[:, :, 2] & m[:, :, 1] & (np.abs(ny) < 0.3)
    floor_y = 0.02 * float(np.median(y[walls])) if walls.any() else 0.0
    sel = walls & (y >= floor_y)
    ya, yb = wr.luminance(halves[0])[sel], wr.luminance(halves[1])[sel]
    noise_w = float(np.sqrt(np.mean((ya - yb) ** 2)) / max(y[sel].mean(), 1e-30)) / 2.0
    noise_mae = float(np.mean(np.abs(ya - yb)) / max(y[sel].mean(), 1e-30)) / 2.0
    onscreen = onscreen_bounce(scenes[2], cam, direct, sel, args.rays,
                               np.random.default_rng(4321))
    share = float(wr.luminance(onscreen)[sel].sum() / max(y[sel].sum(), 1e-30))
    mask = np.stack([sel, m[:, :, 1], m[:, :, 2]], axis=-1).astype(np.float32)
    wr.write_exr(os.path.join(args.out, case["name"] + "_bounce_onscreen.exr"), onscreen)
    os.makedirs(args.out, exist_ok=True)
    wr.write_exr(os.path.join(args.out, case["name"] + "_bounce.exr"), bounce)
    wr.write_exr(os.path.join(args.out, case["name"] + "_bounce_mask.exr"), mask)
    meta = {
        "case": case["name"], "world": case["world"], "camera": cam,
        "command": "/tmp/venv/bin/python tools/bounce_reference.py " + " ".join(sys.argv[1:]),
        "mitsuba": mi.__version__, "variant": variant,
        "integrator": {"type": "path", "max_depth": [3, 2], "hide_emitters": False},
        "spp": 2 * args.spp,
        "lights": lights,
        "mask_pixels": int(sel.sum()),
        "mask_mean_bounce_luminance": float(y[sel].mean()),
        "onscreen_rays_per_pixel": args.rays,
        "onscreen_share_of_bounce": round(share, 4),
        "noise_weighted_rms": round(noise_w, 5),
        "noise_weighted_mae": round(noise_mae, 5),
        "about_noise": "of the mean of the two halves, over the mask: RMS (and mean) of "
                       "|Y_A - Y_B| / mean Y, divided by 2",
        "render_s": round(time.time() - t0, 1),
    }
    with open(os.path.join(args.out, case["name"] + "_bounce.json"), "w") as fh:
        json.dump(meta, fh, indent=1)
        fh.write("\n")
    print(f"{case['name']}: {int(sel.sum())} masked pixels, mean bounce {y[sel].mean():.2f} "
          f"cd/m2, noise {100 * noise_w:.2f} % (weighted RMS), {100 * noise_mae:.2f} % "
          f"(weighted MAE), {time.time() - t0:.0f} s", file=sys.stderr)
    return 0 if math.isfinite(noise_w) else 1


if __name__ == "__main__":
    sys.exit(main())
