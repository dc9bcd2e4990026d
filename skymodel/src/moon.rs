//! The Moon: its state for one instant ([`MoonState`]), its photometry
//! (Hapke–Lommel–Seeliger BRDF with the opposition surge, an albedo map,
//! earthshine), lunar-eclipse shading and the per-pixel shader
//! ([`MoonShader`]) that both renderers evaluate.
//!
//! ## Photometry
//!
//! Radiance of a surface point lit by the Sun (Hapke 1963, "A theoretical
//! photometric function for the lunar surface", JGR 68, 4571; the seed
//! thesis' eqs. 4.5–4.8):
//!
//! L = E☉ · (p/π) · a(x) · [2 B(g) S(g) / B(0)] · μ0 / (μ0 + μ)
//!
//! * E☉ — solar illuminance at the Moon (the 1 AU value × (1 AU / r)²);
//! * μ0, μ — cosines of the incidence and emergence angles; μ0/(μ0 + μ) is
//!   the Lommel–Seeliger law;
//! * B(g) = 1 + B0 / (1 + tan(g/2)/h) — the shadow-hiding opposition surge
//!   in Hapke's later form (Hapke 1986, Icarus 67, 264; the seed thesis
//!   uses Hapke's 1963 form, see below), B0 = 0.9, h = 0.08
//!   ([`SURGE_B0`], [`SURGE_H`]);
//! * S(g) = [sin g + (π − g) cos g]/π + c (1 − cos g)² — Hapke's (1963)
//!   phase law (as in the seed thesis), c = 0.065 ([`HAPKE_S_COEFF`];
//!   Hapke's value is 0.1); S(0) = 1;
//! * a(x) — the albedo map, normalised so that its mean over the mean
//!   near side weighted by projected area is 1 ([`AlbedoMap`]);
//! * p — the Moon's geometric albedo in V, 0.125 ([`GEOMETRIC_ALBEDO`]).
//!
//! At g = 0 the law gives L = E☉ p/π · a(x) everywhere on the disk, so the
//! disk-integrated illuminance at full phase is p E☉ (R☾/Δ)², the definition
//! of the geometric albedo: the albedo scale is p and nothing else.
//!
//! **Calibration.** B0, h, c and p were fitted together (minimax, uniform
//! albedo, disk integral on a 300 × 300 grid) to the observed lunar phase
//! curve V = −12.73 + 0.026 φ + 4 × 10⁻⁹ φ⁴ (Allen's Astrophysical
//! Quantities, 4th ed., Cox 2000) over φ = 5°–120° (largest residual 5.4 % with
//! c = 0.075); c was then lowered to 0.065 because with the albedo map both
//! crescents at φ = 120° came out 9–15 % bright (uniform-disk residuals with
//! c = 0.065: −10 % … +5 %). The fitted values agree with the published ones — p = 0.12
//! (Allen; Lane & Irvine 1973, AJ 78, 267), B0 ≈ 1 and h ≈ 0.05–0.08 for the
//! lunar surge (Helfenstein & Veverka 1987, Icarus 72, 342). The seed's
//! Hapke (1963) surge B(g) = 2 − tan g/(2h′)(1 − e^(−h′/tan g))(3 − e^(−h′/tan g))
//! with h′ = 0.6 ([`hapke_1963_b`]) falls too fast: with the albedo map the
//! waning Moon at φ = 60° came out 16 % below the curve. The remaining
//! waxing/waning difference (the maria of the western hemisphere) is real:
//! the observed Moon is ~0.1 mag brighter before full than after.
//!
//! Colour: the lunar reflectance rises towards the red; the relative
//! reflectance 1 + 0.0017 (λ − 550 nm) reproduces the Moon's B − V = 0.92
//! against the Sun's 0.65 (Allen's Astrophysical Quantities) and is normalised to 1 in V
//! (luminance under the solar spectrum).
//!
//! Relief: μ0 and μ use the normal of Stellarium's lunar normal map
//! ([`NormalMap`]) instead of the sphere's, so that craters and mountains
//! cast their shading near the terminator; at full phase (μ0 = μ) the law
//! is unchanged, so the calibration holds. Points beyond the sphere's
//! terminator stay dark (the map has no self-shadowing).
//!
//! ## Earthshine
//!
//! The Earth lights the Moon with E⊕ = p⊕ · E☉ · (R⊕ / d)² · Φ(α⊕), where
//! p⊕ = 0.367 is the Earth's visual geometric albedo (NASA Earth fact sheet),
//! R⊕ = 6371 km, d the Earth–Moon distance, α⊕ the Earth's phase angle seen
//! from the Moon (the Moon's geocentric elongation from the Sun) and
//! Φ(α) = [sin α + (π − α) cos α]/π the Lambert-sphere phase law (Russell
//! 1916). This is the seed thesis' eq. 4.9 in physical units. The Moon
//! reflects it at phase angle ≈ 0 (the Earth is behind the observer), so its
//! radiance is E⊕ p/π a(x).
//!
//! ## Lunar eclipses
//!
//! [`eclipse_transfer`] gives, per band, the sunlight reaching a point of the
//! Moon at angular distance d from the shadow axis (relative to the
//! uneclipsed Sun), integrated over the solar disk: direct light from the part
//! of the Sun not hidden by the solid Earth, and light refracted through the
//! Earth's limb at tangent height h. A ray grazing at height h is bent by
//! δ(h) = δ0 e^(−h/H) (δ0 = 2 × 34.5′, twice the horizontal refraction,
//! Bennett 1982; H the Rayleigh scale height), attenuated by the grazing
//! optical depth of the scene's atmosphere (Rayleigh, aerosols, ozone —
//! integrated through [`crate::atmosphere::Medium`]) and by clouds (half of the
//! limb opaque below 10 km), and diluted by the spreading of the ray bundle
//! (Link 1956, *Die Mondfinsternisse*): the solid angle of a solar element
//! changes by (σ_app/σ) (dσ_app/dh)/(dσ/dh). The penumbra, the red umbra
//! darkening towards the centre and the blue-turquoise fringe at the umbra's
//! edge (rays through the ozone layer above the Rayleigh-reddened heights)
//! follow from this; the umbra's apparent edge falls near Danjon's enlarged
//! shadow of [`himmel_astro::events::ShadowGeometry`].

use std::sync::OnceLock;

use glam::{DVec3, Vec3};
use himmel_astro::events::ShadowGeometry;
use serde::Serialize;

use crate::atmosphere::{AtmosphereLuts, Medium};
use crate::spectrum::{luminance, BandWeights, Spectrum};
use crate::units::{Lux, Radians};

/// Hapke's (1963) compaction parameter h′ of the lunar regolith (his "g"),
/// for [`hapke_1963_b`].
pub const HAPKE_H: f64 = 0.6;
/// Amplitude B0 of the opposition surge (fitted, see the module documentation).
pub const SURGE_B0: f64 = 0.9;
/// Angular width h of the opposition surge (fitted).
pub const SURGE_H: f64 = 0.08;
/// Coefficient of the (1 − cos g)² term of Hapke's S(g) (fitted; Hapke 1963: 0.1).
pub const HAPKE_S_COEFF: f64 = 0.065;
/// The Moon's geometric albedo in V (fitted; Allen's Astrophysical
/// Quantities, 4th ed., gives 0.12).
pub const GEOMETRIC_ALBEDO: f64 = 0.125;
/// The Earth's visual geometric albedo (NASA Earth fact sheet, 0.367).
pub const EARTH_GEOMETRIC_ALBEDO: f64 = 0.367;
/// Mean radius of the Earth, km.
pub const EARTH_RADIUS_KM: f64 = 6371.0;
/// Mean Earth–Moon distance of the Allen phase curve, km.
pub const MEAN_MOON_DISTANCE_KM: f64 = 384_400.0;
/// Illuminance of a magnitude-0 source outside the atmosphere, lux
/// (conventions.md).
pub const LUX_MAG0: f64 = 2.54e-6;

/// The opposition surge B(g) = 1 + B0/(1 + tan(g/2)/h) (Hapke 1986, Icarus
/// 67, 264); `g` the phase angle in radians; 1 + B0 at g = 0.
pub fn surge_b(g: f64) -> f64 {
    let g = g.abs().min(std::f64::consts::PI * 0.999_999);
    1.0 + SURGE_B0 / (1.0 + (g / 2.0).tan() / SURGE_H)
}

/// The opposition surge B(g) of Hapke (1963, JGR 68, 4571; the seed
/// thesis) with compaction `h`; `g` the phase angle in radians; 2
/// at g = 0, 1 for g ≥ 90°. Kept for comparison (see the module documentation).
pub fn hapke_1963_b(g: f64, h: f64) -> f64 {
    let g = g.abs();
    if g >= std::f64::consts::FRAC_PI_2 {
        return 1.0;
    }
    if g < 1e-9 {
        return 2.0;
    }
    let t = g.tan();
    let e = (-h / t).exp();
    2.0 - t / (2.0 * h) * (1.0 - e) * (3.0 - e)
}

/// Hapke's (1963) phase law S(g) = [sin g + (π − g) cos g]/π + 0.1 (1 − cos g)².
pub fn hapke_s(g: f64) -> f64 {
    let g = g.abs().min(std::f64::consts::PI);
    (g.sin() + (std::f64::consts::PI - g) * g.cos()) / std::f64::consts::PI
        + HAPKE_S_COEFF * (1.0 - g.cos()).powi(2)
}

/// The Lambert-sphere phase law Φ(α) = [sin α + (π − α) cos α]/π (Russell 1916).
pub fn lambert_sphere_phase(alpha: f64) -> f64 {
    let a = alpha.abs().min(std::f64::consts::PI);
    (a.sin() + (std::f64::consts::PI - a) * a.cos()) / std::f64::consts::PI
}

/// The observed lunar phase curve (Allen's Astrophysical Quantities, 4th ed.,
/// Cox 2000): V = −12.73 + 0.026 φ + 4 × 10⁻⁹ φ⁴ at the mean distances (φ in
/// degrees), moved to the Moon's distance `moon_km` from the observer and
/// the Sun's distance `sun_au` from the Moon by the inverse-square law.
pub fn allen_magnitude(phase_deg: f64, moon_km: f64, sun_au: f64) -> f64 {
    let p = phase_deg.abs();
    -12.73 + 0.026 * p + 4e-9 * p.powi(4) + 5.0 * (moon_km / MEAN_MOON_DISTANCE_KM * sun_au).log10()
}

/// Earthshine illuminance on the Moon, lux: p⊕ E☉ (R⊕/d)² Φ(α⊕), with the
/// solar illuminance `sun_lux` at the Moon, the Earth–Moon distance `d_km`
/// and the Earth's phase angle `earth_phase` (radians) seen from the Moon.
pub fn earthshine_lux(sun_lux: f64, d_km: f64, earth_phase: f64) -> Lux {
    EARTH_GEOMETRIC_ALBEDO
        * sun_lux
        * (EARTH_RADIUS_KM / d_km).powi(2)
        * lambert_sphere_phase(earth_phase)
}

/// Relative spectral reflectance of the lunar surface (1 + 0.0017 (λ − 550))
/// normalised so that its luminance under the solar spectrum is 1.
pub fn lunar_reflectance_spectrum() -> Spectrum {
    let w = BandWeights::solar();
    let raw = Spectrum::from_fn(|nm| (1.0 + 0.0017 * (nm - 550.0)).max(0.1));
    let k = w.solar_illuminance_lux() as f32 / w.to_y(&raw);
    raw * k
}

/// The lunar albedo map: relative albedo on a 1024 × 512 equirectangular
/// grid (selenographic longitude −180° at the left edge, 0° at the centre,
/// east to the right; north at the top), from Stellarium's public-domain
/// texture (USGS Astrogeology and Clementine via Celestia; see README).
#[derive(Debug, Clone)]
pub struct AlbedoMap {
    /// Width in texels.
    pub w: usize,
    /// Height in texels.
    pub h: usize,
    /// Relative albedo, row-major, normalised to a mean of 1 over the mean
    /// near side weighted by projected area.
    pub data: Vec<f32>,
}

static MAP_BYTES: &[u8] = include_bytes!("../data/moon_albedo_1024x512.u8");

impl AlbedoMap {
    /// The embedded map, normalised once.
    pub fn get() -> &'static AlbedoMap {
        static MAP: OnceLock<AlbedoMap> = OnceLock::new();
        MAP.get_or_init(|| {
            let (w, h) = (1024usize, 512usize);
            // The 8-bit values are taken as proportional to albedo (the source
            // mosaics are calibrated reflectance; see the README).
            let mut data: Vec<f32> = MAP_BYTES.iter().map(|&b| b as f32 / 255.0).collect();
            // Mean over the near side (|lon| < 90°) weighted by the
            // projected area cos(lat) cos(lon) · cos(lat) dlat dlon.
            let (mut s, mut ws) = (0.0f64, 0.0f64);
            for j in 0..h {
                let lat = std::f64::consts::FRAC_PI_2
                    - std::f64::consts::PI * (j as f64 + 0.5) / h as f64;
                for i in 0..w {
                    let lon =
                        -std::f64::consts::PI + std::f64::consts::TAU * (i as f64 + 0.5) / w as f64;
                    if lon.abs() >= std::f64::consts::FRAC_PI_2 {
                        continue;
                    }
                    let wt = lat.cos() * lat.cos() * lon.cos();
                    s += data[j * w + i] as f64 * wt;
                    ws += wt;
                }
            }
            let k = (ws / s) as f32;
            for v in data.iter_mut() {
                *v *= k;
            }
            AlbedoMap { w, h, data }
        })
    }

    /// Relative albedo at selenographic longitude `lon` and latitude `lat`
    /// (radians), bilinear, wrapping in longitude.
    #[inline]
    pub fn sample(&self, lon: f32, lat: f32) -> f32 {
        let u = (lon / std::f32::consts::TAU + 0.5) * self.w as f32 - 0.5;
        let v = (0.5 - lat / std::f32::consts::PI) * self.h as f32 - 0.5;
        let v = v.clamp(0.0, (self.h - 1) as f32);
        let (i0, j0) = (u.floor(), v.floor());
        let (fu, fv) = (u - i0, v - j0);
        let w = self.w as i32;
        let i0 = (i0 as i32).rem_euclid(w) as usize;
        let i1 = (i0 + 1) % self.w;
        let j0 = j0 as usize;
        let j1 = (j0 + 1).min(self.h - 1);
        let d = &self.data;
        let a = d[j0 * self.w + i0] * (1.0 - fu) + d[j0 * self.w + i1] * fu;
        let b = d[j1 * self.w + i0] * (1.0 - fu) + d[j1 * self.w + i1] * fu;
        a * (1.0 - fv) + b * fv
    }
}

/// The lunar normal map: the surface normal's east and north components
/// (tangent frame of the mean sphere) on a 512 × 256 equirectangular grid
/// laid out like [`AlbedoMap`], from Stellarium's public-domain
/// `moon_normals.png` (converted by `tools/moon_normals.py`). Used to shade
/// the relief near the terminator.
#[derive(Debug, Clone)]
pub struct NormalMap {
    /// Width in texels.
    pub w: usize,
    /// Height in texels.
    pub h: usize,
    /// (east, north) components, row-major.
    pub data: Vec<[f32; 2]>,
}

static NORMAL_BYTES: &[u8] = include_bytes!("../data/moon_normals_512x256.u8");

impl NormalMap {
    /// The embedded map, decoded once.
    pub fn get() -> &'static NormalMap {
        static MAP: OnceLock<NormalMap> = OnceLock::new();
        MAP.get_or_init(|| NormalMap {
            w: 512,
            h: 256,
            data: NORMAL_BYTES
                .chunks_exact(2)
                .map(|c| [c[0] as f32 / 127.5 - 1.0, c[1] as f32 / 127.5 - 1.0])
                .collect(),
        })
    }

    /// (east, north) normal components at selenographic `lon`, `lat`
    /// (radians), bilinear.
    #[inline]
    pub fn sample(&self, lon: f32, lat: f32) -> [f32; 2] {
        let u = (lon / std::f32::consts::TAU + 0.5) * self.w as f32 - 0.5;
        let v = ((0.5 - lat / std::f32::consts::PI) * self.h as f32 - 0.5)
            .clamp(0.0, (self.h - 1) as f32);
        let (i0, j0) = (u.floor(), v.floor());
        let (fu, fv) = (u - i0, v - j0);
        let i0 = (i0 as i32).rem_euclid(self.w as i32) as usize;
        let i1 = (i0 + 1) % self.w;
        let j0 = j0 as usize;
        let j1 = (j0 + 1).min(self.h - 1);
        let d = &self.data;
        let mut out = [0.0f32; 2];
        for k in 0..2 {
            let a = d[j0 * self.w + i0][k] * (1.0 - fu) + d[j0 * self.w + i1][k] * fu;
            let b = d[j1 * self.w + i0][k] * (1.0 - fu) + d[j1 * self.w + i1][k] * fu;
            out[k] = a * (1.0 - fv) + b * fv;
        }
        out
    }
}

/// atan2(y, x) in f32 with a degree-11 odd minimax polynomial for atan on
/// [−1, 1] (max error 2 × 10⁻⁶ rad; coefficients of the classic
/// Hastings-type fit, cf. Abramowitz & Stegun 4.4.49); for texture lookups.
#[inline]
pub fn fast_atan2(y: f32, x: f32) -> f32 {
    let (ax, ay) = (x.abs(), y.abs());
    let (num, den, swap) = if ay > ax {
        (ax, ay, true)
    } else {
        (ay, ax, false)
    };
    if den == 0.0 {
        return 0.0;
    }
    let t = num / den;
    let t2 = t * t;
    let mut a = t
        * (0.999_977_26
            + t2 * (-0.332_623_47
                + t2 * (0.193_543_46
                    + t2 * (-0.116_432_87 + t2 * (0.052_653_32 + t2 * -0.011_721_2)))));
    if swap {
        a = std::f32::consts::FRAC_PI_2 - a;
    }
    if x < 0.0 {
        a = std::f32::consts::PI - a;
    }
    if y < 0.0 {
        -a
    } else {
        a
    }
}

/// Lunar-eclipse geometry for the shader: the Earth's shadow relative to
/// the Moon (from [`ShadowGeometry`], geocentric).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct LunarShadow {
    /// The Moon centre's offset from the shadow axis toward celestial east
    /// and north, radians (gnomonic, geocentric).
    pub offset_east: Radians,
    /// See `offset_east`.
    pub offset_north: Radians,
    /// The Moon's geocentric semidiameter, radians.
    pub moon_semidiameter: Radians,
    /// Danjon umbra radius at the Moon's distance, radians.
    pub umbra_radius: Radians,
    /// Danjon penumbra radius at the Moon's distance, radians.
    pub penumbra_radius: Radians,
    /// Umbral magnitude.
    pub umbral_magnitude: f64,
    /// Penumbral magnitude.
    pub penumbral_magnitude: f64,
    /// The Earth's geometric angular radius seen from the Moon (R⊕/d), radians.
    pub earth_radius: Radians,
    /// The Sun's horizontal parallax, radians.
    pub sun_parallax: Radians,
    /// The Sun's angular radius seen from the Moon, radians.
    pub sun_radius: Radians,
    /// Rows 0/1: the geocentric sky east/north unit vectors expressed in the
    /// Moon's topocentric sky frame (east, north, towards the observer).
    pub sky_to_geo: [[f64; 3]; 2],
}

/// The Moon for one instant and observer. Angles in radians unless named
/// `_deg`. The "sky frame" at the Moon is (east, north, towards the
/// observer), topocentric.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct MoonState {
    /// Unit vector towards the Moon's refracted apparent topocentric place (ENU).
    pub enu: [f64; 3],
    /// Topocentric altitude without refraction, degrees.
    pub alt_deg: f64,
    /// Altitude with standard refraction, degrees.
    pub alt_refracted_deg: f64,
    /// Azimuth, degrees.
    pub az_deg: f64,
    /// Topocentric distance (observer–Moon centre), km.
    pub distance_km: f64,
    /// Geocentric distance, km.
    pub geocentric_distance_km: f64,
    /// Topocentric semidiameter asin(R☾/Δ), radians.
    pub angular_radius: Radians,
    /// Geocentric phase angle (Meeus ch. 48).
    pub phase_angle: Radians,
    /// Topocentric phase angle (Sun–Moon–observer), used for shading.
    pub phase_angle_topo: Radians,
    /// Geocentric illuminated fraction.
    pub illuminated_fraction: f64,
    /// Geocentric elongation from the Sun (= the Earth's phase angle seen from the Moon).
    pub elongation: Radians,
    /// Position angle of the bright limb's midpoint (North through East).
    pub bright_limb_pa: Radians,
    /// Libration in longitude (Meeus ch. 53).
    pub libration_lon: Radians,
    /// Libration in latitude.
    pub libration_lat: Radians,
    /// Position angle of the Moon's axis.
    pub axis_pa: Radians,
    /// Parallactic angle q (Meeus eq. 14.1): the position angle of the zenith.
    pub parallactic_angle: Radians,
    /// Unit vector from the Moon to the Sun in the sky frame.
    pub sun_in_sky: [f64; 3],
    /// Selenographic axes X (lon 0, lat 0), Y (lon 90° E), Z (north pole)
    /// in the sky frame.
    pub axes_in_sky: [[f64; 3]; 3],
    /// Solar illuminance at the Moon, lux.
    pub sun_illuminance_lux: Lux,
    /// Earthshine illuminance on the Moon, lux.
    pub earthshine_lux: Lux,
    /// Visual magnitude from the observed phase curve ([`allen_magnitude`]).
    pub magnitude: f64,
    /// Illuminance at the observer outside the atmosphere from that
    /// magnitude, lux.
    pub illuminance_lux: Lux,
    /// Shadow geometry when the Moon is in or near the Earth's penumbra.
    pub eclipse: Option<LunarShadow>,
    /// Why the eclipse shading does not run (None when it runs).
    pub eclipse_reason: Option<String>,
}

fn radec_unit(ra: f64, dec: f64) -> DVec3 {
    DVec3::new(dec.cos() * ra.cos(), dec.cos() * ra.sin(), dec.sin())
}

fn sky_basis(ra: f64, dec: f64) -> (DVec3, DVec3, DVec3) {
    let c = radec_unit(ra, dec);
    let east = DVec3::new(-ra.sin(), ra.cos(), 0.0);
    let north = DVec3::new(-dec.sin() * ra.cos(), -dec.sin() * ra.sin(), dec.cos());
    (east, north, c)
}

/// Inputs of [`MoonState::new`]: apparent places (true equator and equinox
/// of date) — geocentric and topocentric — and the Moon's physical ephemeris.
#[derive(Debug, Clone, Copy)]
pub struct MoonInputs {
    /// Geocentric apparent Moon (ra, dec, km).
    pub moon_geo: (f64, f64, f64),
    /// Geocentric apparent Sun (ra, dec, km).
    pub sun_geo: (f64, f64, f64),
    /// Topocentric Moon (ra, dec, km).
    pub moon_topo: (f64, f64, f64),
    /// Topocentric Sun (ra, dec, km).
    pub sun_topo: (f64, f64, f64),
    /// Refracted apparent ENU direction of the Moon.
    pub enu: DVec3,
    /// Altitude (unrefracted / refracted) and azimuth, degrees.
    pub alt_az_deg: (f64, f64, f64),
    /// Parallactic angle, radians.
    pub parallactic_angle: Radians,
    /// Physical ephemeris (Meeus ch. 48, 53), geocentric.
    pub physical: himmel_astro::moon::MoonPhysical,
    /// Solar illuminance at 1 AU, lux.
    pub solar_lux_1au: f64,
}

impl MoonState {
    /// Builds the Moon's state: orientation from libration and axis position
    /// angle (Meeus ch. 53) seen geocentrically and re-expressed in the
    /// topocentric sky frame; illumination geometry from the topocentric
    /// vectors; eclipse geometry from the geocentric vectors.
    pub fn new(i: &MoonInputs) -> MoonState {
        let ph = &i.physical;
        let (mg_ra, mg_dec, mg_d) = i.moon_geo;
        let (sg_ra, sg_dec, sg_d) = i.sun_geo;
        let (mt_ra, mt_dec, mt_d) = i.moon_topo;
        let (st_ra, st_dec, st_d) = i.sun_topo;
        // Body axes in the equatorial frame from the geocentric view.
        let (eg, ng, cg) = sky_basis(mg_ra, mg_dec);
        let o = -cg; // Moon → Earth centre.
        let (b, l, p) = (ph.libration_lat, ph.libration_lon, ph.axis_pa);
        let z = o * b.sin() + (ng * p.cos() + eg * p.sin()) * b.cos();
        let z = z.normalize();
        let o_perp = (o - z * o.dot(z)).normalize();
        let wv = z.cross(o_perp);
        let x = o_perp * l.cos() - wv * l.sin();
        let y = o_perp * l.sin() + wv * l.cos();
        // Topocentric sky frame.
        let (et, nt, ct) = sky_basis(mt_ra, mt_dec);
        let to_sky = |v: DVec3| [v.dot(et), v.dot(nt), -v.dot(ct)];
        let sun_vec = radec_unit(st_ra, st_dec) * st_d - ct * mt_d;
        let sun_from_moon = sun_vec.normalize();
        let sun_moon_au = sun_vec.length() / himmel_astro::units::KM_PER_AU;
        let phase_topo = sun_from_moon.angle_between(-ct);
        let sun_lux = i.solar_lux_1au / (sun_moon_au * sun_moon_au);
        let earthshine = earthshine_lux(sun_lux, mg_d, ph.elongation);
        let radius = (himmel_astro::units::MOON_RADIUS_KM / mt_d).min(1.0).asin();
        let magnitude = allen_magnitude(phase_topo.to_degrees(), mt_d, sun_moon_au);
        // Eclipse geometry (geocentric vectors).
        let sg = ShadowGeometry::from_vectors(
            radec_unit(sg_ra, sg_dec) * sg_d,
            radec_unit(mg_ra, mg_dec) * mg_d,
        );
        let margin = 0.2f64.to_radians();
        let near = sg.moon_axis_distance < sg.penumbra_radius + sg.moon_semidiameter + margin;
        let (eclipse, eclipse_reason) = if near {
            (
                Some(LunarShadow {
                    offset_east: sg.offset_east,
                    offset_north: sg.offset_north,
                    moon_semidiameter: sg.moon_semidiameter,
                    umbra_radius: sg.umbra_radius,
                    penumbra_radius: sg.penumbra_radius,
                    umbral_magnitude: sg.umbral_magnitude(),
                    penumbral_magnitude: sg.penumbral_magnitude(),
                    earth_radius: (EARTH_RADIUS_KM / mg_d).asin(),
                    sun_parallax: (himmel_astro::units::WGS84_A_KM / sg_d).asin(),
                    sun_radius: (himmel_astro::units::SUN_RADIUS_KM / sg_d).asin(),
                    sky_to_geo: [to_sky(eg), to_sky(ng)],
                }),
                None,
            )
        } else {
            (
                None,
                Some(format!(
                    "no lunar eclipse: the Moon is {:.1}° from the shadow axis, beyond the penumbra ({:.2}°) and the Moon's radius",
                    sg.moon_axis_distance.to_degrees(),
                    sg.penumbra_radius.to_degrees()
                )),
            )
        };
        MoonState {
            enu: i.enu.normalize().to_array(),
            alt_deg: i.alt_az_deg.0,
            alt_refracted_deg: i.alt_az_deg.1,
            az_deg: i.alt_az_deg.2,
            distance_km: mt_d,
            geocentric_distance_km: mg_d,
            angular_radius: radius,
            phase_angle: ph.phase_angle,
            phase_angle_topo: phase_topo,
            illuminated_fraction: ph.illuminated_fraction,
            elongation: ph.elongation,
            bright_limb_pa: ph.bright_limb_pa,
            libration_lon: l,
            libration_lat: b,
            axis_pa: p,
            parallactic_angle: i.parallactic_angle,
            sun_in_sky: to_sky(sun_from_moon),
            axes_in_sky: [to_sky(x), to_sky(y), to_sky(z)],
            sun_illuminance_lux: sun_lux,
            earthshine_lux: earthshine,
            magnitude,
            illuminance_lux: LUX_MAG0 * 10f64.powf(-0.4 * magnitude),
            eclipse,
            eclipse_reason,
        }
    }

    /// The refracted direction as a glam vector.
    pub fn dir(&self) -> DVec3 {
        DVec3::from_array(self.enu)
    }
}

/// Below this refracted altitude (degrees) the Moon is drawn with the
/// differential refraction across its disk (it flattens the disk by 0.8 %
/// at 10°, 3 % at 5° and 20 % at the horizon).
pub const REFRACTION_FRAME_BELOW_DEG: f64 = 15.0;

/// The refraction (radians) that [`unrefract`] takes off the apparent
/// altitude `alt` (radians): Bennett's formula (Meeus eq. 16.3) at the
/// standard 1010 hPa and 10 °C.
#[inline]
pub fn refraction_of_apparent(alt: f32) -> f32 {
    himmel_astro::frames::refraction_apparent_to_true(
        alt as f64,
        himmel_astro::frames::STANDARD_PRESSURE_HPA,
        himmel_astro::frames::STANDARD_TEMPERATURE_C,
    ) as f32
}

/// The airless direction of the apparent (refracted) direction `d` (ENU,
/// unit): its altitude lowered by Bennett's refraction (Meeus eq. 16.3,
/// standard 1010 hPa, 10 °C), azimuth kept.
#[inline]
pub fn unrefract(d: Vec3) -> Vec3 {
    let alt = d.z.clamp(-1.0, 1.0).asin();
    let r = refraction_of_apparent(alt);
    let hz = (d.x * d.x + d.y * d.y).sqrt();
    if hz < 1e-9 {
        return d;
    }
    let (s, c) = (alt - r).sin_cos();
    Vec3::new(d.x / hz * c, d.y / hz * c, s)
}

/// Number of axis-distance samples of the eclipse table.
pub const ECLIPSE_TABLE_N: usize = 160;

/// Refraction of a ray grazing the Earth at sea level, from space to
/// space: twice the horizontal refraction 34.5′ (Bennett 1982), radians.
pub const GRAZING_REFRACTION: f64 = 2.0 * 34.5 / 60.0 * std::f64::consts::PI / 180.0;

/// Band transmittance of a ray grazing the Earth's limb at tangent height
/// `h` km through `medium` (both halves of the path), times the cloud
/// factor (half of the limb opaque below 10 km, fading over 10–12 km).
pub fn grazing_transmittance(medium: &Medium, h: f64) -> Spectrum {
    let r_t = medium.bottom as f64 + h.max(0.0);
    let top = medium.top as f64;
    let s_max = (top * top - r_t * r_t).max(0.0).sqrt();
    let n = 400;
    let mut od = Spectrum::ZERO;
    // Quadratic spacing: most of the column is near the tangent point.
    let mut s_prev = 0.0;
    for k in 0..n {
        let xk = (k as f64 + 1.0) / n as f64;
        let s1 = s_max * xk * xk;
        let sm = 0.5 * (s_prev + s1);
        let ds = s1 - s_prev;
        s_prev = s1;
        let r = (r_t * r_t + sm * sm).sqrt() as f32;
        let ext = medium.extinction(medium.densities(r));
        od += ext * (2.0 * ds) as f32;
    }
    let cloud = if h < 10.0 {
        0.5
    } else if h < 12.0 {
        0.5 + 0.25 * (h - 10.0)
    } else {
        1.0
    };
    od.exp_neg() * cloud as f32
}

/// Per-band sunlight (relative to the uneclipsed Sun, 1 = full sunlight)
/// reaching lunar points at axis distances `d = d_max · k / (N − 1)`,
/// `k = 0..N` (see the module documentation), integrated over the solar
/// disk (uniform) with 16 × 32 samples.
pub fn eclipse_transfer(s: &LunarShadow, medium: &Medium, d_max: f64) -> Vec<Spectrum> {
    let pe = s.earth_radius;
    let r_e = EARTH_RADIUS_KM;
    let h_scale = 1.0 / medium.inv_h_r as f64;
    // Tangent-height table: σ(h) = pe (1 + h/R) − δ(h), its derivative and
    // the transmittance.
    let nh = 240;
    let h_top = 60.0;
    let hs: Vec<f64> = (0..nh)
        .map(|k| h_top * k as f64 / (nh - 1) as f64)
        .collect();
    let sig: Vec<f64> = hs
        .iter()
        .map(|&h| pe * (1.0 + h / r_e) - GRAZING_REFRACTION * (-h / h_scale).exp())
        .collect();
    let trans: Vec<Spectrum> = hs
        .iter()
        .map(|&h| grazing_transmittance(medium, h))
        .collect();
    let sig_top = sig[nh - 1];
    let (nr, na) = (16usize, 32usize);
    let rs = s.sun_radius;
    (0..ECLIPSE_TABLE_N)
        .map(|k| {
            let d = d_max * k as f64 / (ECLIPSE_TABLE_N - 1) as f64;
            let sigma = (d - s.sun_parallax).max(0.0);
            let mut acc = Spectrum::ZERO;
            let mut wsum = 0.0f64;
            for ir in 0..nr {
                let rr = rs * ((ir as f64 + 0.5) / nr as f64).sqrt();
                for ia in 0..na {
                    let a = std::f64::consts::TAU * (ia as f64 + 0.5) / na as f64;
                    let (u, v) = (sigma + rr * a.cos(), rr * a.sin());
                    let sp = (u * u + v * v).sqrt();
                    wsum += 1.0;
                    if sp >= sig_top {
                        // Above the atmosphere's refracting layers: direct.
                        acc += if sp > pe * (1.0 + h_top / r_e) {
                            Spectrum::ONE
                        } else {
                            trans[nh - 1]
                        };
                        continue;
                    }
                    if sp <= sig[0] {
                        continue; // would need more bending than the ground ray
                    }
                    // σ(h) is increasing: binary search.
                    let (mut lo, mut hi) = (0usize, nh - 1);
                    while hi - lo > 1 {
                        let mid = (lo + hi) / 2;
                        if sig[mid] <= sp {
                            lo = mid;
                        } else {
                            hi = mid;
                        }
                    }
                    let f = (sp - sig[lo]) / (sig[hi] - sig[lo]);
                    let h = hs[lo] + f * (hs[hi] - hs[lo]);
                    let delta = GRAZING_REFRACTION * (-h / h_scale).exp();
                    let app = pe * (1.0 + h / r_e);
                    let dapp = pe / r_e;
                    let dilution = (app / sp.max(1e-9)) * dapp / (dapp + delta / h_scale);
                    let t = trans[lo] * (1.0 - f as f32) + trans[hi] * f as f32;
                    acc += t * dilution.min(50.0) as f32;
                }
            }
            acc * (1.0 / wsum) as f32
        })
        .collect()
}

/// Per-frame constants of the Moon shader and its per-pixel evaluation.
#[derive(Debug, Clone)]
pub struct MoonShader {
    /// Centre direction (ENU, unit, refracted).
    pub centre: Vec3,
    /// Drawn angular radius, radians.
    pub radius: f32,
    cos_radius: f32,
    sin_radius: f32,
    east: Vec3,
    north: Vec3,
    refract: bool,
    sun: Vec3,
    axes: [Vec3; 3],
    /// B(g) S(g) p/π: the sunlit BRDF factor without μ0/(μ0 + μ) and albedo.
    sun_factor: f32,
    /// Linear sRGB (cd/m² per unit BRDF factor) of the sunlight after
    /// extinction at the Moon's centre, and of the earthshine.
    sun_rgb: [f32; 3],
    earth_rgb: [f32; 3],
    /// Extinction relative to the centre over the disk's z range.
    ext_z0: f32,
    ext_dz: f32,
    ext: Vec<[f32; 3]>,
    /// Eclipse table (RGB, relative to `sun_rgb`'s normalisation) and geometry.
    eclipse: Option<EclipseShader>,
    map: &'static AlbedoMap,
    normals: &'static NormalMap,
}

/// [`MoonShader`]'s per-frame constants and tables ([`MoonShader::parts`]);
/// the fields are those of [`MoonShader::new`] (sky frame: x east, y north,
/// z towards the observer).
#[derive(Debug, Clone, PartialEq)]
pub struct MoonShaderParts {
    /// Centre direction (ENU, unit, refracted).
    pub centre: Vec3,
    /// Drawn angular radius, radians.
    pub radius: f32,
    /// Sine of the drawn radius.
    pub sin_radius: f32,
    /// Celestial east and north at the disk's (airless, when `refract`)
    /// centre, ENU unit vectors ([`MoonShader::sky_xy`]).
    pub east: Vec3,
    /// See `east`.
    pub north: Vec3,
    /// Whether pixel directions are un-refracted first ([`unrefract`]).
    pub refract: bool,
    /// Unit vector from the Moon to the Sun in the sky frame.
    pub sun: Vec3,
    /// Selenographic axes X, Y, Z in the sky frame.
    pub axes: [Vec3; 3],
    /// B(g) S(g) p/π normalised as in [`MoonShader::radiance`].
    pub sun_factor: f32,
    /// Linear sRGB of the sunlight and of the earthshine at the centre's
    /// extinction (cd/m² per unit BRDF factor).
    pub sun_rgb: [f32; 3],
    /// See `sun_rgb`.
    pub earth_rgb: [f32; 3],
    /// First node and spacing (zenith cosine) of `ext`.
    pub ext_z0: f32,
    /// See `ext_z0`.
    pub ext_dz: f32,
    /// Extinction relative to the centre's per node, linear sRGB factors.
    pub ext: Vec<[f32; 3]>,
    /// The lunar-eclipse shading, when it runs.
    pub eclipse: Option<MoonEclipseParts>,
}

/// The lunar-eclipse part of [`MoonShaderParts`].
#[derive(Debug, Clone, PartialEq)]
pub struct MoonEclipseParts {
    /// The Moon centre's offset from the shadow axis (east, north), radians.
    pub offset: [f32; 2],
    /// The Moon's geocentric semidiameter, radians.
    pub semidiameter: f32,
    /// Geocentric sky east and north in the Moon's topocentric sky frame.
    pub geo_east: Vec3,
    /// See `geo_east`.
    pub geo_north: Vec3,
    /// Axis distance (radians) of the table's last node.
    pub d_max: f32,
    /// Sunlight relative to the uneclipsed Sun's at axis distances
    /// d_max · k / ([`ECLIPSE_TABLE_N`] − 1), linear sRGB factors.
    pub table: Vec<[f32; 3]>,
}

#[derive(Debug, Clone)]
struct EclipseShader {
    off: [f32; 2],
    sd: f32,
    geo_e: Vec3,
    geo_n: Vec3,
    d_max: f32,
    table: Vec<[f32; 3]>,
}

impl MoonShader {
    /// The shader for the frame's Moon as the Moon passes draw it: the
    /// scene's `moon_scale`, its atmosphere, the state's celestial pole,
    /// seen from radius `r0` (km) through `luts` when the atmosphere runs
    /// ([`MoonShader::new`]).
    pub fn for_frame(
        scene: &crate::Scene,
        state: &crate::SkyState,
        luts: Option<&AtmosphereLuts>,
        r0: f32,
    ) -> MoonShader {
        let pole = DVec3::from_array(state.celestial_pole).as_vec3();
        MoonShader::new(
            &state.moon,
            scene.moon_scale,
            luts,
            r0,
            pole,
            &scene.atmosphere,
        )
    }

    /// The shader for `moon` drawn `scale` times its true size; with
    /// `luts` the extinction along the line of sight from radius `r0` (km
    /// from the Earth's centre) is applied; `celestial_pole` is the ENU
    /// direction of the celestial north pole; `atmosphere` is the Earth's
    /// atmosphere that refracts sunlight into the umbra during a lunar
    /// eclipse (used whether or not the atmosphere pass runs).
    pub fn new(
        moon: &MoonState,
        scale: f64,
        luts: Option<&AtmosphereLuts>,
        r0: f32,
        celestial_pole: Vec3,
        atmosphere: &crate::atmosphere::AtmosphereParams,
    ) -> MoonShader {
        let centre = moon.dir().as_vec3().normalize();
        let radius = (moon.angular_radius * scale).clamp(1e-6, 0.5) as f32;
        // Low Moons are drawn in the airless frame: each pixel's direction
        // is un-refracted first, so that the disk shows the refraction's
        // vertical flattening (Bennett's formula, standard conditions).
        let refract = moon.alt_refracted_deg < REFRACTION_FRAME_BELOW_DEG;
        let frame_centre = if refract {
            crate::projection::enu_from_alt_az(moon.alt_deg.to_radians(), moon.az_deg.to_radians())
                .as_vec3()
                .normalize()
        } else {
            centre
        };
        let pn = celestial_pole - frame_centre * celestial_pole.dot(frame_centre);
        let north = if pn.length_squared() > 1e-12 {
            pn.normalize()
        } else {
            // The Moon at a celestial pole: any north.
            frame_centre.any_orthonormal_vector()
        };
        let east = north.cross(frame_centre);
        let v3 = |a: [f64; 3]| Vec3::new(a[0] as f32, a[1] as f32, a[2] as f32);
        let g = moon.phase_angle_topo;
        // Normalised so that L = E p/π a at g = 0 (μ0/(μ0 + μ) = 1/2 there).
        let sun_factor = (GEOMETRIC_ALBEDO / std::f64::consts::PI * 2.0 * surge_b(g) * hapke_s(g)
            / surge_b(0.0)) as f32;
        let w = BandWeights::solar();
        let refl = lunar_reflectance_spectrum();
        let trans_at = |z: f32| -> Spectrum {
            match luts {
                Some(l) => l.sun_transmittance(r0, z),
                None => Spectrum::ONE,
            }
        };
        let t_c = trans_at(centre.z);
        // Band weights are per unit 1 AU irradiance: scale to lux at the Moon.
        let e_scale = (moon.sun_illuminance_lux / w.solar_illuminance_lux()) as f32;
        let es_scale = (moon.earthshine_lux / w.solar_illuminance_lux()) as f32;
        let base = refl * t_c;
        // Deep-red light near the horizon can leave the sRGB gamut: clip.
        let rgb_c = crate::spectrum::clip_to_gamut(w.to_rgb(&base));
        let sun_rgb = rgb_c.map(|c| c * e_scale);
        let earth_rgb =
            rgb_c.map(|c| c * es_scale * (GEOMETRIC_ALBEDO / std::f64::consts::PI) as f32);
        // Extinction across the disk relative to the centre (16 samples in z).
        let zr = radius * 1.05;
        let (z0, z1) = (centre.z - zr, centre.z + zr);
        let n = 16;
        let ext: Vec<[f32; 3]> = (0..n)
            .map(|k| {
                let z = z0 + (z1 - z0) * k as f32 / (n - 1) as f32;
                let c = crate::spectrum::clip_to_gamut(w.to_rgb(&(refl * trans_at(z))));
                [0, 1, 2].map(|i| if rgb_c[i] > 0.0 { c[i] / rgb_c[i] } else { 0.0 })
            })
            .collect();
        let eclipse = match &moon.eclipse {
            Some(s) => {
                let medium = Medium::new(atmosphere);
                let d_max = s.penumbra_radius + 2.0 * s.sun_radius;
                let spec = eclipse_transfer(s, &medium, d_max);
                let table = spec
                    .iter()
                    .map(|f| {
                        let c = crate::spectrum::clip_to_gamut(w.to_rgb(&(*f * base)));
                        [0, 1, 2].map(|i| if rgb_c[i] > 0.0 { c[i] / rgb_c[i] } else { 0.0 })
                    })
                    .collect();
                Some(EclipseShader {
                    off: [s.offset_east as f32, s.offset_north as f32],
                    sd: s.moon_semidiameter as f32,
                    geo_e: v3(s.sky_to_geo[0]),
                    geo_n: v3(s.sky_to_geo[1]),
                    d_max: d_max as f32,
                    table,
                })
            }
            None => None,
        };
        MoonShader {
            centre,
            radius,
            cos_radius: radius.cos(),
            sin_radius: radius.sin(),
            east,
            north,
            refract,
            sun: v3(moon.sun_in_sky).normalize(),
            axes: moon.axes_in_sky.map(v3),
            sun_factor,
            sun_rgb,
            earth_rgb,
            ext_z0: z0,
            ext_dz: (z1 - z0) / (n - 1) as f32,
            ext,
            eclipse,
            map: AlbedoMap::get(),
            normals: NormalMap::get(),
        }
    }

    /// Cosine of the disk's angular radius enlarged by `margin` radians
    /// (for bounding tests).
    pub fn cos_bound(&self, margin: f32) -> f32 {
        (self.radius + margin).min(std::f32::consts::PI).cos()
    }

    /// Whether the unit direction `d` falls on the drawn disk.
    #[inline]
    pub fn covers(&self, d: Vec3) -> bool {
        d.dot(self.centre) >= self.cos_radius
    }

    /// Whether the unit direction `d` falls on the drawn disk, from the
    /// sine of the angle to the centre (accurate in f32 for small disks,
    /// unlike the cosine test of [`MoonShader::covers`]).
    #[inline]
    pub fn covers_exact(&self, d: Vec3) -> bool {
        let (x, y) = self.sky_xy(d);
        d.dot(self.centre) > 0.0 && x * x + y * y < 1.0
    }

    /// Offsets of the apparent direction `d` from the disk's centre toward
    /// celestial east and north, in units of the disk's radius (for a low
    /// Moon after removing the refraction of `d`).
    #[inline]
    pub fn sky_xy(&self, d: Vec3) -> (f32, f32) {
        let d = if self.refract { unrefract(d) } else { d };
        (
            d.dot(self.east) / self.sin_radius,
            d.dot(self.north) / self.sin_radius,
        )
    }

    /// The point of the lunar sphere seen in direction `d` in the sky frame
    /// (x east, y north, z towards the observer; unit Moon radii), with `d`
    /// pulled onto the disk if it misses.
    #[inline]
    pub fn surface_point(&self, d: Vec3) -> Vec3 {
        // Orthographic to within (angular radius)²: fine for ρ ≤ 0.5 rad.
        let (x, y) = self.sky_xy(d);
        let r2 = x * x + y * y;
        if r2 >= 1.0 {
            let r = r2.sqrt();
            return Vec3::new(x / r, y / r, 0.0);
        }
        Vec3::new(x, y, (1.0 - r2).sqrt())
    }

    /// Linear sRGB radiance (cd/m²) of the Moon at sky-frame surface point
    /// `p` (see [`MoonShader::surface_point`]) whose line of sight has
    /// ENU z component `z`.
    #[inline]
    pub fn radiance(&self, p: Vec3, z: f32) -> [f32; 3] {
        let a = &self.axes;
        let (sx, sy, sz) = (p.dot(a[0]), p.dot(a[1]), p.dot(a[2]));
        let cl = (sx * sx + sy * sy).sqrt();
        let lat = fast_atan2(sz, cl);
        let lon = fast_atan2(sy, sx);
        let alb = self.map.sample(lon, lat);
        // Relief: the normal map's east/north tilt in the local tangent
        // frame (east = Z × p / cos lat, north = (Z − sin lat · p) / cos lat).
        // Faded out towards the limb (μ < 0.2), where the foreshortened
        // relief would only add noise to μ → 0.
        let fade = (p.z * 5.0).min(1.0);
        let n = if cl > 1e-4 && fade > 0.0 {
            let [te, tn] = self.normals.sample(lon, lat);
            let (te, tn) = (te * fade, tn * fade);
            let east = a[2].cross(p) / cl;
            let north = (a[2] - p * sz) / cl;
            let up = (1.0 - te * te - tn * tn).max(0.0).sqrt();
            east * te + north * tn + p * up
        } else {
            p
        };
        let mu = n.z.max(0.0);
        // Beyond the sphere's terminator the body's curvature shadows every
        // facet (the map carries no self-shadowing).
        let mu0 = if p.dot(self.sun) > 0.0 {
            n.dot(self.sun)
        } else {
            0.0
        };
        let ls = if mu0 > 0.0 {
            mu0 / (mu0 + mu).max(1e-6)
        } else {
            0.0
        };
        let direct = self.sun_factor * ls * alb;
        let mut sun = self.sun_rgb;
        if let Some(e) = &self.eclipse {
            let de = e.off[0] + e.sd * p.dot(e.geo_e);
            let dn = e.off[1] + e.sd * p.dot(e.geo_n);
            let d = (de * de + dn * dn).sqrt();
            let x = (d / e.d_max * (ECLIPSE_TABLE_N - 1) as f32).min((ECLIPSE_TABLE_N - 1) as f32);
            let i0 = x.floor() as usize;
            let i1 = (i0 + 1).min(ECLIPSE_TABLE_N - 1);
            let f = x - i0 as f32;
            for k in 0..3 {
                sun[k] *= e.table[i0][k] * (1.0 - f) + e.table[i1][k] * f;
            }
        }
        let zx = ((z - self.ext_z0) / self.ext_dz).clamp(0.0, (self.ext.len() - 1) as f32);
        let j0 = zx.floor() as usize;
        let j1 = (j0 + 1).min(self.ext.len() - 1);
        let fz = zx - j0 as f32;
        let mut out = [0.0f32; 3];
        for k in 0..3 {
            let t = self.ext[j0][k] * (1.0 - fz) + self.ext[j1][k] * fz;
            out[k] = (sun[k] * direct + self.earth_rgb[k] * alb) * t;
        }
        out
    }

    /// Radiance and coverage of the pixel whose centre direction is `d`
    /// and whose angular size is `pixel` radians: analytic anti-aliasing
    /// of the limb (coverage falls linearly over one pixel across the edge;
    /// the colour is taken at the nearest point of the disk). `None` when
    /// the pixel does not touch the disk.
    #[inline]
    pub fn shade(&self, d: Vec3, pixel: f32) -> Option<([f32; 3], f32)> {
        // Offsets on the sky in units of the disk's radius: the angle from
        // the centre is ≈ r · radius (orthographic, as in surface_point).
        let (x, y) = self.sky_xy(d);
        let r = (x * x + y * y).sqrt();
        let cov = ((1.0 - r) * self.radius / pixel + 0.5).clamp(0.0, 1.0);
        if cov <= 0.0 || d.dot(self.centre) <= 0.0 {
            return None;
        }
        let p = if r >= 1.0 {
            Vec3::new(x / r, y / r, 0.0)
        } else {
            Vec3::new(x, y, (1.0 - r * r).sqrt())
        };
        Some((self.radiance(p, d.z), cov))
    }

    /// The shader's per-frame constants and tables, for a backend that
    /// evaluates [`MoonShader::radiance`] and [`MoonShader::shade`]
    /// elsewhere (the wgpu backend's WGSL port).
    pub fn parts(&self) -> MoonShaderParts {
        MoonShaderParts {
            centre: self.centre,
            radius: self.radius,
            sin_radius: self.sin_radius,
            east: self.east,
            north: self.north,
            refract: self.refract,
            sun: self.sun,
            axes: self.axes,
            sun_factor: self.sun_factor,
            sun_rgb: self.sun_rgb,
            earth_rgb: self.earth_rgb,
            ext_z0: self.ext_z0,
            ext_dz: self.ext_dz,
            ext: self.ext.clone(),
            eclipse: self.eclipse.as_ref().map(|e| MoonEclipseParts {
                offset: e.off,
                semidiameter: e.sd,
                geo_east: e.geo_e,
                geo_north: e.geo_n,
                d_max: e.d_max,
                table: e.table.clone(),
            }),
        }
    }

    /// Luminance of [`MoonShader::radiance`] (for tests and metering).
    pub fn luminance_at(&self, p: Vec3, z: f32) -> f32 {
        luminance(self.radiance(p, z))
    }

    /// The illuminance of the whole drawn disk, lux: Σ Y(L) dΩ over an
    /// `n` × `n` grid of the disk in the orthographic sky frame (dΩ =
    /// (2 radius / n)²), at the line of sight of the centre. Built without
    /// LUTs (`luts` None) it is the Moon's light outside the atmosphere —
    /// sunlit part, earthshine and any lunar-eclipse shading included —
    /// which is what lights the moonlit sky.
    pub fn disk_illuminance_lux(&self, n: usize) -> f64 {
        let n = n.max(2);
        let mut sum = 0.0f64;
        for j in 0..n {
            let y = -1.0 + 2.0 * (j as f32 + 0.5) / n as f32;
            for i in 0..n {
                let x = -1.0 + 2.0 * (i as f32 + 0.5) / n as f32;
                let r2 = x * x + y * y;
                if r2 < 1.0 {
                    let p = Vec3::new(x, y, (1.0 - r2).sqrt());
                    sum += self.luminance_at(p, self.centre.z) as f64;
                }
            }
        }
        let cell = 2.0 * self.radius as f64 / n as f64;
        sum * cell * cell
    }
}

/// The Moon's state for `observer` through `sky`, and the visible fraction
/// of the Sun's disk (1 − the uniform-disk overlap of the topocentric disks
/// of the Sun and the Moon; the Sun's limb darkening is not weighted in).
pub fn moon_state(
    sky: &himmel_astro::Sky,
    observer: &himmel_astro::Observer,
    sun: &crate::state::SunState,
) -> Result<(MoonState, f64), himmel_astro::AstroError> {
    use himmel_astro::Body;
    let mg = sky.apparent(Body::Moon)?;
    let sg = sky.apparent(Body::Sun)?;
    let mt = sky.topocentric(Body::Moon, observer)?;
    let st = sky.topocentric(Body::Sun, observer)?;
    let physical = sky.moon_physical()?;
    let alt_r = mt.alt_refracted_deg();
    let enu = crate::projection::enu_from_alt_az(alt_r.to_radians(), mt.az);
    let state = MoonState::new(&MoonInputs {
        moon_geo: (mg.ra, mg.dec, mg.distance_km),
        sun_geo: (sg.ra, sg.dec, sg.distance_km),
        moon_topo: (mt.ra, mt.dec, mt.distance_km),
        sun_topo: (st.ra, st.dec, st.distance_km),
        enu,
        alt_az_deg: (mt.alt_deg(), alt_r, mt.az_deg()),
        parallactic_angle: mt.parallactic_angle_deg().to_radians(),
        physical,
        solar_lux_1au: sun.illuminance_lux / sun.irradiance_scale,
    });
    let sep = st.separation_deg(&mt).to_radians();
    let covered = himmel_astro::events::solar_eclipse::disk_overlap_fraction(
        sep,
        sun.angular_radius,
        state.angular_radius,
    );
    Ok((state, (1.0 - covered).clamp(0.0, 1.0)))
}

/// The Moon's entry of the pass plan: the pass does not run when the
/// drawn disk lies entirely below the horizon (refracted altitude +
/// drawn radius < 0°). The threshold is the horizon itself because the
/// Moon pass draws only the disk (the ground hides what is below the
/// horizon); the moonlit sky belongs to the atmosphere pass
/// ([`moonlight_scale`], down to [`MOONLIGHT_BELOW_DEG`]).
pub fn plan_moon(passes: &mut [crate::state::PlannedPass], scene: &crate::Scene, moon: &MoonState) {
    for p in passes.iter_mut() {
        if p.effect != crate::Effect::Moon || !p.run {
            continue;
        }
        let top = moon.alt_refracted_deg + (moon.angular_radius * scene.moon_scale).to_degrees();
        if top < 0.0 {
            p.run = false;
            p.reason = Some(format!(
                "the Moon's disk is below the horizon (refracted altitude {:.2}°; the moonlit sky is part of the atmosphere pass{})",
                moon.alt_refracted_deg,
                if moon.alt_refracted_deg < MOONLIGHT_BELOW_DEG {
                    format!(", which leaves it out below {MOONLIGHT_BELOW_DEG}°")
                } else {
                    String::new()
                }
            ));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::spectrum::{band_centre_nm, BANDS};

    #[test]
    fn hapke_limits() {
        assert_eq!(hapke_1963_b(0.0, HAPKE_H), 2.0);
        assert!((hapke_s(0.0) - 1.0).abs() < 1e-12);
        assert_eq!(hapke_1963_b(2.0, HAPKE_H), 1.0);
        // Continuous near 0 and 90°.
        assert!((hapke_1963_b(1e-6, HAPKE_H) - 2.0).abs() < 1e-3);
        assert!((hapke_1963_b(std::f64::consts::FRAC_PI_2 - 1e-4, HAPKE_H) - 1.0).abs() < 0.01);
        assert!(hapke_s(std::f64::consts::PI).is_finite());
        assert!((surge_b(0.0) - 1.0 - SURGE_B0).abs() < 1e-12);
        assert!(surge_b(std::f64::consts::PI).is_finite());
        // Monotonic decrease of both surges; the new one halves within ~9°.
        let (mut p1, mut p2) = (2.0, surge_b(0.0));
        for k in 1..180 {
            let g = (k as f64).to_radians();
            let (b1, b2) = (hapke_1963_b(g, HAPKE_H), surge_b(g));
            assert!(b1 <= p1 + 1e-12 && b2 <= p2 + 1e-12);
            (p1, p2) = (b1, b2);
        }
        // Half the surge at tan(g/2) = h (g ≈ 9.1°).
        let half = 1.0 + SURGE_B0 / 2.0;
        assert!((surge_b(2.0 * SURGE_H.atan()) - half).abs() < 1e-12);
    }

    #[test]
    fn albedo_map_orientation() {
        // Mare Crisium (59° E, 17° N) is dark, the highlands south of it
        // and Tycho's ray system (11° W, 43° S) are bright; Oceanus
        // Procellarum (57° W, 10° N) is dark; the far side highlands bright.
        let m = AlbedoMap::get();
        let at = |lon: f32, lat: f32| m.sample(lon.to_radians(), lat.to_radians());
        let crisium = at(59.0, 17.0);
        let tycho = at(-11.4, -43.3);
        let procellarum = at(-57.0, 10.0);
        let far = at(180.0, 0.0);
        assert!(crisium < 0.75 * tycho, "{crisium} {tycho}");
        assert!(procellarum < 0.75 * far, "{procellarum} {far}");
        // The mirrored places are not dark (a flipped map fails): Mare
        // Humorum (39° W, 24° S) against the highlands at 39° E, and
        // Crisium against 17° S.
        let humorum = at(-39.0, -24.0);
        assert!(at(39.0, -24.0) > humorum * 1.5, "{humorum}");
        assert!(at(59.0, -17.0) > crisium * 1.5);
    }

    #[test]
    fn fast_atan2_matches_std() {
        let mut worst = 0.0f32;
        for i in 0..400 {
            for j in 0..400 {
                let (x, y) = (-2.0 + i as f32 * 0.01, -2.0 + j as f32 * 0.01);
                if x == 0.0 && y == 0.0 {
                    continue;
                }
                worst = worst.max((fast_atan2(y, x) - y.atan2(x)).abs());
            }
        }
        assert!(worst < 1e-5, "{worst}");
        assert_eq!(fast_atan2(0.0, 0.0), 0.0);
    }

    #[test]
    fn earthshine_magnitude() {
        // Full Earth from the Moon: ~12 lx.
        let e = earthshine_lux(127_000.0, 384_400.0, 0.0);
        assert!((10.0..14.0).contains(&e), "{e}");
        assert!(earthshine_lux(127_000.0, 384_400.0, std::f64::consts::PI) < 1e-6);
    }

    #[test]
    fn reflectance_is_reddish_and_normalised() {
        let r = lunar_reflectance_spectrum();
        assert!(r.0[BANDS - 1] > r.0[0] * 1.5);
        assert!(band_centre_nm(BANDS - 1) > 700.0);
        let w = BandWeights::solar();
        assert!((w.to_y(&r) as f64 / w.solar_illuminance_lux() - 1.0).abs() < 1e-4);
    }
}

#[cfg(test)]
mod eclipse_tests {
    use super::*;
    use crate::spectrum::clip_to_gamut;

    /// A central eclipse at the mean distance: Danjon radii ρu ≈ 0.70°, ρp ≈ 1.23°.
    #[test]
    fn shadow_profile_red_umbra_blue_fringe_penumbra() {
        let d_moon = 384_400.0f64;
        let s = LunarShadow {
            offset_east: 0.0,
            offset_north: 0.0,
            moon_semidiameter: (1737.4 / d_moon).asin(),
            umbra_radius: 0.0121,
            penumbra_radius: 0.0215,
            umbral_magnitude: 1.0,
            penumbral_magnitude: 2.0,
            earth_radius: (EARTH_RADIUS_KM / d_moon).asin(),
            sun_parallax: 4.26e-5,
            sun_radius: 0.00465,
            sky_to_geo: [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
        };
        let m = Medium::new(&crate::atmosphere::AtmosphereParams::default());
        let d_max = 0.025;
        let t = eclipse_transfer(&s, &m, d_max);
        let w = BandWeights::solar();
        let r = lunar_reflectance_spectrum();
        let c0 = w.to_rgb(&r);
        let at = |deg: f64| {
            let k = ((deg.to_radians() / d_max) * (ECLIPSE_TABLE_N - 1) as f64).round() as usize;
            let c = clip_to_gamut(w.to_rgb(&(t[k] * r)));
            (
                luminance(c) / luminance(c0),
                (c[0] / c[2].max(1e-30)) / (c0[0] / c0[2]),
            )
        };
        // Outside the penumbra: full sunlight; inside it: the visible part of the Sun.
        assert!((at(1.3).0 - 1.0).abs() < 1e-3);
        let mid = at(0.96).0;
        assert!((0.3..0.75).contains(&mid), "{mid}");
        // The umbra: dark, red, darker towards the centre.
        let (y_centre, rb_centre) = at(0.0);
        let (y_half, rb_half) = at(0.35);
        assert!(y_centre < y_half && y_half < 1e-3, "{y_centre} {y_half}");
        assert!(y_centre > 1e-7, "{y_centre}");
        assert!(rb_centre > 5.0 && rb_half > 5.0, "{rb_centre} {rb_half}");
        // The umbra's edge sits near Danjon's radius (the light jumps by 10×
        // between 0.66° and 0.73°), and there the light is bluer than
        // sunlight: the ozone fringe.
        assert!(at(0.73).0 > 10.0 * at(0.66).0);
        let bluest = (660..730)
            .map(|k| at(k as f64 / 1000.0).1)
            .fold(f32::MAX, f32::min);
        assert!(bluest < 0.95, "{bluest}");
        // Monotonic brightening outwards.
        for k in 1..ECLIPSE_TABLE_N {
            assert!(w.to_y(&t[k]) >= w.to_y(&t[k - 1]) * 0.999, "{k}");
        }
    }
}

/// Below this refracted altitude, degrees, the Moon lights no sky worth
/// computing (its light then reaches the observer's sky only through the
/// twilight arch, which is below 10⁻³ of its light).
pub const MOONLIGHT_BELOW_DEG: f64 = -6.0;

/// The moonlit sky: when `scene` asks for the Moon, the Moon is above
/// [`MOONLIGHT_BELOW_DEG`] and the Sun is below the horizon (with the Sun
/// up, moonlight adds less than 10⁻⁵ to the sky), the irradiance scale of
/// the Moon's light relative to the Sun's at 1 AU — the
/// [`crate::atmosphere::SkyViewInput::irradiance_scale`] of a second sky
/// view lit from the Moon's direction. The Moon's light is its disk's
/// illuminance outside the atmosphere ([`MoonShader::disk_illuminance_lux`]:
/// phase, earthshine and lunar-eclipse shading included); it is treated
/// as sunlight of that illuminance (the Moon's reddening, +0.17 % per
/// 100 nm in [`lunar_reflectance_spectrum`], is left out of the sky).
pub fn moonlight_scale(
    scene: &crate::Scene,
    sun: &crate::state::SunState,
    moon: &MoonState,
    celestial_pole: Vec3,
) -> Option<f64> {
    if !scene.wants(crate::Effect::Moon)
        || moon.alt_refracted_deg < MOONLIGHT_BELOW_DEG
        || sun.alt_refracted_deg > 0.0
    {
        return None;
    }
    let shader = MoonShader::new(moon, 1.0, None, 0.0, celestial_pole, &scene.atmosphere);
    let lux = shader.disk_illuminance_lux(48);
    Some(lux / BandWeights::solar().solar_illuminance_lux())
}
