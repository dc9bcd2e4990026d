//! Uniform data shared with the WGSL shaders: `#[repr(C)]` Pod mirrors of
//! the WGSL structs, field for field. Every quantity has its own field; a
//! vec3 (`[f32; 3]`, alignment 16 and size 12 in the uniform address space)
//! is followed by a 4-byte scalar (a named quantity or a `_pad` field), and
//! every struct's size is a multiple of 16, so that the Rust and WGSL
//! layouts coincide (the tests compare them with naga's).

use bytemuck::{Pod, Zeroable};

/// Projection codes of `Frame.projection` (src/shaders/frame.wgsl).
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
/// camera, Sun and table parameters, per band of rows. 160 bytes.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct FrameUniforms {
    /// Image width, px (the 6H×H strip for a cube map).
    pub width: u32,
    /// Image height, px.
    pub height: u32,
    /// Projection code ([`projection_code`]).
    pub projection: u32,
    /// Cube face size H, px.
    pub face_size: u32,
    /// Perspective camera's forward vector (ENU, unit).
    pub forward: [f32; 3],
    /// tan of half the perspective camera's vertical field of view.
    pub tan_half_fov: f32,
    /// Perspective camera's right vector (ENU, unit).
    pub right: [f32; 3],
    /// Padding (the vec3 `up` starts at a multiple of 16).
    pub _pad0: f32,
    /// Perspective camera's up vector (ENU, unit).
    pub up: [f32; 3],
    /// Padding.
    pub _pad1: f32,
    /// The Sun's centre (ENU, unit).
    pub sun: [f32; 3],
    /// cos of the Sun pass's supersampling margin around the centre.
    pub cos_sun_margin: f32,
    /// The direction the moonlit sky view is lit from: the Moon's centre
    /// (ENU, unit; zero when [`Self::moonlit`] is 0).
    pub moonlight: [f32; 3],
    /// 1 when the sky buffer also holds the moonlit sky view (a second
    /// LUT after the Sun's), 0 otherwise.
    pub moonlit: u32,
    /// Solar eclipses: the Moon's centre (ENU, unit); the Sun pass hides
    /// the sub-samples behind its disk.
    pub eclipse_moon: [f32; 3],
    /// Sine of the Moon's drawn radius.
    pub sin_moon_radius: f32,
    /// Sine of the Sun's drawn radius.
    pub sin_sun_radius: f32,
    /// Line-of-sight zenith cosine of the Sun table's first z node.
    pub sun_z_min: f32,
    /// Line-of-sight zenith cosine of the Sun table's last z node.
    pub sun_z_max: f32,
    /// Sun sub-samples per pixel axis.
    pub sun_subsamples: u32,
    /// Sun table nodes in ρ (normalised disk radius).
    pub sun_rho_nodes: u32,
    /// Sun table nodes in z.
    pub sun_z_nodes: u32,
    /// First pixel column of the Sun dispatch's rectangle.
    pub sun_x0: u32,
    /// First pixel row of the Sun dispatch's rectangle in this band.
    pub sun_y0: u32,
    /// Sky-view LUT width, texels.
    pub sky_view_width: u32,
    /// Sky-view LUT height, texels.
    pub sky_view_height: u32,
    /// First image row of this dispatch's band.
    pub band_first_row: u32,
    /// Rows in this dispatch's band.
    pub band_rows: u32,
}

/// Mirror of WGSL `struct Atmo` (src/shaders/atmo.wgsl): the medium,
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
    /// Local Sun direction (x, 0, z; unit; lut.rs `SkyView::sun_local`).
    pub sun: [f32; 3],
    /// The light's irradiance scale (`SkyViewInput::irradiance_scale`).
    pub irradiance_scale: f32,
    /// Ground radius, km.
    pub bottom_radius: f32,
    /// Top-of-atmosphere radius, km.
    pub top_radius: f32,
    /// Inverse Rayleigh scale height, km⁻¹.
    pub inv_h_rayleigh: f32,
    /// Inverse aerosol scale height, km⁻¹.
    pub inv_h_mie: f32,
    /// Ozone peak altitude, km.
    pub ozone_peak: f32,
    /// Inverse ozone half width, km⁻¹.
    pub inv_ozone_width: f32,
    /// Aerosol asymmetry parameter g.
    pub mie_g: f32,
    /// Ground albedo.
    pub ground_albedo: f32,
    /// The Sun's angular radius, rad.
    pub sun_angular_radius: f32,
    /// The observer's radius r0, km.
    pub observer_radius: f32,
    /// cos of the forward peak's half angle.
    pub cos_forward_peak: f32,
    /// 1 when the aerosol phase is flattened within the forward peak, 0
    /// otherwise.
    pub forward_peak: u32,
    /// Transmittance LUT width, texels.
    pub transmittance_width: u32,
    /// Transmittance LUT height, texels.
    pub transmittance_height: u32,
    /// Multiple-scattering LUT size n (n × n texels).
    pub multiscatter_n: u32,
    /// Ray-march steps per sky-view texel.
    pub sky_view_steps: u32,
    /// Sky-view LUT width, texels.
    pub sky_view_width: u32,
    /// Sky-view LUT height, texels.
    pub sky_view_height: u32,
    /// Padding.
    pub _pad0: u32,
    /// Padding.
    pub _pad1: u32,
}

/// Mirror of WGSL `struct Night` (src/shaders/frame.wgsl): the per-frame
/// constants of the Milky Way pass (skymodel milkyway.rs
/// `NightBackground`) and of the point-source passes. 160 bytes.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct NightUniforms {
    /// First row of the ENU → ICRS rotation.
    pub enu_to_icrs_x: [f32; 3],
    /// sin ε (J2000 obliquity).
    pub sin_obliquity: f32,
    /// Second row of the ENU → ICRS rotation.
    pub enu_to_icrs_y: [f32; 3],
    /// cos ε.
    pub cos_obliquity: f32,
    /// Third row of the ENU → ICRS rotation.
    pub enu_to_icrs_z: [f32; 3],
    /// Padding.
    pub _pad0: f32,
    /// Airglow at the zenith, linear sRGB cd/m².
    pub airglow: [f32; 3],
    /// (R / (R + h))² of the airglow layer (van Rhijn).
    pub van_rhijn_k2: f32,
    /// Zodiacal light per S10, linear sRGB cd/m².
    pub zodiacal: [f32; 3],
    /// Padding.
    pub _pad1: f32,
    /// Faint-star floor, linear sRGB cd/m².
    pub floor: [f32; 3],
    /// Padding.
    pub _pad2: f32,
    /// Milky Way map width, texels.
    pub map_width: u32,
    /// Milky Way map height, texels.
    pub map_height: u32,
    /// Extinction table nodes.
    pub extinction_nodes: u32,
    /// Point sources: tile size, px ([`crate::POINT_TILE`]).
    pub tile_size: u32,
    /// Point sources: tiles per image row.
    pub tiles_per_row: u32,
    /// First word of the stars' tile list.
    pub star_list: u32,
    /// First word of the planets' tile list.
    pub planet_list: u32,
    /// First word of the stars' non-empty tile indices.
    pub star_busy_first: u32,
    /// First word of the planets' non-empty tile indices.
    pub planet_busy_first: u32,
    /// Number of the stars' non-empty tiles.
    pub star_busy_count: u32,
    /// Number of the planets' non-empty tiles.
    pub planet_busy_count: u32,
    /// Point sources: core radius r, px (an integer).
    pub core_radius: f32,
    /// Point sources: 1 / (2σ²) of the Gaussian core, px⁻².
    pub inv_two_sigma2: f32,
    /// Scale of the quad target (a power of two; 1 for rgba32float).
    pub quad_scale: f32,
    /// Padding.
    pub _pad3: f32,
    /// Padding.
    pub _pad4: f32,
}

/// Mirror of WGSL `struct Point` (src/shaders/frame.wgsl): one point
/// source's footprint (`himmel_skymodel::stars::SplatPlan`). 48 bytes.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct PointRecord {
    /// Position x, px (continuous image coordinates).
    pub x: f32,
    /// Position y, px.
    pub y: f32,
    /// Core scale, lux.
    pub core_scale: f32,
    /// Glare disk radius, px (0: none).
    pub glare_radius: f32,
    /// Colour, linear sRGB of luminance 1.
    pub colour: [f32; 3],
    /// Glare scale, lux.
    pub glare_scale: f32,
    /// ⌊x⌋, the pixel column holding the position.
    pub pixel_x: i32,
    /// ⌊y⌋.
    pub pixel_y: i32,
    /// Cube face (0 for the other projections).
    pub face: i32,
    /// 1 when the footprint is checked against the ground.
    pub near_horizon: u32,
}

/// Mirror of the header of WGSL `struct Moon` (src/shaders/moon.wgsl):
/// the Moon pass's per-frame constants (skymodel moon.rs `MoonShader`) and
/// the corona's; [`MOON_TABLE_ROWS`] vec4 table rows follow it in the
/// uniform buffer. 288 bytes.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct MoonUniforms {
    /// Disk centre (ENU, unit, refracted).
    pub centre: [f32; 3],
    /// Drawn radius, rad.
    pub radius: f32,
    /// Celestial east at the (airless) centre (sky frame, unit).
    pub east: [f32; 3],
    /// Sine of the drawn radius.
    pub sin_radius: f32,
    /// Celestial north at the (airless) centre (sky frame, unit).
    pub north: [f32; 3],
    /// 1 when pixel directions are un-refracted first, 0 otherwise.
    pub refract: u32,
    /// Moon → Sun unit vector (sky frame).
    pub sun: [f32; 3],
    /// B(g) S(g) p/π (moon.rs `MoonShaderParts::sun_factor`).
    pub sun_factor: f32,
    /// Selenographic X axis (sky frame, unit).
    pub axis_x: [f32; 3],
    /// The angle a pixel subtends at the disk, rad.
    pub pixel_angle: f32,
    /// Selenographic Y axis (sky frame, unit).
    pub axis_y: [f32; 3],
    /// Cosine of the disk's radius with its limb margin (the disk test).
    pub cos_bound: f32,
    /// Selenographic Z axis, the north pole (sky frame, unit).
    pub axis_z: [f32; 3],
    /// Padding.
    pub _pad0: f32,
    /// Sunlight at the Moon, linear sRGB.
    pub sun_rgb: [f32; 3],
    /// First node of the extinction table (line-of-sight zenith cosine).
    pub extinction_z0: f32,
    /// Earthshine, linear sRGB.
    pub earth_rgb: [f32; 3],
    /// Extinction table node spacing (zenith cosine).
    pub extinction_dz: f32,
    /// Geocentric sky east in the sky frame (unit).
    pub geo_east: [f32; 3],
    /// First node of the refraction table (apparent altitude, rad).
    pub refraction_alt0: f32,
    /// Geocentric sky north in the sky frame (unit).
    pub geo_north: [f32; 3],
    /// Refraction table node spacing, rad.
    pub refraction_dalt: f32,
    /// Lunar eclipse: the centre's offset from the shadow axis toward
    /// celestial east, rad.
    pub shadow_east: f32,
    /// The offset toward celestial north, rad.
    pub shadow_north: f32,
    /// The Moon's geocentric semidiameter, rad.
    pub semidiameter: f32,
    /// Axis distance of the eclipse table's last node, rad.
    pub shadow_last: f32,
    /// Extinction table nodes.
    pub extinction_nodes: u32,
    /// Eclipse table nodes (0: no eclipse shading).
    pub eclipse_nodes: u32,
    /// Refraction table nodes.
    pub refraction_nodes: u32,
    /// Sub-samples per pixel axis (0: analytic limb).
    pub subsamples: u32,
    /// Albedo map width, texels.
    pub albedo_width: u32,
    /// Albedo map height, texels.
    pub albedo_height: u32,
    /// Normal map width, texels.
    pub normal_width: u32,
    /// Normal map height, texels.
    pub normal_height: u32,
    /// The disk's pixel rectangle [x0, x1) × [y0, y1): x0.
    pub disk_x0: u32,
    /// y0.
    pub disk_y0: u32,
    /// x1.
    pub disk_x1: u32,
    /// y1.
    pub disk_y1: u32,
    /// The corona's pixel rectangle [x0, x1) × [y0, y1): x0.
    pub corona_x0: u32,
    /// y0.
    pub corona_y0: u32,
    /// x1.
    pub corona_x1: u32,
    /// y1.
    pub corona_y1: u32,
    /// cos of the corona's outer radius (6 R☉).
    pub corona_cos_outer: f32,
    /// The Sun's drawn radius, rad.
    pub corona_sun_radius: f32,
    /// The Moon's drawn radius, rad.
    pub corona_moon_radius: f32,
    /// The camera's largest pixel angle, rad.
    pub max_pixel_angle: f32,
    /// First node of the corona table (line-of-sight zenith cosine).
    pub corona_z0: f32,
    /// Corona table node spacing (zenith cosine).
    pub corona_dz: f32,
    /// Corona table nodes.
    pub corona_nodes: u32,
    /// Baumbach's profile at 6 R☉ (subtracted from the profile).
    pub corona_floor: f32,
}

impl MoonUniforms {
    /// The disk's pixel rectangle [x0, x1) × [y0, y1) as [x0, y0, x1, y1].
    pub fn disk_rect(&self) -> [u32; 4] {
        [self.disk_x0, self.disk_y0, self.disk_x1, self.disk_y1]
    }

    /// The corona's pixel rectangle [x0, x1) × [y0, y1) as [x0, y0, x1, y1].
    pub fn corona_rect(&self) -> [u32; 4] {
        [
            self.corona_x0,
            self.corona_y0,
            self.corona_x1,
            self.corona_y1,
        ]
    }
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
/// the atmosphere's uniforms and LUT lookups it shares with the clouds pass
/// (`atmo.wgsl`) and the medium functions it shares with the LUT passes
/// (`medium.wgsl`).
pub const SKYVIEW_WGSL: &str = concat!(
    include_str!("shaders/skyview.wgsl"),
    include_str!("shaders/atmo.wgsl"),
    include_str!("shaders/medium.wgsl"),
    include_str!("shaders/bilinear.wgsl")
);

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use std::mem::{align_of, size_of};

    /// `(name, byte offset, Rust type name)` of the listed fields of a
    /// struct, for [`assert_wgsl_layout`].
    macro_rules! fields {
        ($t:ty, [$($f:ident),* $(,)?]) => {{
            fn type_of<T>(_: &T) -> &'static str {
                std::any::type_name::<T>()
            }
            let z = <$t as bytemuck::Zeroable>::zeroed();
            vec![$((stringify!($f), std::mem::offset_of!($t, $f), type_of(&z.$f))),*]
        }};
    }
    pub(crate) use fields;

    /// The Rust spelling of a naga member type (`f32`, `[f32; 3]`,
    /// `[[f32; 4]; 3]`, …).
    fn rust_type(module: &naga::Module, ty: naga::Handle<naga::Type>) -> String {
        let scalar = |s: &naga::Scalar| match (s.kind, s.width) {
            (naga::ScalarKind::Float, 4) => "f32",
            (naga::ScalarKind::Uint, 4) => "u32",
            (naga::ScalarKind::Sint, 4) => "i32",
            _ => panic!("scalar {s:?}"),
        };
        match &module.types[ty].inner {
            naga::TypeInner::Scalar(s) => scalar(s).to_string(),
            naga::TypeInner::Vector { size, scalar: s } => {
                format!("[{}; {}]", scalar(s), *size as u8)
            }
            naga::TypeInner::Array {
                base,
                size: naga::ArraySize::Constant(n),
                ..
            } => format!("[{}; {n}]", rust_type(module, *base)),
            other => panic!("member type {other:?}"),
        }
    }

    /// The WGSL struct `name` in `wgsl` has naga's size `size` and the
    /// members `rust` (name, byte offset, Rust type) in order: the
    /// uniform-address-space layout of a `#[repr(C)]` mirror, field for
    /// field, with the same scalar types.
    pub(crate) fn assert_wgsl_layout(
        wgsl: &str,
        name: &str,
        size: usize,
        rust: &[(&str, usize, &str)],
    ) {
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
        assert_eq!(size % 16, 0, "{name}");
        let wgsl: Vec<_> = members
            .iter()
            .map(|m| {
                let field = m.name.clone().unwrap_or_default();
                (field, m.offset as usize, rust_type(&module, m.ty))
            })
            .collect();
        let rust: Vec<_> = rust
            .iter()
            .map(|&(f, off, ty)| (f.to_string(), off, ty.to_string()))
            .collect();
        assert_eq!(wgsl, rust, "{name}");
    }

    /// The Rust struct's size and field offsets equal the layout naga
    /// computes for the WGSL `Frame` (uniform address space rules).
    #[test]
    fn frame_uniforms_mirror_the_wgsl_struct() {
        assert_eq!(size_of::<FrameUniforms>(), 160);
        assert_eq!(align_of::<FrameUniforms>(), 4);
        let rust = fields!(
            FrameUniforms,
            [
                width,
                height,
                projection,
                face_size,
                forward,
                tan_half_fov,
                right,
                _pad0,
                up,
                _pad1,
                sun,
                cos_sun_margin,
                moonlight,
                moonlit,
                eclipse_moon,
                sin_moon_radius,
                sin_sun_radius,
                sun_z_min,
                sun_z_max,
                sun_subsamples,
                sun_rho_nodes,
                sun_z_nodes,
                sun_x0,
                sun_y0,
                sky_view_width,
                sky_view_height,
                band_first_row,
                band_rows
            ]
        );
        assert_wgsl_layout(STORE_WGSL, "Frame", size_of::<FrameUniforms>(), &rust);
    }

    #[test]
    fn night_uniforms_mirror_the_wgsl_struct() {
        assert_eq!(size_of::<NightUniforms>(), 160);
        let rust = fields!(
            NightUniforms,
            [
                enu_to_icrs_x,
                sin_obliquity,
                enu_to_icrs_y,
                cos_obliquity,
                enu_to_icrs_z,
                _pad0,
                airglow,
                van_rhijn_k2,
                zodiacal,
                _pad1,
                floor,
                _pad2,
                map_width,
                map_height,
                extinction_nodes,
                tile_size,
                tiles_per_row,
                star_list,
                planet_list,
                star_busy_first,
                planet_busy_first,
                star_busy_count,
                planet_busy_count,
                core_radius,
                inv_two_sigma2,
                quad_scale,
                _pad3,
                _pad4
            ]
        );
        assert_wgsl_layout(STORE_WGSL, "Night", size_of::<NightUniforms>(), &rust);
    }

    /// `PointRecord` has the size and offsets naga computes for `Point`.
    #[test]
    fn point_record_mirrors_the_wgsl_struct() {
        assert_eq!(size_of::<PointRecord>(), 48);
        let rust = fields!(
            PointRecord,
            [
                x,
                y,
                core_scale,
                glare_radius,
                colour,
                glare_scale,
                pixel_x,
                pixel_y,
                face,
                near_horizon
            ]
        );
        assert_wgsl_layout(STORE_WGSL, "Point", size_of::<PointRecord>(), &rust);
    }

    #[test]
    fn atmosphere_uniforms_mirror_the_wgsl_struct() {
        assert_eq!(size_of::<AtmosphereUniforms>(), 480);
        let rust = fields!(
            AtmosphereUniforms,
            [
                rayleigh,
                mie_scattering,
                mie_extinction,
                ozone,
                forward,
                w_r,
                w_g,
                w_b,
                sun,
                irradiance_scale,
                bottom_radius,
                top_radius,
                inv_h_rayleigh,
                inv_h_mie,
                ozone_peak,
                inv_ozone_width,
                mie_g,
                ground_albedo,
                sun_angular_radius,
                observer_radius,
                cos_forward_peak,
                forward_peak,
                transmittance_width,
                transmittance_height,
                multiscatter_n,
                sky_view_steps,
                sky_view_width,
                sky_view_height,
                _pad0,
                _pad1
            ]
        );
        assert_wgsl_layout(SKYVIEW_WGSL, "Atmo", size_of::<AtmosphereUniforms>(), &rust);
    }

    /// `MoonUniforms` and the table rows have the layout naga computes
    /// for `Moon`; the table offsets match the WGSL constants.
    #[test]
    fn moon_uniforms_mirror_the_wgsl_struct() {
        assert_eq!(size_of::<MoonUniforms>(), 288);
        let mut rust = fields!(
            MoonUniforms,
            [
                centre,
                radius,
                east,
                sin_radius,
                north,
                refract,
                sun,
                sun_factor,
                axis_x,
                pixel_angle,
                axis_y,
                cos_bound,
                axis_z,
                _pad0,
                sun_rgb,
                extinction_z0,
                earth_rgb,
                extinction_dz,
                geo_east,
                refraction_alt0,
                geo_north,
                refraction_dalt,
                shadow_east,
                shadow_north,
                semidiameter,
                shadow_last,
                extinction_nodes,
                eclipse_nodes,
                refraction_nodes,
                subsamples,
                albedo_width,
                albedo_height,
                normal_width,
                normal_height,
                disk_x0,
                disk_y0,
                disk_x1,
                disk_y1,
                corona_x0,
                corona_y0,
                corona_x1,
                corona_y1,
                corona_cos_outer,
                corona_sun_radius,
                corona_moon_radius,
                max_pixel_angle,
                corona_z0,
                corona_dz,
                corona_nodes,
                corona_floor
            ]
        );
        rust.push(("tables", size_of::<MoonUniforms>(), "[[f32; 4]; 304]"));
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
