//! Draws the chart overlay ([`himmel_skymodel::overlay`]) into a developed
//! 8-bit sRGB image: after the camera stage, so that it never touches the
//! radiance (an EXR has none), and the same for either backend.
//!
//! Lines and glyphs first build one coverage mask (the largest coverage
//! any of them gives a pixel, so that joints and crossings are not drawn
//! twice), then the mask blends the overlay colour over the image:
//! out = img + (colour − img) · coverage, in display sRGB.
//!
//! * Lines: a pixel is covered by the part of a box filter one pixel wide
//!   that the line, a capsule of `line_width` around its segments, covers
//!   along the distance to it: coverage = clamp(w/2 + 1/2 − d, 0, 1) (an
//!   anti-aliased line whose integral across it equals its width).
//! * Text: DejaVu Sans (`data/DejaVuSans.ttf`, Bitstream Vera licence,
//!   see `backend-cpu/README.md`) through `ab_glyph`, which gives each
//!   glyph's outline coverage per pixel; kerning from the font.
//!   Constellation names are centred on their anchor, star and planet
//!   names start beside theirs; a label that would overlap one placed
//!   before it (planets, then stars from the brightest, then
//!   constellations) moves one line down, or is left out.

use ab_glyph::{Font, FontRef, PxScale, ScaleFont};
use himmel_skymodel::overlay::{LabelKind, OverlayGeometry};
use himmel_skymodel::OverlaySpec;

/// DejaVu Sans 2.37 (Debian `fonts-dejavu-core`), unmodified.
const FONT: &[u8] = include_bytes!("../data/DejaVuSans.ttf");

/// Longest piece a line segment is rasterised in, px (keeps each piece's
/// bounding box small for long diagonal segments).
const PIECE_PX: f64 = 16.0;

/// A coverage mask over the image, 0–255 per pixel (one byte: the 8-bit
/// image needs no finer steps, and a 64 Mpx frame's mask stays 64 MB).
struct Mask {
    width: usize,
    height: usize,
    cover: Vec<u8>,
}

impl Mask {
    fn cover(&mut self, x: i64, y: i64, c: f32) {
        if x < 0 || y < 0 || x >= self.width as i64 || y >= self.height as i64 {
            return;
        }
        let m = &mut self.cover[y as usize * self.width + x as usize];
        *m = (*m).max((c.clamp(0.0, 1.0) * 255.0).round() as u8);
    }

    /// The segment from `a` to `b` (continuous image positions) with
    /// half-width `hw` px.
    fn segment(&mut self, a: [f64; 2], b: [f64; 2], hw: f64) {
        let Some((a, b)) = clip(a, b, self.width as f64, self.height as f64, hw + 1.0) else {
            return;
        };
        let len = (b[0] - a[0]).hypot(b[1] - a[1]);
        let pieces = (len / PIECE_PX).ceil().max(1.0) as usize;
        for k in 0..pieces {
            let t0 = k as f64 / pieces as f64;
            let t1 = (k + 1) as f64 / pieces as f64;
            let p = [a[0] + (b[0] - a[0]) * t0, a[1] + (b[1] - a[1]) * t0];
            let q = [a[0] + (b[0] - a[0]) * t1, a[1] + (b[1] - a[1]) * t1];
            self.piece(p, q, hw);
        }
    }

    fn piece(&mut self, p: [f64; 2], q: [f64; 2], hw: f64) {
        let r = hw + 1.0;
        let x0 = (p[0].min(q[0]) - r).floor() as i64;
        let x1 = (p[0].max(q[0]) + r).ceil() as i64;
        let y0 = (p[1].min(q[1]) - r).floor() as i64;
        let y1 = (p[1].max(q[1]) + r).ceil() as i64;
        let (dx, dy) = (q[0] - p[0], q[1] - p[1]);
        let l2 = dx * dx + dy * dy;
        for y in y0..=y1 {
            for x in x0..=x1 {
                let (cx, cy) = (x as f64 + 0.5, y as f64 + 0.5);
                let t = if l2 > 0.0 {
                    (((cx - p[0]) * dx + (cy - p[1]) * dy) / l2).clamp(0.0, 1.0)
                } else {
                    0.0
                };
                let d = (cx - p[0] - t * dx).hypot(cy - p[1] - t * dy);
                let c = hw + 0.5 - d;
                if c > 0.0 {
                    self.cover(x, y, c as f32);
                }
            }
        }
    }

    /// `text` with its baseline's left end at (x, y), `px` high.
    fn text(&mut self, font: &FontRef<'_>, text: &str, x: f32, y: f32, px: f32) {
        let scaled = font.as_scaled(PxScale::from(px));
        let mut pen = x;
        let mut last = None;
        for ch in text.chars() {
            let id = font.glyph_id(ch);
            if let Some(prev) = last {
                pen += scaled.kern(prev, id);
            }
            let glyph = id.with_scale_and_position(px, ab_glyph::point(pen, y));
            pen += scaled.h_advance(id);
            last = Some(id);
            if let Some(outline) = font.outline_glyph(glyph) {
                let b = outline.px_bounds();
                outline.draw(|gx, gy, c| {
                    self.cover(b.min.x as i64 + gx as i64, b.min.y as i64 + gy as i64, c);
                });
            }
        }
    }
}

/// Width of `text` at `px`, px.
fn text_width(font: &FontRef<'_>, text: &str, px: f32) -> f32 {
    let scaled = font.as_scaled(PxScale::from(px));
    let mut w = 0.0;
    let mut last = None;
    for ch in text.chars() {
        let id = font.glyph_id(ch);
        if let Some(prev) = last {
            w += scaled.kern(prev, id);
        }
        w += scaled.h_advance(id);
        last = Some(id);
    }
    w
}

/// Where the labels go (text, baseline-left x, y), planets first, then
/// stars (brightest first, the catalogue's order), then constellations:
/// each at its own place, else one line lower, else left out, so that no
/// two labels' boxes overlap.
fn place_labels<'a>(
    font: &FontRef<'_>,
    geometry: &'a OverlayGeometry,
    px: f32,
) -> Vec<(&'a str, f32, f32)> {
    let mut placed: Vec<[f32; 4]> = Vec::new();
    let mut out = Vec::new();
    for kind in [LabelKind::Planet, LabelKind::Star, LabelKind::Constellation] {
        for l in geometry.labels.iter().filter(|l| l.kind == kind) {
            let width = text_width(font, &l.text, px);
            let (x, y) = (l.pos[0] as f32, l.pos[1] as f32);
            let (x, y) = match kind {
                LabelKind::Constellation => (x - width / 2.0, y + px / 3.0),
                LabelKind::Star | LabelKind::Planet => (x + px / 2.0, y - px / 4.0),
            };
            for y in [y, y + 1.1 * px] {
                // The box from the ascenders to the descenders.
                let b = [x, y - 0.8 * px, x + width, y + 0.25 * px];
                let free = placed
                    .iter()
                    .all(|p| b[2] <= p[0] || p[2] <= b[0] || b[3] <= p[1] || p[3] <= b[1]);
                if free {
                    placed.push(b);
                    out.push((l.text.as_str(), x, y));
                    break;
                }
            }
        }
    }
    out
}

/// The part of segment a–b inside the image grown by `margin` px
/// (Liang–Barsky), or `None` when it misses it.
fn clip(a: [f64; 2], b: [f64; 2], w: f64, h: f64, margin: f64) -> Option<([f64; 2], [f64; 2])> {
    let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
    let (mut t0, mut t1) = (0.0f64, 1.0f64);
    for (p, q) in [
        (-dx, a[0] + margin),
        (dx, w + margin - a[0]),
        (-dy, a[1] + margin),
        (dy, h + margin - a[1]),
    ] {
        if p == 0.0 {
            if q < 0.0 {
                return None;
            }
        } else {
            let r = q / p;
            if p < 0.0 {
                t0 = t0.max(r);
            } else {
                t1 = t1.min(r);
            }
        }
    }
    (t0 <= t1).then(|| {
        (
            [a[0] + t0 * dx, a[1] + t0 * dy],
            [a[0] + t1 * dx, a[1] + t1 * dy],
        )
    })
}

/// Draws `geometry` with `spec`'s colour, line width and label size into
/// `rgb8` (8-bit sRGB, `width` × `height`, rows top to bottom).
pub fn draw(
    rgb8: &mut [u8],
    width: usize,
    height: usize,
    geometry: &OverlayGeometry,
    spec: &OverlaySpec,
) -> Result<(), String> {
    if rgb8.len() != width * height * 3 {
        return Err(format!(
            "overlay: an image of {} bytes is not {width}×{height} RGB",
            rgb8.len()
        ));
    }
    let mut mask = Mask {
        width,
        height,
        cover: vec![0; width * height],
    };
    let hw = spec.line_width / 2.0;
    for line in &geometry.lines {
        for pair in line.windows(2) {
            mask.segment(pair[0], pair[1], hw);
        }
    }
    if !geometry.labels.is_empty() {
        let font = FontRef::try_from_slice(FONT).map_err(|e| format!("overlay font: {e}"))?;
        for (text, x, y) in place_labels(&font, geometry, spec.label_px as f32) {
            mask.text(&font, text, x, y, spec.label_px as f32);
        }
    }
    let colour = spec.colour.map(|c| (c * 255.0) as f32);
    for (px, &c) in rgb8.chunks_exact_mut(3).zip(&mask.cover) {
        if c > 0 {
            let c = f32::from(c) / 255.0;
            for k in 0..3 {
                let v = px[k] as f32;
                px[k] = (v + (colour[k] - v) * c).round().clamp(0.0, 255.0) as u8;
            }
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn spec() -> OverlaySpec {
        OverlaySpec {
            colour: [1.0, 0.0, 0.0],
            ..OverlaySpec::default()
        }
    }

    /// A horizontal line one pixel wide on a pixel row's centre covers
    /// that row fully and carries its width: the summed coverage across it
    /// is 1 pixel per column.
    #[test]
    fn a_line_carries_its_width() {
        let (w, h) = (32, 16);
        let mut img = vec![0u8; w * h * 3];
        let g = OverlayGeometry {
            vertices: vec![],
            lines: vec![vec![[4.0, 8.5], [28.0, 8.5]]],
            labels: vec![],
        };
        draw(&mut img, w, h, &g, &spec()).unwrap();
        let red = |x: usize, y: usize| img[(y * w + x) * 3] as f64 / 255.0;
        assert_eq!(red(16, 8), 1.0);
        let column: f64 = (0..h).map(|y| red(16, y)).sum();
        assert!((column - 1.0).abs() < 0.01, "{column}");
        // Nothing beyond the ends (plus the anti-aliasing pixel) or off the row.
        assert_eq!(red(1, 8), 0.0);
        assert_eq!(red(16, 3), 0.0);
        // Green and blue untouched: the colour is pure red.
        assert!(img.chunks(3).all(|p| p[1] == 0 && p[2] == 0));
    }

    /// Segments far outside the image cost nothing and draw nothing; one
    /// crossing it from far away is clipped and drawn.
    #[test]
    fn far_segments_are_clipped() {
        let (w, h) = (16, 16);
        let mut img = vec![0u8; w * h * 3];
        let far = OverlayGeometry {
            vertices: vec![],
            lines: vec![vec![[-1e9, -1e9], [-1e9, 1e9]]],
            labels: vec![],
        };
        draw(&mut img, w, h, &far, &spec()).unwrap();
        assert!(img.iter().all(|&v| v == 0));
        let across = OverlayGeometry {
            vertices: vec![],
            lines: vec![vec![[-1e9, 8.5], [1e9, 8.5]]],
            labels: vec![],
        };
        draw(&mut img, w, h, &across, &spec()).unwrap();
        assert!((0..w).all(|x| img[(8 * w + x) * 3] == 255));
    }

    /// A label puts glyph pixels where it says and nowhere far from it.
    #[test]
    fn labels_are_drawn_at_their_anchor() {
        let (w, h) = (96, 32);
        let mut img = vec![0u8; w * h * 3];
        let g = OverlayGeometry {
            vertices: vec![],
            lines: vec![],
            labels: vec![himmel_skymodel::overlay::Label {
                text: "Orion".into(),
                pos: [48.0, 16.0],
                kind: LabelKind::Constellation,
            }],
        };
        draw(&mut img, w, h, &g, &spec()).unwrap();
        let lit: Vec<(usize, usize)> = (0..w * h)
            .filter(|i| img[i * 3] > 128)
            .map(|i| (i % w, i / w))
            .collect();
        assert!(lit.len() > 30, "{} pixels", lit.len());
        let (mx, my) = lit.iter().fold((0.0, 0.0), |(a, b), (x, y)| {
            (
                a + *x as f64 / lit.len() as f64,
                b + *y as f64 / lit.len() as f64,
            )
        });
        // Centred on the anchor, within the text's height.
        assert!(
            (mx - 48.0).abs() < 4.0 && (my - 16.0).abs() < 8.0,
            "{mx} {my}"
        );
        assert!(draw(&mut img[..10], w, h, &g, &spec()).is_err());
    }

    /// Labels never overlap: a star's name over a constellation's moves
    /// the constellation's one line down; a third at the same place is
    /// left out.
    #[test]
    fn labels_make_room_for_each_other() {
        let font = FontRef::try_from_slice(FONT).unwrap();
        let label = |text: &str, kind| himmel_skymodel::overlay::Label {
            text: text.into(),
            pos: [40.0, 40.0],
            kind,
        };
        let g = OverlayGeometry {
            vertices: vec![],
            lines: vec![],
            labels: vec![
                label("Orion", LabelKind::Constellation),
                label("Betelgeuse", LabelKind::Star),
                label("Rigel", LabelKind::Star),
            ],
        };
        let placed = place_labels(&font, &g, 13.0);
        let names: Vec<&str> = placed.iter().map(|p| p.0).collect();
        assert_eq!(names, ["Betelgeuse", "Rigel"]);
        assert!((placed[1].2 - placed[0].2 - 1.1 * 13.0).abs() < 1e-4);
        let apart = OverlayGeometry {
            labels: vec![
                label("Orion", LabelKind::Constellation),
                himmel_skymodel::overlay::Label {
                    pos: [40.0, 90.0],
                    ..label("Rigel", LabelKind::Star)
                },
            ],
            ..g
        };
        assert_eq!(place_labels(&font, &apart, 13.0).len(), 2);
    }
}
