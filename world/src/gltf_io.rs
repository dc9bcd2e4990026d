//! glTF 2.0 in and out.
//!
//! **Loading** ([`load`], [`from_slice`]): `.glb`, or `.gltf` with embedded
//! (data URI) or relative buffers and images. The default scene (else every
//! scene, else every root node) is walked with the node transforms applied
//! (normals by the inverse transpose; a mirroring transform flips the
//! winding back). Triangle lists, strips and fans are read; points and
//! lines are skipped with a warning, as are extensions other than
//! `KHR_materials_emissive_strength` (`World::warnings`). Before a byte is
//! read, every accessor the meshes use is checked against its buffer view
//! and buffer and against the formats glTF allows for its use, and every
//! index against the vertex count; a node reached twice (a cycle or a second
//! parent) is an error. A truncated, corrupted or malformed file is an
//! error naming the accessor, index or node, never a panic or a hang
//! (`himmel-fuzz gltf`, `docs/hardening.md`).
//!
//! **Export** ([`to_glb`]): one `.glb` with the world's meshes (positions,
//! normals, texture coordinates, u32 indices; one node per mesh, identity
//! transforms) and materials (base colour, metallic, roughness, emission as
//! `emissiveFactor` × `KHR_materials_emissive_strength`). Textures are not
//! written (the procedural worlds have none).

use std::borrow::Cow;
use std::collections::BTreeMap;
use std::path::Path;

use glam::{Mat3, Mat4, Vec3};
use gltf::json;
use json::validation::Checked::Valid;
use json::validation::USize64;

use crate::{Material, Mesh, Texture, World, WorldError, WorldErrorKind};

/// Extensions whose content is read; any other one used by a file is
/// reported in `World::warnings` and ignored.
pub const SUPPORTED_EXTENSIONS: [&str; 1] = ["KHR_materials_emissive_strength"];

/// Loads a `.gltf` or `.glb` file (relative buffers and images beside it).
pub fn load(path: &Path) -> Result<World, WorldError> {
    let file = path.display().to_string();
    let bytes = std::fs::read(path).map_err(|e| WorldError {
        file: file.clone(),
        kind: WorldErrorKind::Io(e.to_string()),
    })?;
    read(&bytes, &file, path.parent())
}

/// Loads a `.glb` or self-contained `.gltf` (data URIs) from memory;
/// `name` stands for the file in errors.
pub fn from_slice(bytes: &[u8], name: &str) -> Result<World, WorldError> {
    read(bytes, name, None)
}

fn read(bytes: &[u8], file: &str, base: Option<&Path>) -> Result<World, WorldError> {
    let err = |kind| WorldError {
        file: file.to_string(),
        kind,
    };
    let parse = |e: gltf::Error| err(WorldErrorKind::Parse(e.to_string()));
    // gltf 1.4 subtracts the 12-byte header from a GLB's declared length
    // unchecked (an overflow panic where overflow checks are on; found by
    // the fuzz smoke run in the dev profile).
    let declared = bytes
        .strip_prefix(b"glTF")
        .and_then(|b| b.get(4..8))
        .map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]));
    if let Some(n) = declared.filter(|&n| n < 12) {
        return Err(err(WorldErrorKind::Parse(format!(
            "the GLB header declares {n} bytes, less than the header itself"
        ))));
    }
    let gltf::Gltf { document, blob } =
        gltf::Gltf::from_slice_without_validation(bytes).map_err(parse)?;
    let document = validated(document).map_err(&err)?;
    let buffers = gltf::import_buffers(&document, base, blob).map_err(parse)?;
    let mut world = World::default();
    for ext in document.extensions_used() {
        if !SUPPORTED_EXTENSIONS.contains(&ext) {
            world
                .warnings
                .push(format!("{file}: extension {ext} ignored"));
        }
    }
    world.textures = read_textures(&document, base, &buffers).map_err(&err)?;
    world.materials = document.materials().map(|m| material(&m)).collect();
    let fallback = world.materials.len();
    let mut used_fallback = false;
    let mut seen = vec![false; document.nodes().len()];
    for (node, transform) in root_nodes(&document) {
        walk(&node, transform, &mut seen, &mut |n, m| {
            let Some(mesh) = n.mesh() else {
                return Ok(());
            };
            for p in mesh.primitives() {
                if let Some(out) = primitive(&p, &mesh, m, &buffers, &mut world.warnings, file)? {
                    let material = p.material().index().unwrap_or_else(|| {
                        used_fallback = true;
                        fallback
                    });
                    world.meshes.push(Mesh { material, ..out });
                }
            }
            Ok(())
        })
        .map_err(&err)?;
    }
    if used_fallback {
        world.materials.push(Material::default());
    }
    Ok(world)
}

/// The document after glTF's validation. Its POSITION check indexes the
/// accessors unchecked (gltf-json 1.4: a primitive naming an accessor that
/// does not exist panics; found by `himmel-fuzz gltf`), so those indices
/// are checked first.
fn validated(document: gltf::Document) -> Result<gltf::Document, WorldErrorKind> {
    let root = document.into_json();
    for (m, mesh) in root.meshes.iter().enumerate() {
        for (p, prim) in mesh.primitives.iter().enumerate() {
            let position = prim
                .attributes
                .get(&Valid(gltf::Semantic::Positions))
                .map(|i| i.value());
            if let Some(a) = position.filter(|&a| a >= root.accessors.len()) {
                return Err(WorldErrorKind::Parse(format!(
                    "mesh {m} primitive {p}: POSITION names accessor {a}, which does not exist"
                )));
            }
        }
    }
    gltf::Document::from_json(root).map_err(|e| WorldErrorKind::Parse(e.to_string()))
}

/// The root nodes to walk with their parents' transform: the default
/// scene's, else every scene's (each node once), else every node no other
/// node lists as a child.
fn root_nodes(doc: &gltf::Document) -> Vec<(gltf::Node<'_>, Mat4)> {
    let mut nodes: Vec<gltf::Node> = match doc.default_scene() {
        Some(s) => s.nodes().collect(),
        None if doc.scenes().len() > 0 => doc.scenes().flat_map(|s| s.nodes()).collect(),
        None => {
            let children: Vec<usize> = doc
                .nodes()
                .flat_map(|n| n.children().map(|c| c.index()))
                .collect();
            doc.nodes()
                .filter(|n| !children.contains(&n.index()))
                .collect()
        }
    };
    let mut listed = vec![false; doc.nodes().len()];
    nodes.retain(|n| !std::mem::replace(&mut listed[n.index()], true));
    nodes.into_iter().map(|n| (n, Mat4::IDENTITY)).collect()
}

/// Calls `f` on `node` and its descendants with their world transforms.
/// `seen` marks the nodes walked so far: a node reached a second time (a
/// cycle, or a second parent, which glTF forbids) is an error, so that no
/// hierarchy is walked more than once per node; nesting stops at 64
/// levels.
fn walk(
    node: &gltf::Node,
    parent: Mat4,
    seen: &mut [bool],
    f: &mut dyn FnMut(&gltf::Node, Mat4) -> Result<(), WorldErrorKind>,
) -> Result<(), WorldErrorKind> {
    fn go(
        node: &gltf::Node,
        parent: Mat4,
        depth: usize,
        seen: &mut [bool],
        f: &mut dyn FnMut(&gltf::Node, Mat4) -> Result<(), WorldErrorKind>,
    ) -> Result<(), WorldErrorKind> {
        let i = node.index();
        if depth > 64 {
            return Err(WorldErrorKind::Parse(format!(
                "node {i} is nested more than 64 levels deep"
            )));
        }
        if seen.get(i).copied().unwrap_or(true) {
            return Err(WorldErrorKind::Parse(format!(
                "node {i} is reached twice in the node hierarchy (a cycle or a second parent)"
            )));
        }
        seen[i] = true;
        let m = parent * Mat4::from_cols_array_2d(&node.transform().matrix());
        f(node, m)?;
        for c in node.children() {
            go(&c, m, depth + 1, seen, f)?;
        }
        Ok(())
    }
    go(node, parent, 0, seen, f)
}

/// Checks that accessor `a` lies within its buffer view and buffer.
fn check_accessor(
    a: &gltf::Accessor,
    buffers: &[gltf::buffer::Data],
) -> Result<(), WorldErrorKind> {
    let bad = |message: String| WorldErrorKind::Accessor {
        accessor: a.index(),
        message,
    };
    if a.sparse().is_some() {
        return Err(bad("sparse accessors are not supported".into()));
    }
    let Some(view) = a.view() else {
        return Err(bad("has no buffer view".into()));
    };
    let buffer = buffers
        .get(view.buffer().index())
        .ok_or_else(|| bad(format!("buffer {} is missing", view.buffer().index())))?;
    let view_end = view.offset().checked_add(view.length());
    if !view_end.is_some_and(|e| e <= buffer.len()) {
        return Err(bad(format!(
            "its buffer view {} ends past the {} bytes of buffer {}",
            view.index(),
            buffer.len(),
            view.buffer().index()
        )));
    }
    let size = a.size();
    let stride = view.stride().unwrap_or(size);
    if a.count() > 0 {
        let end = (a.count() - 1)
            .checked_mul(stride)
            .and_then(|v| v.checked_add(a.offset()))
            .and_then(|v| v.checked_add(size));
        if !end.is_some_and(|e| e <= view.length()) {
            return Err(bad(format!(
                "{} elements of {size} bytes at offset {} do not fit buffer view {} ({} bytes)",
                a.count(),
                a.offset(),
                view.index(),
                view.length()
            )));
        }
    }
    Ok(())
}

/// One primitive as a mesh in world coordinates (material not yet set),
/// or `None` when it is skipped (points, lines: with a warning).
fn primitive(
    p: &gltf::Primitive,
    mesh: &gltf::Mesh,
    m: Mat4,
    buffers: &[gltf::buffer::Data],
    warnings: &mut Vec<String>,
    file: &str,
) -> Result<Option<Mesh>, WorldErrorKind> {
    use gltf::mesh::Mode;
    let mode = p.mode();
    if !matches!(
        mode,
        Mode::Triangles | Mode::TriangleStrip | Mode::TriangleFan
    ) {
        warnings.push(format!(
            "{file}: mesh {} primitive {}: {mode:?} skipped (only triangles are drawn)",
            mesh.index(),
            p.index()
        ));
        return Ok(None);
    }
    let positions = p.get(&gltf::Semantic::Positions).ok_or_else(|| {
        WorldErrorKind::Parse(format!(
            "mesh {} primitive {} has no POSITION",
            mesh.index(),
            p.index()
        ))
    })?;
    // The formats glTF allows for each use: the reader assumes them (it
    // panics on an index or texture-coordinate type outside them; found by
    // `himmel-fuzz gltf`) and reinterprets positions and normals.
    use gltf::accessor::{DataType as D, Dimensions as V};
    let uses = [
        (Some(positions.clone()), "POSITION", &[D::F32][..], V::Vec3),
        (
            p.get(&gltf::Semantic::Normals),
            "NORMAL",
            &[D::F32],
            V::Vec3,
        ),
        (
            p.get(&gltf::Semantic::TexCoords(0)),
            "TEXCOORD_0",
            &[D::F32, D::U8, D::U16],
            V::Vec2,
        ),
        (p.indices(), "indices", &[D::U8, D::U16, D::U32], V::Scalar),
    ];
    for (a, name, types, dims) in uses {
        let Some(a) = a else { continue };
        check_accessor(&a, buffers)?;
        if !types.contains(&a.data_type()) || a.dimensions() != dims {
            return Err(WorldErrorKind::Accessor {
                accessor: a.index(),
                message: format!(
                    "{name} must be {dims:?} of {types:?}, not {:?} of {:?}",
                    a.dimensions(),
                    a.data_type()
                ),
            });
        }
    }
    let reader = p.reader(|b| buffers.get(b.index()).map(|d| &d.0[..]));
    let n = positions.count();
    let pos: Vec<Vec3> = reader
        .read_positions()
        .map(|it| {
            it.map(|v| m.transform_point3(Vec3::from_array(v)))
                .collect()
        })
        .unwrap_or_default();
    let normal_m = Mat3::from_mat4(m).inverse().transpose();
    let normals: Option<Vec<[f32; 3]>> = reader.read_normals().map(|it| {
        it.map(|v| {
            (normal_m * Vec3::from_array(v))
                .normalize_or_zero()
                .to_array()
        })
        .collect()
    });
    let uvs: Vec<[f32; 2]> = reader
        .read_tex_coords(0)
        .map(|t| t.into_f32().collect())
        .unwrap_or_else(|| vec![[0.0; 2]; n]);
    let raw: Vec<u32> = match reader.read_indices() {
        Some(i) => i.into_u32().collect(),
        None => (0..n as u32).collect(),
    };
    if let Some(&bad) = raw.iter().find(|&&i| i as usize >= n) {
        return Err(WorldErrorKind::Index {
            mesh: mesh.index(),
            primitive: p.index(),
            index: bad,
            vertices: n,
        });
    }
    let mut indices = triangle_list(mode, &raw);
    // A mirroring transform turns the triangles' winding inside out.
    if Mat3::from_mat4(m).determinant() < 0.0 {
        for t in indices.chunks_exact_mut(3) {
            t.swap(1, 2);
        }
    }
    let positions: Vec<[f32; 3]> = pos.iter().map(|p| p.to_array()).collect();
    let normals = match normals {
        Some(nr) if nr.len() == n => nr,
        _ => vertex_normals(&positions, &indices),
    };
    Ok(Some(Mesh {
        positions,
        normals,
        uvs,
        indices,
        material: 0,
    }))
}

/// Triangle-list indices of a list, strip or fan.
fn triangle_list(mode: gltf::mesh::Mode, raw: &[u32]) -> Vec<u32> {
    use gltf::mesh::Mode;
    match mode {
        Mode::TriangleStrip => (0..raw.len().saturating_sub(2))
            .flat_map(|i| {
                if i % 2 == 0 {
                    [raw[i], raw[i + 1], raw[i + 2]]
                } else {
                    [raw[i + 1], raw[i], raw[i + 2]]
                }
            })
            .collect(),
        Mode::TriangleFan => (1..raw.len().saturating_sub(1))
            .flat_map(|i| [raw[0], raw[i], raw[i + 1]])
            .collect(),
        _ => raw[..raw.len() / 3 * 3].to_vec(),
    }
}

/// Area-weighted vertex normals of a triangle list (for primitives
/// without NORMAL).
pub fn vertex_normals(positions: &[[f32; 3]], indices: &[u32]) -> Vec<[f32; 3]> {
    let mut acc = vec![Vec3::ZERO; positions.len()];
    for t in indices.chunks_exact(3) {
        let p = |i: u32| Vec3::from_array(positions[i as usize]);
        let n = (p(t[1]) - p(t[0])).cross(p(t[2]) - p(t[0]));
        for &i in t {
            acc[i as usize] += n;
        }
    }
    acc.into_iter()
        .map(|n| n.normalize_or(Vec3::Y).to_array())
        .collect()
}

fn material(m: &gltf::Material) -> Material {
    let pbr = m.pbr_metallic_roughness();
    let strength = m.emissive_strength().unwrap_or(1.0);
    Material {
        name: m.name().map(str::to_string),
        base_color: pbr.base_color_factor(),
        base_color_texture: pbr
            .base_color_texture()
            .map(|t| t.texture().source().index()),
        metallic: pbr.metallic_factor(),
        roughness: pbr.roughness_factor(),
        emissive: m.emissive_factor().map(|e| e * strength),
    }
}

/// The sRGB transfer function inverted (IEC 61966-2-1).
fn srgb_to_linear(c: u8) -> f32 {
    let c = c as f32 / 255.0;
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

/// Every image of the file decoded to linear RGBA (indexed like the
/// file's images; base-colour textures are sRGB-encoded).
fn read_textures(
    doc: &gltf::Document,
    base: Option<&Path>,
    buffers: &[gltf::buffer::Data],
) -> Result<Vec<Texture>, WorldErrorKind> {
    if doc.images().len() == 0 {
        return Ok(Vec::new());
    }
    let images = gltf::import_images(doc, base, buffers)
        .map_err(|e| WorldErrorKind::Parse(format!("image: {e}")))?;
    use gltf::image::Format;
    Ok(images
        .into_iter()
        .map(|d| {
            let px = &d.pixels;
            let texels = match d.format {
                Format::R8G8B8A8 => px
                    .chunks_exact(4)
                    .map(|c| {
                        let l = |v| srgb_to_linear(v);
                        [l(c[0]), l(c[1]), l(c[2]), c[3] as f32 / 255.0]
                    })
                    .collect(),
                Format::R8G8B8 => px
                    .chunks_exact(3)
                    .map(|c| {
                        [
                            srgb_to_linear(c[0]),
                            srgb_to_linear(c[1]),
                            srgb_to_linear(c[2]),
                            1.0,
                        ]
                    })
                    .collect(),
                Format::R8 => px
                    .iter()
                    .map(|&c| {
                        let v = srgb_to_linear(c);
                        [v, v, v, 1.0]
                    })
                    .collect(),
                // 16-bit and float images: white (base-colour textures are
                // 8-bit in practice).
                _ => vec![[1.0; 4]; (d.width * d.height) as usize],
            };
            Texture {
                width: d.width,
                height: d.height,
                texels,
            }
        })
        .collect())
}

/// The world as a binary glTF (`.glb`) file.
pub fn to_glb(world: &World) -> Vec<u8> {
    let mut root = json::Root::default();
    let mut bin: Vec<u8> = Vec::new();
    let buffer = root.push(json::Buffer {
        byte_length: USize64(0),
        extensions: Default::default(),
        extras: Default::default(),
        name: None,
        uri: None,
    });
    let view = |bin: &mut Vec<u8>, root: &mut json::Root, bytes: &[u8], target| {
        while bin.len() % 4 != 0 {
            bin.push(0);
        }
        let offset = bin.len();
        bin.extend_from_slice(bytes);
        root.push(json::buffer::View {
            buffer,
            byte_length: USize64::from(bytes.len()),
            byte_offset: Some(USize64::from(offset)),
            byte_stride: None,
            extensions: Default::default(),
            extras: Default::default(),
            name: None,
            target: Some(Valid(target)),
        })
    };
    let materials: Vec<json::Index<json::Material>> = world
        .materials
        .iter()
        .map(|m| root.push(material_json(m)))
        .collect();
    let mut nodes = Vec::new();
    for mesh in &world.meshes {
        let f32s = |v: &[f32]| v.iter().flat_map(|x| x.to_le_bytes()).collect::<Vec<u8>>();
        let flat3: Vec<f32> = mesh.positions.iter().flatten().copied().collect();
        let (min, max) = world_min_max(&mesh.positions);
        let array = json::buffer::Target::ArrayBuffer;
        let pv = view(&mut bin, &mut root, &f32s(&flat3), array);
        let normals: Vec<f32> = mesh.normals.iter().flatten().copied().collect();
        let nv = view(&mut bin, &mut root, &f32s(&normals), array);
        let uvs: Vec<f32> = mesh.uvs.iter().flatten().copied().collect();
        let uv = view(&mut bin, &mut root, &f32s(&uvs), array);
        let idx: Vec<u8> = mesh.indices.iter().flat_map(|i| i.to_le_bytes()).collect();
        let iv = view(
            &mut bin,
            &mut root,
            &idx,
            json::buffer::Target::ElementArrayBuffer,
        );
        let n = mesh.positions.len();
        let accessor = |root: &mut json::Root, view, count, ty, component, bounds| {
            let (min, max): (Option<json::Value>, Option<json::Value>) = match bounds {
                Some((a, b)) => (
                    Some(json::Value::from(Vec::from(a))),
                    Some(json::Value::from(Vec::from(b))),
                ),
                None => (None, None),
            };
            root.push(json::Accessor {
                buffer_view: Some(view),
                byte_offset: Some(USize64(0)),
                count: USize64::from(count),
                component_type: Valid(json::accessor::GenericComponentType(component)),
                extensions: Default::default(),
                extras: Default::default(),
                type_: Valid(ty),
                min,
                max,
                name: None,
                normalized: false,
                sparse: None,
            })
        };
        use json::accessor::{ComponentType as C, Type as T};
        let pa = accessor(&mut root, pv, n, T::Vec3, C::F32, Some((min, max)));
        let na = accessor(&mut root, nv, n, T::Vec3, C::F32, None);
        let ua = accessor(&mut root, uv, n, T::Vec2, C::F32, None);
        let ia = accessor(&mut root, iv, mesh.indices.len(), T::Scalar, C::U32, None);
        let mut attributes = BTreeMap::new();
        attributes.insert(Valid(json::mesh::Semantic::Positions), pa);
        attributes.insert(Valid(json::mesh::Semantic::Normals), na);
        attributes.insert(Valid(json::mesh::Semantic::TexCoords(0)), ua);
        let m = root.push(json::Mesh {
            extensions: Default::default(),
            extras: Default::default(),
            name: None,
            primitives: vec![json::mesh::Primitive {
                attributes,
                extensions: Default::default(),
                extras: Default::default(),
                indices: Some(ia),
                material: materials.get(mesh.material).copied(),
                mode: Valid(json::mesh::Mode::Triangles),
                targets: None,
            }],
            weights: None,
        });
        nodes.push(root.push(json::Node {
            mesh: Some(m),
            ..Default::default()
        }));
    }
    let scene = root.push(json::Scene {
        extensions: Default::default(),
        extras: Default::default(),
        name: None,
        nodes,
    });
    root.scene = Some(scene);
    if world
        .materials
        .iter()
        .any(|m| m.emissive.iter().any(|&e| e > 1.0))
    {
        root.extensions_used
            .push("KHR_materials_emissive_strength".to_string());
    }
    while bin.len() % 4 != 0 {
        bin.push(0);
    }
    root.buffers[0].byte_length = USize64::from(bin.len());
    let json_text = json::serialize::to_string(&root).unwrap_or_default();
    let mut json_bytes = json_text.into_bytes();
    while json_bytes.len() % 4 != 0 {
        json_bytes.push(b' ');
    }
    let length = 12 + 8 + json_bytes.len() + 8 + bin.len();
    let glb = gltf::binary::Glb {
        header: gltf::binary::Header {
            magic: *b"glTF",
            version: 2,
            length: length as u32,
        },
        json: Cow::Owned(json_bytes),
        bin: Some(Cow::Owned(bin)),
    };
    glb.to_vec().unwrap_or_default()
}

fn world_min_max(p: &[[f32; 3]]) -> ([f32; 3], [f32; 3]) {
    match crate::Aabb::around(p) {
        Some(b) => (b.min.to_array(), b.max.to_array()),
        None => ([0.0; 3], [0.0; 3]),
    }
}

fn material_json(m: &Material) -> json::Material {
    use json::material::{
        EmissiveFactor, PbrBaseColorFactor, PbrMetallicRoughness, StrengthFactor,
    };
    let peak = m.emissive.iter().fold(0.0f32, |a, &b| a.max(b));
    let (factor, strength) = if peak > 1.0 {
        (m.emissive.map(|e| e / peak), Some(peak))
    } else {
        (m.emissive, None)
    };
    json::Material {
        name: m.name.clone(),
        pbr_metallic_roughness: PbrMetallicRoughness {
            base_color_factor: PbrBaseColorFactor(m.base_color),
            metallic_factor: StrengthFactor(m.metallic),
            roughness_factor: StrengthFactor(m.roughness),
            ..Default::default()
        },
        emissive_factor: EmissiveFactor(factor),
        extensions: strength.map(|s| json::extensions::material::Material {
            emissive_strength: Some(json::extensions::material::EmissiveStrength {
                emissive_strength: json::extensions::material::EmissiveStrengthFactor(s),
            }),
        }),
        ..Default::default()
    }
}
