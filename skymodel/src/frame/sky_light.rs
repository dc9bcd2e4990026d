//! The sky's in-scattered light of one frame: the sky-view LUT lit by the
//! Sun and, on a moonlit night, a second one lit by the Moon
//! ([`crate::moon::moonlight_scale`]), looked up per view direction.
//!
//! Who computes the sky views is the backend's choice ([`SkyViewSource`]):
//! the CPU on all cores ([`CpuSkyViews`]) or a GPU's compute shaders read
//! back (`himmel-wgpu`). The frame plan asks for them only when it needs
//! them on the CPU side (the metering and culling of the night passes);
//! a backend that draws the atmosphere itself may never ask.

use std::cell::Cell;

use glam::Vec3;

use crate::atmosphere::{AtmosphereLuts, SkyView, SkyViewInput};
use crate::error::RenderError;

mod band;

thread_local! {
    static CPU_SKY_VIEWS: Cell<usize> = const { Cell::new(0) };
}

/// How many sky-view LUTs this thread has computed on the CPU
/// ([`cpu_sky_view`]): a GPU backend whose sky view runs on the GPU
/// computes none, which tests assert through this count.
pub fn cpu_sky_views_computed() -> usize {
    CPU_SKY_VIEWS.with(Cell::get)
}

/// Computes a sky-view LUT on all cores (its rows in parallel); a view
/// that is provably black (the sunlit sky of a night with the Sun far
/// below the horizon, [`SkyView::in_earth_shadow`]) is filled with zeros,
/// which is what its march would give.
pub fn cpu_sky_view(luts: &AtmosphereLuts, input: &SkyViewInput) -> SkyView {
    use rayon::prelude::*;
    CPU_SKY_VIEWS.with(|c| c.set(c.get() + 1));
    let (w, h) = (luts.config.sky_view_w, luts.config.sky_view_h);
    let rows = if SkyView::in_earth_shadow(luts, input) {
        vec![vec![[0.0f32; 3]; w]; h]
    } else {
        (0..h)
            .into_par_iter()
            .map(|j| SkyView::row(luts, input, j))
            .collect()
    };
    SkyView::from_rows(luts, input, rows)
}

/// Computes the sky views of a frame.
pub trait SkyViewSource {
    /// The sky view of each of `inputs` (in order) for `luts`.
    fn sky_views(
        &mut self,
        luts: &AtmosphereLuts,
        inputs: &[SkyViewInput],
    ) -> Result<Vec<SkyView>, RenderError>;
}

/// Sky views computed on the CPU ([`cpu_sky_view`]).
#[derive(Debug, Default, Clone, Copy)]
pub struct CpuSkyViews;

impl SkyViewSource for CpuSkyViews {
    fn sky_views(
        &mut self,
        luts: &AtmosphereLuts,
        inputs: &[SkyViewInput],
    ) -> Result<Vec<SkyView>, RenderError> {
        Ok(inputs.iter().map(|i| cpu_sky_view(luts, i)).collect())
    }
}

/// The sky-view inputs of a frame: the Sun's and, on a moonlit night, the
/// Moon's, with the directions their lookups use.
#[derive(Debug, Clone, Copy)]
pub struct SkyInputs {
    /// The sky lit by the Sun (scaled by the visible fraction of its disk).
    pub sun: SkyViewInput,
    /// The Sun's ENU direction (unit).
    pub sun_dir: Vec3,
    /// The sky lit by the Moon and the Moon's ENU direction (unit).
    pub moon: Option<(SkyViewInput, Vec3)>,
}

impl SkyInputs {
    /// The inputs in order: the Sun's, then the Moon's.
    pub fn list(&self) -> Vec<SkyViewInput> {
        let mut v = vec![self.sun];
        v.extend(self.moon.map(|(i, _)| i));
        v
    }
}

/// The sky radiance of one frame (sunlit, and moonlit when the Moon lights
/// the sky).
#[derive(Debug, Clone)]
pub struct SkyLight {
    /// The sky lit by the Sun (ground below the horizon included).
    pub sun: SkyView,
    /// The Sun's ENU direction (unit).
    pub sun_dir: Vec3,
    /// The sky lit by the Moon, and the Moon's ENU direction.
    pub moon: Option<(SkyView, Vec3)>,
    /// The Sun's and the Moon's azimuths (radians from East towards
    /// North, the angle of their horizontal components).
    azimuths: (f32, f32),
}

/// The angle between two azimuths (radians in [−π, π]), in [0, π].
#[inline]
fn azimuth_between(a: f32, b: f32) -> f32 {
    let d = (a - b).abs();
    if d > std::f32::consts::PI {
        std::f32::consts::TAU - d
    } else {
        d
    }
}

impl SkyLight {
    /// The sky light from the views of [`SkyInputs::list`] (in that order).
    pub fn from_views(inputs: &SkyInputs, views: Vec<SkyView>) -> Option<SkyLight> {
        let mut views = views.into_iter();
        let sun = views.next()?;
        let moon = match inputs.moon {
            Some((_, dir)) => Some((views.next()?, dir)),
            None => None,
        };
        let azimuth = |d: Vec3| crate::angle::atan2(d.y, d.x);
        let moon_azimuth = inputs.moon.map_or(0.0, |(_, d)| azimuth(d));
        Some(SkyLight {
            sun,
            sun_dir: inputs.sun_dir,
            moon,
            azimuths: (azimuth(inputs.sun_dir), moon_azimuth),
        })
    }

    /// Sky radiance (linear sRGB, cd/m²) towards ENU `dir` (unit); the
    /// ground's luminance below the horizon.
    #[inline]
    pub fn radiance(&self, dir: Vec3) -> [f32; 3] {
        let Some((sv, m)) = &self.moon else {
            return self.sun.radiance(dir, self.sun_dir);
        };
        if dir.z < 0.0 {
            let (a, b) = (self.sun.ground_rgb, sv.ground_rgb);
            return [a[0] + b[0], a[1] + b[1], a[2] + b[2]];
        }
        // Both views share the elevation's lookup when they have one size,
        // and the direction's azimuth: its angle from the Sun's and from
        // the Moon's is a difference of azimuths (one arctangent instead of
        // one per view; the same angle up to float rounding).
        let v = self.sun.row_coordinate(dir);
        let phi = crate::angle::atan2(dir.y, dir.x);
        let (sun_az, moon_az) = self.azimuths;
        let mut l = self.sun.radiance_at(azimuth_between(phi, sun_az), v);
        let k = if sv.lut.h == self.sun.lut.h {
            sv.radiance_at(azimuth_between(phi, moon_az), v)
        } else {
            sv.radiance(dir, *m)
        };
        for c in 0..3 {
            l[c] += k[c];
        }
        l
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn azimuth_differences_equal_the_angle_between_directions() {
        // The difference of two azimuths, folded into [0, π], against the
        // angle between the horizontal components (atan2 of |cross|, dot),
        // over a sweep of both: equal to within 1 µrad (float rounding).
        for i in 0..720 {
            for j in 0..97 {
                let (a, b) = (i as f32 * 0.5f32.to_radians(), j as f32 * 0.065 - 3.1);
                let (da, db) = (
                    Vec3::new(a.cos(), a.sin(), 0.3),
                    Vec3::new(b.cos(), b.sin(), -0.2),
                );
                let cross = da.x * db.y - da.y * db.x;
                let dot = da.x * db.x + da.y * db.y;
                let want = (cross.abs() as f64).atan2(dot as f64);
                let got = azimuth_between(
                    crate::angle::atan2(da.y, da.x),
                    crate::angle::atan2(db.y, db.x),
                );
                assert!((got as f64 - want).abs() < 1e-6, "{a} {b}: {got} vs {want}");
                assert!((0.0..=std::f32::consts::PI).contains(&got));
            }
        }
    }
}
