#!/usr/bin/env python3
"""Mitsuba 3 path-traced references for Himmel's low cloud layer (issue 18).

Run by hand, never in CI. Reads tests/fixtures/cloud_ref/setup.json (the
`clouds.low` scene key of a cloud patch, the voxel grid, the cameras and two
Sun positions), then

1. exports Himmel's own density field on the voxel grid by running
   `cargo run --release -p himmel-skymodel --example cloud_grid` (extinction
   in km⁻¹ at the voxel centres of [−e, e]² × [base, top], e = extent_km;
   the example prints the sum of the values, which goes into the output JSON
   so that the Rust test can prove the references were made from the field
   it renders);
2. renders with Mitsuba's `volpath` (all orders of scattering, Russian
   roulette, no depth limit) a `cube` bounding a `heterogeneous` medium whose
   σ_t is that grid (`gridvolume`, trilinear; world units km, so σ_t in km⁻¹),
   single-scattering albedo 1 and the phase function of
   `skymodel/src/clouds/march.rs` (`CLOUD_PHASE`: `blendphase` of two `hg`
   lobes, g 0.8 with weight 0.8 and g −0.3), lit by a `directional` emitter of
   irradiance 1 (linear sRGB) per Sun of the setup, in an empty black world
   (no atmosphere, no sky light: the configuration `himmel render --effects
   clouds` renders, with the lights unextinguished and no ambient light);
   the camera stands at the origin (ground, world frame x East, y North,
   z Up), looks at the zenith with North up (`look_at` up = +y, so East is
   on the left, as a fisheye looking up) → `<sun>_radiance.exr`;
3. renders the transmittance of the direct Sun through the layer: the same
   medium with albedo 0 in front of a constant environment of radiance 1, seen
   by an orthographic camera looking towards the Sun (centre: the origin,
   half-width `shadow_camera.half_width_km`, up hint +y, moved `back_km`
   away from the Sun so that no ray starts inside the cloud's box), so each
   pixel is e^{−τ} along the Sun's ray through its point of the plane through
   the origin perpendicular to the Sun → `<sun>_transmittance.exr`;
4. writes `references.json`: Mitsuba's version and variant, spp, render
   times, the grid sum, and each image's noise (the relative RMS difference
   of two half-sample images, over the pixels with Y ≥ 1 % of the maximum).

Setup (Debian, 2 cores, no GPU): `python3 -m venv /tmp/venv &&
/tmp/venv/bin/pip install mitsuba numpy` (3.9.1); the llvm_ad_rgb variant
needs libLLVM 19 (`DRJIT_LIBLLVM_PATH=/usr/lib/x86_64-linux-gnu/libLLVM.so.19.1`),
else scalar_rgb is used (slower).

Usage (from the repository root):

    /tmp/venv/bin/python tools/cloud_reference.py [--spp 1024] [--shadow-spp 64]
        [--out tests/fixtures/cloud_ref] [--only sun20_radiance ...]
        [--seed 17] [--max-depth -1]

`--seed` changes the sampler's seeds (the committed references use 17): an
independent copy at the same spp, compared with the committed image in the
test's metric, measures the reference's own noise (README, "The
reference's noise is not what is left"):

    /tmp/venv/bin/python tools/cloud_reference.py --out /tmp/copy --spp 16384 \
        --only sun20_radiance --seed 1017

`--max-depth 2` renders single scattering alone (a diagnostic: which order
of scattering carries an error).

Mitsuba 3 is BSD-3-Clause (Wenzel Jakob et al.).
"""

import argparse
import json
import math
import os
import subprocess
import sys
import tempfile
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.normpath(os.path.join(HERE, ".."))
LLVM = "/usr/lib/x86_64-linux-gnu/libLLVM.so.19.1"
Y_WEIGHTS = np.array([0.2126, 0.7152, 0.0722])

# skymodel/src/clouds/march.rs, CLOUD_PHASE.
G_FORWARD, G_BACK, W_FORWARD = 0.8, -0.3, 0.8

mi = None


def setup_mitsuba():
    global mi
    os.environ.setdefault("DRJIT_LIBLLVM_PATH", LLVM)
    import mitsuba

    mi = mitsuba
    for v in ["llvm_ad_rgb", "scalar_rgb"]:
        try:
            mi.set_variant(v)
            if v.startswith("llvm"):
                mi.load_dict({"type": "scene"})
            return v
        except Exception as e:  # noqa: BLE001 - report and fall back
            print(f"note: Mitsuba variant {v} unavailable ({e})", file=sys.stderr)
    sys.exit("error: no usable Mitsuba variant")


def unit_towards(alt_deg, az_deg):
    """ENU unit vector (x East, y North, z Up) at altitude/azimuth."""
    a, z = math.radians(alt_deg), math.radians(az_deg)
    return [math.cos(a) * math.sin(z), math.cos(a) * math.cos(z), math.sin(a)]


def export_grid(setup_path, work):
    out = os.path.join(work, "grid.f32")
    cmd = ["cargo", "run", "--release", "-q", "-p", "himmel-skymodel", "--example",
           "cloud_grid", "--", setup_path, out]
    res = subprocess.run(cmd, cwd=ROOT, check=True, capture_output=True, text=True)
    return out, float(res.stdout.strip().splitlines()[-1])


def medium(setup, grid_path, albedo):
    low = setup["low"]
    nx, ny, nz = setup["grid"]
    e, b, t = low["extent_km"], low["base_km"], low["top_km"]
    data = np.fromfile(grid_path, dtype="<f4").reshape(nz, ny, nx, 1)
    vol_path = grid_path + ".vol"
    mi.VolumeGrid(data).write(vol_path)
    # The grid's unit cube [0, 1]³ onto the patch.
    to_world = mi.ScalarTransform4f().translate([-e, -e, b]).scale([2 * e, 2 * e, t - b])
    return {
        "type": "heterogeneous",
        "sigma_t": {"type": "gridvolume", "filename": vol_path, "to_world": to_world,
                    "filter_type": "trilinear"},
        "albedo": {"type": "constvolume", "value": float(albedo)},
        "scale": 1.0,
        "phase": {"type": "blendphase", "weight": 1.0 - W_FORWARD,
                  "phase1": {"type": "hg", "g": G_FORWARD},
                  "phase2": {"type": "hg", "g": G_BACK}},
    }


def box(setup, med):
    low = setup["low"]
    e, b, t = low["extent_km"], low["base_km"], low["top_km"]
    return {"type": "cube", "bsdf": {"type": "null"}, "interior": med,
            "to_world": mi.ScalarTransform4f().translate([0, 0, 0.5 * (b + t)])
            .scale([e, e, 0.5 * (t - b)])}


def film(w, h):
    return {"type": "hdrfilm", "width": w, "height": h, "rfilter": {"type": "box"},
            "pixel_format": "rgb", "component_format": "float32"}


def radiance_scene(setup, grid_path, sun, max_depth=-1):
    cam = setup["camera"]
    towards = unit_towards(sun["alt_deg"], sun["az_deg"])
    return mi.load_dict({
        "type": "scene",
        "integrator": {"type": "volpath", "max_depth": max_depth, "rr_depth": 64},
        "sensor": {"type": "perspective", "fov_axis": "y", "fov": float(cam["fov_deg"]),
                   "near_clip": 1e-3, "far_clip": 1e3,
                   "to_world": mi.ScalarTransform4f().look_at(
                       origin=[0, 0, 0], target=[0, 0, 1], up=[0, 1, 0]),
                   "film": film(cam["width"], cam["height"]),
                   "sampler": {"type": "independent"}},
        "cloud": box(setup, medium(setup, grid_path, 1.0)),
        "sun": {"type": "directional", "direction": [-c for c in towards],
                "irradiance": {"type": "rgb", "value": [1.0, 1.0, 1.0]}},
    })


def transmittance_scene(setup, grid_path, sun):
    cam = setup["shadow_camera"]
    towards = unit_towards(sun["alt_deg"], sun["az_deg"])
    s, back = cam["half_width_km"], cam["back_km"]
    centre = [-back * c for c in towards]
    return mi.load_dict({
        "type": "scene",
        "integrator": {"type": "volpath", "max_depth": -1},
        "sensor": {"type": "orthographic", "near_clip": 1e-3, "far_clip": 1e3,
                   "to_world": mi.ScalarTransform4f().look_at(
                       origin=centre, target=[0, 0, 0], up=[0, 1, 0]).scale([s, s, 1]),
                   "film": film(cam["width"], cam["height"]),
                   "sampler": {"type": "independent"}},
        "cloud": box(setup, medium(setup, grid_path, 0.0)),
        "sky": {"type": "constant", "radiance": {"type": "rgb", "value": [1.0, 1.0, 1.0]}},
    })


def render_halves(scene, spp, seed):
    """Two independent half-sample images (their mean is the reference)."""
    a = np.array(mi.render(scene, spp=spp // 2, seed=seed), dtype=np.float64)[:, :, :3]
    b = np.array(mi.render(scene, spp=spp // 2, seed=seed + 7919), dtype=np.float64)[:, :, :3]
    return a, b


def noise(a, b):
    ya, yb = a @ Y_WEIGHTS, b @ Y_WEIGHTS
    m = 0.5 * (ya + yb)
    sel = m >= 0.01 * m.max()
    if not sel.any():
        return float("nan")
    # The mean of two halves has half the variance of the difference.
    return float(np.sqrt(np.mean(((ya - yb)[sel] / m[sel]) ** 2)) / 2.0)


def write_exr(path, rgb):
    bmp = mi.Bitmap(np.ascontiguousarray(rgb, dtype=np.float32),
                    pixel_format=mi.Bitmap.PixelFormat.RGB)
    tmp = path + ".tmp.exr"
    bmp.write(tmp)
    os.replace(tmp, path)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--setup", default=os.path.join(ROOT, "tests/fixtures/cloud_ref/setup.json"))
    ap.add_argument("--out", default=os.path.join(ROOT, "tests/fixtures/cloud_ref"))
    ap.add_argument("--spp", type=int, default=1024)
    ap.add_argument("--shadow-spp", type=int, default=64)
    ap.add_argument("--seed", type=int, default=17,
                    help="base seed of the sampler (another value renders an independent copy, "
                         "e.g. to measure the reference's own noise with the test's metric)")
    ap.add_argument("--max-depth", type=int, default=-1,
                    help="volpath's max_depth for the radiance (-1: all orders; 2: single "
                         "scattering alone, a diagnostic)")
    ap.add_argument("--only", action="append", default=[],
                    help="render only these images (e.g. sun20_radiance), keeping the others "
                         "and their entries in references.json")
    args = ap.parse_args()
    os.makedirs(args.out, exist_ok=True)
    with open(args.setup) as f:
        setup = json.load(f)
    variant = setup_mitsuba()
    work = tempfile.mkdtemp(prefix="himmel-cloud-ref-")
    grid_path, grid_sum = export_grid(os.path.abspath(args.setup), work)
    report = {"mitsuba": mi.__version__, "variant": variant, "grid_sum": grid_sum, "images": {}}
    old_path = os.path.join(args.out, "references.json")
    if args.only and os.path.exists(old_path):
        with open(old_path) as f:
            old = json.load(f)
        for name, entry in old.get("images", {}).items():
            # Entries of the first version carried the spp at the top level.
            kind_spp = old.get("shadow_spp" if "transmittance" in name else "spp")
            entry.setdefault("spp", kind_spp)
            report["images"][name] = entry
    for k, sun in enumerate(setup["suns"]):
        for kind, make, spp in [
            ("radiance", radiance_scene, args.spp),
            ("transmittance", transmittance_scene, args.shadow_spp),
        ]:
            if args.only and f"{sun['name']}_{kind}" not in args.only:
                continue
            scene = (make(setup, grid_path, sun, args.max_depth) if kind == "radiance"
                     else make(setup, grid_path, sun))
            t0 = time.time()
            a, b = render_halves(scene, spp, seed=args.seed + 100 * k)
            name = f"{sun['name']}_{kind}.exr"
            write_exr(os.path.join(args.out, name), 0.5 * (a + b))
            report["images"][name] = {"spp": spp, "noise": noise(a, b),
                                      "seconds": time.time() - t0}
            print(name, report["images"][name], flush=True)
    with open(os.path.join(args.out, "references.json"), "w") as f:
        json.dump(report, f, indent=2)
        f.write("\n")


if __name__ == "__main__":
    main()
