//! The renderers' errors: typed, with the one-line messages the CLI prints.

use crate::scene::{Effect, SceneError};

/// A renderer failure.
#[derive(Debug, Clone, PartialEq)]
pub enum RenderError {
    /// The scene is invalid.
    Scene(SceneError),
    /// The backend cannot render this frame (`--backend auto` then falls
    /// back to the CPU).
    Unavailable(Unavailable),
    /// The effect has no pass in this backend's version.
    PassNotAvailable(Effect),
    /// The GPU driver reported an error (its message).
    Device(String),
    /// The scene has a world (`world.gltf`) but the renderer was given none.
    WorldMissing,
    /// A sky texture cannot be read or has the wrong size (naming the file).
    Texture(crate::texture_sky::TextureError),
}

/// Why a backend cannot render a frame.
#[derive(Debug, Clone, PartialEq)]
pub enum Unavailable {
    /// No adapter of the enabled GPU backends exists (the driver's words).
    NoAdapter(String),
    /// The adapter refused to create a device (the driver's words).
    DeviceRefused(String),
    /// A pass of the scene is not ported to this backend yet.
    PassNotPorted(Effect),
    /// The image exceeds the adapter's limits.
    ImageTooLarge {
        /// Image width, px.
        width: u32,
        /// Image height, px.
        height: u32,
        /// The adapter's largest texture side, px.
        max_side: u32,
    },
    /// The point-source quads cannot blend into this target format (its
    /// name) on this adapter.
    QuadFormat(String),
    /// The frame's sky textures need more storage than the adapter binds.
    TextureTooLarge {
        /// Bytes the textures need.
        bytes: u64,
        /// The adapter's largest storage-buffer binding, bytes.
        max_bytes: u64,
    },
}

impl std::fmt::Display for Unavailable {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Unavailable::NoAdapter(m) => write!(f, "no wgpu adapter available ({m})"),
            Unavailable::DeviceRefused(m) => {
                write!(f, "the wgpu adapter cannot create a device ({m})")
            }
            Unavailable::PassNotPorted(e) => write!(
                f,
                "the {} pass is not yet available in the wgpu backend",
                e.name()
            ),
            Unavailable::ImageTooLarge {
                width,
                height,
                max_side,
            } => write!(
                f,
                "a {width}×{height} image exceeds this wgpu adapter's limits ({max_side} px per side)"
            ),
            Unavailable::QuadFormat(format) => write!(
                f,
                "the point-source quads cannot blend into {format} on this adapter"
            ),
            Unavailable::TextureTooLarge { bytes, max_bytes } => write!(
                f,
                "the sky textures need {:.1} MiB of GPU storage, more than this adapter binds ({:.1} MiB)",
                *bytes as f64 / 1048576.0,
                *max_bytes as f64 / 1048576.0
            ),
        }
    }
}

impl std::fmt::Display for RenderError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            RenderError::Scene(e) => write!(f, "{}: {}", e.field, e.message),
            RenderError::Unavailable(u) => u.fmt(f),
            RenderError::PassNotAvailable(e) => {
                write!(f, "the {} pass is not available in this version", e.name())
            }
            RenderError::Device(m) => write!(f, "wgpu: {m}"),
            RenderError::WorldMissing => {
                f.write_str("the scene has a 3D world but the renderer was given none (set_world)")
            }
            RenderError::Texture(e) => e.fmt(f),
        }
    }
}

impl std::error::Error for RenderError {}

impl From<SceneError> for RenderError {
    fn from(e: SceneError) -> Self {
        RenderError::Scene(e)
    }
}
