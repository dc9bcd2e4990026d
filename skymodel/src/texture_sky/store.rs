//! The textures of the last frames, decoded and prepared once
//! ([`TextureStore`], kept by the renderer's `LutStore`). This crate reads
//! no image file format (design.md): the decoding is a [`TextureLoader`]
//! given by the caller (`himmel_cpu::texture_io::ImageLoader` reads PNG,
//! JPEG, EXR and Radiance HDR through the `image` crate).

use std::collections::HashMap;
use std::path::Path;
use std::sync::Arc;

use glam::DVec3;

use super::{LinearImage, Mapping, SkyTexture, TextureError};

/// A decoded image: linear RGB, and whether it came from a high-dynamic-
/// range file (EXR, HDR: values in the file's own units) or not (PNG,
/// JPEG: sRGB decoded to linear 0 … 1).
#[derive(Debug, Clone, PartialEq)]
pub struct Decoded {
    /// The linear image.
    pub image: LinearImage,
    /// Whether the file is high-dynamic-range.
    pub hdr: bool,
}

/// Decodes image files for the texture store.
pub trait TextureLoader: Send + Sync + std::fmt::Debug {
    /// The image at `path`, or an error naming the file.
    fn load(&self, path: &Path) -> Result<Decoded, TextureError>;
}

/// How a prepared texture is keyed: file, mapping, sun mask (direction
/// bits or none, radius bits).
type Key = (String, Mapping, Option<([u64; 3], u64)>, bool);

/// Decoded and prepared textures (the most recent ones; a scene's
/// schedule rarely holds more than a few).
#[derive(Debug, Default, Clone)]
pub struct TextureStore {
    loader: Option<Arc<dyn TextureLoader>>,
    decoded: HashMap<String, Arc<Decoded>>,
    prepared: HashMap<Key, Arc<SkyTexture>>,
}

/// Prepared textures kept before the store starts afresh.
const KEEP: usize = 16;

/// A texture's sun mask: its direction in the texture's frame (`None`:
/// the brightest region) and radius, radians.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SunMask {
    /// Direction (ENU unit vector in the texture's frame) or none.
    pub dir: Option<DVec3>,
    /// Radius, radians.
    pub radius: f64,
}

impl TextureStore {
    /// Sets the image decoder.
    pub fn set_loader(&mut self, loader: Arc<dyn TextureLoader>) {
        self.loader = Some(loader);
    }

    /// Whether a decoder is set.
    pub fn has_loader(&self) -> bool {
        self.loader.is_some()
    }

    /// Registers an image under `name` (used instead of a file of that
    /// name: generated textures, tests).
    pub fn insert(&mut self, name: &str, decoded: Decoded) {
        self.prepared.retain(|k, _| k.0 != name);
        self.decoded.insert(name.to_string(), Arc::new(decoded));
    }

    /// The decoded image `path` (from memory, else the loader).
    pub fn decoded(&mut self, path: &str) -> Result<Arc<Decoded>, TextureError> {
        if let Some(d) = self.decoded.get(path) {
            return Ok(d.clone());
        }
        let loader = self
            .loader
            .as_ref()
            .ok_or_else(|| TextureError::NoLoader(path.to_string()))?;
        let d = Arc::new(loader.load(Path::new(path))?);
        if self.decoded.len() >= KEEP {
            self.decoded.clear();
        }
        self.decoded.insert(path.to_string(), d.clone());
        Ok(d)
    }

    /// The texture `path` prepared for `mapping` with an optional sun
    /// mask, and whether its file is high-dynamic-range; the image's size
    /// is checked against the mapping (an error naming the file).
    pub fn prepared(
        &mut self,
        path: &str,
        mapping: Mapping,
        mask: Option<SunMask>,
    ) -> Result<(Arc<SkyTexture>, bool), TextureError> {
        let d = self.decoded(path)?;
        let key: Key = (
            path.to_string(),
            mapping,
            mask.map(|m| {
                let v = m.dir.unwrap_or(DVec3::splat(f64::NAN));
                ([v.x, v.y, v.z].map(f64::to_bits), m.radius.to_bits())
            }),
            d.hdr,
        );
        if let Some(t) = self.prepared.get(&key) {
            return Ok((t.clone(), d.hdr));
        }
        let img = &d.image;
        mapping
            .check_size(img.width, img.height)
            .map_err(|reason| TextureError::Size {
                path: path.to_string(),
                reason,
            })?;
        let mut t = SkyTexture::new(mapping, img);
        if let Some(m) = mask {
            t = t.with_masked_sun(img, m.dir, m.radius);
        }
        let t = Arc::new(t);
        if self.prepared.len() >= KEEP {
            self.prepared.clear();
        }
        self.prepared.insert(key, t.clone());
        Ok((t, d.hdr))
    }
}
