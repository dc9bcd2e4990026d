#!/usr/bin/env python3
"""How finely must the sky be sampled to light a wall through a window?

The world renderer's sky light is a quadrature: the sky is cut into cells
around a fixed set of directions (the fine partition of all the interleaved
sets, backend-wgpu/src/passes/lighting/env.rs), and each cell counts whole
when its direction is visible. This script measures that quadrature's error
in the ideal case (exact visibility per direction, exact cell moments) for
points on the sun room's west wall (x = -3 m, y = 1.5 m), which see the
south window (x in [-1, 1] m, y in [0.8, 2.3] m, a 0.2 m deep opening from
z = 2.5 m to 2.7 m) at grazing angles, under a sky brightening towards the
horizon. The direction sets are view.rs's `direction_sets(n, true, 16)`.

    python3 tools/window_quadrature.py

prints, per set size, the relative error at 23 points along the wall, %.
"""
import numpy as np


def direction_sets(n, sets):
    golden = np.pi * (3 - np.sqrt(5))
    out = []
    for s in range(sets):
        shift = (s + 0.5) / sets
        turn = 2 * np.pi * s / sets
        i = np.arange(n)
        y = 1 - (i + shift) / n
        r = np.sqrt(np.maximum(0, 1 - y * y))
        phi = golden * i + turn
        up = np.stack([r * np.cos(phi), y, r * np.sin(phi)], 1)
        out.append(np.concatenate([up, up * np.array([1, -1, 1])]))
    return np.concatenate(out)


def through_window(p, d):
    ok = d[:, 2] > 1e-6
    dz = np.where(ok, d[:, 2], 1.0)
    for z in (2.5, 2.7):
        t = (z - p[2]) / dz
        x = p[0] + t * d[:, 0]
        y = p[1] + t * d[:, 1]
        ok &= (x > -1) & (x < 1) & (y > 0.8) & (y < 2.3)
    return ok.astype(float)


def main():
    rng = np.random.default_rng(0)
    n_samples = 2_000_000
    v = rng.normal(size=(n_samples, 3))
    v /= np.linalg.norm(v, axis=1)[:, None]
    radiance = np.where(v[:, 1] > 0, 1 + 2 * (1 - v[:, 1]) ** 3, 0.0)
    sa = 4 * np.pi / n_samples
    normal = np.array([1.0, 0.0, 0.0])
    for per_hemisphere in (32, 128):
        dirs = direction_sets(per_hemisphere, 16)
        cell = np.empty(n_samples, int)
        for upper in (True, False):
            m = (v[:, 1] >= 0) == upper
            idx = np.where((dirs[:, 1] > 0) == upper)[0]
            cell[m] = idx[np.argmax(v[m] @ dirs[idx].T, axis=1)]
        moments = np.zeros((len(dirs), 3))
        np.add.at(moments, cell, v * (radiance * sa)[:, None])
        errors = []
        for z in np.linspace(-2.2, 2.2, 23):
            p = np.array([-3 + 0.01, 1.5, z])
            exact = (radiance * through_window(p, v) * np.maximum(0, v @ normal)).sum() * sa
            quad = (through_window(p, dirs) * np.maximum(0, moments @ normal)).sum()
            errors.append(100 * (quad / exact - 1))
        print(f"{len(dirs)} directions:", " ".join(f"{e:+.0f}" for e in errors))


if __name__ == "__main__":
    main()
