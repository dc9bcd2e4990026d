//! The renderer's star field: the fast path of `himmel_astro::stars` over a
//! whole catalogue, with unit vectors re-based ("refreshed") when the date
//! moves more than a tolerance from the refresh epoch.

use himmel_astro::stars::{FastStar, FrameRotation};
use himmel_astro::units::JulianDay;
use himmel_astro::{Epoch, Observer};

use crate::error::CatalogError;
use crate::star::Star;

/// Per-star unit vectors and proper-motion rates for a frame-by-frame
/// renderer. Each frame costs one [`FrameRotation`] (a 3×3 matrix and an
/// aberration vector) plus a few multiply-adds per star.
#[derive(Debug, Clone)]
pub struct StarField {
    refresh_jd_tt: JulianDay,
    tolerance_days: f64,
    source: Vec<himmel_astro::stars::Astrometry>,
    stars: Vec<FastStar>,
}

impl StarField {
    /// Prepares `stars` at `jd_tt`; they are re-based when a later date is
    /// more than `tolerance_days` (> 0, finite) from the refresh epoch.
    pub fn new(
        stars: &[Star],
        jd_tt: JulianDay,
        tolerance_days: f64,
    ) -> Result<Self, CatalogError> {
        CatalogError::check_range("jd_tt", jd_tt, 0.0, 1e7)?;
        CatalogError::check_range("refresh tolerance (days)", tolerance_days, 1e-6, 1e7)?;
        let source: Vec<_> = stars.iter().map(|s| s.astrometry).collect();
        let fast = source.iter().map(|a| FastStar::new(a, jd_tt)).collect();
        Ok(StarField {
            refresh_jd_tt: jd_tt,
            tolerance_days,
            source,
            stars: fast,
        })
    }

    /// Re-bases the unit vectors at `jd_tt` if it lies beyond the tolerance;
    /// returns whether it did.
    pub fn refresh_if_needed(&mut self, jd_tt: JulianDay) -> bool {
        if !jd_tt.is_finite() || (jd_tt - self.refresh_jd_tt).abs() <= self.tolerance_days {
            return false;
        }
        self.refresh_jd_tt = jd_tt;
        for (f, a) in self.stars.iter_mut().zip(&self.source) {
            *f = FastStar::new(a, jd_tt);
        }
        true
    }

    /// The refresh epoch, JD (TT).
    pub fn refresh_jd_tt(&self) -> JulianDay {
        self.refresh_jd_tt
    }

    /// The prepared stars, in the order given to [`StarField::new`].
    pub fn stars(&self) -> &[FastStar] {
        &self.stars
    }

    /// The frame's rotation for `observer` at `epoch` (after
    /// [`StarField::refresh_if_needed`] if the renderer wants it).
    pub fn frame(&self, epoch: &Epoch, observer: &Observer) -> FrameRotation {
        FrameRotation::new(epoch, observer, self.refresh_jd_tt)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Catalog;
    use himmel_astro::frames::NutationModel;
    use himmel_astro::stars::StarReduction;
    use himmel_astro::Instant;

    #[test]
    fn refreshes_only_beyond_the_tolerance_and_stays_accurate() {
        let cat = Catalog::embedded().unwrap();
        let stars = cat.brighter_than(3.0);
        let mut field = StarField::new(stars, 2_451_545.0, 3652.5).unwrap();
        assert!(!field.refresh_if_needed(2_451_545.0 + 3000.0));
        assert!(!field.refresh_if_needed(f64::NAN));
        assert!(field.refresh_if_needed(2_451_545.0 + 4000.0));
        assert_eq!(field.refresh_jd_tt(), 2_451_545.0 + 4000.0);
        // After a refresh, one frame against the exact path, polar observer.
        let obs = Observer::new(-90.0, 0.0, 0.0).unwrap();
        let epoch = Epoch::new(
            &Instant::from_tt(2_451_545.0 + 4100.0),
            NutationModel::Iau1980,
        );
        let frame = field.frame(&epoch, &obs);
        let red = StarReduction::new(&epoch);
        for (s, f) in stars.iter().zip(field.stars()) {
            let exact = red.topocentric(&s.astrometry, &obs).enu();
            let fast = frame.enu(f);
            let err = exact
                .cross(fast)
                .length()
                .atan2(exact.dot(fast))
                .to_degrees()
                * 3600.0;
            assert!(err < 1.0, "HIP {}: {err}″", s.hip);
        }
        assert!(StarField::new(stars, 2_451_545.0, 0.0).is_err());
        assert!(StarField::new(stars, f64::NAN, 1.0).is_err());
    }
}
