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

mod eclipse;
mod maps;
mod photometry;
mod shader;

pub use eclipse::{
    eclipse_transfer, grazing_transmittance, LunarShadow, ECLIPSE_TABLE_N, GRAZING_REFRACTION,
};
pub use maps::{fast_atan2, AlbedoMap, NormalMap};
pub use photometry::{
    allen_magnitude, earthshine_lux, hapke_1963_b, hapke_s, lambert_sphere_phase,
    lunar_reflectance_spectrum, surge_b, EARTH_GEOMETRIC_ALBEDO, EARTH_RADIUS_KM, GEOMETRIC_ALBEDO,
    HAPKE_H, HAPKE_S_COEFF, LUX_MAG0, MEAN_MOON_DISTANCE_KM, SURGE_B0, SURGE_H,
};
pub use shader::{
    refraction_of_apparent, unrefract, MoonEclipse, MoonShader, REFRACTION_FRAME_BELOW_DEG,
};

use glam::{DVec3, Vec3};
use himmel_astro::events::ShadowGeometry;
use serde::Serialize;

use crate::spectrum::BandWeights;
use crate::units::{Lux, Radians};

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

/// The Moon's state for `observer` through `sky`, and the visible fraction
/// of the Sun's disk (1 − the uniform-disk overlap of the topocentric disks
/// of the Sun and the Moon; the Sun's limb darkening is not weighted in).
pub fn moon_state(
    sky: &himmel_astro::Sky,
    observer: &himmel_astro::Observer,
    sun: &crate::sun::SunState,
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
    sun: &crate::sun::SunState,
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
