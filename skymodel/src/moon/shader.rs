//! The per-pixel Moon shader that both renderers evaluate
//! ([`MoonShader`], with its lunar-eclipse part [`MoonEclipse`]), and
//! Bennett's refraction across a low Moon's disk ([`unrefract`]).

use glam::Vec3;

use super::eclipse::{eclipse_transfer, ECLIPSE_TABLE_N};
use super::maps::{fast_atan2, AlbedoMap, NormalMap};
use super::photometry::{hapke_s, lunar_reflectance_spectrum, surge_b, GEOMETRIC_ALBEDO};
use super::MoonState;
use crate::atmosphere::{AtmosphereLuts, Medium};
use crate::spectrum::{luminance, BandWeights, Spectrum};

/// Below this refracted altitude (degrees) the Moon is drawn with the
/// differential refraction across its disk (it flattens the disk by 0.8 %
/// at 10°, 3 % at 5° and 20 % at the horizon).
pub const REFRACTION_FRAME_BELOW_DEG: f64 = 15.0;

pub use crate::refraction::refraction_of_apparent;
/// The airless direction of the apparent direction `d`
/// ([`crate::refraction::unrefracted`]).
pub use crate::refraction::unrefracted as unrefract;

/// Per-frame constants of the Moon shader and its per-pixel evaluation.
///
/// The "sky frame" at the Moon is x east, y north, z towards the observer
/// (topocentric); surface points of the lunar sphere are given in it in
/// units of the Moon's radius ([`MoonShader::surface_point`]). ENU vectors
/// are the observer's east, north, up.
#[derive(Debug, Clone)]
pub struct MoonShader {
    /// Centre direction of the drawn disk (ENU, unit, refracted apparent
    /// place).
    pub centre: Vec3,
    /// Drawn angular radius (the topocentric semidiameter times the scene's
    /// `moon_scale`, clamped to 10⁻⁶ … 0.5), radians.
    pub radius: f32,
    /// Cosine of `radius` (the disk test of [`MoonShader::covers`]).
    pub cos_radius: f32,
    /// Sine of `radius`: the disk's radius in the orthographic sky plane
    /// ([`MoonShader::sky_xy`]).
    pub sin_radius: f32,
    /// Celestial east at the disk's centre (the airless centre when
    /// `refract`), ENU unit vector: the sky frame's x axis on the sky
    /// ([`MoonShader::sky_xy`]).
    pub east: Vec3,
    /// Celestial north at the disk's centre (the airless centre when
    /// `refract`), ENU unit vector: the sky frame's y axis on the sky.
    pub north: Vec3,
    /// Whether pixel directions are un-refracted first ([`unrefract`]):
    /// the Moon's refracted altitude is below [`REFRACTION_FRAME_BELOW_DEG`].
    pub refract: bool,
    /// Unit vector from the Moon to the Sun in the sky frame (topocentric).
    pub sun: Vec3,
    /// Selenographic axes X (lon 0, lat 0), Y (lon 90° E) and Z (north
    /// pole) in the sky frame, unit vectors.
    pub axes: [Vec3; 3],
    /// 2 B(g) S(g) p / (π B(0)) at the topocentric phase angle g: the sunlit
    /// BRDF factor without the albedo map and without μ0/(μ0 + μ), sr⁻¹
    /// (normalised so that L = E p/π a at g = 0, where μ0/(μ0 + μ) = 1/2).
    pub sun_factor: f32,
    /// Linear sRGB of the sunlight at the Moon (solar illuminance times the
    /// lunar reflectance colour) after the extinction along the line of sight
    /// to the disk's centre: cd/m² per unit BRDF factor (sr⁻¹), i.e. lux.
    pub sun_rgb: [f32; 3],
    /// Linear sRGB radiance of the earthshine, E⊕ p/π in the lunar
    /// reflectance colour after the extinction to the disk's centre: cd/m²
    /// per unit albedo.
    pub earth_rgb: [f32; 3],
    /// ENU z component (cosine of the zenith angle) of the line of sight at
    /// the first node of `ext`.
    pub ext_z0: f32,
    /// Spacing of the nodes of `ext` in ENU z.
    pub ext_dz: f32,
    /// Extinction relative to the disk centre's at the nodes
    /// `ext_z0 + k · ext_dz` across the disk's z range, linear sRGB factors
    /// (1 at the centre; 1 everywhere without the atmosphere).
    pub ext: Vec<[f32; 3]>,
    /// The lunar-eclipse shading, when the Moon is in or near the Earth's
    /// penumbra ([`MoonState::eclipse`]); `None` otherwise.
    pub eclipse: Option<MoonEclipse>,
    /// The albedo map ([`AlbedoMap::get`]).
    pub map: &'static AlbedoMap,
    /// The relief's normal map ([`NormalMap::get`]).
    pub normals: &'static NormalMap,
}

/// The lunar-eclipse part of [`MoonShader`]: where a point of the Moon lies
/// in the Earth's shadow, and the sunlight that reaches it there
/// ([`eclipse_transfer`]).
#[derive(Debug, Clone, PartialEq)]
pub struct MoonEclipse {
    /// The Moon centre's offset from the shadow axis toward geocentric
    /// celestial east and north (gnomonic), radians.
    pub offset: [f32; 2],
    /// The Moon's geocentric semidiameter, radians: turns a sky-frame
    /// surface point (unit Moon radii) into an angular offset.
    pub semidiameter: f32,
    /// Geocentric sky east expressed in the Moon's topocentric sky frame,
    /// unit vector.
    pub geo_east: Vec3,
    /// Geocentric sky north expressed in the Moon's topocentric sky frame,
    /// unit vector.
    pub geo_north: Vec3,
    /// Axis distance of the table's last node (the penumbra's radius plus
    /// the Sun's diameter seen from the Moon), radians.
    pub d_max: f32,
    /// Sunlight relative to the uneclipsed Sun's at axis distances
    /// d_max · k / ([`ECLIPSE_TABLE_N`] − 1), k = 0 … [`ECLIPSE_TABLE_N`] − 1,
    /// linear sRGB factors applied to [`MoonShader::sun_rgb`].
    pub table: Vec<[f32; 3]>,
}

impl MoonShader {
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
                Some(MoonEclipse {
                    offset: [s.offset_east as f32, s.offset_north as f32],
                    semidiameter: s.moon_semidiameter as f32,
                    geo_east: v3(s.sky_to_geo[0]),
                    geo_north: v3(s.sky_to_geo[1]),
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
            let de = e.offset[0] + e.semidiameter * p.dot(e.geo_east);
            let dn = e.offset[1] + e.semidiameter * p.dot(e.geo_north);
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
