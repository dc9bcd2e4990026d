//! The night passes of the CPU renderer: Milky Way / night-sky light, and
//! the stars' and planets' footprints splatted into the image. What to
//! draw, at which exposure and extinction, comes from the frame plan's
//! [`NightFrame`] (physics in `himmel_skymodel::{stars, milkyway, night}`).

use glam::Vec3;
use himmel_skymodel::frame::NightFrame;
use himmel_skymodel::stars::{splat_at, PointSource, Psf, SplatScratch};
use himmel_skymodel::{Camera, Scene};
use rayon::prelude::*;

/// A source ready to splat.
struct Prepared {
    pos: (f64, f64),
    dir_z: f32,
    lux: f32,
    rgb: [f32; 3],
    glare: bool,
}

impl Prepared {
    /// Splats the source into `pixels`, the image's rows from pixel
    /// `offset` on ([`splat_at`]).
    fn splat(
        &self,
        pixels: &mut [[f32; 3]],
        offset: usize,
        cam: &Camera,
        psf: &Psf,
        scratch: &mut SplatScratch,
    ) {
        let (pos, z, rgb) = (self.pos, self.dir_z, self.rgb);
        splat_at(pixels, offset, cam, pos, z, self.lux, rgb, psf, scratch);
    }
}

/// Splats `sources` (extinction applied here) into `pixels`: sources whose
/// core may overflow into a glare disk one after the other over the whole
/// image, the rest in parallel over bands of rows (each band takes the
/// sources whose core footprint reaches it and writes only its own rows;
/// the footprint and its normalisation are the whole image's, so the
/// result is the same as a serial splat).
pub fn splat_all(
    frame: &NightFrame,
    pixels: &mut [[f32; 3]],
    scene: &Scene,
    sources: &[PointSource],
) {
    let psf = frame.psf(scene);
    let cam = &scene.camera;
    let (w, h) = cam.image_size();
    let (w, h) = (w as usize, h as usize);
    // Upper bound of the core's peak weight (see `core_peak_luminance`).
    let sigma = psf.core_px.max(0.1);
    let w0 = (1.0 / (2.0 * std::f32::consts::PI * sigma * sigma)).min(1.0);
    // Extinction, colour and image position of each source, in parallel.
    let mut prepared: Vec<Prepared> = sources
        .par_iter()
        .with_min_len(256)
        .filter_map(|s| {
            let p = frame.place(cam, s)?;
            let (cx, cy) = p.pos;
            let lux = s.lux * p.y;
            // Glare candidates: a core peak within 2× of white (the splat
            // decides exactly).
            let glare = psf.glare > 0.0 && {
                let omega = cam.pixel_solid_angle(cx.floor() + 0.5, cy.floor() + 0.5) as f32;
                lux * w0 * 2.0 >= psf.white_cd_m2 * omega
            };
            Some(Prepared {
                pos: p.pos,
                dir_z: s.dir.z,
                lux,
                rgb: [p.rgb[0] / p.y, p.rgb[1] / p.y, p.rgb[2] / p.y],
                glare,
            })
        })
        .collect();
    prepared.sort_by(|a, b| a.pos.1.total_cmp(&b.pos.1));
    let reach = (2.5 * psf.core_px).ceil() as f64 + 1.0;
    let bands = (rayon::current_num_threads() * 4).clamp(1, h.max(1));
    let rows = h.div_ceil(bands);
    pixels
        .par_chunks_mut(rows * w)
        .enumerate()
        .for_each(|(b, band)| {
            let (y0, y1) = ((b * rows) as f64, ((b + 1) * rows) as f64);
            let first = prepared.partition_point(|p| p.pos.1 < y0 - reach);
            let mut scratch = SplatScratch::default();
            for p in prepared[first..]
                .iter()
                .take_while(|p| p.pos.1 < y1 + reach)
            {
                if !p.glare {
                    p.splat(band, b * rows * w, cam, &psf, &mut scratch);
                }
            }
        });
    let mut scratch = SplatScratch::default();
    for p in prepared.iter().filter(|p| p.glare) {
        p.splat(pixels, 0, cam, &psf, &mut scratch);
    }
}

/// The Milky Way pass: the diffuse night sky, extinguished, above the horizon.
pub fn milkyway(frame: &NightFrame, pixels: &mut [[f32; 3]], dirs: &[Option<Vec3>]) {
    crate::bands::par_chunks(pixels, dirs, 4096, |_, p, d| milkyway_band(frame, p, d));
}

/// [`milkyway`] over a band of pixels and their directions.
/// ([`himmel_skymodel::milkyway::NightBackground::add_band`]).
pub fn milkyway_band(frame: &NightFrame, pixels: &mut [[f32; 3]], dirs: &[Option<Vec3>]) {
    frame.background.add_band(&frame.extinction, pixels, dirs);
}
