//! Uniform data shared with the WGSL shaders: `#[repr(C)]` Pod mirrors of
//! the WGSL structs, field for field (vec4-sized fields only, so that the
//! Rust and WGSL uniform layouts coincide without padding rules).

use bytemuck::{Pod, Zeroable};

/// Projection codes of `Frame.size.z` (src/shaders/frame.wgsl).
pub mod projection_code {
    /// All-sky azimuthal equidistant.
    pub const FISHEYE: u32 = 0;
    /// Equirectangular.
    pub const EQUIRECT: u32 = 1;
    /// Pinhole perspective.
    pub const PERSPECTIVE: u32 = 2;
    /// Cube map (6H×H strip; six layers in the target texture).
    pub const CUBEMAP: u32 = 3;
}

/// Mirror of WGSL `struct Frame` (src/shaders/frame.wgsl): per-frame
/// camera, Sun and table parameters. 176 bytes.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct FrameUniforms {
    /// Image width, height (the 6H×H strip for a cube map), projection
    /// code ([`projection_code`]), cube face size H.
    pub size: [u32; 4],
    /// Perspective forward vector (ENU); w = tan(fov / 2).
    pub persp_f: [f32; 4],
    /// Perspective right vector (ENU).
    pub persp_r: [f32; 4],
    /// Perspective up vector (ENU).
    pub persp_u: [f32; 4],
    /// Sun centre direction (ENU, unit); w = cos of the supersampling margin.
    pub sun: [f32; 4],
    /// cos(disk radius), sin(disk radius), z_min, z_max of the Sun table.
    pub disk: [f32; 4],
    /// Sky-view LUT width, height; Sun table ρ nodes, z nodes.
    pub tables: [u32; 4],
    /// Sun sub-samples per axis; first pixel x, y of the Sun dispatch; reserved.
    pub opts: [u32; 4],
    /// The band of rows of this dispatch: first row, row count; reserved.
    pub band: [u32; 4],
    /// The Moon's centre direction (ENU, unit); w = 1 when the sky holds
    /// the moonlit sky view (a second LUT after the Sun's), 0 otherwise.
    pub moon: [f32; 4],
    /// The Moon's centre direction (ENU, unit) and the sine of its drawn
    /// radius: the Sun pass hides the sub-samples behind it.
    pub eclipse: [f32; 4],
}

/// Mirror of WGSL `struct Atmo` (src/shaders/skyview.wgsl): the medium,
/// band weights and sky-view geometry of the GPU sky-view LUT. Spectra
/// (10 bands) are three vec4 band groups, the last two lanes zero. 480 bytes.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct AtmosphereUniforms {
    /// Rayleigh scattering at sea level, km⁻¹.
    pub rayleigh: [[f32; 4]; 3],
    /// Aerosol scattering at sea level, km⁻¹.
    pub mie_scattering: [[f32; 4]; 3],
    /// Aerosol extinction at sea level, km⁻¹.
    pub mie_extinction: [[f32; 4]; 3],
    /// Ozone absorption at the peak, km⁻¹.
    pub ozone: [[f32; 4]; 3],
    /// δ-scaled forward scattering f·σ_M, km⁻¹.
    pub forward: [[f32; 4]; 3],
    /// Band → linear sRGB red weights, lux.
    pub w_r: [[f32; 4]; 3],
    /// Band → green weights, lux.
    pub w_g: [[f32; 4]; 3],
    /// Band → blue weights, lux.
    pub w_b: [[f32; 4]; 3],
    /// Ground radius, top radius (km), 1/H_R, 1/H_M (km⁻¹).
    pub s0: [f32; 4],
    /// Ozone peak altitude (km), 1/ozone half width (km⁻¹), g, albedo.
    pub s1: [f32; 4],
    /// Sun angular radius (rad), observer radius r0 (km), cos of the
    /// forward peak, 1 when the forward peak is on.
    pub s2: [f32; 4],
    /// Local Sun direction (x, 0, z); irradiance scale.
    pub sun: [f32; 4],
    /// Transmittance LUT w, h; multiple-scattering LUT n; march steps.
    pub dims: [u32; 4],
    /// Sky-view LUT w, h; reserved.
    pub dims2: [u32; 4],
}

/// Mirror of WGSL `struct Night` (src/shaders/frame.wgsl): the per-frame
/// constants of the Milky Way pass (skymodel milkyway.rs
/// `NightBackground`) and of the point-source passes. 160 bytes.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct NightUniforms {
    /// First row of the ENU → ICRS rotation; w = sin ε (J2000 obliquity).
    pub enu_to_icrs_x: [f32; 4],
    /// Second row; w = cos ε.
    pub enu_to_icrs_y: [f32; 4],
    /// Third row; w = (R / (R + h))² of the airglow layer (van Rhijn).
    pub enu_to_icrs_z: [f32; 4],
    /// Airglow at the zenith, linear sRGB cd/m².
    pub airglow: [f32; 4],
    /// Zodiacal light per S10, linear sRGB cd/m².
    pub zodiacal: [f32; 4],
    /// Faint-star floor, linear sRGB cd/m².
    pub floor: [f32; 4],
    /// Milky Way map width, height; extinction table nodes; reserved.
    pub dims: [u32; 4],
    /// Point sources: tile size (px), tiles per row, first word of the
    /// stars' and of the planets' tile lists.
    pub tiles: [u32; 4],
    /// Point sources: core radius r (px), reserved, 1 / (2σ²) (px⁻²), the
    /// scale of the quad target (a power of two; 1 for rgba32float).
    pub psf: [f32; 4],
    /// Point sources: first word of the stars' and of the planets'
    /// non-empty tile indices, and their numbers.
    pub busy: [u32; 4],
}

/// Mirror of WGSL `struct Point` (src/shaders/frame.wgsl): one point
/// source's footprint (`himmel_skymodel::stars::SplatPlan`). 48 bytes.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct PointRecord {
    /// Position cx, cy (px), core scale (lux), glare radius (px; 0: none).
    pub a: [f32; 4],
    /// Colour (linear sRGB, luminance 1), glare scale (lux).
    pub b: [f32; 4],
    /// ⌊cx⌋, ⌊cy⌋, cube face, 1 when checked against the ground.
    pub c: [i32; 4],
}

/// Mirror of the header of WGSL `struct Moon` (src/shaders/moon.wgsl):
/// the Moon pass's per-frame constants (skymodel moon.rs `MoonShader`) and
/// the corona's; [`MOON_TABLE_ROWS`] vec4 table rows follow it in the
/// uniform buffer. 288 bytes.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct MoonUniforms {
    /// Disk centre (ENU, unit, refracted); w = drawn radius (rad).
    pub centre: [f32; 4],
    /// Celestial east at the (airless) centre; w = sin of the drawn radius.
    pub east: [f32; 4],
    /// Celestial north; w = 1 when pixel directions are un-refracted first.
    pub north: [f32; 4],
    /// Moon → Sun unit vector (sky frame); w = B(g) S(g) p/π.
    pub sun: [f32; 4],
    /// Selenographic X axis (sky frame); w = the pixel angle (rad).
    pub axis_x: [f32; 4],
    /// Selenographic Y axis; w = cosine bounding the disk with its margin.
    pub axis_y: [f32; 4],
    /// Selenographic Z axis (north pole); w reserved.
    pub axis_z: [f32; 4],
    /// Sunlight, linear sRGB; w = first extinction node (zenith cosine).
    pub sun_rgb: [f32; 4],
    /// Earthshine, linear sRGB; w = extinction node spacing.
    pub earth_rgb: [f32; 4],
    /// Lunar eclipse: offset from the shadow axis (east, north),
    /// geocentric semidiameter, axis distance of the last node (rad).
    pub eclipse: [f32; 4],
    /// Geocentric sky east in the sky frame; w = first refraction node
    /// (apparent altitude, rad).
    pub geo_e: [f32; 4],
    /// Geocentric sky north; w = refraction node spacing (rad).
    pub geo_n: [f32; 4],
    /// Extinction nodes, eclipse nodes (0: none), sub-samples per axis (0:
    /// analytic limb), refraction nodes.
    pub dims: [u32; 4],
    /// Albedo map width, height; normal map width, height.
    pub maps: [u32; 4],
    /// The disk's pixel rectangle x0, y0, x1, y1.
    pub rect: [u32; 4],
    /// The corona's pixel rectangle x0, y0, x1, y1.
    pub corona_rect: [u32; 4],
    /// Corona: cos of 6 R☉, the Sun's drawn radius, the Moon's drawn
    /// radius (rad), the camera's largest pixel angle.
    pub corona: [f32; 4],
    /// Corona table: first node, spacing (zenith cosine), nodes; the
    /// profile at 6 R☉.
    pub corona_z: [f32; 4],
}

/// Table rows after [`MoonUniforms`] (WGSL `Moon.tables`).
pub const MOON_TABLE_ROWS: usize = 304;
/// First row of the extinction table (at most 16 rows).
pub const MOON_EXT: usize = 0;
/// First row of the refraction table ([`MOON_REFR_N`] rows).
pub const MOON_REFR: usize = 16;
/// Rows of the refraction table.
pub const MOON_REFR_N: usize = 64;
/// First row of the eclipse table (`ECLIPSE_TABLE_N` = 160 rows).
pub const MOON_ECL: usize = 80;
/// First row of the corona table ([`MOON_COR_N`] rows).
pub const MOON_COR: usize = 240;
/// Rows of the corona table.
pub const MOON_COR_N: usize = 64;

// The tables do not overlap, the eclipse table fits, and the whole
// uniform fits the default 64 KiB uniform binding.
const _: () = assert!(MOON_REFR + MOON_REFR_N <= MOON_ECL);
const _: () = assert!(MOON_ECL + himmel_skymodel::moon::ECLIPSE_TABLE_N <= MOON_COR);
const _: () = assert!(MOON_COR + MOON_COR_N == MOON_TABLE_ROWS);
const _: () = assert!(std::mem::size_of::<MoonUniforms>() + 16 * MOON_TABLE_ROWS <= 65536);

// One WGSL module per pass: frame.wgsl (the group-0 bindings, the uniform
// structs and the projection helpers every image pass uses) followed by the
// pass's file and what it calls. `concat!` takes literals only, hence the
// repeated `include_str!`.

/// The atmosphere pass: frame.wgsl, atmosphere.wgsl and the bilinear
/// lookup it shares with the LUT passes (bilinear.wgsl).
pub const ATMOSPHERE_WGSL: &str = concat!(
    include_str!("shaders/frame.wgsl"),
    include_str!("shaders/atmosphere.wgsl"),
    include_str!("shaders/bilinear.wgsl")
);

/// The Sun pass: frame.wgsl and sun.wgsl.
pub const SUN_WGSL: &str = concat!(
    include_str!("shaders/frame.wgsl"),
    include_str!("shaders/sun.wgsl")
);

/// The Milky Way pass: frame.wgsl and milkyway.wgsl.
pub const MILKYWAY_WGSL: &str = concat!(
    include_str!("shaders/frame.wgsl"),
    include_str!("shaders/milkyway.wgsl")
);

/// The tiled point-source passes (stars, planets): frame.wgsl and
/// points.wgsl.
pub const POINTS_WGSL: &str = concat!(
    include_str!("shaders/frame.wgsl"),
    include_str!("shaders/points.wgsl")
);

/// The store pass: frame.wgsl and store.wgsl.
pub const STORE_WGSL: &str = concat!(
    include_str!("shaders/frame.wgsl"),
    include_str!("shaders/store.wgsl")
);

/// The Moon and corona passes: frame.wgsl and moon.wgsl (its own bind
/// group 1).
pub const MOON_WGSL: &str = concat!(
    include_str!("shaders/frame.wgsl"),
    include_str!("shaders/moon.wgsl")
);

/// The point sources as instanced quads: frame.wgsl, points.wgsl (the
/// footprint and tile helpers) and quads.wgsl (the quad target in bind
/// group 1).
pub const QUADS_WGSL: &str = concat!(
    include_str!("shaders/frame.wgsl"),
    include_str!("shaders/points.wgsl"),
    include_str!("shaders/quads.wgsl")
);

/// The WGSL source of the sky-view LUT passes: `skyview.wgsl` followed by
/// the medium functions it shares with the LUT passes (`medium.wgsl`).
pub const SKYVIEW_WGSL: &str = concat!(
    include_str!("shaders/skyview.wgsl"),
    include_str!("shaders/medium.wgsl"),
    include_str!("shaders/bilinear.wgsl")
);

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use std::mem::{align_of, offset_of, size_of};

    /// The WGSL struct `name` in `wgsl` has naga's size `size` and the
    /// members `rust` (name, byte offset) in order: the uniform-address-space
    /// layout of a `#[repr(C)]` mirror.
    pub(crate) fn assert_wgsl_layout(wgsl: &str, name: &str, size: usize, rust: &[(&str, usize)]) {
        let module = naga::front::wgsl::parse_str(wgsl).expect("WGSL parses");
        let mut layouter = naga::proc::Layouter::default();
        layouter.update(module.to_ctx()).expect("layout");
        let (handle, ty) = module
            .types
            .iter()
            .find(|(_, t)| t.name.as_deref() == Some(name))
            .unwrap_or_else(|| panic!("struct {name}"));
        let naga::TypeInner::Struct { members, span } = &ty.inner else {
            panic!("{name} is not a struct");
        };
        assert_eq!(*span as usize, size, "{name}");
        assert_eq!(layouter[handle].size as usize, size, "{name}");
        assert_eq!(members.len(), rust.len(), "{name}");
        for (m, (field, off)) in members.iter().zip(rust) {
            assert_eq!(m.name.as_deref(), Some(*field), "{name}");
            assert_eq!(m.offset as usize, *off, "{name}.{field}");
        }
    }

    /// The Rust struct's size and field offsets equal the layout naga
    /// computes for the WGSL `Frame` (uniform address space rules).
    #[test]
    fn frame_uniforms_mirror_the_wgsl_struct() {
        assert_eq!(size_of::<FrameUniforms>(), 176);
        assert_eq!(align_of::<FrameUniforms>(), 4);
        let rust = [
            ("size", offset_of!(FrameUniforms, size)),
            ("persp_f", offset_of!(FrameUniforms, persp_f)),
            ("persp_r", offset_of!(FrameUniforms, persp_r)),
            ("persp_u", offset_of!(FrameUniforms, persp_u)),
            ("sun", offset_of!(FrameUniforms, sun)),
            ("disk", offset_of!(FrameUniforms, disk)),
            ("tables", offset_of!(FrameUniforms, tables)),
            ("opts", offset_of!(FrameUniforms, opts)),
            ("band", offset_of!(FrameUniforms, band)),
            ("moon", offset_of!(FrameUniforms, moon)),
            ("eclipse", offset_of!(FrameUniforms, eclipse)),
        ];
        assert_wgsl_layout(STORE_WGSL, "Frame", size_of::<FrameUniforms>(), &rust);
    }

    #[test]
    fn night_uniforms_mirror_the_wgsl_struct() {
        assert_eq!(size_of::<NightUniforms>(), 160);
        let rust = [
            ("enu_to_icrs_x", offset_of!(NightUniforms, enu_to_icrs_x)),
            ("enu_to_icrs_y", offset_of!(NightUniforms, enu_to_icrs_y)),
            ("enu_to_icrs_z", offset_of!(NightUniforms, enu_to_icrs_z)),
            ("airglow", offset_of!(NightUniforms, airglow)),
            ("zodiacal", offset_of!(NightUniforms, zodiacal)),
            ("floor", offset_of!(NightUniforms, floor)),
            ("dims", offset_of!(NightUniforms, dims)),
            ("tiles", offset_of!(NightUniforms, tiles)),
            ("psf", offset_of!(NightUniforms, psf)),
            ("busy", offset_of!(NightUniforms, busy)),
        ];
        assert_wgsl_layout(STORE_WGSL, "Night", size_of::<NightUniforms>(), &rust);
    }

    /// `PointRecord` has the size and offsets naga computes for `Point`.
    #[test]
    fn point_record_mirrors_the_wgsl_struct() {
        assert_eq!(size_of::<PointRecord>(), 48);
        let rust = [
            ("a", offset_of!(PointRecord, a)),
            ("b", offset_of!(PointRecord, b)),
            ("c", offset_of!(PointRecord, c)),
        ];
        assert_wgsl_layout(STORE_WGSL, "Point", size_of::<PointRecord>(), &rust);
    }

    #[test]
    fn atmosphere_uniforms_mirror_the_wgsl_struct() {
        assert_eq!(size_of::<AtmosphereUniforms>(), 480);
        let rust = [
            ("rayleigh", offset_of!(AtmosphereUniforms, rayleigh)),
            (
                "mie_scattering",
                offset_of!(AtmosphereUniforms, mie_scattering),
            ),
            (
                "mie_extinction",
                offset_of!(AtmosphereUniforms, mie_extinction),
            ),
            ("ozone", offset_of!(AtmosphereUniforms, ozone)),
            ("forward", offset_of!(AtmosphereUniforms, forward)),
            ("w_r", offset_of!(AtmosphereUniforms, w_r)),
            ("w_g", offset_of!(AtmosphereUniforms, w_g)),
            ("w_b", offset_of!(AtmosphereUniforms, w_b)),
            ("s0", offset_of!(AtmosphereUniforms, s0)),
            ("s1", offset_of!(AtmosphereUniforms, s1)),
            ("s2", offset_of!(AtmosphereUniforms, s2)),
            ("sun", offset_of!(AtmosphereUniforms, sun)),
            ("dims", offset_of!(AtmosphereUniforms, dims)),
            ("dims2", offset_of!(AtmosphereUniforms, dims2)),
        ];
        assert_wgsl_layout(SKYVIEW_WGSL, "Atmo", size_of::<AtmosphereUniforms>(), &rust);
    }

    /// `MoonUniforms` and the table rows have the layout naga computes
    /// for `Moon`; the table offsets match the WGSL constants.
    #[test]
    fn moon_uniforms_mirror_the_wgsl_struct() {
        assert_eq!(size_of::<MoonUniforms>(), 288);
        let rust = [
            ("centre", offset_of!(MoonUniforms, centre)),
            ("east", offset_of!(MoonUniforms, east)),
            ("north", offset_of!(MoonUniforms, north)),
            ("sun", offset_of!(MoonUniforms, sun)),
            ("axis_x", offset_of!(MoonUniforms, axis_x)),
            ("axis_y", offset_of!(MoonUniforms, axis_y)),
            ("axis_z", offset_of!(MoonUniforms, axis_z)),
            ("sun_rgb", offset_of!(MoonUniforms, sun_rgb)),
            ("earth_rgb", offset_of!(MoonUniforms, earth_rgb)),
            ("eclipse", offset_of!(MoonUniforms, eclipse)),
            ("geo_e", offset_of!(MoonUniforms, geo_e)),
            ("geo_n", offset_of!(MoonUniforms, geo_n)),
            ("dims", offset_of!(MoonUniforms, dims)),
            ("maps", offset_of!(MoonUniforms, maps)),
            ("rect", offset_of!(MoonUniforms, rect)),
            ("corona_rect", offset_of!(MoonUniforms, corona_rect)),
            ("corona", offset_of!(MoonUniforms, corona)),
            ("corona_z", offset_of!(MoonUniforms, corona_z)),
            ("tables", size_of::<MoonUniforms>()),
        ];
        let size = size_of::<MoonUniforms>() + 16 * MOON_TABLE_ROWS;
        assert_wgsl_layout(MOON_WGSL, "Moon", size, &rust);
        // The table offsets of the WGSL constants.
        for (name, want) in [
            ("MOON_EXT", MOON_EXT),
            ("MOON_REFR", MOON_REFR),
            ("MOON_ECL", MOON_ECL),
            ("MOON_COR", MOON_COR),
        ] {
            let line = format!("const {name}: u32 = {want}u;");
            assert!(MOON_WGSL.contains(&line), "{line}");
        }
    }

    /// Every pass's module parses and validates on its own (naga, all
    /// checks; with all capabilities, and with none, as a baseline adapter
    /// offers) and holds the entry points its pipelines use.
    #[test]
    fn every_pass_module_validates() {
        let modules = [
            ("atmosphere", ATMOSPHERE_WGSL, &["atmosphere"][..]),
            ("sun", SUN_WGSL, &["sun"]),
            ("milkyway", MILKYWAY_WGSL, &["milkyway"]),
            ("points", POINTS_WGSL, &["stars", "planets"]),
            ("store", STORE_WGSL, &["store"]),
            ("moon", MOON_WGSL, &["moon_disk", "corona"]),
            (
                "quads",
                QUADS_WGSL,
                &[
                    "stars",
                    "planets",
                    "quad_vs",
                    "quad_clear_vs",
                    "quad_clear_fs",
                    "quad_fs",
                    "quad_resolve_stars",
                    "quad_resolve_planets",
                ],
            ),
            ("skyview", SKYVIEW_WGSL, &["sky_view", "ground"]),
            (
                "luts",
                crate::luts::LUTS_WGSL,
                &["transmittance", "multiscatter"],
            ),
        ];
        for (name, wgsl, entries) in modules {
            let module = naga::front::wgsl::parse_str(wgsl)
                .unwrap_or_else(|e| panic!("{name}: {}", e.emit_to_string(wgsl)));
            for caps in [
                naga::valid::Capabilities::all(),
                naga::valid::Capabilities::empty(),
            ] {
                naga::valid::Validator::new(naga::valid::ValidationFlags::all(), caps)
                    .validate(&module)
                    .unwrap_or_else(|e| panic!("{name} ({caps:?}): {e:?}"));
            }
            let names: Vec<_> = module
                .entry_points
                .iter()
                .map(|e| e.name.as_str())
                .collect();
            assert_eq!(names, entries, "{name}");
        }
    }
}
