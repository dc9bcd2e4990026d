//! The LUT lookups of the view-ray march ([`super::march`]) with their
//! radius-only parts computed once per march step: a sky-view row marches
//! one ray per elevation and looks the Sun's light up at every step for
//! each of its azimuths, at the same radii. [`AtRadius`] keeps what
//! [`Medium::sun_visibility`], [`super::lut::transmittance_uv`] and
//! [`AtmosphereLuts::multiscatter_at`] compute from the radius alone (the
//! horizon's cosine, the Sun's disk, the transmittance LUT's row, Ψ_ms's
//! row); the lookups are then the same operations in the same order as
//! [`AtmosphereLuts::sun_transmittance`],
//! [`AtmosphereLuts::scattering_sun_transmittance`] and
//! [`AtmosphereLuts::multiscatter_at`], so they give the same values bit
//! for bit (test `lookups_at_a_radius_equal_the_luts`). Ψ_ms's columns
//! that are zero in both of a radius's rows (the Earth's shadow) are
//! known too: a lookup there, or a whole source with the Sun below the
//! radius's horizon ([`AtRadius::dark`]: the sunlit sky of a night), is
//! +0 without reading the tables.

use super::lut::{tex_from_unit, unit_from_mu_s, AtmosphereLuts, Lut2};
use super::medium::{safe_sqrt, smoothstep, Medium};
use crate::spectrum::Spectrum;

/// One axis of a bilinear lookup (`Lut2::corners`): the first texel, the
/// next one and its weight.
#[derive(Debug, Clone, Copy)]
pub(super) struct Tap {
    i0: usize,
    i1: usize,
    f: f32,
}

impl Tap {
    /// The tap of texture coordinate `u` on an axis of `n` texels.
    #[inline]
    fn new(u: f32, n: usize) -> Tap {
        let x = (u * n as f32 - 0.5).clamp(0.0, (n - 1) as f32);
        let i0 = x as usize;
        Tap {
            i0,
            i1: (i0 + 1).min(n - 1),
            f: x - i0 as f32,
        }
    }
}

impl Lut2<Spectrum> {
    /// [`Lut2::sample`] at (u, v) with v's tap given.
    #[inline]
    fn sample_in_rows(&self, u: f32, row: Tap) -> Spectrum {
        let x = Tap::new(u, self.w);
        let (y0, y1) = (row.i0 * self.w, row.i1 * self.w);
        let a = self.data[y0 + x.i0] * (1.0 - x.f) + self.data[y0 + x.i1] * x.f;
        let b = self.data[y1 + x.i0] * (1.0 - x.f) + self.data[y1 + x.i1] * x.f;
        a * (1.0 - row.f) + b * row.f
    }
}

/// The radius-only parts of the Sun's transmittance and of Ψ_ms at one
/// radius (see the module documentation).
#[derive(Debug, Clone, Copy)]
pub(super) struct AtRadius {
    r: f32,
    /// The horizon's cosine (negative) and the Sun's disk radius there.
    cos_h: f32,
    disk: f32,
    /// The transmittance LUT's distances to the top: least and greatest.
    d_min: f32,
    d_max: f32,
    /// The rows of the transmittance, the δ-scaled transmittance and Ψ_ms.
    transmittance: Tap,
    scattering: Tap,
    multiscatter: Tap,
    /// The leading columns of Ψ_ms that are zero (every band, +0) in both
    /// of its rows: the Earth's shadow at low Sun cosines.
    multiscatter_zeros: usize,
}

/// The number of leading texels of `row` whose bands are all +0.
fn zero_prefix(row: &[Spectrum]) -> usize {
    row.iter()
        .take_while(|s| s.0.iter().all(|v| v.to_bits() == 0))
        .count()
}

impl AtRadius {
    /// The parts at radius `r` (km).
    #[inline]
    pub(super) fn new(luts: &AtmosphereLuts, r: f32) -> Self {
        let m = &luts.medium;
        // Medium::sun_visibility
        let sin_h = (m.bottom / r).min(1.0);
        let cos_h = -safe_sqrt(1.0 - sin_h * sin_h);
        let disk = m.sun_angular_radius * sin_h;
        // transmittance_uv
        let hh = safe_sqrt(m.top * m.top - m.bottom * m.bottom);
        let rho = safe_sqrt(r * r - m.bottom * m.bottom);
        let x_r = (rho / hh).clamp(0.0, 1.0);
        let row = |t: &Lut2<Spectrum>| Tap::new(tex_from_unit(x_r, t.h), t.h);
        // multiscatter_at (a square table: its width for both axes)
        let ms = &luts.multiscatter;
        let v = tex_from_unit(((r - m.bottom) / (m.top - m.bottom)).clamp(0.0, 1.0), ms.w);
        let multiscatter = Tap::new(v, ms.h);
        let zeros = |i: usize| zero_prefix(&ms.data[i * ms.w..(i + 1) * ms.w]);
        let multiscatter_zeros = zeros(multiscatter.i0).min(zeros(multiscatter.i1));
        AtRadius {
            r,
            cos_h,
            disk,
            d_min: m.top - r,
            d_max: rho + hh,
            transmittance: row(&luts.transmittance),
            scattering: row(&luts.scattering_transmittance),
            multiscatter,
            multiscatter_zeros,
        }
    }

    /// `lut::sun_transmittance` of table `t` (whose row is `row`) towards
    /// Sun zenith cosine `mu_s`.
    #[inline]
    fn lookup(&self, m: &Medium, t: &Lut2<Spectrum>, row: Tap, mu_s: f32) -> Spectrum {
        let vis = smoothstep(-self.disk, self.disk, mu_s - self.cos_h);
        if vis <= 0.0 {
            return Spectrum::ZERO;
        }
        let d = m.distance_to_top(self.r, mu_s);
        let x_mu = if self.d_max > self.d_min {
            ((d - self.d_min) / (self.d_max - self.d_min)).clamp(0.0, 1.0)
        } else {
            0.0
        };
        t.sample_in_rows(tex_from_unit(x_mu, t.w), row) * vis
    }

    /// [`AtmosphereLuts::sun_transmittance`] at this radius.
    #[inline]
    pub(super) fn sun_transmittance(&self, luts: &AtmosphereLuts, mu_s: f32) -> Spectrum {
        self.lookup(&luts.medium, &luts.transmittance, self.transmittance, mu_s)
    }

    /// [`AtmosphereLuts::scattering_sun_transmittance`] at this radius.
    #[inline]
    pub(super) fn scattering_sun_transmittance(
        &self,
        luts: &AtmosphereLuts,
        mu_s: f32,
    ) -> Spectrum {
        let t = &luts.scattering_transmittance;
        self.lookup(&luts.medium, t, self.scattering, mu_s)
    }

    /// [`AtmosphereLuts::multiscatter_at`] at this radius.
    #[inline]
    pub(super) fn multiscatter(&self, luts: &AtmosphereLuts, mu_s: f32) -> Spectrum {
        let ms = &luts.multiscatter;
        let u = tex_from_unit(unit_from_mu_s(mu_s), ms.w);
        if self.in_shadow(ms, u) {
            return Spectrum::ZERO;
        }
        ms.sample_in_rows(u, self.multiscatter)
    }

    /// Whether the Ψ_ms lookup at column coordinate `u` reads only +0
    /// texels with finite weights: its bilinear sum is then +0 in every
    /// band (what [`Lut2::sample`] gives), without the reads.
    #[inline]
    fn in_shadow(&self, ms: &Lut2<Spectrum>, u: f32) -> bool {
        let x = Tap::new(u, ms.w);
        x.i1 < self.multiscatter_zeros && x.f.is_finite() && self.multiscatter.f.is_finite()
    }

    /// Whether the whole scattering source at Sun zenith cosine `mu_s` is
    /// zero: the Sun below the horizon of this radius (no beam, direct or
    /// δ-scaled) and Ψ_ms in its zero columns. [`super::march`]'s source
    /// is then +0 in every band (each of its terms is a non-negative
    /// coefficient times +0), which the caller may return at once.
    #[inline]
    pub(super) fn dark(&self, luts: &AtmosphereLuts, mu_s: f32) -> bool {
        let ms = &luts.multiscatter;
        smoothstep(-self.disk, self.disk, mu_s - self.cos_h) <= 0.0
            && self.in_shadow(ms, tex_from_unit(unit_from_mu_s(mu_s), ms.w))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::atmosphere::{AtmosphereParams, LutConfig};

    #[test]
    fn dark_rows_equal_their_march() {
        // Sky views from the nadir Sun to daylight, on the ground and at
        // 3 km: each row equals its texel-by-texel march bit for bit, and
        // the night's rows take the shortcut.
        use crate::atmosphere::{SkyView, SkyViewInput};
        let luts = AtmosphereLuts::compute(&AtmosphereParams::default(), &LutConfig::small());
        let mut dark_rows = 0;
        for alt in [
            -90.0f32, -60.0, -39.4, -25.0, -18.0, -12.0, -6.0, -1.0, 5.0, 40.0,
        ] {
            for h_km in [0.0, 3.0] {
                let input = SkyViewInput {
                    observer_altitude_km: h_km,
                    sun_sin_elevation: alt.to_radians().sin(),
                    irradiance_scale: 1.0,
                };
                for j in 0..luts.config.sky_view_h {
                    let (row, want) = (
                        SkyView::row(&luts, &input, j),
                        SkyView::row_marched(&luts, &input, j),
                    );
                    let bits =
                        |r: &[[f32; 3]]| r.iter().map(|p| p.map(f32::to_bits)).collect::<Vec<_>>();
                    assert_eq!(bits(&row), bits(&want), "{alt}° {h_km} km row {j}");
                    let r0 = m_r0(&luts, h_km);
                    let mu = SkyView::texel_direction(
                        0.5,
                        (j as f32 + 0.5) / luts.config.sky_view_h as f32,
                        luts.config.sky_view_w,
                        luts.config.sky_view_h,
                    )
                    .z;
                    let march = super::super::march::ViewMarch::new(
                        &luts,
                        r0,
                        mu,
                        luts.config.sky_view_steps,
                    );
                    if march.dark(&luts, r0, 1.0, input.sun_sin_elevation) {
                        dark_rows += 1;
                    }
                }
            }
        }
        assert!(dark_rows > 0, "no dark row");
    }

    /// The observer's radius of the sky view at altitude `h_km`.
    fn m_r0(luts: &AtmosphereLuts, h_km: f32) -> f32 {
        let m = &luts.medium;
        m.bottom + h_km.clamp(0.0, m.top - m.bottom - 0.01)
    }

    #[test]
    fn lookups_at_a_radius_equal_the_luts() {
        // Radii from the ground to above the top, Sun cosines through the
        // terminator and the whole range: the same bits.
        let luts = AtmosphereLuts::compute(&AtmosphereParams::default(), &LutConfig::small());
        let m = &luts.medium;
        let bits = |s: Spectrum| s.0.map(f32::to_bits);
        let mut dark = 0;
        for i in 0..=60 {
            let r = m.bottom + (m.top - m.bottom) * (i as f32 / 58.0) - 0.01;
            let at = AtRadius::new(&luts, r);
            for j in 0..=2000 {
                let mu = -1.0 + 2.0 * j as f32 / 2000.0;
                let mu = if j % 2 == 1 { mu * 0.01 } else { mu };
                let (a, b) = (
                    at.sun_transmittance(&luts, mu),
                    luts.sun_transmittance(r, mu),
                );
                assert_eq!(bits(a), bits(b), "{r} {mu}");
                let (a, b) = (
                    at.scattering_sun_transmittance(&luts, mu),
                    luts.scattering_sun_transmittance(r, mu),
                );
                assert_eq!(bits(a), bits(b), "{r} {mu}");
                let (a, b) = (at.multiscatter(&luts, mu), luts.multiscatter_at(r, mu));
                assert_eq!(bits(a), bits(b), "{r} {mu}");
                if at.dark(&luts, mu) {
                    // No light at all: each lookup of the source is +0.
                    dark += 1;
                    let zero = bits(Spectrum::ZERO);
                    assert_eq!(bits(luts.sun_transmittance(r, mu)), zero, "{r} {mu}");
                    let t = luts.scattering_sun_transmittance(r, mu);
                    assert_eq!(bits(t), zero, "{r} {mu}");
                    assert_eq!(bits(luts.multiscatter_at(r, mu)), zero, "{r} {mu}");
                }
            }
        }
        // The night side of the LUTs is dark at some of these points.
        assert!(dark > 1000, "{dark}");
    }
}
