//! Stars and planets as point sources in absolute units, and the
//! energy-conserving point-spread function that draws them.
//!
//! **Flux.** A source of visual magnitude V outside the atmosphere gives the
//! illuminance E = 2.54 × 10⁻⁶ lx · 10^(−0.4 V) (conventions.md, Photometry;
//! Allen's Astrophysical Quantities, 4th ed., §15.3). Along its line of sight
//! it is multiplied by the atmosphere's transmittance ([`Extinction`]).
//!
//! **Position.** Catalogue stars go through the one-matrix fast path of
//! `himmel_astro::stars` (space motion, aberration, frame bias, precession,
//! nutation, sidereal time, latitude), then standard refraction
//! (Saemundsson, Meeus eq. 16.4, 1010 hPa, 10 °C) raises the altitude
//! ([`refracted`]). Sources whose refracted altitude is below 0 are hidden by
//! the ground.
//!
//! **PSF** (adapted from the seed thesis §4.3.2: a fixed-size core for every
//! star plus a glare for the bright ones, here made energy-conserving). The
//! core is a Gaussian of standard deviation `core_px` pixels, truncated at
//! 2.5 σ. Its weights wᵢ are normalised to Σ wᵢ = 1 over the pixels it
//! touches, and pixel i receives the luminance Lᵢ = E · wᵢ / Ωᵢ with Ωᵢ the
//! pixel's true solid angle in the projection
//! ([`crate::Camera::pixel_solid_angle`]), so Σ Lᵢ Ωᵢ = E exactly, whatever
//! the projection or the field of view (a narrow field has small pixels: the
//! same flux gives a higher luminance and fainter stars show; a wide field
//! has large pixels and a star never covers more than its core). When the
//! core's peak would exceed the luminance the camera shows as white
//! (`white_cd_m2`, from the chosen exposure), the core keeps exactly the flux
//! that reaches white and the excess spreads over a glare disk with the
//! profile (1 − r/R)², R = `glare` · √(6 E_excess / (π L_white Ω)) pixels
//! (the disk whose peak is L_white carries E_excess): bright stars look
//! larger, not clipped, and their total flux stays right. `glare = 0` keeps
//! all the flux in the core.
//!
//! **Scintillation** (optional, deterministic; after the seed thesis eq. 4.38,
//! a noise-modulated brightness that grows towards the horizon): the flux is
//! multiplied by max(0, 1 + σ(X) n) with n a unit-variance hash noise of
//! (seed, star, 0.1 s time step) and σ(X) = 0.1 X^1.75 (at most 0.8), X the
//! airmass 1/cos z (Young 1967, AJ 72, 747: scintillation ∝ X^1.75).

use std::sync::OnceLock;

use glam::Vec3;
use himmel_astro::stars::{FastStar, FrameRotation};
use himmel_astro::units::J2000;
use himmel_catalog::color::{star_rgb, LocusModel};
use himmel_catalog::Catalog;

use crate::projection::{Camera, Projection};
use crate::spectrum::{BandWeights, Spectrum};
use crate::units::{CandelaPerM2, Lux};

/// Illuminance of a V = 0 source outside the atmosphere, lux (conventions.md).
pub const V0_ILLUMINANCE_LUX: Lux = 2.54e-6;

/// Extraterrestrial illuminance of a source of visual magnitude `vmag`, lux.
#[inline]
pub fn illuminance_lux(vmag: f64) -> Lux {
    V0_ILLUMINANCE_LUX * 10f64.powf(-0.4 * vmag)
}

/// A point source ready to draw.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PointSource {
    /// Apparent (refracted) direction, ENU unit vector.
    pub dir: Vec3,
    /// Illuminance outside the atmosphere, lux (after scintillation).
    pub lux: f32,
    /// Colour, linear sRGB with luminance 1.
    pub rgb: [f32; 3],
    /// Identifier (Hipparcos number for stars; 1–5 for Mercury–Saturn).
    pub id: u32,
}

pub use crate::refraction::refracted;

/// A catalogue star prepared for rendering.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CatalogueStar {
    /// Fast-path astrometry, refreshed at J2000.0 (linear space motion
    /// is exact for the embedded catalogue, which carries no radial velocity).
    pub fast: FastStar,
    /// Johnson V magnitude.
    pub vmag: f32,
    /// Colour from B−V (blackbody locus, `himmel_catalog::color`), luminance 1.
    pub rgb: [f32; 3],
    /// Hipparcos number.
    pub hip: u32,
}

/// B−V → colour at 0.01 mag steps over [−0.4, 2.5] (the range
/// `star_rgb` clamps to), interpolated linearly: the same colours as
/// `star_rgb` within 10⁻³, without a Planck integration per star.
struct ColourTable(Vec<[f32; 3]>);

impl ColourTable {
    const LO: f64 = -0.4;
    const STEP: f64 = 0.01;
    const N: usize = 291;

    fn new() -> Self {
        ColourTable(
            (0..Self::N)
                .map(|i| colour_from_bv(Self::LO + Self::STEP * i as f64))
                .collect(),
        )
    }

    fn rgb(&self, bv: Option<f64>) -> [f32; 3] {
        let Some(bv) = bv.filter(|b| b.is_finite()) else {
            let c = star_rgb(None, LocusModel::Blackbody);
            return [c[0] as f32, c[1] as f32, c[2] as f32];
        };
        let x = ((bv - Self::LO) / Self::STEP).clamp(0.0, (Self::N - 1) as f64);
        let i = (x as usize).min(Self::N - 2);
        let f = (x - i as f64) as f32;
        let (a, b) = (self.0[i], self.0[i + 1]);
        [
            a[0] + (b[0] - a[0]) * f,
            a[1] + (b[1] - a[1]) * f,
            a[2] + (b[2] - a[2]) * f,
        ]
    }
}

fn prepare(cat: &Catalog) -> Vec<CatalogueStar> {
    let colours = ColourTable::new();
    cat.stars()
        .iter()
        .map(|s| {
            let c = colours.rgb(s.bv);
            CatalogueStar {
                fast: FastStar::new(&s.astrometry, J2000),
                vmag: s.vmag as f32,
                rgb: c,
                hip: s.hip,
            }
        })
        .collect()
}

/// The catalogue stars with V ≤ `limit_mag`, brightest first: the embedded
/// V ≤ 6.5 table, or the V ≤ 8 table above 6.5. Prepared once per process.
pub fn catalogue(limit_mag: f64) -> &'static [CatalogueStar] {
    static BRIGHT: OnceLock<Vec<CatalogueStar>> = OnceLock::new();
    static FAINT: OnceLock<Vec<CatalogueStar>> = OnceLock::new();
    let all: &'static [CatalogueStar] = if limit_mag > 6.5 {
        FAINT.get_or_init(|| Catalog::embedded_faint().map(prepare).unwrap_or_default())
    } else {
        BRIGHT.get_or_init(|| Catalog::embedded().map(prepare).unwrap_or_default())
    };
    let n = all.partition_point(|s| (s.vmag as f64) <= limit_mag);
    &all[..n]
}

/// The frame rotation of the catalogue stars (refreshed at J2000.0).
pub fn star_frame(epoch: &himmel_astro::Epoch, observer: &himmel_astro::Observer) -> FrameRotation {
    FrameRotation::new(epoch, observer, J2000)
}

/// Deterministic scintillation (see the module documentation).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Scintillation {
    /// Seed of the noise.
    pub seed: u64,
    /// 0.1 s time step index.
    pub step: i64,
}

impl Scintillation {
    /// Flux factor for source `id` at zenith cosine `cos_z` (> 0).
    pub fn factor(&self, id: u32, cos_z: f32) -> f32 {
        let x = 1.0 / cos_z.max(0.025);
        let sigma = (0.1 * x.powf(1.75)).min(0.8);
        let mut h = self.seed
            ^ (id as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15)
            ^ (self.step as u64).wrapping_mul(0xC2B2_AE3D_27D4_EB4F);
        // SplitMix64 finaliser.
        h = (h ^ (h >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        h = (h ^ (h >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        h ^= h >> 31;
        let u = (h >> 40) as f32 / (1u64 << 24) as f32;
        // Uniform on [−√3, √3]: unit variance, zero mean.
        let n = (2.0 * u - 1.0) * 3f32.sqrt();
        (1.0 + sigma * n).max(0.0)
    }
}

/// The point source of catalogue star `s` in `frame`, or `None` below the
/// horizon (refracted altitude < 0).
#[inline]
pub fn star_source(
    frame: &FrameRotation,
    s: &CatalogueStar,
    scint: Option<&Scintillation>,
) -> Option<PointSource> {
    let enu = frame.enu(&s.fast);
    // Refraction lifts by at most 0.6°: anything lower stays hidden.
    if enu.z < -0.011 {
        return None;
    }
    let d = refracted(enu);
    if d.z < 0.0 {
        return None;
    }
    let dir = d.as_vec3();
    let mut lux = illuminance_lux(s.vmag as f64) as f32;
    if let Some(sc) = scint {
        lux *= sc.factor(s.hip, dir.z);
    }
    Some(PointSource {
        dir,
        lux,
        rgb: s.rgb,
        id: s.hip,
    })
}

/// B−V colour indices of the planets (Mercury, Venus, Mars, Jupiter,
/// Saturn), magnitudes: Allen's Astrophysical Quantities, 4th ed. (Cox 2000),
/// §12.3 table of planetary magnitudes and colours.
pub const PLANET_BV: [f64; 5] = [0.93, 0.82, 1.36, 0.83, 1.04];

/// The colour (linear sRGB, luminance 1) of a body of colour index `bv`.
pub fn colour_from_bv(bv: f64) -> [f32; 3] {
    let c = star_rgb(Some(bv), LocusModel::Blackbody);
    [c[0] as f32, c[1] as f32, c[2] as f32]
}

/// Atmospheric extinction of point sources as linear sRGB factors, tabulated
/// against the zenith cosine μ = sin(apparent altitude) (0–1 in 1024 steps,
/// 0.056° of altitude at the horizon; linear interpolation).
/// The band transmittance T(λ) is turned into per-channel factors with the
/// solar spectrum's band weights: f_k = Σ_b T_b w_bk / Σ_b w_bk (an
/// approximation for stars whose spectra differ from the Sun's).
#[derive(Debug, Clone, PartialEq)]
pub struct Extinction {
    table: Vec<[f32; 3]>,
}

const EXTINCTION_STEPS: usize = 1024;

impl Extinction {
    /// No atmosphere: every factor is 1.
    pub fn none() -> Self {
        Extinction {
            table: vec![[1.0; 3]; 2],
        }
    }

    /// Tabulates `transmittance(μ)` (band transmittance to space towards
    /// zenith cosine μ, e.g. `AtmosphereLuts::sun_transmittance`).
    pub fn from_transmittance(transmittance: impl Fn(f32) -> Spectrum) -> Self {
        let w = BandWeights::solar();
        let one = w.to_rgb(&Spectrum::ONE);
        let table = (0..=EXTINCTION_STEPS)
            .map(|i| {
                let mu = i as f32 / EXTINCTION_STEPS as f32;
                let rgb = w.to_rgb(&transmittance(mu));
                [rgb[0] / one[0], rgb[1] / one[1], rgb[2] / one[2]]
            })
            .collect();
        Extinction { table }
    }

    /// The table: per-channel factors at μ = i / (len − 1), i = 0 … len − 1
    /// (for renderers that upload it, e.g. `himmel-wgpu`).
    pub fn table(&self) -> &[[f32; 3]] {
        &self.table
    }

    /// Per-channel transmittance towards ENU direction `dir` (unit).
    #[inline]
    pub fn rgb(&self, dir: Vec3) -> [f32; 3] {
        let n = self.table.len() - 1;
        let x = dir.z.clamp(0.0, 1.0) * n as f32;
        let i = (x as usize).min(n - 1);
        let f = x - i as f32;
        let (a, b) = (self.table[i], self.table[i + 1]);
        [
            a[0] + (b[0] - a[0]) * f,
            a[1] + (b[1] - a[1]) * f,
            a[2] + (b[2] - a[2]) * f,
        ]
    }
}

/// The point-spread function's settings for one frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Psf {
    /// Core standard deviation, pixels.
    pub core_px: f32,
    /// Glare scale (0 = no glare).
    pub glare: f32,
    /// Luminance the camera shows as white at the chosen exposure, cd/m².
    pub white_cd_m2: CandelaPerM2,
}

/// Reusable buffers of [`splat`].
#[derive(Debug, Default, Clone)]
pub struct SplatScratch {
    taps: Vec<(usize, f32, f32)>,
}

/// Image pixels a footprint may touch: the pixel index of integer pixel
/// (i, j), or `None` outside the image / across a cube-map face edge.
#[inline]
fn pixel_index(cam: &Camera, w: i64, h: i64, i: i64, j: i64, face: i64) -> Option<usize> {
    if j < 0 || j >= h {
        return None;
    }
    let i = match cam.projection {
        Projection::Equirect => i.rem_euclid(w),
        Projection::Cubemap => {
            if i < face * h || i >= (face + 1) * h {
                return None;
            }
            i
        }
        _ => {
            if i < 0 || i >= w {
                return None;
            }
            i
        }
    };
    Some((j * w + i) as usize)
}

/// Adds the image of one point source to `pixels` (row-major linear sRGB,
/// cd/m², the camera's image size): illuminance `lux` (already extincted)
/// with colour `rgb` (luminance 1) at ENU direction `dir`. Returns the
/// luminance-weighted flux actually deposited (lux; equals `lux` unless the
/// whole footprint falls outside the image or below the horizon).
pub fn splat(
    pixels: &mut [[f32; 3]],
    cam: &Camera,
    dir: Vec3,
    lux: f32,
    rgb: [f32; 3],
    psf: &Psf,
    scratch: &mut SplatScratch,
) -> f32 {
    let Some((cx, cy)) = cam.dir_to_pixel(dir.as_dvec3()) else {
        return 0.0;
    };
    splat_at(pixels, 0, cam, (cx, cy), dir.z, lux, rgb, psf, scratch)
}

/// [`splat`] at the continuous image position `(cx, cy)` of a source whose
/// direction has zenith cosine `dir_z`, writing only the part of the image
/// held by `pixels`: the row-major pixels from index `offset` on (a band of
/// rows, so that bands can be splatted in parallel; the footprint and its
/// normalisation are always those of the whole image). Returns the flux
/// deposited in the whole image.
#[allow(clippy::too_many_arguments)]
pub fn splat_at(
    pixels: &mut [[f32; 3]],
    offset: usize,
    cam: &Camera,
    pos: (f64, f64),
    dir_z: f32,
    lux: f32,
    rgb: [f32; 3],
    psf: &Psf,
    scratch: &mut SplatScratch,
) -> f32 {
    splat_impl(
        Some((pixels, offset)),
        cam,
        pos,
        dir_z,
        lux,
        psf,
        rgb,
        scratch,
    )
    .0
}

/// The footprint of one source as [`splat_at`] computes it, without
/// depositing: for renderers that evaluate the footprint per pixel (e.g.
/// `himmel-wgpu`). Pixel (i, j) of the core (|i − ⌊cx⌋| ≤ r, |j − ⌊cy⌋| ≤ r,
/// (i + ½ − cx)² + (j + ½ − cy)² ≤ r² + ½, with Ω > 0, in the image or,
/// equirect, wrapped in x, on the same cube face, above the ground when
/// `near_horizon`) receives `core_scale` · w / Ω · rgb with w =
/// exp(−(i + ½ − cx)²/2σ²) · exp(−(j + ½ − cy)²/2σ²); pixel (i, j) of the
/// glare disk (distance d < `glare_r_px`, same conditions) receives
/// `glare_scale` · (1 − d / R)² / Ω · rgb. `None` when nothing is deposited.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SplatPlan {
    /// Continuous image position of the source, px.
    pub pos: (f64, f64),
    /// The cube face of the source (cube maps), ⌊cx / H⌋.
    pub face: i64,
    /// Whether footprint pixels are checked against the ground.
    pub near_horizon: bool,
    /// Core radius r = ⌈2.5 σ⌉, px.
    pub r: i64,
    /// 1 / (2σ²), px⁻².
    pub inv2s2: f32,
    /// Core flux over the sum of the core weights, lux.
    pub core_scale: f32,
    /// Glare disk radius R, px (0: no glare).
    pub glare_r_px: f32,
    /// Glare flux over the sum of the glare weights, lux.
    pub glare_scale: f32,
}

/// [`SplatPlan`] of a source (arguments as [`splat_at`]).
pub fn splat_plan(
    cam: &Camera,
    pos: (f64, f64),
    dir_z: f32,
    lux: f32,
    psf: &Psf,
    scratch: &mut SplatScratch,
) -> Option<SplatPlan> {
    splat_impl(None, cam, pos, dir_z, lux, psf, [1.0; 3], scratch).1
}

#[allow(clippy::too_many_arguments)]
fn splat_impl(
    mut out: Option<(&mut [[f32; 3]], usize)>,
    cam: &Camera,
    (cx, cy): (f64, f64),
    dir_z: f32,
    lux: f32,
    psf: &Psf,
    rgb: [f32; 3],
    scratch: &mut SplatScratch,
) -> (f32, Option<SplatPlan>) {
    if lux <= 0.0 || !lux.is_finite() {
        return (0.0, None);
    }
    let (w, h) = cam.image_size();
    let (w, h) = (w as i64, h as i64);
    let face = (cx / h as f64).floor() as i64;
    // Near the horizon each footprint pixel is checked against the ground.
    let near_horizon = (dir_z as f64) < 4.0 * cam.max_pixel_angle() * psf.core_px.max(1.0) as f64;
    let sigma = psf.core_px.max(0.1);
    let r = (2.5 * sigma).ceil() as i64;
    let (ci, cj) = (cx.floor() as i64, cy.floor() as i64);
    let inv2s2 = 1.0 / (2.0 * sigma * sigma);
    // The Gaussian is separable: one exponential per column and per row.
    let mut gx = [0.0f32; 32];
    let mut gy = [0.0f32; 32];
    let n = (2 * r + 1).min(32) as usize;
    for k in 0..n {
        let o = (k as i64 - r) as f64 + 0.5;
        gx[k] = (-(((ci as f64 + o - cx).powi(2)) as f32) * inv2s2).exp();
        gy[k] = (-(((cj as f64 + o - cy).powi(2)) as f32) * inv2s2).exp();
    }
    // A footprint pixel: its index and centre (off the image or its
    // cube face: None), then its solid angle where it shows sky (None at
    // zero solid angle, or below the horizon near it).
    let pixel = |i: i64, j: i64| {
        pixel_index(cam, w, h, i, j, face).map(|idx| (idx, i as f64 + 0.5, j as f64 + 0.5))
    };
    let sky_omega = |px: f64, py: f64| {
        let omega = cam.pixel_solid_angle(px, py) as f32;
        let shown =
            omega > 0.0 && !(near_horizon && cam.pixel_to_dir(px, py).map_or(true, |d| d.z < 0.0));
        shown.then_some(omega)
    };
    let taps = &mut scratch.taps;
    taps.clear();
    let mut sum = 0.0f32;
    let mut peak = (0.0f32, 1.0f32);
    for (b, j) in (cj - r..=cj + r).enumerate().take(n) {
        for (a, i) in (ci - r..=ci + r).enumerate().take(n) {
            let Some((idx, px, py)) = pixel(i, j) else {
                continue;
            };
            let d2 = ((px - cx).powi(2) + (py - cy).powi(2)) as f32;
            if d2 > (r * r) as f32 + 0.5 {
                continue;
            }
            let Some(omega) = sky_omega(px, py) else {
                continue;
            };
            let wt = gx[a] * gy[b];
            sum += wt;
            if wt > peak.0 {
                peak = (wt, omega);
            }
            taps.push((idx, wt, omega));
        }
    }
    if sum <= 0.0 {
        return (0.0, None);
    }
    // Split the flux between the core and the glare.
    let peak_l = lux * peak.0 / sum / peak.1;
    let core_lux = if psf.glare > 0.0 && peak_l > psf.white_cd_m2 && psf.white_cd_m2 > 0.0 {
        lux * psf.white_cd_m2 / peak_l
    } else {
        lux
    };
    if let Some((pixels, offset)) = out.as_mut() {
        deposit(pixels, *offset, taps, core_lux / sum, rgb);
    }
    let mut plan = SplatPlan {
        pos: (cx, cy),
        face,
        near_horizon,
        r,
        inv2s2,
        core_scale: core_lux / sum,
        glare_r_px: 0.0,
        glare_scale: 0.0,
    };
    let excess = lux - core_lux;
    if excess <= 0.0 {
        return (lux, Some(plan));
    }
    // Glare disk: peak ≈ white, radius from the excess flux.
    let r_px = (psf.glare
        * (6.0 * excess / (std::f32::consts::PI * psf.white_cd_m2 * peak.1)).sqrt())
    .clamp(2.0, 256.0);
    let rg = r_px.ceil() as i64;
    taps.clear();
    let mut gsum = 0.0f32;
    for j in cj - rg..=cj + rg {
        for i in ci - rg..=ci + rg {
            let Some((idx, px, py)) = pixel(i, j) else {
                continue;
            };
            let d = ((px - cx).powi(2) + (py - cy).powi(2)).sqrt() as f32;
            if d >= r_px {
                continue;
            }
            let Some(omega) = sky_omega(px, py) else {
                continue;
            };
            let x = 1.0 - d / r_px;
            let wt = x * x;
            gsum += wt;
            taps.push((idx, wt, omega));
        }
    }
    if gsum <= 0.0 {
        return (core_lux, Some(plan));
    }
    if let Some((pixels, offset)) = out {
        deposit(pixels, offset, taps, excess / gsum, rgb);
    }
    plan.glare_r_px = r_px;
    plan.glare_scale = excess / gsum;
    (lux, Some(plan))
}

/// The peak luminance (cd/m²) that the core of a source of illuminance
/// `lux` reaches at ENU direction `dir` (used by the pass culling), or 0
/// when the direction falls outside the image.
pub fn core_peak_luminance(cam: &Camera, dir: Vec3, lux: f32, core_px: f32) -> f32 {
    let Some((cx, cy)) = cam.dir_to_pixel(dir.as_dvec3()) else {
        return 0.0;
    };
    let (w, h) = cam.image_size();
    if !(cx >= 0.0 && cy >= 0.0 && cx < w as f64 && cy < h as f64) {
        return 0.0;
    }
    let omega = cam.pixel_solid_angle(cx.floor() + 0.5, cy.floor() + 0.5) as f32;
    if omega <= 0.0 {
        return 0.0;
    }
    // Best case: the star centred on a pixel; the discrete Gaussian's
    // central weight is at most 1/(2πσ²) (or 1 for a tiny σ).
    let sigma = core_px.max(0.1);
    let w0 = (1.0 / (2.0 * std::f32::consts::PI * sigma * sigma)).min(1.0);
    lux * w0 / omega
}

/// Adds `k · weight / Ω` × `rgb` to each tap's pixel (luminance from a
/// share of illuminance spread over taps of solid angle Ω); `offset` is
/// the index of `pixels[0]` in the whole image (band-parallel splats).
fn deposit(
    pixels: &mut [[f32; 3]],
    offset: usize,
    taps: &[(usize, f32, f32)],
    k: f32,
    rgb: [f32; 3],
) {
    for &(idx, wt, omega) in taps {
        let Some(p) = idx.checked_sub(offset).and_then(|i| pixels.get_mut(i)) else {
            continue;
        };
        let l = k * wt / omega;
        p[0] += l * rgb[0];
        p[1] += l * rgb[1];
        p[2] += l * rgb[2];
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec3;

    fn integrate(pixels: &[[f32; 3]], cam: &Camera) -> f64 {
        let (w, _) = cam.image_size();
        let w = w as usize;
        pixels
            .iter()
            .enumerate()
            .map(|(i, p)| {
                let (x, y) = ((i % w) as f64 + 0.5, (i / w) as f64 + 0.5);
                crate::spectrum::luminance(*p) as f64 * cam.pixel_solid_angle(x, y)
            })
            .sum()
    }

    #[test]
    fn splat_conserves_flux_in_every_projection_with_and_without_glare() {
        let dirs = [
            Vec3::Z,
            Vec3::new(0.3, 0.5, 0.81).normalize(),
            Vec3::new(-0.9, 0.1, 0.05).normalize(),
        ];
        for p in [
            Projection::Fisheye,
            Projection::Equirect,
            Projection::Perspective,
            Projection::Cubemap,
        ] {
            let cam = Camera {
                projection: p,
                width: 96,
                height: 64,
                yaw_deg: 20.0,
                pitch_deg: 30.0,
                fov_deg: 120.0,
                ..Camera::default()
            };
            let (w, h) = cam.image_size();
            for &d in &dirs {
                for &(white, glare) in &[(1e9f32, 1.0f32), (1e-6, 1.0), (1e-6, 0.0)] {
                    let mut px = vec![[0.0f32; 3]; (w * h) as usize];
                    let psf = Psf {
                        core_px: 0.7,
                        glare,
                        white_cd_m2: white,
                    };
                    let rgb = colour_from_bv(1.5);
                    let lux = illuminance_lux(-1.46) as f32;
                    let dep = splat(
                        &mut px,
                        &cam,
                        d,
                        lux,
                        rgb,
                        &psf,
                        &mut SplatScratch::default(),
                    );
                    if dep == 0.0 {
                        continue;
                    }
                    let e = integrate(&px, &cam);
                    assert!(
                        (e / lux as f64 - 1.0).abs() < 1e-3,
                        "{p:?} {d} white {white}: {e} vs {lux}"
                    );
                }
            }
        }
    }

    #[test]
    fn flux_scale_and_refraction() {
        // Five magnitudes are a factor 100.
        assert!((illuminance_lux(0.0) / illuminance_lux(5.0) - 100.0).abs() < 1e-9);
        // Refraction at the true horizon is ≈ 29′ (Meeus ch. 16), none at the zenith.
        let h = refracted(DVec3::new(0.0, 1.0, 0.0));
        let lift = h.z.asin().to_degrees() * 60.0;
        assert!((lift - 28.7).abs() < 1.0, "{lift}′");
        assert_eq!(refracted(DVec3::Z), DVec3::Z);
        assert!((refracted(DVec3::new(0.6, 0.0, 0.8)).length() - 1.0).abs() < 1e-12);
    }

    #[test]
    fn scintillation_is_deterministic_unbiased_and_stronger_low_down() {
        let s = Scintillation { seed: 7, step: 42 };
        assert_eq!(s.factor(32349, 0.5), s.factor(32349, 0.5));
        let spread = |cz: f32| {
            let v: Vec<f32> = (0..4000).map(|i| s.factor(i, cz)).collect();
            let m = v.iter().sum::<f32>() / v.len() as f32;
            let var = v.iter().map(|x| (x - m).powi(2)).sum::<f32>() / v.len() as f32;
            (m, var.sqrt())
        };
        let (m_hi, sd_hi) = spread(1.0);
        let (_, sd_lo) = spread(0.2);
        assert!((m_hi - 1.0).abs() < 0.01, "{m_hi}");
        assert!((sd_hi - 0.1).abs() < 0.01, "{sd_hi}");
        assert!(sd_lo > 3.0 * sd_hi);
    }

    #[test]
    fn catalogue_limits_and_order() {
        let bright = catalogue(6.5);
        assert_eq!(bright.len(), 8874);
        assert!(bright.windows(2).all(|p| p[0].vmag <= p[1].vmag));
        assert!(catalogue(8.0).len() > 40_000);
        assert!(catalogue(1.0).len() < 30);
        // Betelgeuse is orange, Rigel blue-white.
        let by = |hip: u32| bright.iter().find(|s| s.hip == hip).unwrap().rgb;
        let (betel, rigel) = (by(27989), by(24436));
        assert!(betel[0] > betel[2] * 1.5, "{betel:?}");
        assert!(rigel[2] > rigel[0], "{rigel:?}");
    }

    #[test]
    fn colour_table_matches_the_catalogue_colours() {
        let t = ColourTable::new();
        for i in 0..=600 {
            let bv = -0.6 + i as f64 * 0.005;
            let want = star_rgb(Some(bv), LocusModel::Blackbody);
            let got = t.rgb(Some(bv));
            for k in 0..3 {
                assert!(
                    (got[k] as f64 - want[k]).abs() < 2e-3,
                    "{bv}: {got:?} vs {want:?}"
                );
            }
        }
        assert_eq!(t.rgb(None), [1.0; 3]);
    }

    #[test]
    fn extinction_table_interpolates_and_reddens() {
        let t = Extinction::from_transmittance(|mu| {
            Spectrum::from_fn(|nm| (-(0.1 * (550.0 / nm).powi(4)) / (mu as f64).max(0.05)).exp())
        });
        let z = t.rgb(Vec3::Z);
        let low = t.rgb(Vec3::new(0.0, 0.996, 0.087));
        assert!(z[1] > 0.85 && z[1] < 0.95, "{z:?}");
        assert!(low[2] / low[0] < z[2] / z[0]);
        assert_eq!(Extinction::none().rgb(Vec3::Z), [1.0; 3]);
    }
}
