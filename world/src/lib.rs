//! `himmel-world`: the 3D world under the sky (`shared/spec/world.md`).
//!
//! * [`World`] — triangle meshes in the world frame (x East, y Up,
//!   z South, metres; glTF's axes map one to one), their metallic–roughness
//!   materials (linear albedo, emissive radiance in cd/m²), base-colour
//!   textures decoded to linear values, and the world's bounds;
//! * [`gltf_io`] — glTF 2.0 loading (`.gltf` with embedded or relative
//!   buffers, `.glb`) with the node transforms applied, and `.glb` export;
//!   errors name the file and what is wrong (accessor, index);
//! * [`procedural`] — the test worlds the lighting passes are judged on:
//!   a sun room, an atrium and a plane with boxes.
//!
//! The crate knows nothing of any renderer.

pub mod gltf_io;
pub mod procedural;

use glam::Vec3;

/// A triangle mesh of one material, in world coordinates.
#[derive(Debug, Clone, PartialEq)]
pub struct Mesh {
    /// Vertex positions, metres (world frame).
    pub positions: Vec<[f32; 3]>,
    /// Unit vertex normals (world frame).
    pub normals: Vec<[f32; 3]>,
    /// Texture coordinates of the base-colour texture (0 where absent).
    pub uvs: Vec<[f32; 2]>,
    /// Three vertex indices per triangle, counter-clockwise seen from the
    /// front.
    pub indices: Vec<u32>,
    /// Index into [`World::materials`].
    pub material: usize,
}

impl Mesh {
    /// The number of triangles.
    pub fn triangles(&self) -> usize {
        self.indices.len() / 3
    }
}

/// A metallic–roughness material (glTF 2.0 core).
#[derive(Debug, Clone, PartialEq)]
pub struct Material {
    /// Its name in the source file, if any.
    pub name: Option<String>,
    /// Linear base colour (albedo for dielectrics) and alpha.
    pub base_color: [f32; 4],
    /// Index into [`World::textures`] of the base-colour texture, which
    /// multiplies `base_color`.
    pub base_color_texture: Option<usize>,
    /// Metalness, 0–1.
    pub metallic: f32,
    /// Perceptual roughness, 0–1.
    pub roughness: f32,
    /// Emitted radiance, linear sRGB cd/m²: `emissiveFactor` ×
    /// `KHR_materials_emissive_strength`.
    pub emissive: [f32; 3],
}

impl Default for Material {
    /// A white Lambertian surface (albedo 1, not metallic, fully rough):
    /// the glTF defaults.
    fn default() -> Self {
        Material {
            name: None,
            base_color: [1.0; 4],
            base_color_texture: None,
            metallic: 1.0,
            roughness: 1.0,
            emissive: [0.0; 3],
        }
    }
}

impl Material {
    /// A diffuse (Lambertian) material of linear albedo `rgb`.
    pub fn diffuse(name: &str, rgb: [f32; 3]) -> Material {
        Material {
            name: Some(name.into()),
            base_color: [rgb[0], rgb[1], rgb[2], 1.0],
            metallic: 0.0,
            roughness: 1.0,
            ..Material::default()
        }
    }
}

/// A base-colour texture decoded to linear RGBA (the glTF file stores it
/// sRGB-encoded).
#[derive(Debug, Clone, PartialEq)]
pub struct Texture {
    /// Width, texels.
    pub width: u32,
    /// Height, texels.
    pub height: u32,
    /// Row-major linear RGBA.
    pub texels: Vec<[f32; 4]>,
}

/// An axis-aligned box.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Aabb {
    /// The smallest corner.
    pub min: Vec3,
    /// The largest corner.
    pub max: Vec3,
}

impl Aabb {
    /// The box around `points` (`None` when empty).
    pub fn around<'a>(points: impl IntoIterator<Item = &'a [f32; 3]>) -> Option<Aabb> {
        points.into_iter().fold(None, |b, p| {
            let p = Vec3::from_array(*p);
            Some(match b {
                None => Aabb { min: p, max: p },
                Some(Aabb { min, max }) => Aabb {
                    min: min.min(p),
                    max: max.max(p),
                },
            })
        })
    }

    /// The diagonal's length, metres.
    pub fn extent(&self) -> f32 {
        (self.max - self.min).length()
    }
}

/// A 3D world: meshes, their materials and textures.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct World {
    /// One mesh per glTF primitive (or procedural part), in world
    /// coordinates.
    pub meshes: Vec<Mesh>,
    /// The materials the meshes index.
    pub materials: Vec<Material>,
    /// The base-colour textures the materials index.
    pub textures: Vec<Texture>,
    /// What was ignored while loading (unsupported extensions, non-triangle
    /// primitives), one line each, for the caller to report.
    pub warnings: Vec<String>,
}

impl World {
    /// The number of triangles.
    pub fn triangles(&self) -> usize {
        self.meshes.iter().map(Mesh::triangles).sum()
    }

    /// The bounds of every vertex (`None` for an empty world).
    pub fn bounds(&self) -> Option<Aabb> {
        Aabb::around(self.meshes.iter().flat_map(|m| &m.positions))
    }

    /// The world's surface area, m² (a check for procedural worlds).
    pub fn area(&self) -> f64 {
        self.meshes
            .iter()
            .flat_map(|m| {
                m.indices.chunks_exact(3).map(move |t| {
                    let p = |i: u32| Vec3::from_array(m.positions[i as usize]).as_dvec3();
                    0.5 * (p(t[1]) - p(t[0])).cross(p(t[2]) - p(t[0])).length()
                })
            })
            .sum()
    }
}

/// Why a world cannot be loaded.
#[derive(Debug, Clone, PartialEq)]
pub struct WorldError {
    /// The file (or the name given to in-memory bytes).
    pub file: String,
    /// What is wrong.
    pub kind: WorldErrorKind,
}

/// What is wrong with a world file.
#[derive(Debug, Clone, PartialEq)]
pub enum WorldErrorKind {
    /// It cannot be read (the system's message).
    Io(String),
    /// It is not valid glTF 2.0 (the parser's message).
    Parse(String),
    /// An accessor (by index) is missing, of the wrong type, or does not
    /// fit its buffer.
    Accessor {
        /// The accessor's index.
        accessor: usize,
        /// What is wrong.
        message: String,
    },
    /// A triangle index points past the primitive's vertices.
    Index {
        /// The mesh's index.
        mesh: usize,
        /// The primitive's index in the mesh.
        primitive: usize,
        /// The offending index value.
        index: u32,
        /// The primitive's vertex count.
        vertices: usize,
    },
}

impl std::fmt::Display for WorldError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}: ", self.file)?;
        match &self.kind {
            WorldErrorKind::Io(m) => write!(f, "cannot read ({m})"),
            WorldErrorKind::Parse(m) => write!(f, "not a valid glTF 2.0 file ({m})"),
            WorldErrorKind::Accessor { accessor, message } => {
                write!(f, "accessor {accessor}: {message}")
            }
            WorldErrorKind::Index {
                mesh,
                primitive,
                index,
                vertices,
            } => write!(
                f,
                "mesh {mesh} primitive {primitive}: index {index} past its {vertices} vertices"
            ),
        }
    }
}

impl std::error::Error for WorldError {}
